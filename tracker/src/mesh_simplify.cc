#include "arttrack/tracker/internal/mesh_simplify.h"

#include "triangle_grid.h"

#include <meshoptimizer.h>

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <limits>
#include <vector>

namespace arttrack {

namespace {

// Points on a mesh's surface to measure its distance to another: its
// vertices, or (with_faces) each triangle's centroid and edge midpoints
// first, where a coarse face lies furthest from a fine surface, so that
// TriangleGrid::largest_distance finds the largest early and stops the
// other points' searches sooner.
std::vector<Eigen::Vector3d> surface_samples(const TriangleMesh& mesh, bool with_faces) {
  std::vector<Eigen::Vector3d> points;
  if (with_faces) {
    for (const Eigen::Vector3i& t : mesh.triangles) {
      const Eigen::Vector3d a = mesh.vertices_m[t[0]].cast<double>();
      const Eigen::Vector3d b = mesh.vertices_m[t[1]].cast<double>();
      const Eigen::Vector3d c = mesh.vertices_m[t[2]].cast<double>();
      points.push_back((a + b + c) / 3);
      points.push_back((a + b) / 2);
      points.push_back((b + c) / 2);
      points.push_back((c + a) / 2);
    }
  }
  for (const Eigen::Vector3f& v : mesh.vertices_m) points.push_back(v.cast<double>());
  return points;
}

// The area around each vertex, m^2: a third of each triangle's it is a
// corner of. And each vertex's normal: unit, area-weighted over those
// triangles (zero for a vertex of degenerate ones only).
void vertex_areas_and_normals(const TriangleMesh& mesh, std::vector<double>* area_m2,
                              std::vector<Eigen::Vector3d>* normals) {
  area_m2->assign(mesh.vertices_m.size(), 0);
  if (normals) normals->assign(mesh.vertices_m.size(), Eigen::Vector3d::Zero());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices_m[t[0]].cast<double>();
    const Eigen::Vector3d n =
        (mesh.vertices_m[t[1]].cast<double>() - a).cross(mesh.vertices_m[t[2]].cast<double>() - a);
    for (int k = 0; k < 3; ++k) {
      (*area_m2)[std::size_t(t[k])] += n.norm() / 6;
      if (normals) (*normals)[std::size_t(t[k])] += n;
    }
  }
  if (normals)
    for (Eigen::Vector3d& n : *normals)
      if (n.norm() > 0) n.normalize();
}

// Edge collapses keep vertices on the original surface, so the new, larger
// faces of a convex part lie inside it and those of a concave part outside:
// rendered, a part sits up to the sag away from where it is, a bias the
// tracker's estimate takes on (a millimetre of camera offset). Moves each
// vertex along its normal so that the new surface fits the original in the
// least-squares sense: the original's vertices, weighted by the area around
// each, against the planes of the new faces nearest to them (point to plane,
// linear in the moves), with a small penalty on the moves that keeps a vertex
// no point sees in place. Twice, the second time from the nearest faces after
// the first moves. Moves are clamped to the bound; the measurement that
// follows keeps the bound whatever this does.
TriangleMesh fitted_to_surface(const TriangleMesh& simplified,
                               const std::vector<Eigen::Vector3d>& original_points,
                               const std::vector<double>& original_area_m2,
                               const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                               double max_error_m) {
  constexpr int kIterations = 2;
  constexpr double kMovePenalty = 1e-3;  // per m^2 of a vertex's own area
  TriangleMesh out = simplified;
  const Eigen::Index vertex_count = Eigen::Index(simplified.vertices_m.size());
  std::vector<double> area_m2;
  std::vector<Eigen::Vector3d> normals;
  vertex_areas_and_normals(simplified, &area_m2, &normals);
  std::vector<Eigen::Triplet<double>> entries;
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    const TriangleGrid grid(out, lo, hi, max_error_m);
    entries.clear();
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(vertex_count);
    for (std::size_t i = 0; i < original_points.size(); ++i) {
      const TriangleGrid::Nearest found = grid.nearest(original_points[i]);
      if (found.triangle < 0) continue;
      const Eigen::Vector3i& t = out.triangles[std::size_t(found.triangle)];
      const Eigen::Vector3d a = out.vertices_m[t[0]].cast<double>();
      const Eigen::Vector3d b = out.vertices_m[t[1]].cast<double>();
      const Eigen::Vector3d c = out.vertices_m[t[2]].cast<double>();
      const Eigen::Vector3d face_normal = (b - a).cross(c - a).normalized();
      const Eigen::Vector3d& w = found.weights;
      const double distance_m =
          face_normal.dot(w[0] * a + w[1] * b + w[2] * c - original_points[i]);
      Eigen::Vector3d slope;  // d distance / d move of each corner
      for (int k = 0; k < 3; ++k) slope[k] = w[k] * face_normal.dot(normals[std::size_t(t[k])]);
      const double weight = original_area_m2[i];
      for (int j = 0; j < 3; ++j) {
        gradient[t[j]] += weight * distance_m * slope[j];
        for (int k = 0; k < 3; ++k) entries.emplace_back(t[j], t[k], weight * slope[j] * slope[k]);
      }
    }
    // (+1e-30: a welded vertex no kept triangle uses has no area and no
    // point; it stays where it is instead of making the matrix singular.)
    for (Eigen::Index v = 0; v < vertex_count; ++v)
      entries.emplace_back(v, v, kMovePenalty * area_m2[std::size_t(v)] + 1e-30);
    Eigen::SparseMatrix<double> normal_matrix(vertex_count, vertex_count);
    normal_matrix.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal_matrix);
    if (solver.info() != Eigen::Success) break;
    const Eigen::VectorXd move_m = solver.solve(-gradient);
    if (solver.info() != Eigen::Success || !move_m.allFinite()) break;
    for (Eigen::Index v = 0; v < vertex_count; ++v)
      out.vertices_m[std::size_t(v)] +=
          (std::clamp(move_m[v], -max_error_m, max_error_m) * normals[std::size_t(v)])
              .cast<float>();
  }
  return out;
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
  // The best result: indices into `welded`, with its own vertex positions.
  std::vector<unsigned> reduced;
  std::vector<Eigen::Vector3f> reduced_vertices = welded;
  const TriangleMesh original = indexed_mesh(welded, indices);
  const float scale = meshopt_simplifyScale(welded[0].data(), unique, kStride);
  const std::vector<Eigen::Vector3d> original_points = surface_samples(original, false);
  std::vector<double> original_area_m2;  // per original point (= vertex)
  vertex_areas_and_normals(original, &original_area_m2, nullptr);
  Eigen::Vector3d lo = original_points[0], hi = lo;
  for (const Eigen::Vector3d& p : original_points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  // The original's grid serves every attempt (the new surface lies within
  // its bounding box but for the fit's moves, within the bound:
  // points outside count in the boundary cells).
  const TriangleGrid original_grid(original, lo, hi, max_error_m);
  // Simplifies for `request_m`; keeps the result when it holds the bound.
  const auto attempt = [&](double request_m) {
    std::vector<unsigned> candidate(index_count);
    const std::size_t count = meshopt_simplify(
        candidate.data(), indices.data(), index_count, welded[0].data(), unique, kStride,
        /*target_index_count=*/0, float(request_m / scale), /*options=*/0, nullptr);
    if (count == 0 || count >= index_count) return false;
    candidate.resize(count);
    TriangleMesh simplified = fitted_to_surface(indexed_mesh(welded, candidate), original_points,
                                                original_area_m2, lo, hi, max_error_m);
    double error_m =
        TriangleGrid(simplified, lo, hi, max_error_m).largest_distance(original_points);
    if (error_m <= max_error_m)
      error_m =
          std::max(error_m, original_grid.largest_distance(surface_samples(simplified, true)));
    if (error_m > max_error_m) return false;
    if (reduced.empty() || count < reduced.size()) {
      reduced = std::move(candidate);
      reduced_vertices = std::move(simplified.vertices_m);
      out.error_m = error_m;
    }
    return true;
  };
  if (max_error_m > 0 && scale > 0) {
    // The requests that held were 0.35-0.6 of the bound (a bumpy sphere, a
    // fine sphere): start at half, and bisect between what held and what
    // failed (the bound itself if half held).
    double failed_m = max_error_m, held_m = 0.5 * max_error_m;
    constexpr int kLowerings = 8, kBisections = 3;
    for (int k = 0; k < kLowerings && !attempt(held_m); ++k) {
      failed_m = held_m;
      held_m *= 0.7;
    }
    for (int k = 0; k < kBisections && !reduced.empty(); ++k) {
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
      vertices.data(), reduced.data(), reduced.size(), reduced_vertices.data(), unique, kStride);
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
