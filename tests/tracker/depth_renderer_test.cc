#include "arttrack/tracker/depth_renderer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <numbers>
#include <random>

#include "../count_allocations.h"
#include "../scratch_dir.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {
namespace {

constexpr double kPi = std::numbers::pi;

// One shape on the base link, seen by a camera `distance` metres above it
// looking down (optical z = -base z, optical x = base x, optical y = -base y).
std::string shape_above(const std::string& geometry, double distance) {
  return R"(<robot name="shape">
  <link name="base_link"><visual><geometry>)" +
         geometry + R"(</geometry></visual></link>
  <link name="camera_optical_frame"/>
  <joint name="mount" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 )" +
         std::to_string(distance) + R"(" rpy="3.141592653589793 0 0"/></joint>
</robot>)";
}

DepthImage render_once(const RobotModel& model, const CameraIntrinsics& camera,
                       const RenderOptions& options = {}) {
  KinematicsState state(model);
  forward_kinematics(model, Eigen::VectorXd::Zero(model.num_joints()), state);
  DepthRenderer renderer(model, camera, options);
  DepthImage depth;
  renderer.render(state, depth);
  return depth;
}

int covered_in_row(const DepthImage& depth, int v) {
  int n = 0;
  for (int u = 0; u < depth.width; ++u) n += depth.at(u, v) > 0;
  return n;
}
int covered_in_column(const DepthImage& depth, int u) {
  int n = 0;
  for (int v = 0; v < depth.height; ++v) n += depth.at(u, v) > 0;
  return n;
}

// Number of pixel centres u + 0.5 within [c - half, c + half].
int centres_within(double c, double half) {
  return int(std::floor(c + half - 0.5) - std::ceil(c - half - 0.5) + 1);
}

TEST(DepthRenderer, BoxFaceHasPlanarDepthAndExactSilhouette) {
  // A 0.2 x 0.3 x 0.1 box, its top face 0.95 m from the camera.
  const RobotModel model =
      RobotModel::from_urdf_string(shape_above(R"(<box size="0.2 0.3 0.1"/>)", 1.0), "");
  for (const auto& [w, h] : {std::pair{80, 60}, {640, 480}, {97, 61}}) {
    const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(w, h, 45 * kPi / 180);
    const DepthImage depth = render_once(model, camera);
    ASSERT_EQ(depth.width, w);
    EXPECT_NEAR(depth.at(w / 2, h / 2), 0.95, 1e-5);
    // Only the top face is visible and it is fronto-parallel: one depth.
    for (float d : depth.depth_m) {
      if (d > 0) {
        ASSERT_NEAR(d, 0.95, 1e-5);
      }
    }
    // Face x in [-0.1, 0.1] (image u), y in [-0.15, 0.15] (image v).
    const int width = centres_within(camera.cx, camera.fx * 0.1 / 0.95);
    const int height = centres_within(camera.cy, camera.fy * 0.15 / 0.95);
    EXPECT_NEAR(covered_in_row(depth, h / 2), width, 1) << w << "x" << h;
    EXPECT_NEAR(covered_in_column(depth, w / 2), height, 1) << w << "x" << h;
  }
}

TEST(DepthRenderer, SphereSilhouetteDepthAndNoCracks) {
  const double r = 0.1, d = 1.0;
  RobotModelOptions options;
  options.sphere_segments = 24;
  const RobotModel model =
      RobotModel::from_urdf_string(shape_above(R"(<sphere radius="0.1"/>)", d), "", options);
  for (const auto& [w, h] : {std::pair{80, 60}, {640, 480}}) {
    const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(w, h, 45 * kPi / 180);
    const DepthImage depth = render_once(model, camera);
    // A centred sphere's silhouette is a circle of radius f r / sqrt(d^2 - r^2).
    const double rho = camera.fx * r / std::sqrt(d * d - r * r);
    const double dy = h / 2 + 0.5 - camera.cy;  // row h/2's centre below the principal point
    EXPECT_NEAR(covered_in_row(depth, h / 2),
                centres_within(camera.cx, std::sqrt(rho * rho - dy * dy)), 1);
    // Depth against the true sphere inside 80 % of the silhouette (it is drawn
    // exactly, in float); and no pixel missing there (no cracks).
    int checked = 0;
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const Eigen::Vector3d ray((u + 0.5 - camera.cx) / camera.fx,
                                  (v + 0.5 - camera.cy) / camera.fy, 1);
        const double off_axis = std::hypot(u + 0.5 - camera.cx, v + 0.5 - camera.cy);
        if (off_axis > 0.8 * rho) continue;
        // Nearest intersection of z * ray with the sphere centred at (0, 0, d).
        const double a = ray.squaredNorm(), b = -2 * d, c = d * d - r * r;
        const double z = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
        ASSERT_GT(depth.at(u, v), 0.f) << "hole at " << u << "," << v;
        EXPECT_NEAR(depth.at(u, v), z, 1e-6) << u << "," << v;
        ++checked;
      }
    }
    EXPECT_GT(checked, 50);
  }
}

// A sphere of a coarsely tessellated model (12 meridians) is drawn as the
// true sphere from every direction: its mean depth over the silhouette is
// within 1 micrometre of the true sphere's (drawn as its tessellation it
// was a fraction of a millimetre off, differently from each direction, and
// pulled the estimate off by a degree).
TEST(DepthRenderer, CoarseSphereIsDrawnExactly) {
  const double r = 0.06, d = 0.8;
  RobotModelOptions options;
  options.sphere_segments = 12;
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(320, 240, 45 * kPi / 180);
  double sum = 0;
  int pixels = 0;
  for (const char* rpy : {"0 0 0", "1.5707963 0 0", "0.4 0.7 0.1", "0 1.2 0.3"}) {
    const std::string urdf = R"(<robot name="ball">
  <link name="base_link"><visual><origin rpy=")" +
                             std::string(rpy) +
                             R"("/><geometry><sphere radius="0.06"/></geometry></visual></link>
  <link name="camera_optical_frame"/>
  <joint name="mount" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 0.8" rpy="3.141592653589793 0 0"/></joint>
</robot>)";
    const DepthImage depth = render_once(RobotModel::from_urdf_string(urdf, "", options), camera);
    for (int v = 0; v < camera.height; ++v) {
      for (int u = 0; u < camera.width; ++u) {
        const Eigen::Vector3d ray((u + 0.5 - camera.cx) / camera.fx,
                                  (v + 0.5 - camera.cy) / camera.fy, 1);
        const double a = ray.squaredNorm(), b = -2 * d, c = d * d - r * r;
        const double disc = b * b - 4 * a * c;
        if (disc <= 0 || !(depth.at(u, v) > 0)) continue;
        sum += depth.at(u, v) - (-b - std::sqrt(disc)) / (2 * a);
        ++pixels;
      }
    }
  }
  ASSERT_GT(pixels, 4000);
  EXPECT_NEAR(sum / pixels, 0.0, 1e-6) << "mean depth error over " << pixels << " pixels";
}

// A slab whose top face is a floor 0.2 m below the camera, from 1 m behind it
// to 3 m ahead: the face crosses the near plane.
constexpr char kFloor[] = R"(<robot name="floor">
  <link name="camera_optical_frame"/>
  <link name="slab"><visual><origin xyz="0 0.3 1"/><geometry><box size="2 0.2 4"/></geometry></visual></link>
  <joint name="mount" type="fixed"><parent link="camera_optical_frame"/><child link="slab"/></joint>
</robot>)";

TEST(DepthRenderer, NearPlaneClipsAndKeepsTheVisiblePart) {
  RobotModelOptions model_options;
  model_options.add_virtual_camera_joints = false;
  const RobotModel model = RobotModel::from_urdf_string(kFloor, "", model_options);
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 45 * kPi / 180);
  for (const float near : {0.01f, 0.6f}) {
    const DepthImage depth = render_once(model, camera, RenderOptions{.near_m = near});
    const int u = 40;  // the centre column
    int rendered_rows = 0;
    for (int v = 0; v < camera.height; ++v) {
      const double below = v + 0.5 - camera.cy;
      // Ray through the pixel centre meets the plane y = 0.2 at z = 0.2 fy / below.
      const double z = below > 0 ? 0.2 * camera.fy / below : 1e9;
      const double expected = (z >= near && z <= 3.0) ? z : 0.0;
      if (std::abs(z - near) < 1e-3 || std::abs(z - 3.0) < 1e-3) continue;  // on a cut
      EXPECT_NEAR(depth.at(u, v), expected, 1e-5 * expected) << "near " << near << " row " << v;
      rendered_rows += expected > 0;
    }
    EXPECT_GT(rendered_rows, 5);
  }
}

// Two links, each with a box, a cylinder or a sphere, on a 4-DOF arm.
constexpr char kArm[] = R"(<robot name="arm">
  <link name="base_link"><visual><origin xyz="0 0 0.05"/><geometry><box size="0.3 0.3 0.1"/></geometry></visual></link>
  <link name="upper">
    <visual><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.05" length="0.4"/></geometry></visual>
    <visual><origin xyz="0 0 0.4"/><geometry><sphere radius="0.07"/></geometry></visual>
  </link>
  <link name="lower"><visual><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.08 0.06"/></geometry></visual></link>
  <link name="pan"/>
  <link name="camera_optical_frame"/>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="upper"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="head_pan" type="revolute"><parent link="base_link"/><child link="pan"/>
    <origin xyz="0.9 0 0.5"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="cam" type="fixed"><parent link="pan"/><child link="camera_optical_frame"/>
    <origin rpy="-1.9 0 1.5707963267948966"/></joint>
</robot>)";

// Brute force: the nearest front-facing triangle hit by each pixel's ray
// (any triangle with `both_sides`), intersected in double precision
// (Moller-Trumbore), and the round shapes by sphere tracing; z >= near.
// A ray meets a triangle in front of the camera only inside the box of its
// projected corners, so each pixel tests only the triangles whose box, a
// pixel wider on every side, holds it (those reaching behind the camera:
// every pixel). The intersections themselves are as before, a hundred
// times fewer of them (AddressSanitizer: 42 s for the clusters test).
DepthImage ray_cast(const RobotModel& model, const KinematicsState& state,
                    const CameraIntrinsics& camera, double near, bool both_sides = false) {
  DepthImage depth(camera.width, camera.height);
  const Eigen::Isometry3d T_cam_root =
      state.T_root_link[model.camera_link()].inverse(Eigen::Isometry);
  struct Triangle {
    std::array<Eigen::Vector3d, 3> p;
    int u_min, u_max, v_min, v_max;  // the pixels whose rays may meet it
  };
  std::vector<Triangle> triangles;
  std::vector<std::pair<RoundShape, Eigen::Isometry3d>> shapes;  // with T_camera_shape
  for (int l : model.links_with_geometry()) {
    const Eigen::Isometry3d T = T_cam_root * state.T_root_link[l];
    const TriangleMesh& mesh = model.link(l).mesh;
    std::vector<bool> of_shape(mesh.triangles.size(), false);
    for (const RoundShape& shape : model.link(l).round_shapes) {
      shapes.push_back({shape, T * shape.T_link_shape});
      for (int i = 0; i < shape.num_triangles; ++i)
        of_shape[std::size_t(shape.first_triangle + i)] = true;
    }
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      if (of_shape[i]) continue;
      const Eigen::Vector3i& t = mesh.triangles[i];
      std::array<Eigen::Vector3d, 3> p;
      for (int k = 0; k < 3; ++k) p[k] = T * mesh.vertices_m[t[k]].cast<double>();
      if (!both_sides && (p[1] - p[0]).cross(p[2] - p[0]).dot(p[0]) >= 0) continue;  // faces away
      Triangle tri{p, 0, camera.width - 1, 0, camera.height - 1};
      if (p[0].z() > 1e-9 && p[1].z() > 1e-9 && p[2].z() > 1e-9) {
        double u_lo = 1e300, u_hi = -1e300, v_lo = 1e300, v_hi = -1e300;
        for (const Eigen::Vector3d& c : p) {
          const double u = camera.fx * c.x() / c.z() + camera.cx - 0.5;  // pixel index
          const double v = camera.fy * c.y() / c.z() + camera.cy - 0.5;
          u_lo = std::min(u_lo, u), u_hi = std::max(u_hi, u);
          v_lo = std::min(v_lo, v), v_hi = std::max(v_hi, v);
        }
        tri.u_min = int(std::max(-1.0, std::floor(u_lo) - 1));
        tri.u_max = int(std::min(double(camera.width), std::ceil(u_hi) + 1));
        tri.v_min = int(std::max(-1.0, std::floor(v_lo) - 1));
        tri.v_max = int(std::min(double(camera.height), std::ceil(v_hi) + 1));
      }
      triangles.push_back(tri);
    }
  }
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray((u + 0.5 - camera.cx) / camera.fx,
                                (v + 0.5 - camera.cy) / camera.fy, 1);
      double best = std::numeric_limits<double>::infinity();
      for (const Triangle& tri : triangles) {
        if (u < tri.u_min || u > tri.u_max || v < tri.v_min || v > tri.v_max) continue;
        const std::array<Eigen::Vector3d, 3>& p = tri.p;
        const Eigen::Vector3d e1 = p[1] - p[0], e2 = p[2] - p[0];
        const Eigen::Vector3d h = ray.cross(e2);
        const double det = e1.dot(h);
        if (std::abs(det) < 1e-15) continue;
        const double s = (-p[0]).dot(h) / det;  // ray origin is the camera centre
        const Eigen::Vector3d qv = (-p[0]).cross(e1);
        const double t = ray.dot(qv) / det;
        const double z = e2.dot(qv) / det;  // ray has unit z: parameter = depth
        if (s < 0 || t < 0 || s + t > 1 || z < near) continue;
        best = std::min(best, z);
      }
      // Round shapes: sphere tracing on their signed distance (a lower bound
      // on the distance to the surface), from the camera to the first point
      // within 1e-9 m of it, the entry; drawn when at or beyond the near plane.
      for (const auto& [shape, T_camera_shape] : shapes) {
        const Eigen::Isometry3d T_shape_camera = T_camera_shape.inverse(Eigen::Isometry);
        const Eigen::Vector3d o = T_shape_camera.translation();
        const Eigen::Vector3d dir = T_shape_camera.linear() * ray;  // z component 1 in the camera
        auto distance = [&](const Eigen::Vector3d& p) {
          if (shape.kind == RoundShape::Kind::kSphere) return p.norm() - shape.radius_m;
          return std::max(p.head<2>().norm() - shape.radius_m,
                          std::abs(p.z()) - 0.5 * shape.length_m);
        };
        double t = 0;
        for (int step = 0; step < 100000 && t < 100; ++step) {
          const double sdf = distance(o + t * dir);
          if (sdf < 1e-9) {
            if (t >= near) best = std::min(best, t);
            break;
          }
          t += sdf / dir.norm();
        }
      }
      if (std::isfinite(best)) depth.at(u, v) = float(best);
    }
  }
  return depth;
}

TEST(DepthRenderer, AgreesWithBruteForceRayCasting) {
  const RobotModel model = RobotModel::from_urdf_string(kArm, "");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  KinematicsState state(model);
  for (const auto& [w, h] : {std::pair{80, 60}, {160, 120}}) {
    const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(w, h, 50 * kPi / 180);
    DepthRenderer renderer(model, camera);
    DepthImage depth;
    int covered = 0, coverage_mismatches = 0, depth_mismatches = 0;
    for (int trial = 0; trial < 6; ++trial) {
      Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
      for (int j = 0; j < 3; ++j) q[j] = 0.8 * U(rng);
      for (int j = 3; j < 6; ++j) q[j] = 0.05 * U(rng);
      for (int j = 6; j < 9; ++j) q[j] = 0.1 * U(rng);
      forward_kinematics(model, q, state);
      renderer.render(state, depth);
      const DepthImage truth = ray_cast(model, state, camera, renderer.options().near_m);
      for (int i = 0; i < w * h; ++i) {
        covered += truth.depth_m[i] > 0;
        if ((depth.depth_m[i] > 0) != (truth.depth_m[i] > 0)) {
          ++coverage_mismatches;
        } else if (std::abs(depth.depth_m[i] - truth.depth_m[i]) > 1e-4 * truth.depth_m[i]) {
          ++depth_mismatches;
        }
      }
    }
    EXPECT_GT(covered, w * h * 6 / 20) << "the arm should cover some 5 % of the view or more";
    // Only a pixel centre within rounding of a silhouette edge may differ.
    EXPECT_LE(coverage_mismatches, 2) << w << "x" << h << " of " << covered;
    EXPECT_LE(depth_mismatches, 2) << w << "x" << h << " of " << covered;
  }
}

// A bumpy closed ball of 9600 triangles, turned to random poses in front of
// the camera: the renderer skips the clusters whose every face turns away
// (about half of them) and those whose screen extent holds no pixel centre
// (most of them at 2 m, where a cluster spans half a pixel, and those off
// the view), and must still draw every front face the brute force finds.
TEST(DepthRenderer, SkippedClustersHideNoFrontFace) {
  const test_support::ScratchDir scratch("depth_renderer_clusters");
  const int rings = 60, segments = 80;
  {
    std::ofstream obj(scratch.path() / "ball.obj");
    std::vector<Eigen::Vector3d> v;
    auto radius = [](double theta, double phi) {
      return 0.12 * (1 + 0.08 * std::sin(5 * theta) * std::cos(7 * phi));
    };
    v.push_back({0, 0, radius(0, 0)});
    for (int i = 1; i < rings; ++i) {
      for (int j = 0; j < segments; ++j) {
        const double theta = kPi * i / rings, phi = 2 * kPi * j / segments;
        const double r = radius(theta, phi);
        v.push_back(r * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                        std::sin(theta) * std::sin(phi), std::cos(theta)));
      }
    }
    v.push_back({0, 0, -radius(kPi, 0)});
    char line[128];
    for (const Eigen::Vector3d& p : v) {
      std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
      obj << line;
    }
    // Wound counter-clockwise seen from outside (the centre is inside).
    auto face = [&](int a, int b, int c) {
      if ((v[b] - v[a]).cross(v[c] - v[a]).dot(v[a]) < 0) std::swap(b, c);
      obj << "f " << a + 1 << " " << b + 1 << " " << c + 1 << "\n";
    };
    auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
    const int bottom = int(v.size()) - 1;
    for (int j = 0; j < segments; ++j) {
      face(0, ring(1, j), ring(1, j + 1));
      face(bottom, ring(rings - 1, j + 1), ring(rings - 1, j));
      for (int i = 1; i + 1 < rings; ++i) {
        face(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
        face(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
      }
    }
  }
  // Near (clusters of about 2 px), far (clusters of about half a pixel,
  // mostly between pixel centres) and across the view's right edge.
  struct Placement {
    const char* xyz;
    int min_covered;
  };
  for (const Placement placement :
       {Placement{"0.02 -0.01 0.5", 3 * 600}, Placement{"0.1 0.05 2.0", 3 * 40},
        Placement{"0.72 0 1.2", 3 * 70}}) {
    SCOPED_TRACE(placement.xyz);
    const RobotModel model = RobotModel::from_urdf_string(std::string(R"(<robot name="ball">
  <link name="camera_optical_frame"/>
  <link name="gimbal_1"/><link name="gimbal_2"/>
  <link name="ball"><visual><geometry><mesh filename="ball.obj"/></geometry></visual></link>
  <joint name="a" type="continuous"><parent link="camera_optical_frame"/><child link="gimbal_1"/>
    <origin xyz=")") + placement.xyz + R"("/><axis xyz="1 0 0"/></joint>
  <joint name="b" type="continuous"><parent link="gimbal_1"/><child link="gimbal_2"/>
    <axis xyz="0 1 0"/></joint>
  <joint name="c" type="continuous"><parent link="gimbal_2"/><child link="ball"/>
    <axis xyz="0 0 1"/></joint>
</robot>)",
                                                          scratch.path().string());
    ASSERT_EQ(model.link(model.link_index("ball")).mesh.triangles.size(),
              std::size_t(2 * segments * (rings - 1)));
    const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 50 * kPi / 180);
    DepthRenderer renderer(model, camera);
    KinematicsState state(model);
    DepthImage depth;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-kPi, kPi);
    int covered = 0, coverage_mismatches = 0, depth_mismatches = 0;
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
      for (const char* joint : {"a", "b", "c"}) q[model.joint_index(joint)] = U(rng);
      forward_kinematics(model, q, state);
      renderer.render(state, depth);
      const DepthImage truth = ray_cast(model, state, camera, renderer.options().near_m);
      for (int i = 0; i < 80 * 60; ++i) {
        covered += truth.depth_m[std::size_t(i)] > 0;
        if ((depth.depth_m[std::size_t(i)] > 0) != (truth.depth_m[std::size_t(i)] > 0)) {
          ++coverage_mismatches;
        } else if (std::abs(depth.depth_m[std::size_t(i)] - truth.depth_m[std::size_t(i)]) >
                   1e-4 * truth.depth_m[std::size_t(i)]) {
          ++depth_mismatches;
        }
      }
    }
    EXPECT_GT(covered, placement.min_covered);
    EXPECT_LE(coverage_mismatches, 2) << "of " << covered;
    EXPECT_LE(depth_mismatches, 2) << "of " << covered;
  }
}

// A link wholly in front of the near plane has its vertices transformed
// four at a time (SSE); one whose bounding sphere reaches the near plane one
// at a time, to clip. Both must give the same bits: a rod across the view
// with the near plane between its bounding sphere's nearest point and its
// own nearest vertex takes the one-at-a-time path without clipping anything.
TEST(DepthRenderer, TransformsLikeOneVertexAtATime) {
  const test_support::ScratchDir scratch("depth_renderer_lanes");
  const int rings = 240, segments = 24;  // 11 520 triangles, 0.4 m x 0.02 m
  {
    std::ofstream obj(scratch.path() / "rod.obj");
    char line[128];
    for (int i = 0; i < rings; ++i) {
      for (int j = 0; j < segments; ++j) {
        const double x = -0.2 + 0.4 * i / (rings - 1), phi = 2 * kPi * j / segments;
        const double r = 0.01 * (1 + 0.2 * std::sin(13 * x) * std::cos(3 * phi));
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", x, r * std::cos(phi),
                      r * std::sin(phi));
        obj << line;
      }
    }
    auto vertex = [&](int i, int j) { return 1 + i * segments + j % segments; };
    for (int i = 0; i + 1 < rings; ++i) {
      for (int j = 0; j < segments; ++j) {  // outward: (+x) x (+phi) points out
        obj << "f " << vertex(i, j) << " " << vertex(i + 1, j) << " " << vertex(i + 1, j + 1)
            << "\n";
        obj << "f " << vertex(i, j) << " " << vertex(i + 1, j + 1) << " " << vertex(i, j + 1)
            << "\n";
      }
    }
  }
  const RobotModel model = RobotModel::from_urdf_string(R"(<robot name="rod">
  <link name="camera_optical_frame"/>
  <link name="gimbal"/>
  <link name="rod"><visual><geometry><mesh filename="rod.obj"/></geometry></visual></link>
  <joint name="spin" type="continuous"><parent link="camera_optical_frame"/><child link="gimbal"/>
    <origin xyz="0.01 -0.02 0.6"/><axis xyz="0 0 1"/></joint>
  <joint name="roll" type="continuous"><parent link="gimbal"/><child link="rod"/>
    <axis xyz="1 0 0"/></joint>
</robot>)",
                                                        scratch.path().string());
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 50 * kPi / 180);
  // Bounding sphere nearest at about 0.4 m, vertices at 0.588 m and beyond.
  DepthRenderer lanes(model, camera, RenderOptions{.near_m = 0.01f});
  DepthRenderer one_at_a_time(model, camera, RenderOptions{.near_m = 0.5f});
  KinematicsState state(model);
  DepthImage a, b;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-kPi, kPi);
  int covered = 0;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
    q[model.joint_index("spin")] = U(rng);
    q[model.joint_index("roll")] = U(rng);
    forward_kinematics(model, q, state);
    lanes.render(state, a);
    one_at_a_time.render(state, b);
    for (int i = 0; i < 80 * 60; ++i) {
      covered += a.depth_m[std::size_t(i)] > 0;
      ASSERT_EQ(a.depth_m[std::size_t(i)], b.depth_m[std::size_t(i)]) << "pixel " << i;
    }
  }
  EXPECT_GT(covered, 5 * 60);  // the rod spans about 50 pixels and 2-3 rows
}

// Published meshes come inside out and open. A box wound inside out is
// drawn like the box; a box without its top, seen from above through the
// opening, shows its floor and inner walls when open parts are drawn from
// both sides, and nothing there when culled as if closed (they face away
// from the camera as wound).
TEST(DepthRenderer, InsideOutAndOpenMeshesShowTheSurfaceTheCameraSees) {
  const test_support::ScratchDir scratch("depth_renderer_open");
  auto write_box = [&](const std::string& name, bool inside_out, bool open_top) {
    std::ofstream obj(scratch.path() / name);
    for (int i = 0; i < 8; ++i)
      obj << "v " << (i & 1 ? 0.1 : -0.1) << " " << (i & 2 ? 0.1 : -0.1) << " "
          << (i & 4 ? 0.1 : -0.1) << "\n";
    // Counter-clockwise seen from outside (1-based corners).
    const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5},
                             {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
    for (int f = 0; f < 6; ++f) {
      if (open_top && f == 1) continue;  // the face at z = +0.1
      const int* c = faces[f];
      if (inside_out) {
        obj << "f " << c[3] << " " << c[2] << " " << c[1] << " " << c[0] << "\n";
      } else {
        obj << "f " << c[0] << " " << c[1] << " " << c[2] << " " << c[3] << "\n";
      }
    }
  };
  write_box("box.obj", false, false);
  write_box("inside_out.obj", true, false);
  write_box("open.obj", false, true);
  auto model_of = [&](const std::string& mesh) {
    return RobotModel::from_urdf_string(R"(<robot name="box">
  <link name="base_link"/>
  <link name="box"><visual><geometry><mesh filename=")" +
                                            mesh +
                                            R"("/></geometry></visual></link>
  <link name="camera_optical_frame"/>
  <joint name="spin" type="continuous"><parent link="base_link"/><child link="box"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="cam" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0.01 0.02 0.6" rpy="3.14159265358979 0 0"/></joint>
</robot>)",
                                        scratch.path().string());
  };
  const RobotModel box = model_of("box.obj"), inside_out = model_of("inside_out.obj"),
                   open = model_of("open.obj");
  const int link = box.link_index("box");
  EXPECT_EQ(box.link(link).mesh_parts.turned_parts, 0);
  EXPECT_EQ(inside_out.link(link).mesh_parts.turned_parts, 1);
  EXPECT_FALSE(inside_out.link(link).has_open_parts());
  EXPECT_EQ(open.link(link).mesh_parts.open_parts, 1);
  EXPECT_TRUE(open.link(link).has_open_parts());

  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 45 * kPi / 180);
  for (const double angle : {0.0, 0.7}) {
    SCOPED_TRACE(angle);
    KinematicsState state(box);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(box.num_joints());
    q[box.joint_index("spin")] = angle;
    forward_kinematics(box, q, state);
    DepthImage expected, turned, opened;
    DepthRenderer(box, camera).render(state, expected);
    DepthRenderer(inside_out, camera).render(state, turned);
    EXPECT_EQ(turned.depth_m, expected.depth_m);

    // Both sides, as asked: the floor, 0.7 m away, seen through the
    // opening. Culled (the default): the opening shows nothing.
    for (const bool both_sides : {true, false}) {
      RenderOptions options;
      options.open_parts_both_sides = both_sides;
      DepthRenderer open_renderer(open, camera, options);
      open_renderer.render(state, opened);
      const DepthImage truth = ray_cast(open, state, camera, options.near_m, both_sides);
      int floor = 0, mismatches = 0;
      for (std::size_t i = 0; i < opened.depth_m.size(); ++i) {
        floor += std::abs(opened.depth_m[i] - 0.7f) < 1e-4f;
        if ((opened.depth_m[i] > 0) != (truth.depth_m[i] > 0) ||
            std::abs(opened.depth_m[i] - truth.depth_m[i]) > 1e-4f * truth.depth_m[i])
          ++mismatches;
      }
      EXPECT_EQ(floor > 100, both_sides) << floor;
      EXPECT_LE(mismatches, 2) << "of " << opened.depth_m.size();
    }
  }
}

// A cylinder turned about its own axis and a sphere turned about its centre
// look the same to a camera, and so must their renders (they are drawn
// exactly), or every image tells the tracker about joint angles it cannot
// see. Drawn as their tessellations, a 16-sided cylinder and a 12-meridian
// sphere change by millimetres.
TEST(DepthRenderer, RoundShapesTurnedAboutThemselvesLookTheSame) {
  constexpr char kTurning[] = R"(<robot name="turning">
  <link name="base_link"/>
  <link name="roller"><visual><origin xyz="0 0 0.1" rpy="0 0 0.4"/><geometry><cylinder radius="0.05" length="0.2"/></geometry></visual></link>
  <link name="ball"><visual><origin xyz="0.03 0 0.04" rpy="0.5 -0.4 1"/><geometry><sphere radius="0.06"/></geometry></visual></link>
  <link name="camera_optical_frame"/>
  <joint name="spin" type="continuous"><parent link="base_link"/><child link="roller"/>
    <origin xyz="-0.1 0 0" rpy="0.3 0.2 0"/><axis xyz="0 0 1"/></joint>
  <joint name="tumble" type="continuous"><parent link="base_link"/><child link="ball"/>
    <origin xyz="0.1 -0.02 0.01"/><axis xyz="0.6 0 0.8"/></joint>
  <joint name="cam" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0.1 -0.6 0.4" rpy="-2.2 0 0.2"/></joint>
</robot>)";
  RobotModelOptions options;
  options.cylinder_segments = 16;
  options.sphere_segments = 12;
  const RobotModel model = RobotModel::from_urdf_string(kTurning, "", options);
  // The roller's cylinder lies along the spin axis, the ball's sphere is
  // centred on the tumble axis.
  ASSERT_EQ(model.link(model.link_index("roller")).round_shapes.size(), 1u);
  ASSERT_EQ(model.link(model.link_index("ball")).round_shapes.size(), 1u);
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(160, 120, 45 * kPi / 180);
  DepthRenderer renderer(model, camera);
  KinematicsState state(model);
  DepthImage reference, turned;
  forward_kinematics(model, Eigen::VectorXd::Zero(model.num_joints()), state);
  renderer.render(state, reference);
  int covered = 0;
  for (const float d : reference.depth_m) covered += d > 0;
  ASSERT_GT(covered, 1000);
  for (const double angle : {0.1, 0.37, 1.3, -2.0}) {
    for (const int dof : {model.joint_index("spin"), model.joint_index("tumble")}) {
      Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
      q[dof] = angle;
      forward_kinematics(model, q, state);
      renderer.render(state, turned);
      int coverage_mismatches = 0;
      double largest_m = 0;
      for (std::size_t i = 0; i < turned.depth_m.size(); ++i) {
        const float a = reference.depth_m[i], b = turned.depth_m[i];
        if ((a > 0) != (b > 0)) {
          ++coverage_mismatches;
        } else if (a > 0) {
          largest_m = std::max(largest_m, double(std::abs(a - b)));
        }
      }
      // Float rounding of the turned poses only.
      EXPECT_LE(coverage_mismatches, 2) << model.joint_name(dof) << " at " << angle;
      EXPECT_LT(largest_m, 1e-5) << model.joint_name(dof) << " at " << angle;
    }
  }
}

// An image subsampled by subsample_depth() is what a render with
// subsampled_intrinsics() sees, pixel for pixel: each kept source pixel's
// ray is the target pixel's. scaled_to() looks half a source pixel beside it
// at even factors, and its silhouettes disagree along every edge.
TEST(DepthRenderer, SubsampledIntrinsicsSeeWhatSubsamplingKeeps) {
  const RobotModel model = RobotModel::from_urdf_string(kArm, "");
  KinematicsState state(model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  q[0] = 0.3;
  q[1] = -0.4;
  q[2] = 0.5;
  forward_kinematics(model, q, state);
  const CameraIntrinsics target = CameraIntrinsics::from_vertical_fov(80, 60, 50 * kPi / 180);
  for (const auto& [w, h] : {std::pair{160, 120}, {640, 480}, {240, 180}, {100, 75}}) {
    const CameraIntrinsics source = CameraIntrinsics::from_vertical_fov(w, h, 50 * kPi / 180);
    DepthRenderer source_renderer(model, source);
    DepthImage full;
    source_renderer.render(state, full);
    const DepthImage kept = subsample_depth(full, 80, 60);
    auto mismatches = [&](const CameraIntrinsics& camera) {
      DepthRenderer renderer(model, camera);
      DepthImage depth;
      renderer.render(state, depth);
      int n = 0;
      for (std::size_t i = 0; i < depth.depth_m.size(); ++i)
        n += (depth.depth_m[i] > 0) != (kept.depth_m[i] > 0) ||
             std::abs(depth.depth_m[i] - kept.depth_m[i]) > 1e-4f;
      return n;
    };
    const CameraIntrinsics subsampled = subsampled_intrinsics(source, 80, 60);
    EXPECT_NEAR(subsampled.fx, target.fx, 1e-9 * target.fx);
    const int with_subsampled = mismatches(subsampled), with_scaled = mismatches(target);
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + ": " +
                 std::to_string(with_subsampled) + " pixels differ with subsampled_intrinsics, " +
                 std::to_string(with_scaled) + " with scaled_to");
    if (w % 80 == 0 && (w / 80) % 2 == 1) {
      // An odd factor keeps the centre pixel: both are exact.
      EXPECT_NEAR(subsampled.cx, target.cx, 1e-9);
      EXPECT_NEAR(subsampled.cy, target.cy, 1e-9);
      EXPECT_LE(with_subsampled, 2);
    } else if (w % 80 == 0) {
      EXPECT_LE(with_subsampled, 2);  // rounding at a silhouette only
      EXPECT_GT(with_scaled, 10);
    } else {
      // 5:4 keeps pixels up to 0.4 source pixels off in both directions;
      // the mean shift is the best single principal point, not exact.
      EXPECT_LE(with_subsampled, with_scaled);
    }
  }
}

TEST(DepthRenderer, SubsetsCachesAndRectangles) {
  const RobotModel model = RobotModel::from_urdf_string(kArm, "");
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 50 * kPi / 180);
  DepthRenderer renderer(model, camera);
  KinematicsState state(model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  q[model.joint_index("shoulder")] = 0.3;
  q[model.joint_index("elbow")] = -0.6;
  forward_kinematics(model, q, state);
  DepthImage all, subset, cached;
  const PixelRect all_rect = renderer.render(state, all);

  // The bounding rectangle is that of the nonzero pixels.
  PixelRect expected{80, 60, 0, 0};
  for (int v = 0; v < 60; ++v) {
    for (int u = 0; u < 80; ++u) {
      if (all.at(u, v) > 0)
        expected = {std::min(expected.u0, u), std::min(expected.v0, v),
                    std::max(expected.u1, u + 1), std::max(expected.v1, v + 1)};
    }
  }
  EXPECT_EQ(all_rect.u0, expected.u0);
  EXPECT_EQ(all_rect.v0, expected.v0);
  EXPECT_EQ(all_rect.u1, expected.u1);
  EXPECT_EQ(all_rect.v1, expected.v1);

  // The elbow's links alone, merged with the rest, give the full image.
  const int elbow = model.joint_index("elbow");
  const LinkSet lower = model.links_moved_by(elbow);
  LinkSet rest(lower.size());
  for (size_t l = 0; l < lower.size(); ++l) rest[l] = !lower[l];
  const PixelRect lower_rect = renderer.render_links(state, lower, subset);
  EXPECT_GT(lower_rect.area(), 0);
  DepthImage merged;
  renderer.render_links(state, rest, merged);
  merge_nearer(subset, lower_rect, merged);
  EXPECT_EQ(merged.depth_m, all.depth_m);
  for (int v = 0; v < 60; ++v) {
    for (int u = 0; u < 80; ++u) {
      const bool inside =
          u >= lower_rect.u0 && u < lower_rect.u1 && v >= lower_rect.v0 && v < lower_rect.v1;
      if (!inside) {
        ASSERT_EQ(subset.at(u, v), 0.f);
      }
    }
  }

  // A cache for the elbow: hypotheses moving only the elbow render exactly
  // like full renders.
  CachedRenderer cache(renderer, {elbow});
  cache.set_reference(state);
  KinematicsState hypothesis(model);
  DepthImage full;
  for (double delta : {0.0, 0.2, -0.5}) {
    Eigen::VectorXd qh = q;
    qh[elbow] += delta;
    forward_kinematics(model, qh, hypothesis);
    cache.render(hypothesis, cached);
    renderer.render(hypothesis, full);
    EXPECT_EQ(cached.depth_m, full.depth_m) << delta;
  }
  // A camera DOF moves everything, so its cache holds nothing.
  CachedRenderer camera_cache(renderer, {model.joint_index("camera_offset_yaw")});
  camera_cache.set_reference(state);
  for (float d : camera_cache.cached_depth().depth_m) ASSERT_EQ(d, 0.f);
  // The head pan moves the camera too.
  const LinkSet pan_links = links_affecting_depth(model, {model.joint_index("head_pan")});
  for (bool b : pan_links) EXPECT_TRUE(b);
}

// A tilted sheet of ~29k jittered triangles: every pixel inside it must be
// drawn (no crack along shared edges, no pixel lost by the per-row spans).
TEST(DepthRenderer, SharedEdgesLeaveNoCracks) {
  const test_support::ScratchDir scratch("depth_renderer_test");
  const std::filesystem::path& dir = scratch.path();
  const int n = 120;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  {
    std::ofstream obj(dir / "sheet.obj");
    char line[128];
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        const bool border = i == 0 || j == 0 || i == n || j == n;
        const double x = -1 + 2.0 * (i + (border ? 0 : jitter(rng))) / n;
        const double y = -1 + 2.0 * (j + (border ? 0 : jitter(rng))) / n;
        std::snprintf(line, sizeof line, "v %.9g %.9g 0\n", x, y);
        obj << line;
      }
    }
    // Wound to face -z, towards the camera.
    auto id = [n](int i, int j) { return j * (n + 1) + i + 1; };
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        obj << "f " << id(i, j) << " " << id(i, j + 1) << " " << id(i + 1, j) << "\n";
        obj << "f " << id(i + 1, j) << " " << id(i, j + 1) << " " << id(i + 1, j + 1) << "\n";
      }
    }
  }
  const std::string urdf = R"(<robot name="sheet">
  <link name="camera_optical_frame"/>
  <link name="sheet"><visual><origin rpy="0.5 0.2 0.1"/>
    <geometry><mesh filename="sheet.obj"/></geometry></visual></link>
  <joint name="turn" type="continuous"><parent link="camera_optical_frame"/><child link="sheet"/>
    <origin xyz="0.01 -0.02 1"/><axis xyz="0 0 1"/></joint>
</robot>)";
  const RobotModel model = RobotModel::from_urdf_string(urdf, dir.string());
  ASSERT_EQ(model.link(model.link_index("sheet")).mesh.triangles.size(), size_t(2 * n * n));
  KinematicsState state(model);
  DepthImage depth;
  int holes = 0;
  for (const auto& [w, h] : {std::pair{640, 480}, {80, 60}}) {
    DepthRenderer renderer(model, CameraIntrinsics::from_vertical_fov(w, h, 45 * kPi / 180));
    for (int step = 0; step < 20; ++step) {
      Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
      q[model.joint_index("turn")] = 0.05 * step;
      forward_kinematics(model, q, state);
      renderer.render(state, depth);
      // Pixels whose ray meets the sheet inside its border must be drawn.
      const Eigen::Isometry3d T_cam_sheet =
          T_camera_link(model, state, model.link_index("sheet")) *
          Eigen::Isometry3d(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()));
      const Eigen::Vector3d normal = T_cam_sheet.linear().col(2);
      const CameraIntrinsics& k = renderer.camera();
      for (int v = 0; v < h; ++v) {
        for (int u = 0; u < w; ++u) {
          const Eigen::Vector3d ray((u + 0.5 - k.cx) / k.fx, (v + 0.5 - k.cy) / k.fy, 1);
          const double z = normal.dot(T_cam_sheet.translation()) / normal.dot(ray);
          const Eigen::Vector3d local = T_cam_sheet.inverse() * (z * ray);
          if (std::abs(local.x()) < 0.98 && std::abs(local.y()) < 0.98) {
            holes += depth.at(u, v) == 0.f;
          }
        }
      }
    }
  }
  EXPECT_EQ(holes, 0);
}

TEST(DepthRenderer, RenderingAllocatesNothingOnceSized) {
  const RobotModel model = RobotModel::from_urdf_string(kArm, "");
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 50 * kPi / 180);
  DepthRenderer renderer(model, camera);
  KinematicsState state(model);
  Eigen::VectorXd q = Eigen::VectorXd::Constant(model.num_joints(), 0.01);
  forward_kinematics(model, q, state);
  DepthImage depth, cached;
  CachedRenderer cache(renderer, {model.joint_index("elbow")});
  cache.set_reference(state);
  const LinkSet links = model.links_moved_by(model.joint_index("shoulder"));
  renderer.render(state, depth);
  cache.render(state, cached);
  const long before = g_allocations.load();
  for (int i = 0; i < 10; ++i) {
    forward_kinematics(model, q, state);
    renderer.render(state, depth);
    renderer.render_links(state, links, depth);
    cache.render(state, cached);
  }
  EXPECT_EQ(g_allocations.load(), before);
}

}  // namespace
}  // namespace arttrack
