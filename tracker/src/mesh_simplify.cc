#include "arttrack/tracker/mesh_simplify.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <limits>
#include <vector>

namespace arttrack {

namespace {

// Distance from p to triangle abc: the closest point by Voronoi region
// (Ericson, Real-Time Collision Detection, 5.1.5).
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (ap - d1 / (d1 - d3) * ab).norm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (ap - d2 / (d2 - d6) * ac).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return (bp - (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b)).norm();
  const double denom = 1 / (va + vb + vc);
  return (ap - ab * (vb * denom) - ac * (vc * denom)).norm();
}

// The largest distance from `points` to the surface of `mesh`, measured
// exactly up to limit_m; a point with no triangle within limit_m counts as
// infinitely far. A uniform grid holds every triangle in the cells its
// bounding box, grown by limit_m, overlaps: a triangle within limit_m of a
// point is then in the point's cell.
double largest_distance(const std::vector<Eigen::Vector3d>& points, const TriangleMesh& mesh,
                        double limit_m) {
  if (points.empty()) return 0;
  if (mesh.empty()) return std::numeric_limits<double>::infinity();
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const Eigen::Vector3d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double extent = (hi - lo).maxCoeff();
  constexpr int kMaxCellsPerAxis = 32;
  const double cell = std::max({extent / kMaxCellsPerAxis, 2 * limit_m, 1e-9});
  Eigen::Array3i size = ((hi - lo) / cell).array().floor().cast<int>() + 1;
  size = size.min(kMaxCellsPerAxis + 1);
  const auto cell_of = [&](const Eigen::Vector3d& p) {
    return (((p - lo) / cell).array().floor().cast<int>().max(0)).min(size - 1).eval();
  };
  std::vector<std::vector<int>> cells(std::size_t(size.prod()));
  for (int t = 0; t < int(mesh.triangles.size()); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[std::size_t(t)];
    Eigen::Vector3d tlo = mesh.vertices_m[tri[0]].cast<double>(), thi = tlo;
    for (int k = 1; k < 3; ++k) {
      tlo = tlo.cwiseMin(mesh.vertices_m[tri[k]].cast<double>());
      thi = thi.cwiseMax(mesh.vertices_m[tri[k]].cast<double>());
    }
    tlo.array() -= limit_m;
    thi.array() += limit_m;
    if ((thi.array() < lo.array()).any() || (tlo.array() > hi.array()).any()) continue;
    const Eigen::Array3i a = cell_of(tlo), b = cell_of(thi);
    for (int x = a.x(); x <= b.x(); ++x)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int z = a.z(); z <= b.z(); ++z)
          cells[std::size_t((x * size.y() + y) * size.z() + z)].push_back(t);
  }
  double largest = 0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Array3i c = cell_of(p);
    double nearest = std::numeric_limits<double>::infinity();
    for (const int t : cells[std::size_t((c.x() * size.y() + c.y()) * size.z() + c.z())]) {
      const Eigen::Vector3i& tri = mesh.triangles[std::size_t(t)];
      nearest = std::min(nearest, point_triangle_distance(p, mesh.vertices_m[tri[0]].cast<double>(),
                                                          mesh.vertices_m[tri[1]].cast<double>(),
                                                          mesh.vertices_m[tri[2]].cast<double>()));
    }
    if (nearest > limit_m) return std::numeric_limits<double>::infinity();
    largest = std::max(largest, nearest);
  }
  return largest;
}

// Points on a mesh's surface to measure its distance to another: its
// vertices, and each triangle's centroid and edge midpoints.
std::vector<Eigen::Vector3d> surface_samples(const TriangleMesh& mesh, bool with_faces) {
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3f& v : mesh.vertices_m) points.push_back(v.cast<double>());
  if (!with_faces) return points;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices_m[t[0]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices_m[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices_m[t[2]].cast<double>();
    points.push_back((a + b + c) / 3);
    points.push_back((a + b) / 2);
    points.push_back((b + c) / 2);
    points.push_back((c + a) / 2);
  }
  return points;
}

TriangleMesh indexed_mesh(const std::vector<Eigen::Vector3f>& vertices,
                          const std::vector<unsigned>& indices) {
  TriangleMesh mesh;
  mesh.vertices_m = vertices;
  mesh.triangles.resize(indices.size() / 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    mesh.triangles[t] =
        Eigen::Vector3i(int(indices[3 * t]), int(indices[3 * t + 1]), int(indices[3 * t + 2]));
  return mesh;
}

}  // namespace

SimplifiedMesh simplify_mesh(const TriangleMesh& mesh, double max_error_m) {
  SimplifiedMesh out;
  if (mesh.empty()) {
    out.mesh = mesh;
    return out;
  }
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "packed float3 vertices");
  constexpr std::size_t kStride = sizeof(Eigen::Vector3f);
  const std::size_t index_count = 3 * mesh.triangles.size();
  const std::size_t vertex_count = mesh.vertices_m.size();
  std::vector<unsigned> indices(index_count);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) indices[3 * t + std::size_t(k)] = unsigned(mesh.triangles[t][k]);

  // One vertex per position: the simplifier collapses edges between shared
  // vertices, and a mesh whose triangles share none has no edge to collapse.
  std::vector<unsigned> remap(vertex_count);
  const std::size_t unique = meshopt_generateVertexRemap(
      remap.data(), indices.data(), index_count, mesh.vertices_m.data(), vertex_count, kStride);
  std::vector<Eigen::Vector3f> welded(unique);
  meshopt_remapVertexBuffer(welded.data(), mesh.vertices_m.data(), vertex_count, kStride,
                            remap.data());
  meshopt_remapIndexBuffer(indices.data(), indices.data(), index_count, remap.data());

  // meshoptimizer's error (relative to the mesh's extent) counts the
  // distance of the kept vertices to the original faces' planes, not the
  // sag of the new, larger faces between them: on a fine sphere, asked for
  // 1 mm, the surfaces lay 1.3 mm apart and more. So each result is
  // measured (both ways: vertices, edge midpoints and centroids) and the
  // request lowered by 30% until it holds, then bisected towards the
  // largest request that holds.
  std::vector<unsigned> reduced;
  const TriangleMesh original = indexed_mesh(welded, indices);
  const float scale = meshopt_simplifyScale(welded[0].data(), unique, kStride);
  const std::vector<Eigen::Vector3d> original_points = surface_samples(original, false);
  // Simplifies for `request_m`; keeps the result when it holds the bound.
  const auto attempt = [&](double request_m) {
    std::vector<unsigned> candidate(index_count);
    const std::size_t count = meshopt_simplify(
        candidate.data(), indices.data(), index_count, welded[0].data(), unique, kStride,
        /*target_index_count=*/0, float(request_m / scale), /*options=*/0, nullptr);
    if (count == 0 || count >= index_count) return false;
    candidate.resize(count);
    const TriangleMesh simplified = indexed_mesh(welded, candidate);
    const double error_m =
        std::max(largest_distance(original_points, simplified, max_error_m),
                 largest_distance(surface_samples(simplified, true), original, max_error_m));
    if (error_m > max_error_m) return false;
    if (reduced.empty() || count < reduced.size()) {
      reduced = std::move(candidate);
      out.error_m = error_m;
    }
    return true;
  };
  if (max_error_m > 0 && scale > 0) {
    double failed_m = 0, held_m = max_error_m;
    constexpr int kLowerings = 8, kBisections = 3;
    for (int k = 0; k < kLowerings && !attempt(held_m); ++k) {
      failed_m = held_m;
      held_m *= 0.7;
    }
    for (int k = 0; k < kBisections && !reduced.empty() && failed_m > 0; ++k) {
      const double middle_m = 0.5 * (held_m + failed_m);
      (attempt(middle_m) ? held_m : failed_m) = middle_m;
    }
  }
  if (reduced.empty()) {  // nothing to reduce within the bound: keep every triangle
    reduced = indices;
    out.error_m = 0;
  }

  // Compact: only the vertices the remaining triangles use, in first-use order.
  std::vector<Eigen::Vector3f> vertices(unique);
  const std::size_t used = meshopt_optimizeVertexFetch(
      vertices.data(), reduced.data(), reduced.size(), welded.data(), unique, kStride);
  vertices.resize(used);
  out.mesh.vertices_m = std::move(vertices);
  out.mesh.triangles.resize(reduced.size() / 3);
  for (std::size_t t = 0; t < out.mesh.triangles.size(); ++t)
    out.mesh.triangles[t] =
        Eigen::Vector3i(int(reduced[3 * t]), int(reduced[3 * t + 1]), int(reduced[3 * t + 2]));
  return out;
}

double mesh_error_bound_m(const CameraIntrinsics& camera, double fraction_of_pixel,
                          double nearest_range_m) {
  const double focal_px = std::max(camera.fx, camera.fy);
  if (!(focal_px > 0)) return 0;
  return fraction_of_pixel * nearest_range_m / focal_px;
}

}  // namespace arttrack
