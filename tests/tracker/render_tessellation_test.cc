// The tessellation of URDF cylinders and spheres: RobotModel::rebuilt keeps
// the kinematics and changes only the primitive meshes. The tracker renders
// those shapes exactly (depth_renderer.h), so its configuration has no
// tessellation to choose.
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

// The render section that chose a coarser tessellation for the hypotheses
// is gone: a file that still has it is told so, not silently ignored.
TEST(RenderTessellation, RenderSectionIsAnError) {
  const std::string error = tracker_config_error("render: {cylinder_segments: 16}\n");
  EXPECT_NE(error.find("render"), std::string::npos) << error;
  EXPECT_NE(error.find("not a known key"), std::string::npos) << error;
}

}  // namespace
}  // namespace arttrack
