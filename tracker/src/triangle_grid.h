// Nearest points on a triangle mesh: the point of a triangle closest to a
// point, and a uniform grid of a mesh's triangles that finds the nearest
// surface point within a distance limit (the simplifier measures its error
// with it, mesh_simplify.h; the image information finds the drawn
// surface's normals with it, image_information.h). Internal to the
// tracker's sources.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "arttrack/tracker/mesh_loader.h"

namespace arttrack {

// The point of triangle abc closest to p, as weights of a, b and c: by
// Voronoi region (Ericson, Real-Time Collision Detection, 5.1.5).
inline Eigen::Vector3d closest_point_weights(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                             const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denom = 1 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

// A mesh's triangles in a uniform grid over a box, to measure distances up
// to limit_m: each triangle is in every cell its bounding box, grown by
// limit_m, overlaps, so a triangle within limit_m of a point in the box is
// in the point's cell.
class TriangleGrid {
 public:
  TriangleGrid(const TriangleMesh& mesh, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
               double limit_m)
      : lo_(lo), limit_m_(limit_m) {
    constexpr int kMaxCellsPerAxis = 96;
    cell_m_ = std::max({(hi - lo).maxCoeff() / kMaxCellsPerAxis, 2 * limit_m, 1e-9});
    size_ = (((hi - lo) / cell_m_).array().floor().cast<int>() + 1).min(kMaxCellsPerAxis + 1);
    // Two passes (count, then fill) into one flat array.
    std::vector<std::pair<Eigen::Array3i, Eigen::Array3i>> ranges(mesh.triangles.size());
    first_.assign(std::size_t(size_.prod()) + 1, 0);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Eigen::Vector3i& tri = mesh.triangles[t];
      Eigen::Vector3d tlo = mesh.vertices_m[tri[0]].cast<double>(), thi = tlo;
      for (int k = 1; k < 3; ++k) {
        tlo = tlo.cwiseMin(mesh.vertices_m[tri[k]].cast<double>());
        thi = thi.cwiseMax(mesh.vertices_m[tri[k]].cast<double>());
      }
      tlo.array() -= limit_m;
      thi.array() += limit_m;
      if ((thi.array() < lo.array()).any() || (tlo.array() > hi.array()).any()) {
        ranges[t] = {Eigen::Array3i::Zero(), Eigen::Array3i::Constant(-1)};  // outside: none
        continue;
      }
      ranges[t] = {cell_of(tlo), cell_of(thi)};
      for_cells(ranges[t], [&](std::size_t c) { ++first_[c + 1]; });
    }
    for (std::size_t c = 1; c < first_.size(); ++c) first_[c] += first_[c - 1];
    triangles_.resize(first_.back());
    std::vector<std::size_t> next(first_.begin(), first_.end() - 1);
    for (std::size_t t = 0; t < ranges.size(); ++t)
      for_cells(ranges[t], [&](std::size_t c) { triangles_[next[c]++] = int(t); });
    corners_.resize(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      Corners& k = corners_[t];
      for (int i = 0; i < 3; ++i) k.p[i] = mesh.vertices_m[mesh.triangles[t][i]].cast<double>();
      k.normal = (k.p[1] - k.p[0]).cross(k.p[2] - k.p[0]);
      const double area2 = k.normal.norm();
      k.normal = area2 > 0 ? Eigen::Vector3d(k.normal / area2) : Eigen::Vector3d::Zero();
    }
  }

  // The largest distance from `points` (inside the box) to the mesh,
  // exact up to the limit; a point with no triangle within it counts as
  // infinitely far.
  double largest_distance(const std::vector<Eigen::Vector3d>& points) const {
    double largest = 0;
    for (const Eigen::Vector3d& p : points) {
      const std::size_t cell = cell_index(cell_of(p));
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t k = first_[cell]; k < first_[cell + 1]; ++k) {
        const Corners& t = corners_[std::size_t(triangles_[k])];
        // The distance to the plane bounds the distance to the triangle.
        if (std::abs(t.normal.dot(p - t.p[0])) >= nearest) continue;
        nearest = std::min(nearest, t.distance_m(p));
        if (nearest <= largest) break;  // this point cannot raise the largest distance
      }
      if (nearest > limit_m_) return std::numeric_limits<double>::infinity();
      largest = std::max(largest, nearest);
    }
    return largest;
  }

  // The point of the mesh nearest to p (inside the box) within the limit:
  // its triangle (-1 when none is within the limit) and the triangle's
  // corners' weights.
  struct Nearest {
    int triangle = -1;
    Eigen::Vector3d weights = Eigen::Vector3d::Zero();
  };
  Nearest nearest(const Eigen::Vector3d& p) const {
    const std::size_t cell = cell_index(cell_of(p));
    Nearest found;
    double nearest_m = limit_m_;
    for (std::size_t k = first_[cell]; k < first_[cell + 1]; ++k) {
      const Corners& t = corners_[std::size_t(triangles_[k])];
      if (std::abs(t.normal.dot(p - t.p[0])) >= nearest_m) continue;
      Eigen::Vector3d weights;
      const double distance_m = t.distance_m(p, &weights);
      if (distance_m < nearest_m) nearest_m = distance_m, found = {triangles_[k], weights};
    }
    return found;
  }

 private:
  std::size_t cell_index(const Eigen::Array3i& c) const {
    return std::size_t((c.x() * size_.y() + c.y()) * size_.z() + c.z());
  }
  Eigen::Array3i cell_of(const Eigen::Vector3d& p) const {
    return (((p - lo_) / cell_m_).array().floor().cast<int>().max(0)).min(size_ - 1);
  }
  template <typename F>
  void for_cells(const std::pair<Eigen::Array3i, Eigen::Array3i>& range, F&& f) const {
    for (int x = range.first.x(); x <= range.second.x(); ++x)
      for (int y = range.first.y(); y <= range.second.y(); ++y)
        for (int z = range.first.z(); z <= range.second.z(); ++z) f(cell_index({x, y, z}));
  }

  struct Corners {
    Eigen::Vector3d p[3];
    Eigen::Vector3d normal;  // unit; zero for a degenerate triangle
    // Distance from q to the triangle, and its closest point's weights.
    double distance_m(const Eigen::Vector3d& q, Eigen::Vector3d* weights_out = nullptr) const {
      const Eigen::Vector3d w = closest_point_weights(q, p[0], p[1], p[2]);
      if (weights_out) *weights_out = w;
      return (q - (w[0] * p[0] + w[1] * p[1] + w[2] * p[2])).norm();
    }
  };
  std::vector<Corners> corners_;  // per triangle
  Eigen::Vector3d lo_;
  double limit_m_, cell_m_ = 0;
  Eigen::Array3i size_;
  std::vector<std::size_t> first_;  // per cell: its triangles' start in triangles_ (and end)
  std::vector<int> triangles_;
};

}  // namespace arttrack
