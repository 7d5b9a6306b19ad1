#include "mesh_convert.h"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/model_limits.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

using Triangle = std::array<Eigen::Vector3f, 3>;

// A binary STL is exactly 84 + 50 n bytes, n being the count at byte 80; an
// ASCII file virtually never is (binary_stl_triangle_count). The header text
// is irrelevant ("solid" is a legal start of a binary header).
bool read_binary_stl(const fs::path& path, std::vector<Triangle>& out) {
  const auto count = binary_stl_triangle_count(path);
  if (!count) return false;
  const auto n = uint32_t(*count);
  std::ifstream in(path, std::ios::binary);
  in.seekg(84);
  std::vector<char> buf(size_t(n) * 50);
  in.read(buf.data(), std::streamsize(buf.size()));
  if (!in) return false;
  out.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    const char* rec = buf.data() + size_t(i) * 50 + 12;  // skip the normal
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 * k, 12);
      out[i][k] = Eigen::Vector3f(xyz[0], xyz[1], xyz[2]);
    }
  }
  return true;
}

void collect(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent,
             std::vector<Triangle>& out) {
  const aiMatrix4x4 T = parent * node->mTransformation;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[i]];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines have no surface
      Triangle t;
      for (int k = 0; k < 3; ++k) {
        const aiVector3D v = T * mesh->mVertices[face.mIndices[k]];
        t[k] = Eigen::Vector3f(v.x, v.y, v.z);
      }
      out.push_back(t);
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect(scene, node->mChildren[c], T, out);
}

void read_with_assimp(const fs::path& path, const std::string& context,
                      std::vector<Triangle>& out) {
  try {
    check_mesh_file(path);
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  Assimp::Importer importer;
  // URDF meshes are used in their file's own axes (ROS does the same).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // Validation refuses face indices beyond the vertices, mesh indices
  // beyond the meshes and the like, which the walk below would follow.
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode)
    throw InputError(context + ": cannot read mesh '" + path.string() +
                     "': " + importer.GetErrorString());
  collect(scene, scene->mRootNode, aiMatrix4x4(), out);
}

// ConvertedMesh::flat: the farthest vertex from the first, the farthest
// from their line, then the farthest from their plane.
bool is_flat(const std::vector<Triangle>& tris) {
  const Eigen::Vector3d p0 = tris[0][0].cast<double>();
  const auto farthest = [&](auto distance) {
    double best = -1;
    Eigen::Vector3d at = p0;
    for (const Triangle& t : tris)
      for (const Eigen::Vector3f& v : t)
        if (const double d = distance(v.cast<double>()); d > best) best = d, at = v.cast<double>();
    return std::make_pair(best, at);
  };
  const auto [size, p1] = farthest([&](const Eigen::Vector3d& v) { return (v - p0).norm(); });
  const double tolerance = 1e-6 * size;
  if (!(size > 0)) return true;
  const Eigen::Vector3d u = (p1 - p0) / size;
  const auto [off_line, p2] =
      farthest([&](const Eigen::Vector3d& v) { return (v - p0 - u * u.dot(v - p0)).norm(); });
  if (off_line <= tolerance) return true;
  const Eigen::Vector3d n = u.cross(p2 - p0).normalized();
  return farthest([&](const Eigen::Vector3d& v) { return std::abs(n.dot(v - p0)); }).first <=
         tolerance;
}

// Turns the parts of a triangle soup outward (orient_parts, on its corners
// joined where they are equal), every triangle kept in its place.
MeshOrientation orient_soup(std::vector<Triangle>& tris) {
  TriangleMesh mesh;
  mesh.vertices_m.reserve(3 * tris.size());
  mesh.triangles.reserve(tris.size());
  for (const Triangle& t : tris) {
    const int first = int(mesh.vertices_m.size());
    mesh.vertices_m.insert(mesh.vertices_m.end(), t.begin(), t.end());
    mesh.triangles.emplace_back(first, first + 1, first + 2);
  }
  mesh.join_equal_vertices();
  const std::vector<Eigen::Vector3i> before = mesh.triangles;
  const MeshOrientation report = orient_parts(mesh);
  for (std::size_t i = 0; i < tris.size(); ++i)
    if (mesh.triangles[i] != before[i]) std::swap(tris[i][1], tris[i][2]);
  return report;
}

void put_f32(std::vector<char>& buf, size_t& at, float v) {
  std::memcpy(buf.data() + at, &v, 4);
  at += 4;
}

}  // namespace

ConvertedMesh convert_mesh_to_binary_stl(const fs::path& source, const fs::path& target_stem,
                                         const Eigen::Vector3d& scale, const std::string& context,
                                         std::uint64_t max_triangles) {
  if (!fs::is_regular_file(source))
    throw InputError(context + ": mesh file '" + source.string() + "' not found");
  const auto too_many = [&](std::uint64_t n) {
    return InputError(context + ": mesh '" + source.string() + "' has " + std::to_string(n) +
                      " triangles, more than the " + std::to_string(max_triangles) +
                      " left of the description's limit (docs/robots.md, 'Limits')");
  };
  if (const auto declared = binary_stl_triangle_count(source);
      declared && *declared > max_triangles)
    throw too_many(*declared);
  std::vector<Triangle> tris;
  std::string ext = source.extension().string();
  for (char& c : ext) c = char(std::tolower(c));
  if (!(ext == ".stl" && read_binary_stl(source, tris))) read_with_assimp(source, context, tris);
  if (tris.empty()) throw InputError(context + ": mesh '" + source.string() + "' has no triangles");
  if (tris.size() > max_triangles) throw too_many(tris.size());

  // A mirroring scale turns the surface inside out; swapping two corners of
  // every triangle keeps normals pointing outward.
  const bool mirror = scale.x() * scale.y() * scale.z() < 0;
  const Eigen::Vector3f s = scale.cast<float>();
  for (Triangle& t : tris) {
    for (auto& v : t) v = v.cwiseProduct(s);
    if (mirror) std::swap(t[1], t[2]);
  }
  ConvertedMesh converted;
  converted.triangles = tris.size();
  converted.flat = is_flat(tris);
  converted.orientation = orient_soup(tris);
  for (std::size_t first = 0; first < tris.size(); first += kMaxStlTriangles) {
    const std::size_t count = std::min<std::size_t>(kMaxStlTriangles, tris.size() - first);
    std::vector<char> buf(84 + 50 * count, 0);
    const char header[] = "binary STL written by arttrack";
    std::memcpy(buf.data(), header, sizeof(header) - 1);
    const auto n = uint32_t(count);
    std::memcpy(buf.data() + 80, &n, 4);
    size_t at = 84;
    for (std::size_t i = first; i < first + count; ++i) {
      const Triangle& t = tris[i];
      Eigen::Vector3f normal = (t[1] - t[0]).cross(t[2] - t[0]);
      if (normal.norm() > 0) normal.normalize();
      for (int k = 0; k < 3; ++k) put_f32(buf, at, normal[k]);
      for (const auto& v : t)
        for (int k = 0; k < 3; ++k) put_f32(buf, at, v[k]);
      at += 2;  // attribute byte count
    }
    const std::size_t part = first / kMaxStlTriangles;
    fs::path target = target_stem;
    if (part > 0) {
      target += '_';
      target += std::to_string(part);
    }
    target += ".stl";
    std::ofstream out(target, std::ios::binary);
    out.write(buf.data(), std::streamsize(buf.size()));
    if (!out)
      throw InputError(context + ": cannot write the converted mesh in the temporary folder " +
                       target.parent_path().string());
    converted.files.push_back(target);
  }
  return converted;
}

}  // namespace arttrack::sim
