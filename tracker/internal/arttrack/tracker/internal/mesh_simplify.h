// Link meshes at the likelihood's resolution: a published robot's visual
// meshes hold tens of thousands of triangles, almost all far below one
// pixel of the image the likelihood compares against (at 80x60 a pixel
// covers 4-20 mm of an arm at 0.3-1.5 m). Drawing them costs the image
// update ten times real time and tells the likelihood nothing.
//
// simplify_mesh() reduces a mesh with meshoptimizer's topology-preserving
// edge-collapse simplifier (meshopt_simplify: quadric error metric, no
// flipped triangles, borders kept; Debian's libmeshoptimizer-dev, the
// simplifier glTF tools and game engines use), stopping before the surface
// would move further than a given distance. A closed mesh wound outwards
// stays closed and wound outwards, which the renderer's back-face culling
// needs. The simplifier's own error is an estimate (distance to the
// original faces' planes) that fell short of the true distance by up to
// half on curved surfaces, so the result is measured against the original
// (both ways) and simplified again with a smaller request until it holds.
//
// mesh_error_bound_m() turns the configured fraction of a pixel into that
// distance: the footprint of one pixel (at the likelihood's resolution) at
// the nearest range the camera sees the robot.
#pragma once

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/mesh_loader.h"

namespace arttrack {

// A simplified mesh and what the simplifier reports.
struct SimplifiedMesh {
  TriangleMesh mesh;
  // The largest distance measured between the two surfaces, metres: from
  // every original vertex to the new surface, and from every new vertex,
  // edge midpoint and triangle centroid to the original (0 when nothing was
  // removed). At most the requested bound.
  double error_m = 0;
};

// Reduces `mesh` to as few triangles as keep its surface within
// max_error_m of the original (as measured, see SimplifiedMesh::error_m).
// Vertices at the same position are merged first (STL repeats them per
// triangle). max_error_m <= 0, or a mesh the simplifier cannot reduce
// within the bound, gives the input with its vertices merged and unused
// ones dropped.
SimplifiedMesh simplify_mesh(const TriangleMesh& mesh, double max_error_m);

// The largest surface error, metres, that stays below `fraction_of_pixel`
// of one pixel at `nearest_range_m` for a camera with these intrinsics
// (the likelihood's resolution): fraction * range / max(fx, fy). A pixel's
// footprint there is range / f on its narrower side; larger ranges only
// make the error a smaller share of a pixel.
double mesh_error_bound_m(const CameraIntrinsics& camera, double fraction_of_pixel,
                          double nearest_range_m);

}  // namespace arttrack
