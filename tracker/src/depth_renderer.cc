#include "arttrack/tracker/depth_renderer.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

// Screen position and inverse depth of a homogeneous image point
// (fx x + cx z, fy y + cy z, z). One formula for mesh and clipped vertices,
// so a point shared by two triangles projects to bit-identical coordinates.
inline Eigen::Vector3f project(const Eigen::Vector3f& hom) {
  const float inv_z = 1.f / hom.z();
  return Eigen::Vector3f(hom.x() * inv_z, hom.y() * inv_z, inv_z);
}

// The first pixel index u in [0, n] whose centre u + 0.5 is at or after x:
// ceil(x - 0.5) clamped, branch-free (x86-64 without SSE4.1 has no ceil
// instruction). Every triangle that meets a boundary at x computes the same
// index from the same x, so spans on both sides of a shared edge tile a row.
inline int first_centre_from(float x, int n) {
  const float t = std::min(std::max(x - 0.5f, -0.5f), float(n));
  const int i = int(t);  // truncates towards zero: i <= ceil(t) <= i + 1 for t >= -0.5
  return i + int(float(i) < t);
}

// Whether a triangle of screen points faces the camera (or, without culling,
// is not degenerate). Twice the signed screen area: with v pointing down, a
// triangle wound counter-clockwise seen from outside has negative area when it
// faces the camera: area = fx fy (n . p_a) / (z_a z_b z_c), n its outward normal.
inline bool faces_camera(const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                         const Eigen::Vector3f& c, bool cull_back_faces) {
  const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  return cull_back_faces ? area < 0.f : area != 0.f;
}

// Whether a triangle's bounding box holds a pixel centre, from its corners'
// first_centre_from() indices: the function is monotonic, so the index of the
// box's edge is the least (greatest) of the corners'.
inline bool box_holds_centre(const Eigen::Vector2i& a, const Eigen::Vector2i& b,
                             const Eigen::Vector2i& c) {
  return std::min({a.x(), b.x(), c.x()}) < std::max({a.x(), b.x(), c.x()}) &&
         std::min({a.y(), b.y(), c.y()}) < std::max({a.y(), b.y(), c.y()});
}

// Whether a triangle of screen points can cover a pixel centre of a W x H
// image and faces the camera (the clipped triangles' test; the mesh loop
// takes the corners' indices from the vertices).
inline bool may_cover(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                      int W, int H, bool cull_back_faces) {
  auto index = [W, H](const Eigen::Vector3f& p) {
    return Eigen::Vector2i(first_centre_from(p.x(), W), first_centre_from(p.y(), H));
  };
  return faces_camera(a, b, c, cull_back_faces) && box_holds_centre(index(a), index(b), index(c));
}

// Whether no triangle within a camera-frame sphere (centre `c`, radius `r`,
// wholly in front of the camera) can pass box_holds_centre(): the sphere's
// screen extent, taken over the corners of its bounding cube, holds no pixel
// centre column or no pixel centre row. The extent is widened by 0.01 px, far
// more than the float rounding of the vertices' own screen positions, so a
// sphere is only ruled out when every vertex in it would have been.
inline bool sphere_holds_no_centre(const Eigen::Vector3f& c, float r, float fx, float fy, float cx,
                                   float cy, int W, int H) {
  const float iz_far = 1.f / (c.z() + r), iz_near = 1.f / (c.z() - r);
  constexpr float kMargin_px = 0.01f;
  // The least and greatest screen coordinate f x / z + cc over the cube: x / z
  // is extreme at its corners.
  auto no_centre = [&](float x, float f, float cc, int n) {
    const float lo = x - r, hi = x + r;
    const float s_lo = std::min(lo * iz_far, lo * iz_near),
                s_hi = std::max(hi * iz_far, hi * iz_near);
    return first_centre_from(f * s_lo + cc - kMargin_px, n) ==
           first_centre_from(f * s_hi + cc + kMargin_px, n);
  };
  return no_centre(c.x(), fx, cx, W) || no_centre(c.y(), fy, cy, H);
}

// Strict order of screen points by v, then u: the two ends of an edge are
// told apart the same way by every triangle that has the edge.
inline bool above(const Eigen::Vector3f& p, const Eigen::Vector3f& q) {
  return p.y() < q.y() || (p.y() == q.y() && p.x() < q.x());
}

}  // namespace

DepthRenderer::DepthRenderer(const RobotModel& model, const CameraIntrinsics& camera,
                             const RenderOptions& options)
    : model_(&model),
      camera_(camera),
      options_(options),
      all_links_(model.num_links(), true),
      bounds_(model.num_links()) {
  ARTTRACK_CHECK_ARGUMENT(model.camera_link() >= 0 && camera.width > 0 && camera.height > 0);
  for (int l : model.links_with_geometry()) {
    const std::vector<Eigen::Vector3f>& v = model.link(l).mesh.vertices_m;
    Eigen::Vector3f lo = v[0], hi = v[0];
    for (const Eigen::Vector3f& p : v) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    LinkBounds& b = bounds_[l];
    b.centre_m = 0.5f * (lo + hi);
    for (const Eigen::Vector3f& p : v) b.radius_m = std::max(b.radius_m, (p - b.centre_m).norm());
    // The exact round shapes, which their tessellations need not enclose.
    for (const RoundShape& shape : model.link(l).round_shapes) {
      const Eigen::Vector3f c = shape.T_link_shape.translation().cast<float>();
      const double half = 0.5 * shape.length_m;
      const float reach = float(std::sqrt(shape.radius_m * shape.radius_m + half * half));
      b.radius_m = std::max(b.radius_m, (c - b.centre_m).norm() + reach);
    }
    b.radius_m *= 1.0001f;  // float rounding of the transformed vertices
  }
  clusters_.resize(std::size_t(model.num_links()));
  std::size_t max_cluster_vertices = 0;
  for (int l : model.links_with_geometry()) {
    const Link& link = model.link(l);
    clusters_[std::size_t(l)].push_back(make_clusters(link.mesh, link.round_shapes));
    for (const Link::MeshLevel& coarser : link.coarser_meshes)
      clusters_[std::size_t(l)].push_back(make_clusters(coarser.mesh, {}));
    for (const Clusters& level : clusters_[std::size_t(l)])
      max_cluster_vertices = std::max(max_cluster_vertices, level.x.size());
  }
  hom_.resize(max_cluster_vertices);
  screen_.resize(max_cluster_vertices);
  first_centre_.resize(max_cluster_vertices);
  // A camera-frame point p is inside the view when 0 <= u <= W and 0 <= v <= H,
  // i.e. fx x + cx z >= 0, -fx x + (W - cx) z >= 0, and the same in y.
  const float fx = float(camera.fx), fy = float(camera.fy);
  const float cx = float(camera.cx), cy = float(camera.cy);
  frustum_planes_ << fx, 0, cx, -fx, 0, float(camera.width) - cx, 0, fy, cy, 0, -fy,
      float(camera.height) - cy;
  frustum_planes_.rowwise().normalize();
}

PixelRect DepthRenderer::render(const KinematicsState& state, DepthImage& out) {
  return render_links(state, all_links_, out);
}

PixelRect DepthRenderer::render_links(const KinematicsState& state, const LinkSet& links,
                                      DepthImage& out) {
  if (out.width != camera_.width || out.height != camera_.height) {
    out = DepthImage(camera_.width, camera_.height);
  } else {
    std::fill(out.depth_m.begin(), out.depth_m.end(), 0.f);
  }
  return draw_links(state, links, out);
}

PixelRect DepthRenderer::draw_links(const KinematicsState& state, const LinkSet& links,
                                    DepthImage& depth) {
  ARTTRACK_CHECK_ARGUMENT(depth.width == camera_.width && depth.height == camera_.height);
  ARTTRACK_CHECK_ARGUMENT(int(state.T_root_link.size()) == model_->num_links());
  const Eigen::Isometry3d T_camera_root =
      state.T_root_link[model_->camera_link()].inverse(Eigen::Isometry);
  PixelRect drawn;
  for (int l : model_->links_with_geometry()) {
    if (links[l]) drawn = drawn.united(draw_link(l, T_camera_root * state.T_root_link[l], depth));
  }
  return drawn;
}

inline void DepthRenderer::transform_vertex(int i, const Eigen::Matrix3f& A,
                                            const Eigen::Vector3f& b, const Clusters& clusters,
                                            bool may_clip) {
  const float x = clusters.x[std::size_t(i)], y = clusters.y[std::size_t(i)],
              z = clusters.z[std::size_t(i)];
  // A x + b in the order Eigen's product sums it, which transform_cluster
  // repeats lane by lane.
  hom_[std::size_t(i)] = Eigen::Vector3f((A(0, 0) * x + (A(0, 1) * y + A(0, 2) * z)) + b.x(),
                                         (A(1, 0) * x + (A(1, 1) * y + A(1, 2) * z)) + b.y(),
                                         (A(2, 0) * x + (A(2, 1) * y + A(2, 2) * z)) + b.z());
  if (!may_clip || hom_[std::size_t(i)].z() >= options_.near_m) {
    screen_[std::size_t(i)] = project(hom_[std::size_t(i)]);
    first_centre_[std::size_t(i)] =
        Eigen::Vector2i(first_centre_from(screen_[std::size_t(i)].x(), camera_.width),
                        first_centre_from(screen_[std::size_t(i)].y(), camera_.height));
  }
}

inline void DepthRenderer::transform_cluster(const Cluster& cluster, const Eigen::Matrix3f& A,
                                             const Eigen::Vector3f& b, const Clusters& clusters) {
  const int end = cluster.first_vertex + (cluster.num_vertices + kLanes - 1) / kLanes * kLanes;
#if defined(__SSE2__)
  // The scalar formulas with each operation on four lanes: IEEE single
  // precision either way, so the same bits (test TransformsLikeOneVertexAtATime).
  const __m128 a00 = _mm_set1_ps(A(0, 0)), a01 = _mm_set1_ps(A(0, 1)), a02 = _mm_set1_ps(A(0, 2));
  const __m128 a10 = _mm_set1_ps(A(1, 0)), a11 = _mm_set1_ps(A(1, 1)), a12 = _mm_set1_ps(A(1, 2));
  const __m128 a20 = _mm_set1_ps(A(2, 0)), a21 = _mm_set1_ps(A(2, 1)), a22 = _mm_set1_ps(A(2, 2));
  const __m128 bx = _mm_set1_ps(b.x()), by = _mm_set1_ps(b.y()), bz = _mm_set1_ps(b.z());
  const __m128 one = _mm_set1_ps(1.f), half = _mm_set1_ps(0.5f), minus_half = _mm_set1_ps(-0.5f);
  const __m128 width = _mm_set1_ps(float(camera_.width)),
               height = _mm_set1_ps(float(camera_.height));
  // first_centre_from, lane by lane (finite x, the link being in front of
  // the near plane: max and min pick the value std::max and std::min do).
  auto first_centre = [&](__m128 x, __m128 n) {
    const __m128 t = _mm_min_ps(_mm_max_ps(_mm_sub_ps(x, half), minus_half), n);
    const __m128i i = _mm_cvttps_epi32(t);
    return _mm_sub_epi32(i, _mm_castps_si128(_mm_cmplt_ps(_mm_cvtepi32_ps(i), t)));
  };
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float) &&
                sizeof(Eigen::Vector2i) == 2 * sizeof(int));
  for (int k = cluster.first_vertex; k < end; k += kLanes) {
    const __m128 x = _mm_loadu_ps(clusters.x.data() + k);
    const __m128 y = _mm_loadu_ps(clusters.y.data() + k);
    const __m128 z = _mm_loadu_ps(clusters.z.data() + k);
    auto row = [&](__m128 r0, __m128 r1, __m128 r2, __m128 r) {
      return _mm_add_ps(
          _mm_add_ps(_mm_mul_ps(r0, x), _mm_add_ps(_mm_mul_ps(r1, y), _mm_mul_ps(r2, z))), r);
    };
    const __m128 hx = row(a00, a01, a02, bx), hy = row(a10, a11, a12, by),
                 hz = row(a20, a21, a22, bz);
    const __m128 iz = _mm_div_ps(one, hz);
    const __m128 u = _mm_mul_ps(hx, iz), v = _mm_mul_ps(hy, iz);
    // (u, v, iz) of four vertices, interleaved into screen_'s 12 floats.
    const __m128 uv01 = _mm_unpacklo_ps(u, v), uv23 = _mm_unpackhi_ps(u, v);
    const __m128 z0u1 = _mm_shuffle_ps(iz, uv01, _MM_SHUFFLE(2, 2, 0, 0));
    const __m128 v1z1 = _mm_shuffle_ps(uv01, iz, _MM_SHUFFLE(1, 1, 3, 3));
    const __m128 z2u3 = _mm_shuffle_ps(iz, uv23, _MM_SHUFFLE(2, 2, 2, 2));
    const __m128 v3z3 = _mm_shuffle_ps(uv23, iz, _MM_SHUFFLE(3, 3, 3, 2));
    float* out = screen_[std::size_t(k)].data();
    _mm_storeu_ps(out, _mm_shuffle_ps(uv01, z0u1, _MM_SHUFFLE(2, 0, 1, 0)));
    _mm_storeu_ps(out + 4, _mm_shuffle_ps(v1z1, uv23, _MM_SHUFFLE(1, 0, 2, 0)));
    _mm_storeu_ps(out + 8, _mm_shuffle_ps(z2u3, v3z3, _MM_SHUFFLE(2, 1, 2, 0)));
    const __m128i cu = first_centre(u, width), cv = first_centre(v, height);
    auto* index = reinterpret_cast<__m128i*>(first_centre_[std::size_t(k)].data());
    _mm_storeu_si128(index, _mm_unpacklo_epi32(cu, cv));
    _mm_storeu_si128(index + 1, _mm_unpackhi_epi32(cu, cv));
  }
#else
  for (int k = cluster.first_vertex; k < end; ++k) transform_vertex(k, A, b, clusters, false);
#endif
}

PixelRect DepthRenderer::draw_link(int link, const Eigen::Isometry3d& T_camera_link,
                                   DepthImage& depth) {
  const float near = options_.near_m;
  // Cull the whole link when its bounding sphere is behind the near plane or
  // outside a side of the view.
  const LinkBounds& bounds = bounds_[link];
  const Eigen::Vector3f centre = (T_camera_link * bounds.centre_m.cast<double>()).cast<float>();
  if (centre.z() + bounds.radius_m < near) return {};
  if ((frustum_planes_ * centre).minCoeff() < -bounds.radius_m) return {};
  const bool may_clip = centre.z() - bounds.radius_m < near;

  // Link frame to homogeneous image coordinates in one 3x4 float matrix.
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = camera_.fx;
  K(1, 1) = camera_.fy;
  K(0, 2) = camera_.cx;
  K(1, 2) = camera_.cy;
  const Eigen::Matrix3f A = (K * T_camera_link.linear()).cast<float>();
  const Eigen::Vector3f b = (K * T_camera_link.translation()).cast<float>();

  // The coarsest level of detail the link's nearest point is far enough for
  // (robot_model.h, Link::coarser_meshes); its triangles hold no round shape.
  const Link& l = model_->link(link);
  std::size_t level_index = 0;
  const float nearest = centre.z() - bounds.radius_m;
  for (std::size_t k = 0; k < l.coarser_meshes.size(); ++k) {
    if (nearest >= l.coarser_meshes[k].min_range_m) level_index = k + 1;
  }
  const Clusters& clusters = clusters_[std::size_t(link)][level_index];
  const Eigen::Vector3f* hom = hom_.data();
  const Eigen::Vector3f* screen = screen_.data();
  const Eigen::Vector2i* centre_index = first_centre_.data();
  // The camera's position in the link frame, for the clusters' cones.
  const Eigen::Vector3f camera_in_link =
      (-(T_camera_link.linear().transpose() * T_camera_link.translation())).cast<float>();

  // The link frame to the camera frame in float, for the clusters' spheres.
  const Eigen::Matrix3f R_camera_link = T_camera_link.linear().cast<float>();
  const Eigen::Vector3f t_camera_link = T_camera_link.translation().cast<float>();
  const float fx = float(camera_.fx), fy = float(camera_.fy);
  const float cx = float(camera_.cx), cy = float(camera_.cy);

  PixelRect drawn{camera_.width, camera_.height, 0, 0};
  // An open mesh part has no back faces (Link::mesh_parts).
  const bool cull_back_faces =
      options_.cull_back_faces && !(options_.open_parts_both_sides && l.has_open_parts());
  for (const Cluster& cluster : clusters.clusters) {
    if (cull_back_faces && cluster.cos_angle > 0.f) {
      // n . (camera - p) over the cluster's normals n and points p is at
      // most (axis . w) cos a + |axis x w| sin a + radius, w = camera -
      // centre: all faces turned away (by 0.01 rad and more) when below
      // -0.01 |w|.
      const Eigen::Vector3f w = camera_in_link - cluster.centre_m;
      const float reach = cluster.axis.dot(w) * cluster.cos_angle +
                          cluster.axis.cross(w).norm() * cluster.sin_angle + cluster.radius_m;
      if (reach < -0.01f * w.norm()) continue;
    }
    // A cluster whose screen extent holds no pixel centre column or row
    // (between centres at 80x60, or off the view) has nothing to draw:
    // skipped before its vertices are transformed (a quarter of the sculpted
    // dual arm's triangles). Clusters across the near plane are left to the
    // per-triangle clipping.
    const Eigen::Vector3f centre_camera = R_camera_link * cluster.centre_m + t_camera_link;
    if (centre_camera.z() - cluster.radius_m >= near &&
        sphere_holds_no_centre(centre_camera, cluster.radius_m, fx, fy, cx, cy, camera_.width,
                               camera_.height)) {
      continue;
    }
    if (may_clip) {
      for (int k = cluster.first_vertex; k < cluster.first_vertex + cluster.num_vertices; ++k)
        transform_vertex(k, A, b, clusters, true);
    } else {
      transform_cluster(cluster, A, b, clusters);
    }
    const Eigen::Vector3i* triangles = clusters.triangles.data() + cluster.first_triangle;
    for (int k = 0; k < cluster.num_triangles; ++k) {
      const Eigen::Vector3i& t = triangles[k];
      if (may_clip) {
        const int in =
            int(hom[t[0]].z() >= near) + int(hom[t[1]].z() >= near) + int(hom[t[2]].z() >= near);
        if (in == 0) continue;
        if (in < 3) {
          const Eigen::Vector3f* corners[3] = {&hom[t[0]], &hom[t[1]], &hom[t[2]]};
          raster_clipped(corners, cull_back_faces, depth, drawn);
          continue;
        }
      }
      // Most triangles at 80x60 hold no pixel centre: the integer test first.
      if (!box_holds_centre(centre_index[t[0]], centre_index[t[1]], centre_index[t[2]])) continue;
      const Eigen::Vector3f &pa = screen[t[0]], &pb = screen[t[1]], &pc = screen[t[2]];
      if (faces_camera(pa, pb, pc, cull_back_faces)) {
        // The rows from the corners' indices (first_centre_from is monotonic).
        const int ya = centre_index[t[0]].y(), yb = centre_index[t[1]].y(),
                  yc = centre_index[t[2]].y();
        raster_triangle(pa, pb, pc, std::min({ya, yb, yc}), std::max({ya, yb, yc}), depth, drawn);
      }
    }
  }
  for (const RoundShape& shape : l.round_shapes)
    draw_round_shape(shape, T_camera_link, depth, drawn);
  return drawn.empty() ? PixelRect{} : drawn;
}

// meshoptimizer's meshlets of the mesh's triangles but the round shapes':
// up to 16 vertices and 16 triangles, grouped by position and (cone weight
// 1) by normal. On the sculpted dual arm's simplified meshes clusters of 64
// skipped 8% of the triangles drawn, clusters of 16 with cone weight 1 30%.
// The cone is our own: the normals' area-weighted mean and the largest
// angle from it, in double; triangles of no area (no normal, never drawn)
// are left out of it.
DepthRenderer::Clusters DepthRenderer::make_clusters(const TriangleMesh& mesh,
                                                     const std::vector<RoundShape>& shapes) {
  constexpr std::size_t kMaxVertices = 16, kMaxTriangles = 16;
  std::vector<unsigned> indices;
  for (const Eigen::Vector3i& t : without_round_shapes(mesh, shapes).triangles)
    for (int c = 0; c < 3; ++c) indices.push_back(unsigned(t[c]));
  Clusters out;
  if (indices.empty()) return out;
  const std::size_t bound = meshopt_buildMeshletsBound(indices.size(), kMaxVertices, kMaxTriangles);
  std::vector<meshopt_Meshlet> meshlets(bound);
  std::vector<unsigned> meshlet_vertices(bound * kMaxVertices);
  std::vector<unsigned char> meshlet_triangles(bound * kMaxTriangles * 3);
  meshlets.resize(meshopt_buildMeshlets(
      meshlets.data(), meshlet_vertices.data(), meshlet_triangles.data(), indices.data(),
      indices.size(), mesh.vertices_m.data()->data(), mesh.vertices_m.size(),
      sizeof(Eigen::Vector3f), kMaxVertices, kMaxTriangles, 1.0f));
  for (const meshopt_Meshlet& m : meshlets) {
    Cluster cluster;
    cluster.first_triangle = int(out.triangles.size());
    cluster.num_triangles = int(m.triangle_count);
    cluster.first_vertex = int(out.x.size());
    cluster.num_vertices = int(m.vertex_count);
    const unsigned padded = (m.vertex_count + kLanes - 1) / kLanes * kLanes;
    for (unsigned k = 0; k < padded; ++k) {
      const Eigen::Vector3f& p =
          mesh.vertices_m[meshlet_vertices[m.vertex_offset + std::min(k, m.vertex_count - 1)]];
      out.x.push_back(p.x());
      out.y.push_back(p.y());
      out.z.push_back(p.z());
    }
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo,
                    normal_sum = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> normals;
    for (unsigned k = 0; k < m.triangle_count; ++k) {
      Eigen::Vector3i t, local;
      for (int c = 0; c < 3; ++c) {
        local[c] = meshlet_triangles[m.triangle_offset + 3 * k + c];
        t[c] = int(meshlet_vertices[m.vertex_offset + unsigned(local[c])]);
      }
      out.triangles.push_back(local + Eigen::Vector3i::Constant(cluster.first_vertex));
      const Eigen::Vector3d a = mesh.vertices_m[std::size_t(t[0])].cast<double>();
      const Eigen::Vector3d b = mesh.vertices_m[std::size_t(t[1])].cast<double>();
      const Eigen::Vector3d c = mesh.vertices_m[std::size_t(t[2])].cast<double>();
      for (const Eigen::Vector3d* p : {&a, &b, &c}) {
        lo = lo.cwiseMin(*p);
        hi = hi.cwiseMax(*p);
      }
      const Eigen::Vector3d n = (b - a).cross(c - a);  // twice the area, outward
      if (n.norm() > 1e-14) {
        normal_sum += n;
        normals.push_back(n.normalized());
      }
    }
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    double radius = 0;
    for (unsigned k = 0; k < m.vertex_count; ++k)
      radius = std::max(
          radius,
          (mesh.vertices_m[meshlet_vertices[m.vertex_offset + k]].cast<double>() - centre).norm());
    cluster.centre_m = centre.cast<float>();
    cluster.radius_m = float(radius * 1.0001 + 1e-6);  // float rounding
    if (normal_sum.norm() > 0 && !normals.empty()) {
      const Eigen::Vector3d axis = normal_sum.normalized();
      double cos_angle = 1;
      for (const Eigen::Vector3d& n : normals) cos_angle = std::min(cos_angle, axis.dot(n));
      const double angle = std::acos(std::clamp(cos_angle, -1.0, 1.0)) + 1e-6;
      if (angle < 0.5 * std::numbers::pi) {
        cluster.axis = axis.cast<float>();
        cluster.cos_angle = float(std::cos(angle));
        cluster.sin_angle = float(std::sin(angle));
      }
    }
    out.clusters.push_back(cluster);
  }
  return out;
}

// Ray casting over the pixels the shape's camera-frame bounding box can
// project to. The ray through pixel (u, v) is p = t d with d = ((u + 0.5 -
// cx) / fx, (v + 0.5 - cy) / fy, 1), so t is the depth. The entry point is
// the nearest hit of a surface facing the ray (a cylinder's side or one of
// its caps).
void DepthRenderer::draw_round_shape(const RoundShape& shape,
                                     const Eigen::Isometry3d& T_camera_link, DepthImage& depth,
                                     PixelRect& drawn) const {
  const double near = options_.near_m;
  const Eigen::Isometry3d T = T_camera_link * shape.T_link_shape;
  const Eigen::Vector3d c = T.translation();
  const Eigen::Vector3d w = T.linear().col(2);  // a cylinder's axis
  const double r = shape.radius_m, h = 0.5 * shape.length_m;
  const bool sphere = shape.kind == RoundShape::Kind::kSphere;
  Eigen::Vector3d extent;
  for (int i = 0; i < 3; ++i)
    extent[i] = sphere ? r : h * std::abs(w[i]) + r * std::sqrt(std::max(0.0, 1 - w[i] * w[i]));
  const Eigen::Vector3d lo = c - extent, hi = c + extent;
  if (hi.z() < near) return;
  // x / z and y / z over the box (z >= near) are extreme at its corners.
  const double z_lo = std::max(lo.z(), near);
  double u_lo = INFINITY, u_hi = -INFINITY, v_lo = INFINITY, v_hi = -INFINITY;
  for (const double z : {z_lo, hi.z()}) {
    for (const double x : {lo.x(), hi.x()}) {
      const double u = camera_.fx * x / z + camera_.cx;
      u_lo = std::min(u_lo, u);
      u_hi = std::max(u_hi, u);
    }
    for (const double y : {lo.y(), hi.y()}) {
      const double v = camera_.fy * y / z + camera_.cy;
      v_lo = std::min(v_lo, v);
      v_hi = std::max(v_hi, v);
    }
  }
  const int W = depth.width, H = depth.height;
  // Pixels whose centre k + 0.5 lies in [lo, hi].
  auto first = [](double x, int n) { return int(std::clamp(std::ceil(x - 0.5), 0.0, double(n))); };
  auto last = [](double x, int n) {
    return int(std::clamp(std::floor(x - 0.5), -1.0, double(n) - 1)) + 1;
  };
  const int u0 = first(u_lo, W), u1 = last(u_hi, W), v0 = first(v_lo, H), v1 = last(v_hi, H);
  // Per pixel, with d = (x, y, 1): a sphere's entry solves a t^2 - 2 b t + k = 0
  // with a = |d|^2, b = d . c, k = |c|^2 - r^2; a cylinder's side the same
  // with d and c projected off its axis w (c_off = c - (c . w) w, so that
  // d_off . c_off = d . c_off).
  const double cw = c.dot(w), h2 = h * h, r2 = r * r;
  const Eigen::Vector3d c_off = c - cw * w;
  const Eigen::Vector3d centre = sphere ? c : c_off;
  const double k = centre.squaredNorm() - r2;
  const double dx = 1 / camera_.fx;
  const double x0 = (u0 + 0.5 - camera_.cx) / camera_.fx;
  int du0 = W, du1 = 0, dv0 = H, dv1 = 0;
  for (int v = v0; v < v1; ++v) {
    float* row = depth.depth_m.data() + std::size_t(v) * W;
    const double y = (v + 0.5 - camera_.cy) / camera_.fy;
    const double yy1 = y * y + 1;
    const double b_row = y * centre.y() + centre.z(), dw_row = y * w.y() + w.z();
    for (int u = u0; u < u1; ++u) {
      const double x = x0 + (u - u0) * dx;
      const double b = x * centre.x() + b_row;
      double t = INFINITY;
      if (sphere) {
        const double a = x * x + yy1;
        const double disc = b * b - a * k;
        if (disc >= 0) t = (b - std::sqrt(disc)) / a;
      } else {
        const double dw = x * w.x() + dw_row;
        const double a = x * x + yy1 - dw * dw;
        const double disc = b * b - a * k;
        // Every point of a cap lies inside the infinite cylinder, so a ray
        // that misses it (disc < 0) misses the caps, and one that enters
        // through the side first meets no cap before (only rounding at the
        // rim could say otherwise): the cap is tried only when the side
        // entry is off the cylinder's length.
        if (disc < 0) continue;
        if (a > 0) {
          const double side = (b - std::sqrt(disc)) / a;
          if (std::abs(side * dw - cw) <= h) t = side;
        }
        if (t == INFINITY && h > 0 && dw != 0) {
          const double s = dw < 0 ? h : -h;  // the cap facing the ray: s dw < 0
          const double cap = (cw + s) / dw;
          const Eigen::Vector3d q = cap * Eigen::Vector3d(x, y, 1) - c;
          if (q.squaredNorm() - h2 <= r2) t = cap;
        }
      }
      if (!(t >= near) || !(t < INFINITY)) continue;
      const float z = float(t);
      const float old = row[u];
      row[u] = (old == 0.f) | (z < old) ? z : old;
      du0 = std::min(du0, u);
      du1 = std::max(du1, u + 1);
      dv0 = std::min(dv0, v);
      dv1 = v + 1;
    }
  }
  if (du0 < du1) {
    drawn.u0 = std::min(drawn.u0, du0);
    drawn.u1 = std::max(drawn.u1, du1);
    drawn.v0 = std::min(drawn.v0, dv0);
    drawn.v1 = std::max(drawn.v1, dv1);
  }
}

// Clips a triangle (homogeneous image points) against z >= near and draws the
// remaining polygon (a triangle or a quadrilateral) as a fan.
void DepthRenderer::raster_clipped(const Eigen::Vector3f* hom[3], bool cull_back_faces,
                                   DepthImage& depth, PixelRect& drawn) const {
  const float near = options_.near_m;
  Eigen::Vector3f poly[4];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3f& p = *hom[k];
    const Eigen::Vector3f& q = *hom[(k + 1) % 3];
    const bool p_in = p.z() >= near, q_in = q.z() >= near;
    if (p_in) poly[n++] = p;
    if (p_in != q_in) {
      // Always interpolate from the inside end, so the triangle across this
      // edge computes the very same point.
      const Eigen::Vector3f& in = p_in ? p : q;
      const Eigen::Vector3f& out = p_in ? q : p;
      const float s = (near - in.z()) / (out.z() - in.z());
      Eigen::Vector3f cut = in + s * (out - in);
      cut.z() = near;
      poly[n++] = cut;
    }
  }
  Eigen::Vector3f screen[4];
  for (int k = 0; k < n; ++k) screen[k] = project(poly[k]);
  for (int k = 1; k + 1 < n; ++k) {
    if (may_cover(screen[0], screen[k], screen[k + 1], depth.width, depth.height,
                  cull_back_faces)) {
      const Eigen::Vector3f &a = screen[0], &b = screen[k], &c = screen[k + 1];
      raster_triangle(a, b, c, first_centre_from(std::min({a.y(), b.y(), c.y()}), depth.height),
                      first_centre_from(std::max({a.y(), b.y(), c.y()}), depth.height), depth,
                      drawn);
    }
  }
}

// Draws one triangle given as screen points (u, v, 1/z), scanline by
// scanline: pixel (u, v) is covered when its centre lies in [left, right) of
// the triangle's boundary on row v + 0.5, for rows in [top, bottom). Every
// boundary x is interpolated along an edge from its upper end, so triangles
// sharing the edge compute the same bits and the half-open spans tile the
// row: no crack, no pixel drawn twice. Only covered pixels are visited.
// The caller has checked may_cover(). At 80x60 most triangles span one row
// (62% on the sculpted dual arm) and half cover no pixel centre, so each
// short edge's slope is computed only for the rows it bounds.
void DepthRenderer::raster_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                                    const Eigen::Vector3f& c, int v_top, int v_bottom,
                                    DepthImage& depth, PixelRect& drawn) const {
  const int W = depth.width, H = depth.height;

  // Corners from top to bottom: the long edge p0-p2 bounds one side of every
  // row, the short edges p0-p1 then p1-p2 the other.
  const Eigen::Vector3f *p0 = &a, *p1 = &b, *p2 = &c;
  if (above(*p1, *p0)) std::swap(p0, p1);
  if (above(*p2, *p1)) std::swap(p1, p2);
  if (above(*p1, *p0)) std::swap(p0, p1);
  auto slope = [](const Eigen::Vector3f& p, const Eigen::Vector3f& q) {
    const float dy = q.y() - p.y();
    return dy > 0.f ? (q.x() - p.x()) / dy : 0.f;
  };
  const float s02 = slope(*p0, *p2);
  // p1 right of the long edge (negative cross product): the long edge is the left side.
  const bool long_left =
      (p2->x() - p0->x()) * (p1->y() - p0->y()) - (p2->y() - p0->y()) * (p1->x() - p0->x()) < 0.f;

  // 1/z is affine in screen coordinates on a planar triangle:
  // 1/z = o.z + gx (x - o.x) + gy (y - o.y), taken from the farthest corner o
  // so that a corner just past the near plane (1/z huge) costs no precision
  // at the far pixels. Set up at the first covered row: at 80x60 many
  // triangles whose bounding box holds a pixel centre cover none.
  float gx = 0.f, gy = 0.f, iz_min = 0.f, iz_max = 0.f;
  const Eigen::Vector3f* o = nullptr;
  auto set_up_depth = [&] {
    const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    const float dxb = b.x() - a.x(), dyb = b.y() - a.y(), dzb = b.z() - a.z();
    const float dxc = c.x() - a.x(), dyc = c.y() - a.y(), dzc = c.z() - a.z();
    const float inv_area = 1.f / area;
    gx = (dzb * dyc - dzc * dyb) * inv_area;
    gy = (dzc * dxb - dzb * dxc) * inv_area;
    const Eigen::Vector3f& ab = a.z() <= b.z() ? a : b;
    o = ab.z() <= c.z() ? &ab : &c;
    // Rounding must not take a depth outside the triangle's own range.
    iz_min = o->z();
    iz_max = std::max({a.z(), b.z(), c.z()});
  };

  float* rows = depth.depth_m.data();
  int u_min = W, u_max = 0, v_min = H, v_max = 0;
  // Row v's span between the long edge and x_short.
  auto draw_row = [&](int v, float py, float x_short) {
    const float x_long = p0->x() + (py - p0->y()) * s02;
    const int u_begin = first_centre_from(long_left ? x_long : x_short, W);
    const int u_end = first_centre_from(long_left ? x_short : x_long, W);
    if (u_begin >= u_end) return;
    if (!o) set_up_depth();
    u_min = std::min(u_min, u_begin);
    u_max = std::max(u_max, u_end);
    v_min = std::min(v_min, v);
    v_max = v + 1;
    float* row = rows + size_t(v) * W;
    const float iz_row = o->z() + gy * (py - o->y());
    for (int u = u_begin; u < u_end; ++u) {
      const float iz = std::clamp(iz_row + gx * (float(u) + 0.5f - o->x()), iz_min, iz_max);
      const float z = 1.f / iz;
      const float d = row[u];
      row[u] = (d == 0.f) | (z < d) ? z : d;
    }
  };
  // Rows above p1 are bounded by p0-p1, the others by p1-p2.
  int v = v_top;
  if (v < v_bottom && float(v) + 0.5f < p1->y()) {
    const float s01 = slope(*p0, *p1);
    for (; v < v_bottom; ++v) {
      const float py = float(v) + 0.5f;
      if (!(py < p1->y())) break;
      draw_row(v, py, p0->x() + (py - p0->y()) * s01);
    }
  }
  if (v < v_bottom) {
    const float s12 = slope(*p1, *p2);
    for (; v < v_bottom; ++v) {
      const float py = float(v) + 0.5f;
      draw_row(v, py, p1->x() + (py - p1->y()) * s12);
    }
  }
  if (u_min < u_max) {
    drawn.u0 = std::min(drawn.u0, u_min);
    drawn.u1 = std::max(drawn.u1, u_max);
    drawn.v0 = std::min(drawn.v0, v_min);
    drawn.v1 = std::max(drawn.v1, v_max);
  }
}

void merge_nearer(const DepthImage& src, const PixelRect& rect, DepthImage& depth) {
  ARTTRACK_CHECK_ARGUMENT(src.width == depth.width && src.height == depth.height);
  for (int v = rect.v0; v < rect.v1; ++v) {
    const float* s = src.depth_m.data() + size_t(v) * src.width;
    float* d = depth.depth_m.data() + size_t(v) * depth.width;
    for (int u = rect.u0; u < rect.u1; ++u) {
      if (s[u] != 0.f && (d[u] == 0.f || s[u] < d[u])) d[u] = s[u];
    }
  }
}

LinkSet links_affecting_depth(const RobotModel& model, const std::vector<int>& dofs) {
  LinkSet links(model.num_links(), false);
  for (int dof : dofs) {
    const LinkSet moved = model.links_moved_by(dof);
    // A DOF that moves the camera moves the whole image.
    if (moved[model.camera_link()]) return LinkSet(model.num_links(), true);
    for (int l = 0; l < model.num_links(); ++l) links[l] = links[l] || moved[l];
  }
  return links;
}

CachedRenderer::CachedRenderer(DepthRenderer& renderer, const std::vector<int>& moving_dofs)
    : renderer_(&renderer),
      moving_(links_affecting_depth(renderer.model(), moving_dofs)),
      fixed_(moving_.size()),
      cached_(renderer.camera().width, renderer.camera().height) {
  for (size_t l = 0; l < moving_.size(); ++l) fixed_[l] = !moving_[l];
}

void CachedRenderer::set_reference(const KinematicsState& state) {
  renderer_->render_links(state, fixed_, cached_);
}

PixelRect CachedRenderer::render(const KinematicsState& state, DepthImage& out) {
  if (out.width != cached_.width || out.height != cached_.height) {
    out = cached_;
  } else {
    std::copy(cached_.depth_m.begin(), cached_.depth_m.end(), out.depth_m.begin());
  }
  return renderer_->draw_links(state, moving_, out);
}

}  // namespace arttrack
