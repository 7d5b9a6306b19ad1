// The cached hypothesis evaluator against brute force: every particle of
// real particle-filter runs on the project robot is also rendered from
// scratch and scored with the exact likelihood.
#include "arttrack/tracker/internal/hypothesis_evaluator.h"
#include "arttrack/tracker/internal/worker_pool.h"
#include "arttrack/tracker/units.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

#include "../dual_arm_home.h"

namespace arttrack {
namespace {

const RobotModel& robot() {
  static const RobotModel model =
      RobotModel::from_urdf_file(std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm.urdf");
  return model;
}

using test_support::dual_arm_home_pose;

// The home pose shared by the tests and benchmarks (dual_arm_home.h, read
// from models/scene_default.yaml) is the pose documented at the top of the
// URDF ("Home configuration (joint: degrees = radians):", written by
// models/generate_robot.py), every physical joint of it, within its limits.
TEST(DualArmHomePose, IsThePoseTheUrdfDocuments) {
  std::ifstream urdf(std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm.urdf");
  std::string line;
  while (std::getline(urdf, line) && line.find("Home configuration") == std::string::npos) {
  }
  std::map<std::string, double> documented;
  for (std::string name, equals; std::getline(urdf, line);) {
    std::istringstream fields(line);
    double deg = 0, rad = 0;
    if (!(fields >> name >> deg >> equals >> rad) || equals != "=") break;
    documented[name] = deg * kRadPerDeg;
  }
  EXPECT_EQ(test_support::dual_arm_home_rad(), documented);
  const RobotModel& model = robot();
  const Eigen::VectorXd home = dual_arm_home_pose(model);
  for (int j = 0; j < model.num_joints(); ++j) {
    if (model.is_virtual_joint(j)) continue;
    EXPECT_EQ(documented.count(model.joint_name(j)), 1u) << model.joint_name(j);
    EXPECT_GE(home[j], model.joint_lower(j)) << model.joint_name(j);
    EXPECT_LE(home[j], model.joint_upper(j)) << model.joint_name(j);
  }
}

const CameraIntrinsics kCamera80x60 = CameraIntrinsics::from_vertical_fov(80, 60, 45 * kRadPerDeg);

// What a camera sees: the robot a little away from the home pose and the
// camera a little off, a wall behind it, a box occluding part of one arm,
// some pixels without return.
DepthImage observation(const RobotModel& model) {
  Eigen::VectorXd q = dual_arm_home_pose(model);
  for (int j = 0; j < model.num_joints(); ++j)
    if (!model.is_virtual_joint(j)) q[j] += (j % 3 - 1) * 2 * kRadPerDeg;
  q[model.joint_index("camera_offset_x")] = 0.005;
  q[model.joint_index("camera_offset_pitch")] = 0.3 * kRadPerDeg;
  KinematicsState state(model);
  forward_kinematics(model, q, state);
  DepthRenderer renderer(model, kCamera80x60);
  DepthImage image;
  renderer.render(state, image);
  std::mt19937_64 rng(3);
  std::normal_distribution<float> noise(0.f, 0.003f);
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u) {
      float& z = image.at(u, v);
      z = z > 0 ? z + noise(rng) : 2.0f + 0.01f * v;
      if (u >= 20 && u < 30 && v >= 30 && v < 42) z = 0.45f;  // occluder
      if ((u * 7 + v * 13) % 31 == 0) z = 0;                  // no return
    }
  return image;
}

// One block per physical joint from the hand to the root (in the reverse
// of the model's depth-first order: right arm, head, left arm), then one per
// camera joint: the tracker's default.
std::vector<SamplingBlock> default_blocks(const RobotModel& model) {
  std::vector<SamplingBlock> blocks;
  const int n = model.num_joints();
  int n_phys = 0;
  while (n_phys < n && !model.is_virtual_joint(n_phys)) ++n_phys;
  for (int j = n_phys - 1; j >= 0; --j) blocks.push_back({model.joint_name(j), {j}});
  for (int j = n_phys; j < n; ++j) blocks.push_back({model.joint_name(j), {j}});
  return blocks;
}

// Hands the fast evaluator's values to the filter and checks each against
// the reference evaluator, within 3e-7 (DepthLikelihood::ratios' bound) per
// covered valid pixel of the particle's brute-force render.
class Comparing : public LogLikelihoodEvaluator {
 public:
  Comparing(HypothesisEvaluator& fast, HypothesisEvaluator& reference, const DepthImage& observed)
      : fast_(fast), reference_(reference), observed_(observed), renderer_(robot(), kCamera80x60) {}

  void evaluate(const ParticleBatch& batch, std::span<double> out, WorkerPool& pool) override {
    fast_.evaluate(batch, out, pool);
    std::vector<double> ref(out.size());
    reference_.evaluate(batch, ref, pool);
    for (int l = 0; l < batch.num_particles; ++l) {
      const auto x = batch.particle(l);
      const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
      forward_kinematics(robot(), q, state_);
      renderer_.render(state_, image_);
      int covered = 0;
      for (size_t i = 0; i < image_.depth_m.size(); ++i)
        covered += image_.depth_m[i] > 0 && observed_.depth_m[i] > 0;
      const double bound = 3e-7 * covered + 1e-9;
      EXPECT_NEAR(out[l], ref[l], bound) << "block " << batch.block << " particle " << l;
      worst_ = std::max(worst_, std::abs(out[l] - ref[l]) / bound);
      ++compared_;
    }
  }
  double worst_fraction_of_bound() const { return worst_; }
  int compared() const { return compared_; }

 private:
  HypothesisEvaluator &fast_, &reference_;
  const DepthImage& observed_;
  DepthRenderer renderer_;
  KinematicsState state_{robot()};
  DepthImage image_;
  double worst_ = 0;
  int compared_ = 0;
};

struct Prior {
  std::vector<double> mean, std;
};

Prior prior_around_home(const RobotModel& model, double arm_std) {
  Prior p;
  const Eigen::VectorXd home = dual_arm_home_pose(model);
  p.mean.assign(home.data(), home.data() + home.size());
  for (int j = 0; j < model.num_joints(); ++j) {
    const std::string& name = model.joint_name(j);
    const bool translation =
        name == "camera_offset_x" || name == "camera_offset_y" || name == "camera_offset_z";
    p.std.push_back(model.is_virtual_joint(j)    ? (translation ? 0.01 : 0.5 * kRadPerDeg)
                    : name.rfind("head", 0) == 0 ? 1 * kRadPerDeg
                                                 : arm_std);
  }
  return p;
}

// Runs the filter `runs` times with the cached evaluator, each particle
// checked against brute force.
// `held`: joints whose prior std is 0 (a search that holds them; their
// blocks change no particle).
void check_against_reference(const std::vector<SamplingBlock>& blocks, int particles, double max_kl,
                             int workers, int runs, const std::vector<std::string>& held = {}) {
  const RobotModel& model = robot();
  const DepthImage observed = observation(model);
  DepthModelParams params;
  DepthLikelihood likelihood(params);
  likelihood.set_observation(observed);
  HypothesisEvaluator fast(model, blocks),
      reference(model, blocks, HypothesisEvaluator::Mode::kReference);
  Comparing comparing(fast, reference, observed);
  CoordinateParticleFilterParams cpf_params;
  cpf_params.num_particles = particles;
  cpf_params.max_kl_divergence = max_kl;
  CoordinateParticleFilter cpf(model.num_joints(), blocks, cpf_params);
  WorkerPool pool(workers);
  std::mt19937_64 rng(11);
  Prior prior = prior_around_home(model, 3 * kRadPerDeg);
  for (const std::string& name : held) prior.std[std::size_t(model.joint_index(name))] = 0;
  for (int run = 0; run < runs; ++run) {
    fast.begin_run(kCamera80x60, likelihood, prior.mean);
    reference.begin_run(kCamera80x60, likelihood, prior.mean);
    cpf.run(prior.mean, prior.std, comparing, rng, pool);
    // The next run starts from this one's posterior (as the tracker's next image would).
    for (int j = 0; j < model.num_joints(); ++j) prior.mean[j] = cpf.mean()[j];
  }
  EXPECT_EQ(comparing.compared(), runs * particles * int(blocks.size()));
  int held_blocks = 0;  // every coordinate held
  for (const SamplingBlock& block : blocks) {
    bool all = true;
    for (int c : block.coordinates)
      all = all && std::find(held.begin(), held.end(), model.joint_name(c)) != held.end();
    held_blocks += all;
  }
  EXPECT_EQ(fast.stats().held_evaluations, (long long)(runs * particles * held_blocks));
  ::testing::Test::RecordProperty("worst_error_over_bound",
                                  std::to_string(comparing.worst_fraction_of_bound()));
  std::cout << "worst |fast - reference| / bound: " << comparing.worst_fraction_of_bound() << "\n";
}

TEST(HypothesisEvaluator, DefaultBlocksCacheTheArmsAndRenderTheCameraBlocksFully) {
  const RobotModel& model = robot();
  const std::vector<SamplingBlock> blocks = default_blocks(model);
  HypothesisEvaluator fast(model, blocks);
  for (int k = 0; k < int(blocks.size()); ++k) {
    const int j = blocks[k].coordinates[0];
    const bool moves_camera = model.is_virtual_joint(j) ||
                              model.joint_name(j) == "head_pan_joint" ||
                              model.joint_name(j) == "head_tilt_joint";
    EXPECT_EQ(fast.renders_fully(k), moves_camera) << blocks[k].name;
  }
  HypothesisEvaluator reference(model, blocks, HypothesisEvaluator::Mode::kReference);
  for (int k = 0; k < int(blocks.size()); ++k) EXPECT_TRUE(reference.renders_fully(k));
}

TEST(HypothesisEvaluator, DefaultBlocksMatchBruteForce) {
  check_against_reference(default_blocks(robot()), 12, 0.69314718055994531, 2, 3);
}

TEST(HypothesisEvaluator, ResamplingAfterEveryBlockMatchesBruteForce) {
  check_against_reference(default_blocks(robot()), 9, 0.0, 1, 2);
}

// Blocks in an order the cache is not made for: the camera first (then every
// link differs per particle), joints of both arms in one block, an arm from
// the root to the hand, some joints not sampled at all.
std::vector<SamplingBlock> unusual_blocks() {
  const RobotModel& model = robot();
  auto j = [&](const char* name) { return model.joint_index(name); };
  return {
      {"camera_xyz", {j("camera_offset_x"), j("camera_offset_y"), j("camera_offset_z")}},
      {"left_1", {j("left_arm_joint_1")}},
      {"left_4", {j("left_arm_joint_4")}},
      {"left_7", {j("left_arm_joint_7")}},
      {"both_wrists", {j("left_arm_joint_6"), j("right_arm_joint_6")}},
      {"right_2", {j("right_arm_joint_2")}},
      {"head_tilt", {j("head_tilt_joint")}},
      {"right_5", {j("right_arm_joint_5")}},
      {"left_2", {j("left_arm_joint_2")}},
  };
}

TEST(HypothesisEvaluator, UnusualBlockOrdersMatchBruteForce) {
  const std::vector<SamplingBlock> blocks = unusual_blocks();
  check_against_reference(blocks, 10, 0.69314718055994531, 2, 2);
  check_against_reference(blocks, 7, 0.0, 2, 1);
}

// A search holds the rest of the robot while it searches one hand
// (acquisition.h): held blocks, cached and full, among sampled ones, with
// and without resampling between them.
TEST(HypothesisEvaluator, HeldBlocksMatchBruteForce) {
  const std::vector<std::string> held = {"right_arm_joint_7", "right_arm_joint_3",
                                         "left_arm_joint_2", "camera_offset_x",
                                         "camera_offset_roll"};
  check_against_reference(default_blocks(robot()), 8, 0.69314718055994531, 2, 2, held);
  check_against_reference(default_blocks(robot()), 6, 0.0, 1, 1, held);
  // The first block held and rendered from scratch; a held block of two joints.
  check_against_reference(unusual_blocks(), 7, 0.69314718055994531, 2, 2,
                          {"camera_offset_x", "camera_offset_y", "camera_offset_z",
                           "left_arm_joint_6", "right_arm_joint_6"});
}

// Records the values the filter was given for each block.
class Recording : public LogLikelihoodEvaluator {
 public:
  explicit Recording(HypothesisEvaluator& inner) : inner_(inner) {}
  void evaluate(const ParticleBatch& batch, std::span<double> out, WorkerPool& pool) override {
    inner_.evaluate(batch, out, pool);
    values[batch.block].assign(out.begin(), out.end());
    particles[batch.block].clear();
    for (int l = 0; l < batch.num_particles; ++l)
      particles[batch.block].emplace_back(batch.particle(l).begin(), batch.particle(l).end());
  }
  std::map<int, std::vector<double>> values;
  std::map<int, std::vector<std::vector<double>>> particles;

 private:
  HypothesisEvaluator& inner_;
};

// A held block that renders from scratch (the camera's) draws nothing, yet
// gives each particle the very number drawing it would: an evaluator whose
// prior mean is elsewhere renders the particle's state and scores it.
TEST(HypothesisEvaluator, AHeldCameraBlockScoresAsRenderingWould) {
  const RobotModel& model = robot();
  const std::vector<SamplingBlock> blocks = default_blocks(model);
  DepthLikelihood likelihood{DepthModelParams{}};
  likelihood.set_observation(observation(model));
  Prior prior = prior_around_home(model, 3 * kRadPerDeg);
  // The first camera block: the blocks before it draw over the cache and
  // sum only the pixels they change.
  const int camera_x = model.joint_index("camera_offset_x");
  prior.std[std::size_t(camera_x)] = 0;
  HypothesisEvaluator fast(model, blocks);
  Recording recording(fast);
  CoordinateParticleFilterParams params;
  params.num_particles = 6;
  // No resampling: the particles stay apart, each with the score its cached
  // updates summed (which the rescoring must not keep).
  params.max_kl_divergence = 1e9;
  CoordinateParticleFilter cpf(model.num_joints(), blocks, params);
  WorkerPool pool(2);
  std::mt19937_64 rng(7);
  fast.begin_run(kCamera80x60, likelihood, prior.mean);
  cpf.run(prior.mean, prior.std, recording, rng, pool);
  int block = 0;
  while (blocks[std::size_t(block)].coordinates[0] != camera_x) ++block;
  ASSERT_FALSE(fast.renders_fully(block - 1));
  ASSERT_TRUE(fast.renders_fully(block));
  EXPECT_EQ(fast.stats().held_evaluations, params.num_particles);
  for (int l = 0; l < params.num_particles; ++l) {
    const std::vector<double>& x = recording.particles[block][std::size_t(l)];
    EXPECT_EQ(x[std::size_t(camera_x)], prior.mean[std::size_t(camera_x)]);
    std::vector<double> elsewhere = x;
    elsewhere[std::size_t(camera_x)] += 1e-3;
    HypothesisEvaluator drawing(model, {blocks[std::size_t(block)]});
    drawing.begin_run(kCamera80x60, likelihood, elsewhere);
    const std::vector<int> parents = {0};
    ParticleBatch batch;
    batch.coordinates = blocks[std::size_t(block)].coordinates;
    batch.particles = x.data();
    batch.num_particles = 1;
    batch.dimension = model.num_joints();
    batch.parents = parents;
    std::vector<double> score(1);
    drawing.evaluate(batch, score, pool);
    EXPECT_EQ(drawing.stats().full_evaluations, 1);
    EXPECT_EQ(recording.values[block][std::size_t(l)], score[0]) << "particle " << l;
  }
}

// Per-particle work only: the numbers cannot depend on the number of workers.
TEST(HypothesisEvaluator, ResultsDoNotDependOnTheWorkers) {
  const RobotModel& model = robot();
  const std::vector<SamplingBlock> blocks = default_blocks(model);
  DepthLikelihood likelihood{DepthModelParams{}};
  likelihood.set_observation(observation(model));
  const Prior prior = prior_around_home(model, 3 * kRadPerDeg);
  std::vector<std::vector<double>> means;
  for (int workers : {1, 2, 3}) {
    HypothesisEvaluator fast(model, blocks);
    CoordinateParticleFilterParams params;
    params.num_particles = 10;
    CoordinateParticleFilter cpf(model.num_joints(), blocks, params);
    WorkerPool pool(workers);
    std::mt19937_64 rng(5);
    for (int run = 0; run < 2; ++run) {
      fast.begin_run(kCamera80x60, likelihood, prior.mean);
      cpf.run(prior.mean, prior.std, fast, rng, pool);
    }
    means.emplace_back(cpf.mean().begin(), cpf.mean().end());
    EXPECT_GT(fast.stats().cached_evaluations, 0);
    EXPECT_GT(fast.stats().full_evaluations, 0);
  }
  EXPECT_EQ(means[0], means[1]);
  EXPECT_EQ(means[0], means[2]);
}

}  // namespace
}  // namespace arttrack
