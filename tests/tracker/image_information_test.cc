#include "arttrack/tracker/internal/image_information.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <numbers>
#include <random>

#include "../count_allocations.h"
#include "../scratch_dir.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/end_effector_fit.h"
#include "arttrack/tracker/internal/worker_pool.h"

namespace arttrack {
namespace {

// The robot `name` of `body` (links and joints from base_link) under a
// camera 1 m above base_link looking down its -z axis, with the six virtual
// camera joints.
RobotModel under_a_camera(const std::string& name, const std::string& body) {
  return RobotModel::from_urdf_string("<robot name=\"" + name + "\">" + body + R"(
  <link name="camera_optical_frame"/>
  <joint name="mount" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 1" rpy="3.141592653589793 0 0"/></joint>
</robot>)",
                                      ".");
}

// A flat plate facing the camera 1 m away.
RobotModel plate_model() {
  return under_a_camera("plate", R"(
  <link name="base_link"><visual><geometry><box size="0.6 0.45 0.02"/></geometry></visual></link>)");
}

struct PlateScene {
  RobotModel model = plate_model();
  CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4);
  DepthRenderer renderer{model, camera};
  DepthModelParams params;
  DepthLikelihood likelihood{params};
  int dof_z = model.joint_index("camera_offset_z");
  int dof_roll = model.joint_index("camera_offset_roll");

  // The plate rendered at configuration q.
  DepthImage render(const Eigen::VectorXd& q) {
    KinematicsState state(model);
    forward_kinematics(model, q, state);
    DepthImage image;
    renderer.render(state, image);
    return image;
  }

  // Observe the plate rendered at configuration q.
  void observe(const Eigen::VectorXd& q) { likelihood.set_observation(render(q)); }
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
  const DepthImage rendered = s.render(q0);
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

  // Residuals of one shape (a shared offset of a sigma and independent noise
  // of half a sigma: neighbour correlation 0.8), and the same a fifth as
  // large: the estimate's variance is s^2 / ess of the model's, so the
  // small ones are worth 25 times the pixels. (The residuals' size once
  // counted only above 1: exact depth, residuals a tenth of sigma, kept 1%
  // of its pixels and reported standard deviations ten times the errors.)
  DepthImage large = rendered, small = rendered;
  std::normal_distribution<float> unit(0.f, 1.f);
  const float sigma = float(s.params.noise_std_m);
  for (std::size_t i = 0; i < rendered.depth_m.size(); ++i) {
    if (!(rendered.depth_m[i] > 0)) continue;
    const float residual = sigma + 0.5f * sigma * unit(rng);
    large.depth_m[i] += residual;
    small.depth_m[i] += 0.2f * residual;
  }
  s.likelihood.set_observation(large);
  info.compute(s.renderer, at_q0, s.likelihood);
  const double large_fraction = info.effective_pixel_fraction();
  s.likelihood.set_observation(small);
  info.compute(s.renderer, at_q0, s.likelihood);
  EXPECT_NEAR(info.effective_pixel_fraction() / large_fraction, 25.0, 1.0);
  EXPECT_LT(info.effective_pixel_fraction(), 1.0);
}

// The residuals with the DOFs' fit taken out are the pixels' noise alone:
// independent noise of the model's sigma reads about 1; the estimate 4 mm
// off along the one DOF (the whole plate nearer) reads about 0 alone, and
// about 1 under that noise, where the fraction above, from the residuals
// before the fit, takes the offset for correlated noise.
TEST(ImageInformation, FittedResidualFactorSeesThePixelsNoiseNotTheEstimatesError) {
  PlateScene s;
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(s.model.num_joints());
  const DepthImage rendered = s.render(q0);
  ImageInformation info(std::vector<int>{s.dof_z}, {.fitted_residuals = true});
  ImageInformation without(std::vector<int>{s.dof_z});
  const std::span<const double> at_q0{q0.data(), std::size_t(q0.size())};
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, float(s.params.noise_std_m));
  auto observe = [&](float offset_m, bool noisy) {
    DepthImage observed = rendered;
    for (float& z : observed.depth_m)
      if (z > 0) z += offset_m + (noisy ? noise(rng) : 0.0f);
    s.likelihood.set_observation(observed);
    info.compute(s.renderer, at_q0, s.likelihood);
    without.compute(s.renderer, at_q0, s.likelihood);
    EXPECT_EQ(without.fitted_residual_factor(), 1.0);  // not asked for
    return info.fitted_residual_factor();
  };
  EXPECT_NEAR(observe(0.0f, true), 1.0, 0.15);
  EXPECT_LT(observe(0.004f, false), 1e-6);
  EXPECT_NEAR(observe(0.004f, true), 1.0, 0.15);
  EXPECT_LT(info.effective_pixel_fraction(), 0.5);
}

// A tilted board in front of the camera with a block fixed on it: two links,
// the block's shift moves it alone, the board's moves both.
RobotModel board_model() {
  return under_a_camera("board", R"(
  <link name="base_link"/>
  <link name="board"><visual><geometry><box size="0.5 0.4 0.04"/></geometry></visual></link>
  <link name="block"><visual><geometry><box size="0.12 0.1 0.08"/></geometry></visual></link>
  <joint name="board_mount" type="fixed"><parent link="base_link"/><child link="board"/>
    <origin xyz="0 0 0" rpy="0.5 0.35 0"/></joint>
  <joint name="block_mount" type="fixed"><parent link="board"/><child link="block"/>
    <origin xyz="0.08 -0.05 0.06" rpy="0 0 0.3"/></joint>)");
}

// The six virtual camera joints' indices.
std::vector<int> camera_offset_dofs(const RobotModel& model) {
  std::vector<int> dofs;
  for (const char* name : {"camera_offset_x", "camera_offset_y", "camera_offset_z",
                           "camera_offset_roll", "camera_offset_pitch", "camera_offset_yaw"})
    dofs.push_back(model.joint_index(name));
  return dofs;
}

// The board at q = 0, seen by an 80x60 camera.
struct BoardScene {
  RobotModel model = board_model();
  DepthRenderer renderer{model, CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4)};
  DepthModelParams params;
  DepthLikelihood likelihood{params};
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.num_joints());
  KinematicsState state = at(q0);
  ImageInformationParams with_shifts{.link_shifts = true};

  KinematicsState at(const Eigen::VectorXd& q) const {
    KinematicsState s(model);
    forward_kinematics(model, q, s);
    return s;
  }
};

// The camera's depth scale (params.depth_scale): against the image of a
// scene scaled for real, every return (1 + c) times the truth, the
// Gauss-Newton gradient at the truth is c times the scale's cross
// information (d r / d c = r at every used pixel); on the plate, where the
// camera's z moves every depth by -1, against the closed form -r I_zz.
TEST(ImageInformation, DepthScaleMatchesAScaledImage) {
  BoardScene b;
  DepthImage truth;
  b.renderer.render(b.state, truth);
  const double c = 0.002;  // 2 mm at 1 m, under a noise sigma: every pixel still explained
  DepthImage scaled = truth;
  for (float& z : scaled.depth_m) z *= float(1 + c);
  b.likelihood.set_observation(scaled);
  const std::vector<int> dofs{b.model.joint_index("camera_offset_z"),
                              b.model.joint_index("camera_offset_roll"),
                              b.model.joint_index("camera_offset_x")};
  ImageInformation info(dofs, {.depth_scale = true});
  info.compute(b.renderer, {b.q0.data(), std::size_t(b.q0.size())}, b.likelihood);
  ASSERT_GT(info.pixels_used(), 500);
  const Eigen::VectorXd& cross = info.depth_scale_cross_information();
  ASSERT_EQ(cross.size(), 3);
  EXPECT_GT(cross.norm(), 0.0);
  EXPECT_TRUE((c * cross).isApprox(info.gradient(), 1e-3)) << cross.transpose() << "\n"
                                                           << info.gradient().transpose();

  PlateScene s;
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(s.model.num_joints());
  s.observe(q0);
  ImageInformation plate(std::vector<int>{s.dof_z}, {.motion_field = true, .depth_scale = true});
  plate.compute(s.renderer, {q0.data(), std::size_t(q0.size())}, s.likelihood);
  const double plate_depth_m = 1 - 0.01;  // its near face
  EXPECT_NEAR(plate.depth_scale_cross_information()[0],
              -plate_depth_m * plate.motion_field_information()(0, 0),
              1e-3 * plate.motion_field_information()(0, 0));
  ImageInformation without(std::vector<int>{s.dof_z});
  without.compute(s.renderer, {q0.data(), std::size_t(q0.size())}, s.likelihood);
  EXPECT_EQ(without.depth_scale_cross_information().size(), 0);
}

// The link-shift derivatives from the rendered depth's slopes, against
// moving the block for real (its pose translated in camera axes, rendered,
// central differences) over the pixels that show the block's interior.
// The board's shift moves the block too: their shared block is exactly the
// block's own information.
TEST(ImageInformation, LinkShiftsMatchMovingTheLink) {
  BoardScene b;
  const RobotModel& model = b.model;
  DepthRenderer& renderer = b.renderer;
  DepthLikelihood& likelihood = b.likelihood;
  const DepthModelParams& params = b.params;
  const Eigen::VectorXd& q0 = b.q0;
  const KinematicsState& state = b.state;
  DepthImage truth;
  renderer.render(state, truth);
  likelihood.set_observation(truth);

  ImageInformation info(std::vector<int>{model.joint_index("camera_offset_z")}, b.with_shifts);
  info.compute(renderer, {q0.data(), std::size_t(q0.size())}, likelihood);
  const std::vector<int>& links = info.shift_links();
  const int board =
      int(std::find(links.begin(), links.end(), model.link_index("board")) - links.begin());
  const int block =
      int(std::find(links.begin(), links.end(), model.link_index("block")) - links.begin());
  ASSERT_EQ(links.size(), 2u);
  const Eigen::MatrixXd& I = info.shift_information();
  const Eigen::Matrix3d shared = I.block(3 * board, 3 * block, 3, 3);
  EXPECT_TRUE(shared.isApprox(I.block(3 * block, 3 * block, 3, 3)));

  // Brute force for the block: its pixels, from a render of the block alone.
  const int block_link = model.link_index("block");
  LinkSet alone(std::size_t(model.num_links()), false);
  alone[std::size_t(block_link)] = true;
  DepthImage block_only, plus, minus;
  renderer.render_links(state, alone, block_only);
  const Eigen::Isometry3d T_root_camera = state.T_root_link[std::size_t(model.camera_link())];
  const double h = 1e-3, sigma = params.noise_std_m;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(80 * 60, 3);
  std::vector<char> interior(80 * 60, 1);
  for (int a = 0; a < 3; ++a) {
    for (const double sign : {1.0, -1.0}) {
      KinematicsState moved = state;
      moved.T_root_link[std::size_t(block_link)].translation() +=
          T_root_camera.linear() * (sign * h * Eigen::Vector3d::Unit(a));
      renderer.render(moved, sign > 0 ? plus : minus);
    }
    for (int p = 0; p < 80 * 60; ++p) {
      const float r = truth.depth_m[std::size_t(p)];
      const bool shows_block = r > 0 && block_only.depth_m[std::size_t(p)] == r;
      const float rp = plus.depth_m[std::size_t(p)], rm = minus.depth_m[std::size_t(p)];
      // Interior: the pixel and its four neighbours show the block, and no
      // move takes it off the block's surface.
      bool inside = shows_block && std::abs(rp - r) < 5e-3 && std::abs(rm - r) < 5e-3;
      const int u = p % 80, v = p / 80;
      for (const auto& [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int uu = u + du, vv = v + dv;
        inside = inside && uu >= 0 && uu < 80 && vv >= 0 && vv < 60 &&
                 block_only.depth_m[std::size_t(vv * 80 + uu)] ==
                     truth.depth_m[std::size_t(vv * 80 + uu)];
      }
      interior[std::size_t(p)] &= inside;
      J(p, a) = (rp - rm) / (2 * h) / sigma;
    }
  }
  Eigen::Matrix3d brute = Eigen::Matrix3d::Zero();
  int pixels = 0;
  for (int p = 0; p < 80 * 60; ++p) {
    if (!interior[std::size_t(p)]) continue;
    brute += J.row(p).transpose() * J.row(p);
    ++pixels;
  }
  ASSERT_GT(pixels, 30);
  // The module also counts the block's border pixels (one-sided slopes):
  // compare per pixel, z and the lateral terms.
  const Eigen::Matrix3d module = I.block<3, 3>(3 * block, 3 * block);
  EXPECT_NEAR(module(2, 2) / module.trace(), brute(2, 2) / brute.trace(), 0.05);
  EXPECT_NEAR(module(0, 0) / module.trace(), brute(0, 0) / brute.trace(), 0.05);
  EXPECT_NEAR(module(0, 2) / module.trace(), brute(0, 2) / brute.trace(), 0.05);
}

// The model-error estimate: 0 when the links are the model's, about the
// block's real shift when the observed block sits 4 mm away from the model's.
TEST(ImageInformation, LinkShiftVarianceSeesAShiftedLink) {
  BoardScene b;
  const RobotModel& model = b.model;
  DepthRenderer& renderer = b.renderer;
  DepthLikelihood& likelihood = b.likelihood;
  const Eigen::VectorXd& q0 = b.q0;
  const KinematicsState& state = b.state;
  const std::vector<int> dofs = camera_offset_dofs(model);
  ImageInformation info(dofs, b.with_shifts);
  const std::span<const double> at_q0{q0.data(), std::size_t(q0.size())};

  DepthImage observed;
  renderer.render(state, observed);
  likelihood.set_observation(observed);
  info.compute(renderer, at_q0, likelihood);
  // Exact depth: every shift fits 0, so each square less its noise is at
  // most 0 (the estimate is unbiased; the tracker clips its average).
  EXPECT_LE(info.link_shift_variance_m2(), 0.0);

  KinematicsState real = state;  // the real block 4 mm nearer the camera
  const int block_link = model.link_index("block");
  real.T_root_link[std::size_t(block_link)].translation() +=
      state.T_root_link[std::size_t(model.camera_link())].linear() * Eigen::Vector3d(0, 0, -0.004);
  renderer.render(real, observed);
  likelihood.set_observation(observed);
  info.compute(renderer, at_q0, likelihood);
  // One shift of 4 mm among the 3 to 6 the image pins (the board's are
  // mostly the camera's): a variance of 16 mm^2 over that many.
  std::vector<char> pinned;
  const double sd = std::sqrt(info.link_shift_variance_m2(&pinned));
  EXPECT_GT(sd, 0.004 / std::sqrt(6.0) * 0.8);
  EXPECT_LT(sd, 0.004 * 1.2);
  // The flags name the shifts counted: 3 per link, the pinned ones 3 to 6.
  ASSERT_EQ(pinned.size(), 3 * info.shift_links().size());
  const long count = std::count(pinned.begin(), pinned.end(), 1);
  EXPECT_GE(count, 3);
  EXPECT_LE(count, 6);
  // The normal equations the fit solved (what LearnedLinkShifts sums):
  // the block's shift along the camera's z reads its 4 mm.
  ImageInformation::ProjectedShiftEquations equations;
  info.link_shift_variance_m2(nullptr, nullptr, &equations);
  EXPECT_GE(equations.noise_var, 1.0);
  const auto& with_geometry = info.shift_links();
  const int block_z = 3 * int(std::find(with_geometry.begin(), with_geometry.end(), block_link) -
                              with_geometry.begin()) +
                      2;
  const auto it = std::find(equations.columns.begin(), equations.columns.end(), block_z);
  ASSERT_NE(it, equations.columns.end());
  const Eigen::MatrixXd A =
      equations.A + 1e-9 * equations.A.diagonal().maxCoeff() *
                        Eigen::MatrixXd::Identity(equations.A.rows(), equations.A.cols());
  const Eigen::VectorXd fit_m = A.ldlt().solve(equations.b);
  EXPECT_NEAR(fit_m[it - equations.columns.begin()], -0.004, 0.001);
}

// A block hung from a bracket `bracket_x_m` to the side of it (the camera
// sees about 0.4 m either side of the block at 1 m).
RobotModel block_on_a_bracket(double bracket_x_m) {
  const std::string x = std::to_string(bracket_x_m);
  return under_a_camera("bracket", R"(
  <link name="base_link"/>
  <link name="bracket"><visual><geometry><box size="0.1 0.1 0.04"/></geometry></visual></link>
  <link name="block"><visual><geometry><box size="0.12 0.1 0.08"/></geometry></visual></link>
  <joint name="bracket_mount" type="fixed"><parent link="base_link"/><child link="bracket"/>
    <origin xyz=")" + x + R"( 0 0" rpy="0 0 0"/></joint>
  <joint name="block_mount" type="fixed"><parent link="bracket"/><child link="block"/>
    <origin xyz=")" + std::to_string(-bracket_x_m) +
                                       R"( 0 0.06" rpy="0.3 0.2 0.3"/></joint>)");
}

// A shift moves its link and every link below it, so a bracket out of view
// moves exactly the block's pixels: the two shifts are one, and only the
// block's columns stay. In view, the bracket's are its own.
TEST(ImageInformation, ShiftsThatMoveTheSamePixelsAreOne) {
  for (const double bracket_x_m : {3.0, 0.2}) {
    const RobotModel model = block_on_a_bracket(bracket_x_m);
    DepthRenderer renderer(model,
                           CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4));
    DepthLikelihood likelihood{DepthModelParams{}};
    const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.num_joints());
    KinematicsState state(model);
    forward_kinematics(model, q0, state);
    DepthImage observed;
    renderer.render(state, observed);
    likelihood.set_observation(observed);
    ImageInformation info(camera_offset_dofs(model), {.link_shifts = true});
    info.compute(renderer, {q0.data(), std::size_t(q0.size())}, likelihood);
    const std::vector<int>& links = info.shift_links();
    ASSERT_EQ(links.size(), 2u);
    const int bracket =
        int(std::find(links.begin(), links.end(), model.link_index("bracket")) - links.begin());
    const int block = 1 - bracket;
    const Eigen::MatrixXd& I = info.shift_information();
    const Eigen::MatrixXd& cross = info.motion_field_shift_cross_information();
    EXPECT_GT((I.block<3, 3>(3 * block, 3 * block).trace()), 0.0);
    EXPECT_GT(cross.middleCols<3>(3 * block).norm(), 0.0);
    const bool hidden = bracket_x_m > 1;
    EXPECT_EQ(I.middleRows<3>(3 * bracket).norm() == 0, hidden) << bracket_x_m;
    EXPECT_EQ(cross.middleCols<3>(3 * bracket).norm() == 0, hidden) << bracket_x_m;
    EXPECT_EQ(info.shift_cross_information().middleCols<3>(3 * bracket).norm() == 0, hidden);
    std::vector<char> pinned;
    info.link_shift_variance_m2(&pinned);
    if (hidden) {
      EXPECT_EQ(std::count(pinned.begin() + 3 * bracket, pinned.begin() + 3 * bracket + 3, 1), 0);
    }
  }
}

// The board with a round post on it instead of the block (a cylinder,
// drawn exactly), `post_scale` times the model's size about its centre,
// its radius `thicker_m` more.
RobotModel board_with_post(double post_scale, double thicker_m = 0) {
  return under_a_camera("board", R"(
  <link name="base_link"/>
  <link name="board"><visual><geometry><box size="0.5 0.4 0.04"/></geometry></visual></link>
  <link name="post"><visual><geometry><cylinder radius=")" +
                                     std::to_string(0.06 * post_scale + thicker_m) +
                                     "\" length=\"" + std::to_string(0.1 * post_scale) +
                                     R"("/></geometry></visual></link>
  <joint name="board_mount" type="fixed"><parent link="base_link"/><child link="board"/>
    <origin xyz="0 0 0" rpy="0.5 0.35 0"/></joint>
  <joint name="post_mount" type="fixed"><parent link="board"/><child link="post"/>
    <origin xyz="0.08 -0.05 0.07" rpy="0 0 0.3"/></joint>)");
}

// The board with the model's post under the camera, and what the camera
// sees of a real post `post_scale` times the model's, its radius
// `thicker_m` more, `nearer_m` nearer the camera: `info` computed on it.
struct PostScene {
  const RobotModel model = board_with_post(1.0);
  DepthRenderer renderer{model, CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4)};
  DepthLikelihood likelihood{DepthModelParams{}};
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.num_joints());

  void observe(ImageInformation& info, double post_scale, double thicker_m, double nearer_m) {
    const RobotModel real = board_with_post(post_scale, thicker_m);
    KinematicsState state(real);
    forward_kinematics(real, q0, state);
    state.T_root_link[std::size_t(real.link_index("post"))].translation() +=
        state.T_root_link[std::size_t(real.camera_link())].linear() *
        Eigen::Vector3d(0, 0, -nearer_m);
    DepthRenderer real_renderer(real, renderer.camera());
    DepthImage observed;
    real_renderer.render(state, observed);
    likelihood.set_observation(observed);
    info.compute(renderer, {q0.data(), std::size_t(q0.size())}, likelihood);
  }
};

// Link scales: the real post 3% larger about its frame's origin (its
// centre: 1.8 mm more radius, its cap 1.5 mm higher) reads as a scale of
// about 0.03 on the post (0.0196 at 2%, 0.039 at 5%: the first-order fit
// under-reads as the steep pixels near the silhouette leave the inliers),
// and the board about 0. A post that is the model's reads 0, and so does
// one 4 mm nearer the camera (a shift, not a size). A box's scale cannot
// be told from a shift where three faces show (each face's offset along
// its normal is a shift's), so the test's link is round.
TEST(ImageInformation, LinkScaleSeesALargerLink) {
  PostScene scene;
  const RobotModel& model = scene.model;
  ImageInformation info(camera_offset_dofs(model), {.link_shifts = true});
  const auto& with_geometry = info.shift_links();
  auto index_of = [&](const char* link) {
    return std::size_t(
        std::find(with_geometry.begin(), with_geometry.end(), model.link_index(link)) -
        with_geometry.begin());
  };
  auto scales_seen = [&](double post_scale, double post_nearer_m) {
    scene.observe(info, post_scale, 0.0, post_nearer_m);
    std::vector<ImageInformation::LinkScaleFit> scales;
    info.link_shift_variance_m2(nullptr, nullptr, nullptr, &scales);
    return scales;
  };
  const auto larger = scales_seen(1.03, 0.0);
  ASSERT_EQ(larger.size(), with_geometry.size());
  const ImageInformation::LinkScaleFit post = larger[index_of("post")];
  ASSERT_FALSE(std::isnan(post.scale));
  EXPECT_NEAR(post.scale, 0.03, 0.005);
  // One image's noise at the likelihood's sigma (3 mm), as a fraction.
  EXPECT_GT(post.noise_var, 0.0);
  EXPECT_LT(std::sqrt(post.noise_var), 0.03);
  const ImageInformation::LinkScaleFit board = larger[index_of("board")];
  if (!std::isnan(board.scale)) {
    EXPECT_NEAR(board.scale, 0.0, 0.005);
  }
  EXPECT_NEAR(scales_seen(1.0, 0.0)[index_of("post")].scale, 0.0, 1e-3);
  EXPECT_NEAR(scales_seen(1.0, 0.004)[index_of("post")].scale, 0.0, 0.002);
}

// A rigid fit's scale columns (RigidFit::scale_cross): the real post 3%
// larger about its centre moves the post's rigid fit, and 0.03 times the
// fit's response to the post's scale predicts where it moves a point 8 cm
// above the post's centre (the translation and the turn both count; the
// same first-order fit, so to a few percent). The board's fit takes both
// links' columns (the post is below it), the post's only its own. The
// predicted shift's outer product is scale_shift_m2()'s.
TEST(ImageInformation, RigidFitScaleColumnsPredictTheFitOfALargerLink) {
  PostScene scene;
  const RobotModel& model = scene.model;
  const int post_link = model.link_index("post"), board_link = model.link_index("board");
  ImageInformation info(camera_offset_dofs(model));
  info.set_rigid_fit_links(model, {post_link, board_link});
  scene.observe(info, 1.03, 0.0, 0.0);
  const auto& with_geometry = info.shift_links();
  const int post =
      int(std::find(with_geometry.begin(), with_geometry.end(), post_link) - with_geometry.begin());
  const int board = 1 - post;
  const ImageInformation::RigidFit& fit = info.rigid_fits()[0];
  ASSERT_EQ(fit.scale_links, std::vector<int>{post});
  ASSERT_EQ(fit.scale_cross.cols(), 1);
  std::vector<int> board_subtree = info.rigid_fits()[1].scale_links;
  std::sort(board_subtree.begin(), board_subtree.end());
  EXPECT_EQ(board_subtree, (std::vector<int>{std::min(post, board), std::max(post, board)}));
  ASSERT_GT(fit.pixels, 50);
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> normal(fit.information);
  const Eigen::Matrix<double, 6, 1> fitted = normal.solve(fit.gradient);
  const Eigen::Matrix<double, 6, 1> predicted = 0.03 * normal.solve(fit.scale_cross.col(0));
  KinematicsState state(model);
  forward_kinematics(model, scene.q0, state);
  const Eigen::Isometry3d T_camera_post = T_camera_link(model, state, post_link);
  const Eigen::Vector3d point_m = T_camera_post * Eigen::Vector3d(0, 0, 0.08);
  auto shift_at = [&](const Eigen::Matrix<double, 6, 1>& x) {
    return Eigen::Vector3d(x.head<3>() + x.tail<3>().cross(point_m - fit.origin_m));
  };
  const Eigen::Vector3d fitted_m = shift_at(fitted), predicted_m = shift_at(predicted);
  EXPECT_GT(fitted_m.norm(), 0.001) << fitted_m.transpose();
  EXPECT_LT((fitted_m - predicted_m).norm(), 0.1 * fitted_m.norm())
      << fitted_m.transpose() << " / " << predicted_m.transpose();
  std::vector<double> scales(with_geometry.size(), std::numeric_limits<double>::quiet_NaN());
  scales[std::size_t(post)] = 0.03;
  const Eigen::Matrix3d expected_m2 = predicted_m * predicted_m.transpose();
  EXPECT_LT((scale_shift_m2(fit, scales, point_m) - expected_m2).norm(), 1e-9 * expected_m2.norm());
  scales[std::size_t(post)] = std::numeric_limits<double>::quiet_NaN();  // not learned: none
  EXPECT_EQ(scale_shift_m2(fit, scales, point_m).norm(), 0.0);
}

// Link bulges: the real post's radius 3 mm more than the model's reads as
// its bulge (2.2 mm: one image's noise variance at the likelihood's 3 mm
// is taken off, and the steepest pixels leave the inliers) and no longer
// as its shifts (0; without the bulge beside them its shifts read 2.8
// mm). A post 4 mm nearer the camera is a shift (2.9 mm; 3.5 without the
// bulge), not a bulge (0). The board is a box, whose faces' bulge is a
// shift of it: it has none. The same with the curved pixels found by the
// motion field or looked up.
TEST(ImageInformation, LinkBulgeSeesAThickerRoundLink) {
  PostScene scene;
  for (const bool motion_field : {false, true}) {
    SCOPED_TRACE(motion_field ? "motion field" : "looked up");
    ImageInformation info(camera_offset_dofs(scene.model),
                          {.link_shifts = true, .motion_field = motion_field});
    struct Seen {
      std::vector<double> bulge_square_m2, column_square_m2;
    };
    auto seen = [&](double thicker_m, double post_nearer_m) {
      scene.observe(info, 1.0, thicker_m, post_nearer_m);
      Seen s;
      info.link_shift_variance_m2(nullptr, &s.column_square_m2, nullptr, nullptr,
                                  &s.bulge_square_m2);
      return s;
    };
    const Seen thicker = seen(0.003, 0.0);
    const auto& with_geometry = info.shift_links();  // after the first compute()
    ASSERT_EQ(with_geometry.size(), 2u);
    const std::size_t post = std::size_t(
        std::find(with_geometry.begin(), with_geometry.end(), scene.model.link_index("post")) -
        with_geometry.begin());
    const std::size_t board = 1 - post;
    auto post_shift_m = [&](const Seen& s) {
      double square_m2 = 0;
      for (std::size_t a = 0; a < 3; ++a) square_m2 += s.column_square_m2[3 * post + a];
      return std::sqrt(std::max(0.0, square_m2));
    };
    ASSERT_EQ(thicker.bulge_square_m2.size(), with_geometry.size());
    EXPECT_TRUE(std::isnan(thicker.bulge_square_m2[board]));
    ASSERT_FALSE(std::isnan(thicker.bulge_square_m2[post]));
    const double bulge_m = std::sqrt(std::max(0.0, thicker.bulge_square_m2[post]));
    EXPECT_GT(bulge_m, 0.0018);
    EXPECT_LT(bulge_m, 0.0033);
    EXPECT_LT(post_shift_m(thicker), 0.001);
    const Seen nearer = seen(0.0, 0.004);
    EXPECT_GT(post_shift_m(nearer), 0.0025);
    EXPECT_LT(post_shift_m(nearer), 0.0045);
    EXPECT_LT(std::sqrt(std::max(0.0, nearer.bulge_square_m2[post])), 0.001);
    const Seen exact = seen(0.0, 0.0);
    EXPECT_LT(std::sqrt(std::max(0.0, exact.bulge_square_m2[post])), 1e-4);
  }
}

// The model-error fits run once per image on the image thread (the
// reported covariance's link_shift_variance_m2() with every output), so
// once sized they allocate nothing: an image that shows the same links as
// the last takes the same workspaces.
TEST(ImageInformation, TheModelErrorFitsAllocateNothingOnceSized) {
  PostScene scene;
  ImageInformation info(camera_offset_dofs(scene.model),
                        {.link_shifts = true, .motion_field = true});
  info.set_rigid_fit_links(scene.model,
                           {scene.model.link_index("post"), scene.model.link_index("board")});
  scene.observe(info, 1.0, 0.003, 0.0);  // a thicker post: shifts, a bulge and scales to fit
  std::vector<char> pinned;
  std::vector<double> column_square_m2, bulge_square_m2;
  ImageInformation::ProjectedShiftEquations equations;
  std::vector<ImageInformation::LinkScaleFit> scales;
  const std::span<const double> at_q0{scene.q0.data(), std::size_t(scene.q0.size())};
  long in_compute = 0, in_fits = 0;
  auto image = [&] {
    const long start = g_allocations.load();
    info.compute(scene.renderer, at_q0, scene.likelihood);
    const long computed = g_allocations.load();
    const double variance_m2 = info.link_shift_variance_m2(&pinned, &column_square_m2, &equations,
                                                           &scales, &bulge_square_m2);
    in_compute += computed - start;
    in_fits += g_allocations.load() - computed;
    return variance_m2;
  };
  const double first = image();
  ASSERT_FALSE(equations.columns.empty());
  ASSERT_TRUE(std::any_of(bulge_square_m2.begin(), bulge_square_m2.end(),
                          [](double b) { return !std::isnan(b); }));
  ASSERT_TRUE(
      std::any_of(scales.begin(), scales.end(),
                  [](const ImageInformation::LinkScaleFit& f) { return !std::isnan(f.scale); }));
  in_compute = in_fits = 0;
  for (int i = 0; i < 3; ++i) EXPECT_EQ(image(), first);
  EXPECT_EQ(in_compute, 0);
  EXPECT_EQ(in_fits, 0);
}

// White depth noise and links that are the model's: each image's estimate
// is noisy and unbiased, so its mean over many images is about 0. Clipped
// at 0 image by image, as the tracker did before stop 84, the mean kept the
// noise's positive half, read as model error (1.2 mm on realistic arm7's
// exact robot).
TEST(ImageInformation, LinkShiftVarianceIsUnbiasedUnderWhiteNoise) {
  BoardScene b;
  const std::vector<int> dofs = camera_offset_dofs(b.model);
  ImageInformation info(dofs, b.with_shifts);
  DepthImage truth, noisy;
  b.renderer.render(b.state, truth);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise_m(0, 0.004);  // over the likelihood's 3 mm
  const int images = 200;
  double sum = 0, sum_sq = 0, clipped_sum = 0;
  for (int i = 0; i < images; ++i) {
    noisy = truth;
    for (float& z : noisy.depth_m)
      if (z > 0) z += float(noise_m(rng));
    b.likelihood.set_observation(noisy);
    info.compute(b.renderer, {b.q0.data(), std::size_t(b.q0.size())}, b.likelihood);
    const double sample = info.link_shift_variance_m2();
    sum += sample;
    sum_sq += sample * sample;
    clipped_sum += std::max(0.0, sample);
  }
  const double mean = sum / images;
  const double sd = std::sqrt(std::max(0.0, sum_sq / images - mean * mean));
  ASSERT_GT(sd, 0.0);
  // Within 3 standard errors of 0, and well under the clipped mean.
  EXPECT_LT(std::abs(mean), 3 * sd / std::sqrt(double(images))) << mean << " sd " << sd;
  EXPECT_LT(std::abs(mean), 0.25 * clipped_sum / images)
      << mean << " clipped " << clipped_sum / images;
}

// A link whose every shift the camera's DOFs explain (the plate alone in
// view: moving it is moving the camera) leaves nothing for the shifts once
// the DOFs are projected out; rounding must not turn that into a model
// error. An indefinite projected matrix gave metres from one image
// (realistic arm7, the first image with the camera's broad prior).
TEST(ImageInformation, LinkShiftsTheDofsExplainGiveNoModelError) {
  PlateScene s;
  const std::vector<int> dofs = camera_offset_dofs(s.model);
  ImageInformationParams with_shifts;
  with_shifts.link_shifts = true;
  ImageInformation info(dofs, with_shifts);
  std::mt19937 rng(7);
  std::normal_distribution<double> offset(0, 0.003);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd observed_q = Eigen::VectorXd::Zero(s.model.num_joints());
    for (int dof : dofs) observed_q[dof] = offset(rng);
    s.observe(observed_q);
    const Eigen::VectorXd q = Eigen::VectorXd::Zero(s.model.num_joints());
    info.compute(s.renderer, {q.data(), std::size_t(q.size())}, s.likelihood);
    std::vector<char> pinned(1, 1);
    const double variance = info.link_shift_variance_m2(&pinned);
    EXPECT_TRUE(variance >= 0 && variance < 1e-6) << "trial " << trial << ": " << variance;
    // Nothing is pinned: the camera's DOFs absorb every shift.
    EXPECT_EQ(std::count(pinned.begin(), pinned.end(), 1), 0) << "trial " << trial;
    EXPECT_EQ(pinned.size(), 3 * info.shift_links().size());
  }
}

// A turntable under the camera, on the optical axis, carrying a tilted
// plate that fills the view, observed at its own configuration (turned 0.3).
struct TurntableScene {
  RobotModel model = under_a_camera("turntable", R"(
  <link name="base_link"/>
  <link name="table"><visual><origin xyz="0.06 0.03 0" rpy="0.4 0 0"/>
    <geometry><box size="3 3 0.02"/></geometry></visual></link>
  <joint name="turn" type="continuous"><parent link="base_link"/><child link="table"/>
    <axis xyz="0 0 1"/></joint>)");
  CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4);
  DepthRenderer renderer{model, camera};
  DepthModelParams params;
  DepthLikelihood likelihood{params};
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());

  TurntableScene() {
    q[model.joint_index("turn")] = 0.3;
    KinematicsState state(model);
    forward_kinematics(model, q, state);
    DepthImage observed;
    renderer.render(state, observed);
    likelihood.set_observation(observed);
  }
  std::span<const double> at_q() const { return {q.data(), std::size_t(q.size())}; }
  static ImageInformationParams field_params() {
    ImageInformationParams params;
    params.motion_field = true;
    return params;
  }
};

// A turntable under the camera, on the optical axis, carrying a tilted
// plate that fills the view. Turning the table and the camera the same way
// about the axis moves no surface relative to the camera: the motion field
// gives that combination no information, whatever it gives each DOF.
// (Central differences need not: a DOF's step can move an edge across a
// pixel centre, and the steps of DOFs whose motions cancel do not cancel;
// on an arm7 image they gave 696 per unit along such a motion, the renders'
// own change along it 7.) Each DOF alone, with no edge in view, the motion
// field agrees with the central differences.
TEST(ImageInformation, MotionFieldSeesNoInformationAlongAMotionThatMovesNoSurface) {
  TurntableScene s;
  ImageInformation info({s.model.joint_index("turn"), s.model.joint_index("camera_offset_yaw")},
                        s.field_params());
  info.compute(s.renderer, s.at_q(), s.likelihood);
  ASSERT_EQ(info.pixels_used(), 80 * 60);
  const Eigen::Matrix2d field = info.motion_field_information();
  const Eigen::Matrix2d central = info.information_matrix();
  ASSERT_GT(field(0, 0), 0);
  // The camera's yaw turns about the optical axis (root -z), the table about
  // root +z: (1, -1) turns both the same way, (1, 1) opposite ways.
  const Eigen::Vector2d same_way(1, -1), opposite(1, 1);
  EXPECT_LT(same_way.dot(field * same_way), 1e-9 * opposite.dot(field * opposite));
  EXPECT_NEAR(field(0, 0), central(0, 0), 0.2 * central(0, 0));
  EXPECT_NEAR(field(1, 1), central(1, 1), 0.2 * central(1, 1));
}

// The same turntable seen turned 5 mrad further than the estimate: the
// motion field's gradient points along turning the table alone, with no
// component along turning table and camera together, which moves no
// surface. Central differences' gradient need not: on arm7 images it had a
// small component along such a motion, of one sign image after image
// (docs/accuracy.md, stop 95).
TEST(ImageInformation, MotionFieldGradientHasNoComponentAlongAMotionThatMovesNoSurface) {
  TurntableScene s;
  const int turn = s.model.joint_index("turn");
  ImageInformation info({turn, s.model.joint_index("camera_offset_yaw")}, s.field_params());
  Eigen::VectorXd q = s.q;
  q[turn] -= 0.005;
  info.compute(s.renderer, {q.data(), std::size_t(q.size())}, s.likelihood);
  ASSERT_GT(info.pixels_used(), 80 * 60 / 2);
  const Eigen::Vector2d field = info.motion_field_gradient(), central = info.gradient();
  const Eigen::Vector2d same_way(1, -1), opposite(1, 1);
  ASSERT_GT(std::abs(opposite.dot(field)), 0);
  EXPECT_LT(std::abs(same_way.dot(field)), 1e-3 * std::abs(opposite.dot(field)));
  // With no edge in view each DOF's agrees with the central differences'.
  EXPECT_NEAR(field[0], central[0], 0.2 * std::abs(central[0]));
  EXPECT_NEAR(field[1], central[1], 0.2 * std::abs(central[1]));
  // Without the motion field it is the central differences'.
  ImageInformation plain({turn, s.model.joint_index("camera_offset_yaw")});
  plain.compute(s.renderer, {q.data(), std::size_t(q.size())}, s.likelihood);
  EXPECT_EQ(plain.motion_field_gradient(), plain.gradient());
}

// The motion field's and the central differences' information about
// `dofs` in an 80x60 image of `model` at q that shows exactly what the
// model renders there.
struct InformationSeen {
  Eigen::MatrixXd field, central;
  int pixels_used = 0;
};
InformationSeen information_seen_as_rendered(const RobotModel& model, const Eigen::VectorXd& q,
                                             const std::vector<int>& dofs) {
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4);
  DepthRenderer renderer(model, camera);
  DepthLikelihood likelihood(DepthModelParams{});
  KinematicsState state(model);
  forward_kinematics(model, q, state);
  DepthImage observed;
  renderer.render(state, observed);
  likelihood.set_observation(observed);
  ImageInformationParams field;
  field.motion_field = true;
  ImageInformation info(dofs, field);
  info.compute(renderer, {q.data(), std::size_t(q.size())}, likelihood);
  return {info.motion_field_information(), info.information_matrix(), info.pixels_used()};
}

// A cylinder turned about its own axis and a sphere about its centre move
// no surface: the renders do not change (the renderer draws them exactly),
// and the motion field gives no information about the turns. From the
// slopes between neighbouring pixels, chords of the curve, it gave some
// (up to a fifth of the shifts' per radian here): arm7's camera turned about
// its round base with the first joint turned back then seemed pinned, its
// standard deviation 5 mm where the estimate was 30 mm off (docs/accuracy.md,
// stop 44).
TEST(ImageInformation, MotionFieldSeesNoInformationInRoundShapesTurnedAboutThemselves) {
  const RobotModel model = under_a_camera("round", R"(
  <link name="base_link"/>
  <link name="roller"><visual><origin rpy="0 1.5707963267948966 0"/>
    <geometry><cylinder radius="0.08" length="0.5"/></geometry></visual></link>
  <joint name="spin" type="continuous"><parent link="base_link"/><child link="roller"/>
    <origin xyz="0 -0.15 0"/><axis xyz="1 0 0"/></joint>
  <link name="ball"><visual><geometry><sphere radius="0.1"/></geometry></visual></link>
  <joint name="roll_ball" type="continuous"><parent link="base_link"/><child link="ball"/>
    <origin xyz="0.05 0.2 0"/><axis xyz="1 1 0.5"/></joint>)");
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  q[model.joint_index("spin")] = 0.3;
  q[model.joint_index("roll_ball")] = -0.2;
  const InformationSeen seen =
      information_seen_as_rendered(model, q,
                                   {model.joint_index("spin"), model.joint_index("roll_ball"),
                                    model.joint_index("camera_offset_x")});
  ASSERT_GT(seen.pixels_used, 300);
  const Eigen::Matrix3d I = seen.field;
  const Eigen::Matrix3d central = seen.central;
  ASSERT_GT(I(2, 2), 1e3);
  EXPECT_EQ(central(0, 0), 0);  // the renders agree: nothing moved
  EXPECT_EQ(central(1, 1), 0);
  EXPECT_LT(I(0, 0), 1e-9 * I(2, 2));
  EXPECT_LT(I(1, 1), 1e-9 * I(2, 2));
  // The outlines' grazing pixels say nothing: the camera's shift gets about
  // half the central differences' information (47%; the chords gave 52%).
  EXPECT_GT(I(2, 2), 0.35 * central(2, 2));
  EXPECT_LT(I(2, 2), central(2, 2));
}

// A closed cylinder of `sides` flat facets along x (radius r, length l)
// as OBJ text: what a robot maker's mesh of a round part is.
std::string faceted_cylinder_obj(int sides, double r, double l) {
  std::string obj;
  char line[192];  // 12 ints of up to 11 characters and the format: no truncation
  for (int end = 0; end < 2; ++end)
    for (int k = 0; k < sides; ++k) {
      const double a = 2 * std::numbers::pi * k / sides;
      std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", (end - 0.5) * l, r * std::cos(a),
                    r * std::sin(a));
      obj += line;
    }
  std::snprintf(line, sizeof line, "v %.9g 0 0\nv %.9g 0 0\n", -0.5 * l, 0.5 * l);
  obj += line;
  const int first_centre = 2 * sides + 1;  // OBJ counts from 1
  for (int k = 0; k < sides; ++k) {
    const int a0 = k + 1, a1 = (k + 1) % sides + 1, b0 = a0 + sides, b1 = a1 + sides;
    std::snprintf(line, sizeof line, "f %d %d %d\nf %d %d %d\nf %d %d %d\nf %d %d %d\n", a0, a1, b1,
                  a0, b1, b0, first_centre, a1, a0, first_centre + 1, b0, b1);
    obj += line;
  }
  return obj;
}

// The same for a mesh: a faceted roller turned about its own axis moves
// its facets but not the round surface they stand for, and the motion field
// takes each pixel's depth change from the mesh's smooth normals
// (surface_normals.h). The renders at the turn's central differences see
// the facets move: 175 per rad^2 with 96 facets (5 mm each, a third of a
// pixel at 1 m), 2957 with 24, 5 with 400. The smooth normals give 1e-8 or
// less; slopes between pixels (chords of the curve) gave 2890 whatever the
// facets, and the facets' own normals about the central differences' (24
// facets: 3230).
TEST(ImageInformation, MotionFieldSeesLittleInformationInAFacetedRollerTurnedAboutItself) {
  const test_support::ScratchDir dir("image_information_test");
  dir.write("roller.obj", faceted_cylinder_obj(96, 0.08, 0.5));
  const RobotModel model = RobotModel::from_urdf_string(R"(<robot name="mesh_roller">
  <link name="base_link"/>
  <link name="roller"><visual><geometry><mesh filename="roller.obj"/></geometry></visual></link>
  <joint name="spin" type="continuous"><parent link="base_link"/><child link="roller"/>
    <origin xyz="0 -0.05 0"/><axis xyz="1 0 0"/></joint>
  <link name="camera_optical_frame"/>
  <joint name="mount" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 1" rpy="3.141592653589793 0 0"/></joint>
</robot>)",
                                                        dir.path().string());
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  q[model.joint_index("spin")] = 0.1;  // no facet faces the camera square on
  const InformationSeen seen = information_seen_as_rendered(
      model, q, {model.joint_index("spin"), model.joint_index("camera_offset_y")});
  ASSERT_GT(seen.pixels_used, 300);
  const Eigen::Matrix2d I = seen.field;
  ASSERT_GT(I(1, 1), 1e3);
  const Eigen::Matrix2d central = seen.central;  // the facets' own change
  ASSERT_GT(central(0, 0), 0);
  EXPECT_LT(I(0, 0), 1e-3 * central(0, 0));
  EXPECT_GT(I(1, 1), 0.5 * central(1, 1));
}

// The motion field is taken at q itself, whatever the central differences
// stepped last: listing the DOFs in another order permutes the matrix. (It
// once used the joints' axes with the last DOF still stepped by h; with a
// step of 0.1 rad in the camera's pitch the matrices differed by percents.)
TEST(ImageInformation, MotionFieldDoesNotDependOnTheOrderOfTheDofs) {
  TurntableScene s;
  const RobotModel& model = s.model;
  ImageInformationParams params = s.field_params();
  params.revolute_step_rad = 0.1;
  params.inlier_sigmas = 1e6;  // the big steps leave every pixel in
  const int turn = model.joint_index("turn"), yaw = model.joint_index("camera_offset_yaw"),
            pitch = model.joint_index("camera_offset_pitch");
  ImageInformation forward({turn, yaw, pitch}, params), backward({pitch, yaw, turn}, params);
  forward.compute(s.renderer, s.at_q(), s.likelihood);
  backward.compute(s.renderer, s.at_q(), s.likelihood);
  ASSERT_EQ(forward.pixels_used(), backward.pixels_used());
  ASSERT_GT(forward.pixels_used(), 0);
  const Eigen::Matrix3d a = forward.motion_field_information();
  const Eigen::Matrix3d b = backward.motion_field_information();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(a(i, j), b(2 - i, 2 - j), 1e-5 * a.diagonal().maxCoeff()) << i << ", " << j;
}

// A two-joint arm before a board: the shoulder moves both arm links, the
// elbow the forearm, the camera's DOFs everything.
RobotModel arm_before_a_board() {
  return under_a_camera("arm", R"(
  <link name="base_link"><visual><origin xyz="0 0 -0.1"/>
    <geometry><box size="0.7 0.5 0.02"/></geometry></visual></link>
  <link name="upper"><visual><origin xyz="0.09 0 0"/><geometry><box size="0.18 0.05 0.04"/>
    </geometry></visual></link>
  <link name="fore"><visual><origin xyz="0.07 0 0"/><geometry><box size="0.14 0.04 0.03"/>
    </geometry></visual></link>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="upper"/>
    <origin xyz="-0.1 0.02 0" rpy="0.3 0.2 0"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0.18 0 0" rpy="0 0 0.4"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>)");
}

// Brute force for the central differences: every step rendered in full,
// the pixel rules of the header (the robot at q explains the observed depth
// within 3 sigma; both steps cover the pixel and stay within 3 sigma of
// it), and the information summed over the pixels every DOF kept. The
// module draws only the links a DOF moves over the others' images, on any
// number of workers: the same matrix.
TEST(ImageInformation, PartialRendersOnWorkersGiveTheFullRendersMatrix) {
  const RobotModel model = arm_before_a_board();
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4);
  DepthRenderer renderer(model, camera);
  DepthModelParams params;
  DepthLikelihood likelihood(params);
  std::vector<int> dofs;
  for (const char* name : {"shoulder", "elbow", "camera_offset_x", "camera_offset_pitch"})
    dofs.push_back(model.joint_index(name));
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints()), seen = q;
  q[dofs[0]] = 0.2;
  q[dofs[1]] = -0.3;
  seen[dofs[0]] = 0.21;  // observed a little off: the residuals are not 0
  seen[dofs[1]] = -0.31;
  KinematicsState state(model);
  forward_kinematics(model, seen, state);
  DepthImage observed;
  renderer.render(state, observed);
  likelihood.set_observation(observed);

  const int num_pixels = 80 * 60;
  const ImageInformationParams steps;
  DepthImage base, plus, minus;
  forward_kinematics(model, q, state);
  renderer.render(state, base);
  std::vector<char> used(num_pixels, 0);
  for (int p = 0; p < num_pixels; ++p) {
    const double r = base.depth_m[std::size_t(p)], z = likelihood.observed_depth_m(p);
    used[std::size_t(p)] = r > 0 && z > 0 && std::abs(z - r) < 3 * likelihood.noise_std_at_m(z);
  }
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(num_pixels, int(dofs.size()));
  for (int k = 0; k < int(dofs.size()); ++k) {
    const double h = steps.revolute_step_rad;  // camera_offset_x is prismatic
    const double step =
        model.joint_type(dofs[k]) == JointType::kPrismatic ? steps.prismatic_step_m : h;
    for (const double sign : {1.0, -1.0}) {
      Eigen::VectorXd stepped = q;
      stepped[dofs[k]] += sign * step;
      forward_kinematics(model, stepped, state);
      renderer.render(state, sign > 0 ? plus : minus);
    }
    for (int p = 0; p < num_pixels; ++p) {
      const double r = base.depth_m[std::size_t(p)], rp = plus.depth_m[std::size_t(p)],
                   rm = minus.depth_m[std::size_t(p)];
      const double sigma = likelihood.noise_std_at_m(likelihood.observed_depth_m(p));
      if (!(rp > 0 && rm > 0) || std::abs(rp - r) > 3 * sigma || std::abs(rm - r) > 3 * sigma)
        used[std::size_t(p)] = 0;
      G(p, k) = (rp - rm) / (2 * step) / sigma;
    }
  }
  Eigen::MatrixXd brute = Eigen::MatrixXd::Zero(int(dofs.size()), int(dofs.size()));
  int pixels = 0;
  for (int p = 0; p < num_pixels; ++p) {
    if (!used[std::size_t(p)]) continue;
    brute += G.row(p).transpose() * G.row(p);
    ++pixels;
  }
  ASSERT_GT(pixels, 200);

  const std::span<const double> at_q{q.data(), std::size_t(q.size())};
  ImageInformation alone(dofs, {.link_shifts = true, .motion_field = true});
  alone.compute(renderer, at_q, likelihood);
  EXPECT_EQ(alone.pixels_used(), pixels);
  EXPECT_TRUE(alone.information_matrix().isApprox(brute, 1e-5))
      << alone.information_matrix() << "\n\n"
      << brute;
  for (const int workers : {2, 3}) {
    WorkerPool pool(workers);
    ImageInformation shared(dofs, {.link_shifts = true, .motion_field = true});
    shared.compute(renderer, at_q, likelihood, &pool);
    shared.compute(renderer, at_q, likelihood, &pool);  // again, on the kept workers
    EXPECT_EQ(shared.pixels_used(), alone.pixels_used()) << workers << " workers";
    EXPECT_EQ(shared.information_matrix(), alone.information_matrix()) << workers << " workers";
    EXPECT_EQ(shared.motion_field_information(), alone.motion_field_information());
    EXPECT_EQ(shared.gradient(), alone.gradient());
    EXPECT_EQ(shared.shift_information(), alone.shift_information());
  }
}

}  // namespace
}  // namespace arttrack
