#include "arttrack/tracker/internal/surface_normals.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "triangle_grid.h"

namespace arttrack {
namespace {

constexpr double kFlatAngleRad = 1e-3 * std::numbers::pi / 180;

}  // namespace

SurfaceNormals::SurfaceNormals() = default;
SurfaceNormals::SurfaceNormals(SurfaceNormals&&) noexcept = default;
SurfaceNormals& SurfaceNormals::operator=(SurfaceNormals&&) noexcept = default;
SurfaceNormals::~SurfaceNormals() = default;

SurfaceNormals::SurfaceNormals(const TriangleMesh& mesh,
                               const std::vector<RoundShape>& round_shapes, double crease_angle_rad,
                               double limit_m) {
  TriangleMesh kept = without_round_shapes(mesh, round_shapes);
  if (kept.triangles.empty()) return;

  kept.join_equal_vertices();  // one index per position: an STL file repeats them
  const std::size_t num_vertices = kept.vertices_m.size();

  // Each triangle's unit normal and its angle at each corner, and the
  // triangles around each vertex.
  const std::size_t num_triangles = kept.triangles.size();
  std::vector<Eigen::Vector3d> unit(num_triangles);
  std::vector<std::array<double, 3>> angle(num_triangles);
  std::vector<int> first(num_vertices + 1, 0);
  for (std::size_t t = 0; t < num_triangles; ++t) {
    const Eigen::Vector3i& tri = kept.triangles[t];
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = kept.vertices_m[std::size_t(tri[k])].cast<double>();
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    unit[t] = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
      angle[t][std::size_t(k)] = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      ++first[std::size_t(tri[k]) + 1];
    }
  }
  std::partial_sum(first.begin(), first.end(), first.begin());
  // Per vertex: (triangle, corner) of each triangle around it.
  std::vector<std::pair<int, int>> around(std::size_t(first.back()));
  std::vector<int> next(first.begin(), first.end() - 1);
  for (std::size_t t = 0; t < num_triangles; ++t)
    for (int k = 0; k < 3; ++k)
      around[std::size_t(next[std::size_t(kept.triangles[t][k])]++)] = {int(t), k};

  const double cos_crease = std::cos(crease_angle_rad);
  corner_normals_.resize(num_triangles);
  for (std::size_t t = 0; t < num_triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::size_t v = std::size_t(kept.triangles[t][k]);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int i = first[v]; i < first[v + 1]; ++i) {
        const auto [g, corner] = around[std::size_t(i)];
        if (unit[std::size_t(g)].dot(unit[t]) >= cos_crease)
          sum += angle[std::size_t(g)][std::size_t(corner)] * unit[std::size_t(g)];
      }
      const double norm = sum.norm();
      corner_normals_[t][std::size_t(k)] = norm > 0 ? Eigen::Vector3d(sum / norm) : unit[t];
    }
    // Flat where every corner keeps the face's own normal (to a
    // thousandth of a degree): a box's face, where the facet is the surface.
    curved_.push_back(false);
    for (const Eigen::Vector3d& n : corner_normals_[t])
      if (n.dot(unit[t]) < std::cos(kFlatAngleRad)) curved_.back() = true;
  }
  // A mesh of flat faces only (a URDF box's) gives no normal anywhere: no
  // grid, so its pixels cost no lookup.
  if (std::find(curved_.begin(), curved_.end(), true) == curved_.end()) return;
  Eigen::Vector3d lo = kept.vertices_m[0].cast<double>(), hi = lo;
  for (const Eigen::Vector3f& p : kept.vertices_m) {
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  lo.array() -= limit_m;
  hi.array() += limit_m;
  grid_ = std::make_unique<TriangleGrid>(kept, lo, hi, limit_m);
}

bool SurfaceNormals::normal_at(const Eigen::Vector3d& p_m, Eigen::Vector3d& normal) const {
  if (!grid_) return false;
  const TriangleGrid::Nearest found = grid_->nearest(p_m);
  if (found.triangle < 0 || !curved_[std::size_t(found.triangle)]) return false;
  const std::array<Eigen::Vector3d, 3>& corners = corner_normals_[std::size_t(found.triangle)];
  const Eigen::Vector3d n =
      found.weights[0] * corners[0] + found.weights[1] * corners[1] + found.weights[2] * corners[2];
  const double norm = n.norm();
  if (!(norm > 0)) return false;
  normal = n / norm;
  return true;
}

}  // namespace arttrack
