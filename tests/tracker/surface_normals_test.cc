#include "arttrack/tracker/internal/surface_normals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace arttrack {
namespace {

// A unit cube centred at the origin, 12 triangles wound outwards, its 8
// corners shared (welded) or repeated per triangle (as an STL file has them).
TriangleMesh cube(bool welded) {
  const Eigen::Vector3f corner[8] = {{-.5f, -.5f, -.5f}, {.5f, -.5f, -.5f}, {.5f, .5f, -.5f},
                                     {-.5f, .5f, -.5f},  {-.5f, -.5f, .5f}, {.5f, -.5f, .5f},
                                     {.5f, .5f, .5f},    {-.5f, .5f, .5f}};
  const int faces[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                            {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  TriangleMesh mesh;
  if (welded) mesh.vertices_m.assign(corner, corner + 8);
  for (const auto& f : faces) {
    if (welded) {
      mesh.triangles.emplace_back(f[0], f[1], f[2]);
    } else {
      const int first = int(mesh.vertices_m.size());
      for (int k = 0; k < 3; ++k) mesh.vertices_m.push_back(corner[f[k]]);
      mesh.triangles.emplace_back(first, first + 1, first + 2);
    }
  }
  return mesh;
}

// A box's edges are creases: its faces stay flat, and a flat face has no
// normal of its own to give (its facets are the surface: slopes between
// pixels are exact there), welded or not. A cube with its corners cut
// blends across the cut's shallow creases.
TEST(SurfaceNormals, ABoxIsFlatWhereItsFacesAre) {
  for (bool welded : {true, false}) {
    const SurfaceNormals normals(cube(welded), {}, 40 * std::numbers::pi / 180, 0.01);
    ASSERT_EQ(normals.num_triangles(), 12);
    Eigen::Vector3d n;
    EXPECT_FALSE(normals.normal_at({0.49, 0.48, 0.5}, n)) << welded;   // top face by a corner
    EXPECT_FALSE(normals.normal_at({0.5, -0.2, 0.499}, n)) << welded;  // +x face by an edge
    EXPECT_FALSE(normals.normal_at({0, 0, 0.52}, n)) << welded;        // 2 cm off: beyond the reach
  }
  // With a 100 degree crease the cube's edges blend: a point near the top
  // face's corner leans towards the corner's sides.
  const SurfaceNormals blended(cube(true), {}, 100 * std::numbers::pi / 180, 0.01);
  Eigen::Vector3d n;
  ASSERT_TRUE(blended.normal_at({0.49, 0.48, 0.5}, n));
  EXPECT_GT(n.x(), 0.1);
  EXPECT_GT(n.y(), 0.1);
}

// A prism of 24 facets stands for a cylinder: inside a facet the normal
// turns with the point, within a few hundredths of a degree of the
// cylinder's own, where the facet's normal is up to 7.5 degrees off. Its
// flat caps stay apart from the side (a 90 degree crease): flat, no normal.
TEST(SurfaceNormals, AFacetedCylinderGetsTheCylindersNormals) {
  const int sides = 24;
  const double r = 0.1, half = 0.2;
  TriangleMesh mesh;
  for (int end = 0; end < 2; ++end)
    for (int k = 0; k < sides; ++k) {
      const double a = 2 * std::numbers::pi * k / sides;
      mesh.vertices_m.emplace_back(float(r * std::cos(a)), float(r * std::sin(a)),
                                   float(end ? half : -half));
    }
  mesh.vertices_m.emplace_back(0.f, 0.f, float(-half));
  mesh.vertices_m.emplace_back(0.f, 0.f, float(half));
  for (int k = 0; k < sides; ++k) {
    const int a0 = k, a1 = (k + 1) % sides, b0 = a0 + sides, b1 = a1 + sides;
    mesh.triangles.emplace_back(a0, a1, b1);
    mesh.triangles.emplace_back(a0, b1, b0);
    mesh.triangles.emplace_back(2 * sides, a1, a0);
    mesh.triangles.emplace_back(2 * sides + 1, b0, b1);
  }
  const SurfaceNormals normals(mesh, {}, 40 * std::numbers::pi / 180, 0.005);
  double worst_rad = 0;
  for (int i = 0; i < 200; ++i) {
    const double angle = 2 * std::numbers::pi * (i + 0.37) / 200;
    const double facet = std::floor(angle / (2 * std::numbers::pi / sides));
    const double a0 = facet * 2 * std::numbers::pi / sides, a1 = a0 + 2 * std::numbers::pi / sides;
    // The point of the facet's chord on the ray at `angle`.
    const Eigen::Vector2d p0(r * std::cos(a0), r * std::sin(a0)),
        p1(r * std::cos(a1), r * std::sin(a1));
    const Eigen::Vector2d d(std::cos(angle), std::sin(angle)), e = p1 - p0;
    const double t = (p0.x() * e.y() - p0.y() * e.x()) / (d.x() * e.y() - d.y() * e.x());
    Eigen::Vector3d n;
    ASSERT_TRUE(normals.normal_at({t * d.x(), t * d.y(), 0.05}, n));
    worst_rad =
        std::max(worst_rad, std::acos(std::min(1.0, n.dot(Eigen::Vector3d(d.x(), d.y(), 0)))));
  }
  EXPECT_LT(worst_rad, 0.05 * std::numbers::pi / 180);
  Eigen::Vector3d n;
  EXPECT_FALSE(normals.normal_at({0.09 * std::cos(0.3), 0.09 * std::sin(0.3), half}, n));
}

// The round shapes' own triangles (drawn exactly, their normals known) are
// left out: a mesh of only those has no surface.
TEST(SurfaceNormals, LeavesTheRoundShapesOut) {
  RoundShape shape;
  shape.first_triangle = 0;
  shape.num_triangles = 12;
  const SurfaceNormals normals(cube(true), {shape}, 40 * std::numbers::pi / 180, 0.01);
  EXPECT_TRUE(normals.empty());
  Eigen::Vector3d n;
  EXPECT_FALSE(normals.normal_at({0, 0, 0.5}, n));
}

}  // namespace
}  // namespace arttrack
