// The simulated depth camera against closed forms: boxes of known size and
// pose in front of a fixed camera.
#include "arttrack/sim/depth_camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "../scratch_dir.h"
#include "arttrack/sim/depth_compare.h"
#include "arttrack/sim/simulator.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;

// A camera 1 m above the floor looking along world +x (ROS optical rpy).
constexpr char kCameraUrdf[] = R"(<robot name="camera_only">
  <link name="base_link"/>
  <joint name="camera_joint" type="fixed">
    <parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 1" rpy="-1.5707963267948966 0 -1.5707963267948966"/>
  </joint>
  <link name="camera_optical_frame"/>
</robot>)";

using test_support::write_scratch_file;

SceneDescription camera_scene() {
  SceneDescription s;
  s.urdf_path = write_scratch_file("camera.urdf", kCameraUrdf);
  s.end_effector_links = {};
  s.width = 160;
  s.height = 120;
  s.fovy_rad = 50.0 * M_PI / 180.0;
  s.near_m = 0.2;
  s.far_m = 5.0;
  s.floor = false;
  return s;
}

SceneShape box(const Eigen::Vector3d& size, const Eigen::Isometry3d& T_world_box) {
  SceneShape b;
  b.name = "box";
  b.type = SceneShape::Type::kBox;
  b.size_m = size;
  b.T_world_shape = T_world_box;
  return b;
}

// Planar depth of the ray through pixel (u, v)'s centre where it meets the
// plane {p : n.p = c} (optical frame), and whether the hit lies inside the
// face's rectangle given by `inside`.
struct Expected {
  double depth_m;
  bool covered;
};

// The box's face towards the camera (-x face of the box in world), as
// centre, normal and two half-axes, all in the optical frame.
template <class Inside>
Expected ray_plane(const CameraIntrinsics& K, int u, int v, const Eigen::Vector3d& point,
                   const Eigen::Vector3d& normal, Inside inside) {
  const Eigen::Vector3d d((u + 0.5 - K.cx) / K.fx, (v + 0.5 - K.cy) / K.fy, 1.0);
  const double t = normal.dot(point) / normal.dot(d);
  return {t, inside(t * d)};
}

// Renders `shape` and compares every pixel whose centre lies more than half
// a pixel from the face's outline with the closed form.
void check_box(const Eigen::Vector3d& size, const Eigen::Isometry3d& T_world_box) {
  SceneDescription scene = camera_scene();
  scene.shapes.push_back(box(size, T_world_box));
  const auto model = build_sim_model(scene);
  Simulator sim(model);
  DepthCamera camera(model);
  DepthImage depth;
  camera.render(sim.data(), DepthContent::kScene, depth);
  const CameraIntrinsics& K = camera.intrinsics();
  ASSERT_EQ(depth.width, 160);
  ASSERT_EQ(depth.height, 120);

  const GroundTruth truth = sim.ground_truth();
  // The URDF's rpy puts the optical axis along world +x, x right = world -y.
  EXPECT_LT((truth.T_world_camera.linear().col(2) - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  EXPECT_LT((truth.T_world_camera.linear().col(0) + Eigen::Vector3d::UnitY()).norm(), 1e-12);
  const Eigen::Isometry3d T_camera_box = truth.T_world_camera.inverse() * T_world_box;

  // The visible face is the box's -x face.
  const Eigen::Vector3d centre = T_camera_box * Eigen::Vector3d(-0.5 * size.x(), 0, 0);
  const Eigen::Vector3d normal = T_camera_box.linear() * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d ay = T_camera_box.linear() * Eigen::Vector3d::UnitY();
  const Eigen::Vector3d az = T_camera_box.linear() * Eigen::Vector3d::UnitZ();
  // Margin of one pixel's footprint on the face, so edge pixels are skipped.
  const double margin = 1.5 * centre.z() / K.fx;
  long checked_in = 0, checked_out = 0;
  for (int v = 0; v < depth.height; ++v)
    for (int u = 0; u < depth.width; ++u) {
      const auto classify = [&](double grow) {
        return ray_plane(K, u, v, centre, normal, [&](const Eigen::Vector3d& p) {
          const Eigen::Vector3d r = p - centre;
          return std::abs(r.dot(ay)) <= 0.5 * size.y() + grow &&
                 std::abs(r.dot(az)) <= 0.5 * size.z() + grow;
        });
      };
      const Expected shrunk = classify(-margin), grown = classify(margin);
      if (shrunk.covered) {
        EXPECT_NEAR(depth.at(u, v), shrunk.depth_m, 1e-3) << "pixel " << u << ", " << v;
        ++checked_in;
      } else if (!grown.covered) {
        EXPECT_EQ(depth.at(u, v), 0.f) << "pixel " << u << ", " << v;
        ++checked_out;
      }
    }
  EXPECT_GT(checked_in, 100);
  EXPECT_GT(checked_out, 100);
}

Eigen::Isometry3d at(double x, double y, double z, double yaw_rad = 0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << x, y, z;
  T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

TEST(DepthCamera, FrontalBoxAtKnownDistances) {
  for (double distance : {0.6, 1.5, 3.2})
    check_box({0.1, 0.4, 0.3}, at(distance + 0.05, 0.05, 1.02));
}

TEST(DepthCamera, ObliqueOffAxisBox) {
  // Turned 35 degrees and off the optical axis: depth varies across the face,
  // which checks focal length and principal point as well as the depth map.
  check_box({0.05, 0.5, 0.4}, at(1.8, 0.3, 0.9, 35.0 * M_PI / 180.0));
}

// A head camera looking down at an arm of a box, a cylinder and a sphere.
constexpr char kPrimitivesArmUrdf[] = R"(<robot name="arm">
  <link name="base_link"><visual><origin xyz="0.3 0 0.1"/><geometry><box size="0.3 0.3 0.2"/></geometry></visual></link>
  <joint name="shoulder" type="continuous"><parent link="base_link"/><child link="upper"/>
    <origin xyz="0.6 0 0.3"/><axis xyz="0 0 1"/></joint>
  <link name="upper"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.05" length="0.3"/></geometry></visual></link>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <link name="fore"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0.15 0 0" rpy="0.4 0 0"/><geometry><box size="0.3 0.08 0.06"/></geometry></visual>
    <visual><origin xyz="0.33 0 0"/><geometry><sphere radius="0.06"/></geometry></visual></link>
  <joint name="camera_joint" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 1.2" rpy="-2.3 0 -1.5707963267948966"/></joint>
  <link name="camera_optical_frame"/>
</robot>)";

// MuJoCo's rasterised depth against its own exact ray caster (analytic
// boxes, cylinders, spheres): checks the depth mapping, the camera pose and
// intrinsics, the row order and the tessellation, pixel by pixel.
TEST(DepthCamera, AgreesWithExactRayCasting) {
  SceneDescription scene = camera_scene();
  scene.urdf_path = write_scratch_file("arm.urdf", kPrimitivesArmUrdf);
  const auto model = build_sim_model(scene);
  Simulator sim(model);
  DepthCamera camera(model, 320, 240);
  const CameraIntrinsics& K = camera.intrinsics();
  DepthImage gl, ray(K.width, K.height);
  const mjtByte visual_only[mjNGROUP] = {0, 1, 0, 0, 0, 0};
  for (const auto& [shoulder, elbow] : {std::pair{0.0, 0.5}, {0.8, -0.4}, {-1.2, 1.3}}) {
    sim.set_joint_positions(Eigen::Vector2d(shoulder, elbow));
    camera.render(sim.data(), DepthContent::kRobot, gl);
    const Eigen::Isometry3d T_world_camera = sim.ground_truth().T_world_camera;
    for (int v = 0; v < K.height; ++v)
      for (int u = 0; u < K.width; ++u) {
        // Ray with unit optical z: MuJoCo's distance is then the planar depth.
        const Eigen::Vector3d d =
            T_world_camera.linear() *
            Eigen::Vector3d((u + 0.5 - K.cx) / K.fx, (v + 0.5 - K.cy) / K.fy, 1);
        int geom = -1;
        const double t = mj_ray(model->mj.get(), sim.data(), T_world_camera.translation().data(),
                                d.data(), visual_only, 1, -1, &geom);
        ray.at(u, v) = t > scene.near_m && t < scene.far_m ? float(t) : 0.f;
      }
    const DepthAgreement a = compare_depth(gl, ray, 2e-3);
    SCOPED_TRACE(a.summary());
    EXPECT_GT(a.pixels_both, 1500);  // the arm is in view
    EXPECT_GE(a.fraction_within(), 0.995);
    EXPECT_GE(a.silhouette_iou(), 0.995);
  }
}

TEST(DepthCamera, RobotOnlyLeavesSceneOut) {
  SceneDescription scene = camera_scene();
  scene.shapes.push_back(box({0.1, 0.4, 0.3}, at(1.5, 0, 1)));
  const auto model = build_sim_model(scene);
  Simulator sim(model);
  DepthCamera camera(model);
  DepthImage depth;
  camera.render(sim.data(), DepthContent::kRobot, depth);
  for (float z : depth.depth_m) ASSERT_EQ(z, 0.f);
  camera.render(sim.data(), DepthContent::kScene, depth);
  EXPECT_GT(depth.at(80, 60), 1.4f);
}

// The floor, drawn as a few large quads (sim_model.cc), against the closed
// form: from 1 m above it, looking along the floor, the ray through a pixel
// below the horizon meets it at planar depth 1 m / (its optical y), and the
// floor beyond the far plane is no return.
TEST(DepthCamera, FloorAgreesWithTheClosedForm) {
  SceneDescription scene = camera_scene();
  scene.floor = true;
  const auto model = build_sim_model(scene);
  Simulator sim(model);
  DepthCamera camera(model, 320, 240);
  DepthImage depth;
  camera.render(sim.data(), DepthContent::kScene, depth);
  const CameraIntrinsics& K = camera.intrinsics();
  const auto floor_depth_m = [&](double v) {
    const double down = (v + 0.5 - K.cy) / K.fy;  // optical y is world -z
    return down > 0 ? 1.0 / down : std::numeric_limits<double>::infinity();
  };
  long checked_floor = 0, checked_beyond = 0;
  for (int v = 0; v < depth.height; ++v) {
    // Rows within a pixel of the far plane's line may go either way.
    const double nearest_m = floor_depth_m(v + 1), furthest_m = floor_depth_m(v - 1);
    for (int u = 0; u < depth.width; ++u) {
      if (furthest_m < scene.far_m) {
        EXPECT_NEAR(depth.at(u, v), floor_depth_m(v), 1e-3) << "pixel " << u << ", " << v;
        ++checked_floor;
      } else if (nearest_m > scene.far_m) {
        EXPECT_EQ(depth.at(u, v), 0.f) << "pixel " << u << ", " << v;
        ++checked_beyond;
      }
    }
  }
  EXPECT_GT(checked_floor, 10000);
  EXPECT_GT(checked_beyond, 10000);
}

TEST(DepthCamera, OtherResolutionKeepsFieldOfView) {
  SceneDescription scene = camera_scene();
  scene.shapes.push_back(box({0.1, 0.4, 0.3}, at(1.5, 0, 1)));
  const auto model = build_sim_model(scene);
  Simulator sim(model);
  DepthCamera camera(model, 320, 240);
  EXPECT_NEAR(camera.intrinsics().fy, model->intrinsics().fy * 2, 1e-9);
  DepthImage depth;
  camera.render(sim.data(), DepthContent::kScene, depth);
  ASSERT_EQ(depth.width, 320);
  EXPECT_NEAR(depth.at(160, 120), 1.45, 1e-3);
}

TEST(DepthCamera, BufferConversionIsInverseOfPerspectiveDepth) {
  // OpenGL's depth for planar distance z: d = (1/near - 1/z) / (1/near - 1/far).
  const double near = 0.1, far = 10;
  for (double z : {0.1, 0.5, 1.0, 3.3, 9.9}) {
    const double d = (1 / near - 1 / z) / (1 / near - 1 / far);
    EXPECT_NEAR(depth_buffer_to_m(float(d), near, far), z, 1e-6 * z * z / near);
  }
  EXPECT_EQ(depth_buffer_to_m(1.f, near, far), 0.f);
}

}  // namespace
}  // namespace arttrack::sim
