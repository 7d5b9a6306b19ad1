// Public preconditions on argument sizes hold in Release builds too (CI
// builds with NDEBUG): a wrong size is std::invalid_argument naming the
// function, never an out-of-bounds read or write.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/internal/belief_buffer.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {
namespace {

// The message of the std::invalid_argument f() throws, "" if none.
template <class F>
std::string invalid_argument_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ArgumentChecks, ForwardKinematicsWantsOneValuePerJoint) {
  const RobotModel model =
      RobotModel::from_urdf_file(std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm.urdf");
  KinematicsState state(model);
  const Eigen::VectorXd short_q = Eigen::VectorXd::Zero(model.num_joints() - 1);
  EXPECT_NE(invalid_argument_of([&] {
              forward_kinematics(model, short_q, state);
            }).find("forward_kinematics: argument check failed: q.size() == model.num_joints()"),
            std::string::npos);
  EXPECT_EQ(invalid_argument_of([&] {
              forward_kinematics(model, Eigen::VectorXd::Zero(model.num_joints()), state);
            }),
            "");
}

TEST(ArgumentChecks, BeliefBufferWantsItsSizes) {
  BeliefBuffer buffer(2, 3, 10);
  const std::vector<double> measurement(1), state(3);
  EXPECT_NE(invalid_argument_of([&] { buffer.push(0, measurement, state); }).find("push"),
            std::string::npos);
  EXPECT_NE(invalid_argument_of([] { BeliefBuffer(2, 3, 0); }).find("capacity > 0"),
            std::string::npos);
}

TEST(ArgumentChecks, ImageSizes) {
  const DepthLikelihood likelihood{DepthModelParams{}};
  const DepthImage wrong(likelihood.width() + 1, likelihood.height());
  EXPECT_NE(invalid_argument_of([&] { likelihood.log_ratio(wrong); }).find("log_ratio"),
            std::string::npos);
  EXPECT_NE(
      invalid_argument_of([] { subsample_depth(DepthImage(4, 4), 0, 2); }).find("subsample_depth"),
      std::string::npos);
  // Into its own source: the pixels would be read after they were written.
  DepthImage image(4, 4);
  EXPECT_NE(
      invalid_argument_of([&] { subsample_depth(image, 2, 2, image); }).find("subsample_depth"),
      std::string::npos);
}

}  // namespace
}  // namespace arttrack
