#include "arttrack/tracker/internal/mesh_simplify.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <utility>

#include "../dual_arm_home.h"
#include "../mesh_checks.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {
namespace {

using test_support::closed_and_consistent;
using test_support::signed_volume_m3;

double point_segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b) {
  const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (p - (a + t * (b - a))).norm();
}

// Distance from p to triangle abc, the obvious way (not the library's
// Voronoi-region walk): the foot of the perpendicular on the plane when it
// falls inside (barycentric signs), else the nearest of the three edges.
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d foot = p - n.dot(p - a) * n;
  const bool inside = (b - a).cross(foot - a).dot(n) >= 0 && (c - b).cross(foot - b).dot(n) >= 0 &&
                      (a - c).cross(foot - c).dot(n) >= 0;
  if (inside) return std::abs(n.dot(p - a));
  return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                   point_segment_distance(p, c, a)});
}

// Signed distances from each vertex of `original`'s triangles to the
// surface of `simplified`, by brute force: to the nearest triangle, positive
// on the side its normal points to (outside a closed mesh wound outwards).
// A triangle within a ball is no nearer than the ball's surface, so one
// whose ball is farther than some triangle is passed over: the same nearest
// triangle, a few exact distances per vertex instead of one per triangle
// (AddressSanitizer: 18 s for the straddle test).
std::vector<double> signed_vertex_distances(const TriangleMesh& original,
                                            const TriangleMesh& simplified) {
  struct Triangle {
    Eigen::Vector3d a, b, c, centre;
    double radius;
  };
  std::vector<Triangle> triangles;
  for (const Eigen::Vector3i& t : simplified.triangles) {
    Triangle tri{simplified.vertices_m[t[0]].cast<double>(),
                 simplified.vertices_m[t[1]].cast<double>(),
                 simplified.vertices_m[t[2]].cast<double>(),
                 {},
                 0};
    tri.centre = (tri.a + tri.b + tri.c) / 3;
    tri.radius = std::max(
        {(tri.a - tri.centre).norm(), (tri.b - tri.centre).norm(), (tri.c - tri.centre).norm()});
    triangles.push_back(tri);
  }
  std::vector<bool> used(original.vertices_m.size(), false);
  for (const Eigen::Vector3i& t : original.triangles)
    for (int k = 0; k < 3; ++k) used[std::size_t(t[k])] = true;
  std::vector<double> distances, ball_distance(triangles.size());
  for (std::size_t i = 0; i < original.vertices_m.size(); ++i) {
    if (!used[i]) continue;
    const Eigen::Vector3d p = original.vertices_m[i].cast<double>();
    if (triangles.empty()) {
      distances.push_back(INFINITY);
      continue;
    }
    for (std::size_t k = 0; k < triangles.size(); ++k)
      ball_distance[k] = (p - triangles[k].centre).norm() - triangles[k].radius;
    // The triangle whose ball is nearest bounds the distance; then every
    // triangle in order that may be as near, so ties go to the first one.
    const std::size_t first = std::size_t(
        std::min_element(ball_distance.begin(), ball_distance.end()) - ball_distance.begin());
    const Triangle& f = triangles[first];
    const double bound = point_triangle_distance(p, f.a, f.b, f.c);
    double nearest = INFINITY, sign = 1;
    for (std::size_t k = 0; k < triangles.size(); ++k) {
      if (ball_distance[k] > bound + 1e-12) continue;
      const Triangle& t = triangles[k];
      const double d = point_triangle_distance(p, t.a, t.b, t.c);
      if (d < nearest) nearest = d, sign = (t.b - t.a).cross(t.c - t.a).dot(p - t.a) >= 0 ? 1 : -1;
    }
    distances.push_back(sign * nearest);
  }
  return distances;
}

// The largest distance from a vertex of `original`'s triangles to the
// surface of `simplified`, by brute force over every triangle.
double largest_vertex_distance(const TriangleMesh& original, const TriangleMesh& simplified) {
  double largest = 0;
  for (double d : signed_vertex_distances(original, simplified))
    largest = std::max(largest, std::abs(d));
  return largest;
}

// 128 meridians, 64 bands (16 000 triangles) on a 6 cm sphere whose radius
// undulates by 5%: a smooth CAD-like surface tessellated far below a
// millimetre, as makers publish them.
TriangleMesh sculpted_sphere() {
  TriangleMesh fine = make_sphere(0.06, 128);
  for (Eigen::Vector3f& v : fine.vertices_m) {
    const double azimuth = std::atan2(v.y(), v.x());
    const double polar = std::acos(std::clamp(double(v.z()) / v.norm(), -1.0, 1.0));
    v *= float(1 + 0.05 * std::sin(6 * azimuth) * std::sin(5 * polar));
  }
  return fine;
}

TEST(SimplifyMesh, FineSculptedSphereKeepsItsSurfaceWithinTheBoundAndStaysClosed) {
  const TriangleMesh fine = sculpted_sphere();
  const double bound_m = 1e-3;
  const SimplifiedMesh s = simplify_mesh(fine, bound_m);
  EXPECT_LT(s.mesh.triangles.size() * 8, fine.triangles.size())
      << s.mesh.triangles.size() << " of " << fine.triangles.size();
  EXPECT_LE(s.error_m, bound_m);
  // Independent of the simplifier's own estimate: the original's vertices
  // lie within the bound of the new surface.
  EXPECT_LE(largest_vertex_distance(fine, s.mesh), bound_m);
  EXPECT_TRUE(closed_and_consistent(s.mesh));
  EXPECT_NEAR(signed_volume_m3(s.mesh), signed_volume_m3(fine), 0.02 * signed_volume_m3(fine));
}

TEST(SimplifyMesh, SimplifiedSurfaceStraddlesTheOriginal) {
  // Edge collapses leave the larger faces of a convex part inside it: drawn
  // as they are, the part sits up to the sag too far from the camera. The
  // fit moves the vertices so that the original lies on both sides of the
  // new surface (without it: mean 0.11 mm outside here) and as near as least
  // squares can (RMS 0.13 mm with it).
  const TriangleMesh fine = sculpted_sphere();
  const double bound_m = 1e-3;
  const std::vector<double> d = signed_vertex_distances(fine, simplify_mesh(fine, bound_m).mesh);
  double sum = 0, sum_sq = 0;
  for (double x : d) sum += x, sum_sq += x * x;
  const double mean_m = sum / double(d.size()), rms_m = std::sqrt(sum_sq / double(d.size()));
  EXPECT_LT(std::abs(mean_m), 0.02 * bound_m) << mean_m;
  EXPECT_LT(rms_m, 0.15 * bound_m) << rms_m;
}

TEST(SimplifyMesh, ZeroErrorKeepsEveryTriangleAndSplitVerticesAreMerged) {
  // A box as an STL holds it: three vertices per triangle.
  const TriangleMesh box = make_box(Eigen::Vector3d(0.1, 0.2, 0.3));
  TriangleMesh split;
  for (const Eigen::Vector3i& t : box.triangles) {
    const int first = int(split.vertices_m.size());
    for (int k = 0; k < 3; ++k) split.vertices_m.push_back(box.vertices_m[t[k]]);
    split.triangles.emplace_back(first, first + 1, first + 2);
  }
  const SimplifiedMesh kept = simplify_mesh(split, 0);
  EXPECT_EQ(kept.mesh.triangles.size(), box.triangles.size());
  EXPECT_EQ(kept.mesh.vertices_m.size(), 8u);
  EXPECT_EQ(kept.error_m, 0);
  EXPECT_TRUE(closed_and_consistent(kept.mesh));
  // A box has nothing to remove within a millimetre.
  EXPECT_EQ(simplify_mesh(split, 1e-3).mesh.triangles.size(), box.triangles.size());
  EXPECT_TRUE(simplify_mesh(TriangleMesh{}, 1e-3).mesh.empty());
}

TEST(SimplifyMesh, ErrorBoundIsAFractionOfAPixelAtTheNearestRange) {
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 45 * M_PI / 180);
  // A pixel at 0.3 m covers 0.3 / fy metres; a quarter of it:
  EXPECT_NEAR(mesh_error_bound_m(camera, 0.25, 0.3), 0.25 * 0.3 / camera.fy, 1e-15);
  EXPECT_EQ(mesh_error_bound_m(camera, 0, 0.3), 0);
}

// The dual arm with meshes: simplified, its round shapes are still drawn
// exactly and the render stays within the bound of the full one.
TEST(SimplifyMesh, RobotModelKeepsRoundShapesAndRendersWithinTheBound) {
  const auto full = std::make_shared<const RobotModel>(RobotModel::from_urdf_file(
      std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm_meshes.urdf"));
  double error_m = -1;
  const double bound_m = 2e-3;
  const double nearest_m = 0.3;  // levels of detail from 0.6 m on, within 2^k bound_m
  const RobotModel drawn = full->with_simplified_meshes(bound_m, &error_m, nearest_m, 4);
  EXPECT_LT(drawn.num_drawn_triangles(), full->num_drawn_triangles());
  EXPECT_GE(error_m, 0);
  EXPECT_LE(error_m, bound_m);
  ASSERT_EQ(drawn.num_links(), full->num_links());
  for (int l = 0; l < full->num_links(); ++l) {
    const Link &a = full->link(l), &b = drawn.link(l);
    ASSERT_EQ(a.round_shapes.size(), b.round_shapes.size()) << a.name;
    for (std::size_t k = 0; k < a.round_shapes.size(); ++k) {
      const RoundShape &ra = a.round_shapes[k], &rb = b.round_shapes[k];
      EXPECT_EQ(ra.radius_m, rb.radius_m);
      ASSERT_EQ(ra.num_vertices, rb.num_vertices);
      ASSERT_EQ(ra.num_triangles, rb.num_triangles);
      for (int v = 0; v < ra.num_vertices; ++v)
        ASSERT_EQ(a.mesh.vertices_m[std::size_t(ra.first_vertex + v)],
                  b.mesh.vertices_m[std::size_t(rb.first_vertex + v)]);
    }
  }
  EXPECT_EQ(full->with_simplified_meshes(0).num_drawn_triangles(), full->num_drawn_triangles());

  // Rendered from the head camera: where both see the robot, depths agree
  // within the bound of the level drawn (at most bound_m z / nearest_m at
  // depth z) plus the rasterizer's own sampling of slanted faces.
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(320, 240, 45 * M_PI / 180);
  KinematicsState state(*full);
  // The home pose (dual_arm_home.h): the head camera sees both lower arms
  // and hands.
  const Eigen::VectorXd q = test_support::dual_arm_home_pose(*full);
  forward_kinematics(*full, q, state);
  DepthImage a, b;
  DepthRenderer(*full, camera).render(state, a);
  DepthRenderer(drawn, camera).render(state, b);
  int both = 0, either = 0, close = 0;
  for (std::size_t i = 0; i < a.depth_m.size(); ++i) {
    const bool in_a = a.depth_m[i] > 0, in_b = b.depth_m[i] > 0;
    either += in_a || in_b;
    if (!(in_a && in_b)) continue;
    ++both;
    const double level_bound_m = bound_m * std::max(1.0, double(a.depth_m[i]) / nearest_m);
    close += std::abs(a.depth_m[i] - b.depth_m[i]) <= 3 * level_bound_m;
  }
  ASSERT_GT(both, 1000);
  EXPECT_GT(double(both) / either, 0.99) << both << " of " << either;
  EXPECT_GT(double(close) / both, 0.99) << close << " of " << both;
}

// Levels of detail: level k is within 2^k of the bound of the full mesh
// and drawn from 2^k times the nearest range on.
TEST(SimplifyMesh, CoarserLevelsStayWithinTheirBoundsAndRanges) {
  // One link of the sculpted dual arm (models/generate_sculpted.py): a
  // 7 cm shoulder sphere of 9 000 triangles, and a cylinder drawn exactly.
  const RobotModel full = RobotModel::from_urdf_string(
      R"(<robot name="r">
        <link name="base"><visual><geometry>
          <mesh filename="meshes/sculpted/sphere_r0.07.stl"/></geometry></visual>
          <visual><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.05" length="0.1"/></geometry>
          </visual></link>
        <link name="camera_optical_frame"/>
        <joint name="c" type="fixed"><parent link="base"/><child link="camera_optical_frame"/>
          <origin xyz="1 0 0"/></joint></robot>)",
      std::string(ARTTRACK_SOURCE_DIR) + "/models");
  const double bound_m = 1e-3, nearest_m = 0.3;
  const RobotModel drawn = full.with_simplified_meshes(bound_m, nullptr, nearest_m, 4);
  int links_with_levels = 0;
  for (int l = 0; l < full.num_links(); ++l) {
    const Link& link = drawn.link(l);
    links_with_levels += !link.coarser_meshes.empty();
    // The link's triangles drawn as triangles (less the cylinder's), at full detail.
    TriangleMesh original = full.link(l).mesh;
    for (const RoundShape& shape : full.link(l).round_shapes)
      original.triangles.erase(
          original.triangles.begin() + shape.first_triangle,
          original.triangles.begin() + shape.first_triangle + shape.num_triangles);
    std::size_t previous = original.triangles.size();
    double previous_range_m = nearest_m;
    for (const Link::MeshLevel& level : link.coarser_meshes) {
      // Level k (ranges 2^k times the nearest; a level may be left out).
      const double factor = level.min_range_m / nearest_m;
      SCOPED_TRACE(link.name + " level from " + std::to_string(level.min_range_m) + " m");
      EXPECT_GT(level.min_range_m, previous_range_m);
      EXPECT_EQ(factor, std::exp2(std::round(std::log2(factor))));
      previous_range_m = level.min_range_m;
      EXPECT_LT(level.mesh.triangles.size(), previous);
      previous = level.mesh.triangles.size();
      EXPECT_TRUE(closed_and_consistent(level.mesh));
      EXPECT_LE(largest_vertex_distance(original, level.mesh), bound_m * factor);
    }
  }
  EXPECT_GT(links_with_levels, 0);
  for (int k = 1; k <= 4; ++k)
    EXPECT_LE(drawn.num_drawn_triangles(k), drawn.num_drawn_triangles(k - 1));
}

// The links are simplified on several threads at once (the largest first):
// the same model, vertex for vertex, as on one.
TEST(SimplifyMesh, ThreadsGiveTheSameModel) {
  const auto full =
      RobotModel::from_urdf_file(std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm_meshes.urdf");
  double error_1 = -1, error_3 = -1;
  const RobotModel one = full.with_simplified_meshes(2e-3, &error_1, 0.3, 4, 1);
  const RobotModel three = full.with_simplified_meshes(2e-3, &error_3, 0.3, 4, 3);
  EXPECT_EQ(error_1, error_3);
  EXPECT_GT(error_1, 0);
  ASSERT_EQ(one.num_links(), three.num_links());
  int compared = 0;
  for (int l = 0; l < one.num_links(); ++l) {
    const Link &a = one.link(l), &b = three.link(l);
    SCOPED_TRACE(a.name);
    ASSERT_EQ(a.coarser_meshes.size(), b.coarser_meshes.size());
    for (std::size_t k = 0; k <= a.coarser_meshes.size(); ++k) {
      const TriangleMesh& ma = k ? a.coarser_meshes[k - 1].mesh : a.mesh;
      const TriangleMesh& mb = k ? b.coarser_meshes[k - 1].mesh : b.mesh;
      ASSERT_EQ(ma.vertices_m, mb.vertices_m);
      ASSERT_EQ(ma.triangles, mb.triangles);
      compared += int(ma.triangles.size());
    }
  }
  EXPECT_GT(compared, 1000);
}

}  // namespace
}  // namespace arttrack
