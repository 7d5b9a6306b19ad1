#include "arttrack/tracker/image_information.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <numbers>
#include <random>

#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

// A flat plate facing a camera 1 m away, with the six virtual camera joints.
RobotModel plate_model() {
  const std::string urdf = R"(<robot name="plate">
  <link name="base_link"><visual><geometry><box size="0.6 0.45 0.02"/></geometry></visual></link>
  <link name="camera_optical_frame"/>
  <joint name="mount" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 1" rpy="3.141592653589793 0 0"/></joint>
</robot>)";
  return RobotModel::from_urdf_string(urdf, ".");
}

struct PlateScene {
  RobotModel model = plate_model();
  CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4);
  DepthRenderer renderer{model, camera};
  DepthModelParams params;
  DepthLikelihood likelihood{params};
  int dof_z = model.joint_index("camera_offset_z");
  int dof_roll = model.joint_index("camera_offset_roll");

  // Observe the plate rendered at configuration q.
  void observe(const Eigen::VectorXd& q) {
    KinematicsState state(model);
    forward_kinematics(model, q, state);
    DepthImage image;
    renderer.render(state, image);
    likelihood.set_observation(image);
  }
};

// Against a closed form: moving the camera along its optical axis changes the
// plate's depth by the same amount everywhere, so the information about z is
// the number of interior plate pixels over sigma^2, and the Gauss-Newton step
// from an offset configuration brings it back.
TEST(ImageInformation, MatchesTheClosedFormForADepthShift) {
  PlateScene s;
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(s.model.num_joints());
  s.observe(q0);
  ImageInformation info(std::vector<int>{s.dof_z, s.dof_roll});
  const Eigen::MatrixXd& I =
      info.compute(s.renderer, {q0.data(), std::size_t(q0.size())}, s.likelihood);
  const double sigma = s.params.noise_std_m;  // at any depth: no quadratic term
  ASSERT_GT(info.pixels_used(), 500);
  EXPECT_NEAR(I(0, 0), info.pixels_used() / (sigma * sigma), 1e-3 * I(0, 0));
  EXPECT_TRUE(I.isApprox(I.transpose()));
  EXPECT_NEAR(info.gradient().norm(), 0.0, 1e-6 * std::sqrt(I(0, 0)));  // at the truth

  Eigen::VectorXd q = q0;
  q[s.dof_z] = 0.004;  // 4 mm, about a noise sigma: every pixel still explained
  info.compute(s.renderer, {q.data(), std::size_t(q.size())}, s.likelihood);
  const Eigen::VectorXd step = info.information_matrix().ldlt().solve(info.gradient());
  EXPECT_NEAR(step[0], -0.004, 2e-4);
}

// Pixels the image does not explain (an occluder in front) say nothing.
TEST(ImageInformation, OccludedPixelsCarryNoInformation) {
  PlateScene s;
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(s.model.num_joints());
  s.observe(q0);
  ImageInformation info(std::vector<int>{s.dof_z});
  const double full =
      info.compute(s.renderer, {q0.data(), std::size_t(q0.size())}, s.likelihood)(0, 0);
  DepthImage occluded(80, 60, 0.3f);  // a wall 30 cm from the camera hides everything
  s.likelihood.set_observation(occluded);
  const double none =
      info.compute(s.renderer, {q0.data(), std::size_t(q0.size())}, s.likelihood)(0, 0);
  EXPECT_GT(full, 0.0);
  EXPECT_EQ(none, 0.0);
  EXPECT_EQ(info.pixels_used(), 0);
  EXPECT_THROW(info.compute(s.renderer, {q0.data(), 3}, s.likelihood), InputError);
}

// How many independent pixels an image is worth, against three cases with a
// known answer: residuals that are independent noise keep about all of them;
// one shared offset (the estimate off by 4 mm along the optical axis, every
// neighbour with the same residual) keeps next to none.
TEST(ImageInformation, EffectivePixelFractionFromTheResiduals) {
  PlateScene s;
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(s.model.num_joints());
  KinematicsState state(s.model);
  forward_kinematics(s.model, q0, state);
  DepthImage rendered;
  s.renderer.render(state, rendered);
  ImageInformation info(std::vector<int>{s.dof_z});
  const std::span<const double> at_q0{q0.data(), std::size_t(q0.size())};

  s.likelihood.set_observation(rendered);  // no residual at all
  info.compute(s.renderer, at_q0, s.likelihood);
  EXPECT_DOUBLE_EQ(info.effective_pixel_fraction(), 1.0);

  DepthImage noisy = rendered;  // independent noise of the model's sigma
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, float(s.params.noise_std_m));
  for (float& z : noisy.depth_m)
    if (z > 0) z += noise(rng);
  s.likelihood.set_observation(noisy);
  info.compute(s.renderer, at_q0, s.likelihood);
  EXPECT_GT(info.effective_pixel_fraction(), 0.8);

  DepthImage shifted = rendered;  // the same 4 mm everywhere
  for (float& z : shifted.depth_m)
    if (z > 0) z += 0.004f;
  s.likelihood.set_observation(shifted);
  info.compute(s.renderer, at_q0, s.likelihood);
  EXPECT_LT(info.effective_pixel_fraction(), 0.01);
}

}  // namespace
}  // namespace arttrack
