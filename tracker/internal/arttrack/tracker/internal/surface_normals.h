// The smooth surface a link's mesh approximates, as its normals: for the
// image information's motion field (image_information.h), which needs how
// the depth at a pixel changes as the surface moves, n . dX / n . ray.
//
// A mesh is faceted; the surface it stands for is not. Turned about its own
// axis, a tessellated (or simplified) round part moves its facets, but not
// the surface they approximate, and slopes taken between pixels (chords of
// the curve) or from the facets themselves make that turn seem to change the
// image: a mesh robot's round base then pinned the camera's turn about it
// (docs/accuracy.md, stop 45). Here each triangle corner takes the mean of
// the normals of the triangles around its vertex that turn less than a
// crease angle from the triangle's own, each weighted by its angle at the
// vertex (a facet split in two counts once, not twice; a box's edges stay
// sharp, a round part's facets blend), and a point inside a triangle the
// corners' normals interpolated by its barycentric weights (Phong's
// normals). Vertices at the same position count as one (an STL file repeats
// them per triangle).
//
// Built once per link from the model; normal_at() is const and allocation-
// free, safe from several threads. Internal to the tracker's sources.
#pragma once

#include <Eigen/Core>

#include <array>
#include <memory>
#include <vector>

#include "arttrack/tracker/mesh_loader.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {

class TriangleGrid;  // triangle_grid.h

class SurfaceNormals {
 public:
  SurfaceNormals();
  // `mesh`'s triangles but the round shapes' (their exact normals are
  // known: RoundShape); a point further than limit_m from every triangle
  // has no normal.
  SurfaceNormals(const TriangleMesh& mesh, const std::vector<RoundShape>& round_shapes,
                 double crease_angle_rad, double limit_m);
  SurfaceNormals(SurfaceNormals&&) noexcept;
  SurfaceNormals& operator=(SurfaceNormals&&) noexcept;
  ~SurfaceNormals();

  bool empty() const { return corner_normals_.empty(); }
  int num_triangles() const { return int(corner_normals_.size()); }

  // The smooth unit normal (mesh frame) at the surface point nearest
  // p_m; false when no triangle lies within the limit, or when that
  // triangle is flat: its corners all keep its own normal (a box's face),
  // where the facet is the surface and slopes between pixels are exact.
  bool normal_at(const Eigen::Vector3d& p_m, Eigen::Vector3d& normal) const;

 private:
  std::unique_ptr<TriangleGrid> grid_;                          // null when no triangle is curved
  std::vector<std::array<Eigen::Vector3d, 3>> corner_normals_;  // per kept triangle
  std::vector<bool> curved_;                                    // per kept triangle
};

}  // namespace arttrack
