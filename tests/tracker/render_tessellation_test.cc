// A coarser tessellation for the hypotheses: RobotModel::rebuilt keeps the
// kinematics and changes only the primitive meshes; the tracker's render
// section selects it.
#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "../error_of.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack/tracker/tracker_config_yaml.h"

namespace arttrack {
namespace {

using arttrack::test_support::tracker_config_error;

const std::string kUrdf = std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm.urdf";

long long triangles(const RobotModel& model) {
  long long n = 0;
  for (int l : model.links_with_geometry()) n += (long long)model.link(l).mesh.triangles.size();
  return n;
}

TEST(RenderTessellation, RebuiltModelHasTheSameKinematicsAndFewerTriangles) {
  const RobotModel fine = RobotModel::from_urdf_file(kUrdf);
  RobotModelOptions options = fine.options();
  EXPECT_EQ(options.cylinder_segments, RobotModelOptions{}.cylinder_segments);
  options.cylinder_segments = 12;
  options.sphere_segments = 8;
  const RobotModel coarse = fine.rebuilt(options);
  EXPECT_EQ(coarse.options().cylinder_segments, 12);
  EXPECT_EQ(coarse.source(), fine.source());
  ASSERT_EQ(coarse.num_links(), fine.num_links());
  EXPECT_EQ(coarse.joint_names(), fine.joint_names());
  EXPECT_EQ(coarse.camera_link(), fine.camera_link());
  EXPECT_LT(3 * triangles(coarse), triangles(fine));

  // Identical forward kinematics at an arbitrary configuration.
  Eigen::VectorXd q(fine.num_joints());
  for (int j = 0; j < q.size(); ++j) q[j] = 0.1 * (j % 5) - 0.2;
  KinematicsState a(fine), b(coarse);
  forward_kinematics(fine, q, a);
  forward_kinematics(coarse, q, b);
  for (int l = 0; l < fine.num_links(); ++l)
    EXPECT_TRUE(a.T_root_link[l].isApprox(b.T_root_link[l], 0)) << fine.link_name(l);

  // The same options give the same meshes.
  const RobotModel again = fine.rebuilt(fine.options());
  for (int l : fine.links_with_geometry())
    EXPECT_EQ(again.link(l).mesh.vertices_m, fine.link(l).mesh.vertices_m);
}

TEST(RenderTessellation, ConfigKeysAreReadAndChecked) {
  const TrackerConfig c = tracker_config_from_yaml(
      load_yaml_string("render: {cylinder_segments: 16, sphere_segments: 12}\n", "t.yaml"));
  EXPECT_EQ(c.render_cylinder_segments, 16);
  EXPECT_EQ(c.render_sphere_segments, 12);
  EXPECT_NE(
      tracker_config_error("render: {cylinder_segments: 2}\n").find("render.cylinder_segments"),
      std::string::npos);
  EXPECT_NE(tracker_config_error("render: {sphere_segments: 3}\n").find("render.sphere_segments"),
            std::string::npos);
  EXPECT_NE(tracker_config_error("render: {segments: 3}\n").find("segments"), std::string::npos);
}

// A tracker on the dual-arm robot with a coarse hypothesis model takes images
// and keeps the kinematic model's frames for its estimate.
TEST(RenderTessellation, TrackerRendersWithTheCoarseModel) {
  auto model = std::make_shared<const RobotModel>(RobotModel::from_urdf_file(kUrdf));
  TrackerConfig config;
  config.render_cylinder_segments = 8;
  config.render_sphere_segments = 6;
  config.particle_filter.num_particles = 3;
  config.threads = 1;
  std::vector<std::string> joints;
  for (int j = 0; j < model->num_joints(); ++j)
    if (!model->is_virtual_joint(j)) joints.push_back(model->joint_name(j));
  Tracker tracker(model, config, joints);
  const std::vector<double> q(joints.size(), 0.2);
  const CameraIntrinsics camera =
      CameraIntrinsics::from_vertical_fov(80, 60, 45 * std::numbers::pi / 180);
  tracker.add_joint_measurement(0.0, q);
  tracker.add_depth_image(0.0, DepthImage(80, 60, 1.5f), camera);
  EXPECT_EQ(tracker.stats().images_applied, 1);
  EXPECT_EQ(tracker.stats().last_evaluations_per_image, 3 * model->num_joints());
  EXPECT_EQ(&tracker.model(), model.get());
}

}  // namespace
}  // namespace arttrack
