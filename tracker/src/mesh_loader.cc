#include "arttrack/tracker/mesh_loader.h"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <unordered_map>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/model_limits.h"

namespace arttrack {

void TriangleMesh::append(const TriangleMesh& other, const Eigen::Affine3d& T_this_other) {
  const int offset = int(vertices_m.size());
  vertices_m.reserve(vertices_m.size() + other.vertices_m.size());
  for (const Eigen::Vector3f& v : other.vertices_m) {
    vertices_m.push_back((T_this_other * v.cast<double>()).cast<float>());
  }
  // A mirror turns counter-clockwise into clockwise: swap two corners back.
  const bool mirrored = T_this_other.linear().determinant() < 0;
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const Eigen::Vector3i& t : other.triangles) {
    const Eigen::Vector3i s = t.array() + offset;
    triangles.push_back(mirrored ? Eigen::Vector3i(s[0], s[2], s[1]) : s);
  }
}

namespace {

// A triangle with a repeated corner: no area, no edges of its own.
bool degenerate(const Eigen::Vector3i& t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; }

}  // namespace

void TriangleMesh::join_equal_vertices() {
  struct Key {
    uint32_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return (size_t(k.x) * 0x9E3779B97F4A7C15ull) ^ (size_t(k.y) * 0xC2B2AE3D27D4EB4Full) ^
             (size_t(k.z) * 0x165667B19E3779F9ull);
    }
  };
  auto bits = [](float f) {
    f += 0.f;  // -0 and +0 are the same point
    uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
  };
  std::unordered_map<Key, int, KeyHash> index_of;
  std::vector<Eigen::Vector3f> welded;
  std::vector<int> remap(vertices_m.size());
  for (size_t i = 0; i < vertices_m.size(); ++i) {
    const Eigen::Vector3f& v = vertices_m[i];
    auto [it, inserted] =
        index_of.try_emplace(Key{bits(v.x()), bits(v.y()), bits(v.z())}, int(welded.size()));
    if (inserted) welded.push_back(v);
    remap[i] = it->second;
  }
  for (Eigen::Vector3i& t : triangles) t = Eigen::Vector3i(remap[t[0]], remap[t[1]], remap[t[2]]);
  vertices_m = std::move(welded);
}

void TriangleMesh::weld_vertices() {
  join_equal_vertices();
  std::erase_if(triangles, degenerate);
}

namespace {

Eigen::Affine3d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return Eigen::Affine3d(e);
}

// Appends the meshes of `node` and of its descendants, each placed by the
// product of the node transforms from the root down.
void collect_node(const aiScene& scene, const aiNode& node, const Eigen::Affine3d& T_parent,
                  TriangleMesh& out) {
  const Eigen::Affine3d T_node = T_parent * to_eigen(node.mTransformation);
  for (unsigned k = 0; k < node.mNumMeshes; ++k) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[k]];
    TriangleMesh part;
    part.vertices_m.reserve(mesh.mNumVertices);
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D& v = mesh.mVertices[i];
      part.vertices_m.emplace_back(v.x, v.y, v.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines have no area
      part.triangles.emplace_back(int(face.mIndices[0]), int(face.mIndices[1]),
                                  int(face.mIndices[2]));
    }
    out.append(part, T_node);
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    collect_node(scene, *node.mChildren[c], T_node, out);
  }
}

// Turns each triangle of a convex shape centred at the origin to face away
// from the centre, so the generators need not track winding by hand.
void orient_outward(TriangleMesh& mesh) {
  for (Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3f& a = mesh.vertices_m[t[0]];
    const Eigen::Vector3f& b = mesh.vertices_m[t[1]];
    const Eigen::Vector3f& c = mesh.vertices_m[t[2]];
    if ((b - a).cross(c - a).dot(a + b + c) < 0) std::swap(t[1], t[2]);
  }
}

// Volume a closed, outward-oriented mesh encloses (divergence theorem).
double enclosed_volume(const TriangleMesh& mesh) {
  double six_v = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices_m[std::size_t(t[0])].cast<double>();
    const Eigen::Vector3d b = mesh.vertices_m[std::size_t(t[1])].cast<double>();
    const Eigen::Vector3d c = mesh.vertices_m[std::size_t(t[2])].cast<double>();
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6;
}

// Circumradius of a regular n-gon with the area of the unit circle.
double area_preserving_radius(int n) {
  const double pi = std::numbers::pi;
  return std::sqrt(2 * pi / (n * std::sin(2 * pi / n)));
}

}  // namespace

MeshOrientation& MeshOrientation::operator+=(const MeshOrientation& other) {
  parts += other.parts;
  turned_parts += other.turned_parts;
  open_parts += other.open_parts;
  open_triangles += other.open_triangles;
  return *this;
}

MeshOrientation orient_parts(TriangleMesh& mesh) {
  const int n = int(mesh.triangles.size());
  // Every triangle's three edges, sorted so that the uses of one edge are
  // adjacent: (lower vertex, higher vertex, triangle, walked lower to higher).
  struct HalfEdge {
    std::uint64_t key;
    int triangle;
    bool upward;
  };
  std::vector<HalfEdge> edges;
  edges.reserve(3 * std::size_t(n));
  for (int t = 0; t < n; ++t) {
    if (degenerate(mesh.triangles[std::size_t(t)])) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[std::size_t(t)][k];
      const int b = mesh.triangles[std::size_t(t)][(k + 1) % 3];
      const auto lo = std::uint64_t(std::min(a, b)), hi = std::uint64_t(std::max(a, b));
      edges.push_back({lo << 32 | hi, t, a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key < y.key || (x.key == y.key && x.triangle < y.triangle);
  });
  // Per triangle: up to three neighbours across edges of exactly two
  // triangles, and whether the neighbour walks the edge the same way (then
  // one of the two is wound the other way). `on_border`: a triangle with an
  // edge of one triangle, or of three and more.
  struct Neighbour {
    int triangle;
    bool same_way;
  };
  std::vector<std::array<Neighbour, 3>> neighbours(mesh.triangles.size());
  std::vector<int> num_neighbours(std::size_t(n), 0);
  std::vector<char> on_border(std::size_t(n), 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i == 2 && edges[i].triangle != edges[i + 1].triangle) {
      const bool same_way = edges[i].upward == edges[i + 1].upward;
      for (const auto& [from, to] :
           {std::pair(edges[i], edges[i + 1]), std::pair(edges[i + 1], edges[i])}) {
        int& count = num_neighbours[std::size_t(from.triangle)];
        neighbours[std::size_t(from.triangle)][std::size_t(count++)] = {to.triangle, same_way};
      }
    } else {
      for (std::size_t k = i; k < j; ++k) on_border[std::size_t(edges[k].triangle)] = 1;
    }
    i = j;
  }
  // Each part in turn: wind its triangles like its first one (a breadth-first
  // walk), then, if it is closed, the way that encloses a positive volume.
  MeshOrientation report;
  std::vector<int> part_of(std::size_t(n), -1);
  std::vector<char> flip(std::size_t(n), 0);
  std::vector<int> members;
  for (int seed = 0; seed < n; ++seed) {
    if (part_of[std::size_t(seed)] >= 0 || degenerate(mesh.triangles[std::size_t(seed)])) continue;
    const int part = report.parts++;
    members.assign(1, seed);
    part_of[std::size_t(seed)] = part;
    bool border = false, conflict = false;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const int t = members[m];
      border = border || on_border[std::size_t(t)];
      for (int k = 0; k < num_neighbours[std::size_t(t)]; ++k) {
        const Neighbour& nb = neighbours[std::size_t(t)][std::size_t(k)];
        const char wanted = char(flip[std::size_t(t)] ^ char(nb.same_way));
        if (part_of[std::size_t(nb.triangle)] < 0) {
          part_of[std::size_t(nb.triangle)] = part;
          flip[std::size_t(nb.triangle)] = wanted;
          members.push_back(nb.triangle);
        } else if (flip[std::size_t(nb.triangle)] != wanted) {
          conflict = true;  // no consistent winding (a Moebius band)
        }
      }
    }
    if (border || conflict) {
      ++report.open_parts;
      report.open_triangles += int(members.size());
    }
    if (conflict) continue;
    // The volume enclosed, wound like the seed, about the part's centroid:
    // exact for a closed part; for an open one with small holes (a crack, a
    // T-junction) nearly so, and then its sign says which side is outside
    // too. An open part enclosing less than 1% of area^1.5 (a sheet, a
    // shell with a wide opening) has no outside: left as it is.
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const int t : members)
      for (int k = 0; k < 3; ++k)
        centroid += mesh.vertices_m[std::size_t(mesh.triangles[std::size_t(t)][k])].cast<double>();
    centroid /= 3.0 * double(members.size());
    double six_volume = 0, twice_area = 0;
    for (const int t : members) {
      const Eigen::Vector3i& tri = mesh.triangles[std::size_t(t)];
      const Eigen::Vector3d a = mesh.vertices_m[std::size_t(tri[0])].cast<double>() - centroid;
      const Eigen::Vector3d b = mesh.vertices_m[std::size_t(tri[1])].cast<double>() - centroid;
      const Eigen::Vector3d c = mesh.vertices_m[std::size_t(tri[2])].cast<double>() - centroid;
      six_volume += (flip[std::size_t(t)] ? -1 : 1) * a.dot(b.cross(c));
      twice_area += (b - a).cross(c - a).norm();
    }
    if (border && !(std::abs(six_volume) >= 6 * 0.01 * std::pow(0.5 * twice_area, 1.5))) continue;
    const char invert = six_volume < 0;
    bool turned = false;
    for (const int t : members) {
      if (!(flip[std::size_t(t)] ^ invert)) continue;
      Eigen::Vector3i& tri = mesh.triangles[std::size_t(t)];
      std::swap(tri[1], tri[2]);
      turned = true;
    }
    report.turned_parts += turned;
  }
  return report;
}

TriangleMesh load_mesh(const std::string& path, const Eigen::Vector3d& scale) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError("mesh file '" + path + "' does not exist or is not a file");
  }
  check_mesh_file(path);
  Assimp::Importer importer;
  // Mesh coordinates are link coordinates (ROS convention): no Y-up rotation.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // Validation refuses face indices beyond the vertices, mesh indices
  // beyond the meshes and the like, which the walk below would follow.
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_ValidateDataStructure);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    throw InputError("cannot read mesh file '" + path + "': " + importer.GetErrorString());
  }
  TriangleMesh mesh;
  Eigen::Affine3d T_scale = Eigen::Affine3d::Identity();
  T_scale.linear() = scale.asDiagonal();
  collect_node(*scene, *scene->mRootNode, T_scale, mesh);
  mesh.weld_vertices();
  if (mesh.empty()) throw InputError("mesh file '" + path + "' holds no triangle");
  for (std::size_t k = 0; k < mesh.vertices_m.size(); ++k)
    if (!mesh.vertices_m[k].allFinite())
      throw InputError("mesh file '" + path + "': vertex " + std::to_string(k) +
                       " is not finite (every coordinate must be a finite number)");
  return mesh;
}

TriangleMesh make_box(const Eigen::Vector3d& size_m) {
  TriangleMesh mesh;
  const Eigen::Vector3f h = (0.5 * size_m).cast<float>();
  // Corner i has x, y, z at the positive side when bits 0, 1, 2 of i are set.
  for (int i = 0; i < 8; ++i) {
    mesh.vertices_m.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(),
                                 i & 4 ? h.z() : -h.z());
  }
  // Each face as two triangles; orient_outward fixes their winding.
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    mesh.triangles.emplace_back(f[0], f[1], f[2]);
    mesh.triangles.emplace_back(f[0], f[2], f[3]);
  }
  orient_outward(mesh);
  return mesh;
}

TriangleMesh make_cylinder(double radius_m, double length_m, int segments) {
  const int n = std::max(segments, 3);
  const double r = radius_m * area_preserving_radius(n);
  const float hz = float(0.5 * length_m);
  TriangleMesh mesh;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    const float x = float(r * std::cos(a)), y = float(r * std::sin(a));
    mesh.vertices_m.emplace_back(x, y, -hz);  // 2i: bottom ring
    mesh.vertices_m.emplace_back(x, y, hz);   // 2i+1: top ring
  }
  const int bottom = 2 * n, top = 2 * n + 1;
  mesh.vertices_m.emplace_back(0.f, 0.f, -hz);
  mesh.vertices_m.emplace_back(0.f, 0.f, hz);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    mesh.triangles.emplace_back(2 * i, 2 * j, 2 * j + 1);
    mesh.triangles.emplace_back(2 * i, 2 * j + 1, 2 * i + 1);
    mesh.triangles.emplace_back(bottom, 2 * i, 2 * j);
    mesh.triangles.emplace_back(top, 2 * i + 1, 2 * j + 1);
  }
  orient_outward(mesh);
  return mesh;
}

TriangleMesh make_sphere(double radius_m, int segments) {
  const int n = std::max(segments, 4);  // meridians
  const int bands = std::max(n / 2, 2);
  const double r = radius_m;  // scaled to the sphere's volume at the end
  const double pi = std::numbers::pi;
  TriangleMesh mesh;
  mesh.vertices_m.emplace_back(0.f, 0.f, float(r));  // 0: north pole
  for (int k = 1; k < bands; ++k) {                  // ring k at index 1 + (k-1) n
    const double polar = pi * k / bands;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * pi * i / n;
      mesh.vertices_m.emplace_back(float(r * std::sin(polar) * std::cos(a)),
                                   float(r * std::sin(polar) * std::sin(a)),
                                   float(r * std::cos(polar)));
    }
  }
  const int south = int(mesh.vertices_m.size());
  mesh.vertices_m.emplace_back(0.f, 0.f, float(-r));
  auto ring = [n](int k, int i) { return 1 + (k - 1) * n + (i % n); };
  for (int i = 0; i < n; ++i) {
    mesh.triangles.emplace_back(0, ring(1, i), ring(1, i + 1));
    mesh.triangles.emplace_back(south, ring(bands - 1, i), ring(bands - 1, i + 1));
    for (int k = 1; k + 1 < bands; ++k) {
      mesh.triangles.emplace_back(ring(k, i), ring(k + 1, i), ring(k + 1, i + 1));
      mesh.triangles.emplace_back(ring(k, i), ring(k + 1, i + 1), ring(k, i + 1));
    }
  }
  orient_outward(mesh);
  // Faces curve away in two directions, so the circle's area factor leaves
  // a UV sphere's faces inside the sphere (2.3% of the radius at 12
  // meridians, a robot drawn 1.4 mm behind the camera's surfaces, enough to
  // pull the estimate along its weakest direction by a degree and more).
  // Scaled to the sphere's volume, the faces lie as far inside as the
  // vertices lie outside.
  const double scale = std::cbrt(4.0 / 3.0 * pi * r * r * r / enclosed_volume(mesh));
  for (Eigen::Vector3f& v : mesh.vertices_m) v *= float(scale);
  return mesh;
}

}  // namespace arttrack
