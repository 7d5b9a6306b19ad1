#include "arttrack/sim/scenario_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <memory>
#include <optional>
#include <random>
#include <thread>

#include "arttrack/sim/depth_camera.h"
#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/method_trackers.h"
#include "arttrack/sim/run_physics.h"
#include "arttrack/sim/sim_model.h"
#include "arttrack/sim/simulator.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack::sim {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Independent streams of one run: encoders, depth noise, frame timing, ...
enum Stream : std::uint64_t { kMotion = 1, kEncoders, kDepth, kFrames, kTracker, kModel };
std::uint64_t stream_seed(std::uint64_t run_seed, Stream s) { return splitmix64(run_seed + s); }

// The joint targets of the run with seed `seed` for the simulator's joints:
// the scenario's motion about the model's home configuration, within its
// limits.
JointTrajectory commanded_motion(const Scenario& sc, const SimModel& m, std::uint64_t seed) {
  std::vector<JointLimit> limits;
  std::vector<double> home;
  for (std::size_t i = 0; i < m.joint_names.size(); ++i) {
    limits.push_back({m.joint_lower[i], m.joint_upper[i]});
    home.push_back(m.initial_joints[i]);
  }
  std::mt19937_64 rng(stream_seed(seed, kMotion));
  return make_trajectory(sc, m.joint_names, limits, home, rng);
}

// Depth agreement below which a robot pixel of the full scene is the robot.
constexpr float kSameSurface_m = 2e-3f;

// (robot pixels hidden by something nearer) / (robot pixels); NaN if none.
// No return where the robot alone has one means something nearer than the
// near plane covers it.
double occluded_fraction(const DepthImage& robot, const DepthImage& scene) {
  std::size_t visible = 0, hidden = 0;
  for (std::size_t i = 0; i < robot.depth_m.size(); ++i) {
    const float r = robot.depth_m[i];
    if (r <= 0) continue;
    ++visible;
    const float z = scene.depth_m[i];
    if (z <= 0 || z < r - kSameSurface_m) ++hidden;
  }
  return visible ? double(hidden) / double(visible) : std::numeric_limits<double>::quiet_NaN();
}

// A captured frame on its way to the trackers.
struct InFlight {
  double stamp_s, arrival_s;
  DepthImage image;
};

// Real time (RunOptions::realtime): a run's measurements and truth, recorded
// by simulating the whole run first, then replayed at the wall clock's pace.
// The camera is then an outside device, as on a robot: the trackers do not
// share the cores with the simulator's physics and full-mesh rendering.
struct Recording {
  std::vector<double> readings_rad;  // per joint step, every simulated joint
  struct Delivery {
    long step;
    InFlight frame;
  };
  struct Scored {
    long step;
    TruthSample truth;
  };
  std::vector<Delivery> deliveries;  // in order
  std::vector<Scored> scored;        // in order
};

// What a Recording may hold, MB: a 640x480 camera at 30 Hz takes 37 MB a
// second (the shipped 60 s occlusion scenario 2.2 GB); a longer --realtime
// run is refused before it starts.
constexpr double kMaxRecording_MB = 4096;

// Everything fixed over the runs of a scenario.
struct Setup {
  SceneDescription scene;  // the simulator's: its URDF, its time step
  std::shared_ptr<const SimModel> sim_model;
  std::shared_ptr<const RobotModel> robot;  // nominal, with virtual camera joints
  std::vector<std::string> joint_names;     // tracker physical joints
  std::vector<int> sim_joint;               // per joint_names: SimModel index
  std::vector<int> sim_ee;                  // per scored end effector: GroundTruth index
  std::vector<TrackingMethod> methods;
};

Setup make_setup(const Scenario& sc, const std::vector<std::string>& method_names) {
  Setup s;
  for (const std::string& m : method_names) s.methods.push_back(parse_method(m, "run options"));

  // The tracker's nominal model.
  s.robot = std::make_shared<const RobotModel>(tracker_robot_model(sc.scene, sc.tracker_urdf()));

  // The simulator's perturbed model; physics steps divide the joint period.
  s.scene = run_scene(sc);
  s.sim_model = build_sim_model(s.scene, sc.perturbation);
  const SimModel& m = *s.sim_model;

  for (int j = 0; j < s.robot->num_joints(); ++j) {
    if (s.robot->is_virtual_joint(j)) continue;
    const int k = m.joint_index(s.robot->joint_name(j));
    if (k < 0)
      throw InputError(sc.source + ": joint '" + s.robot->joint_name(j) +
                       "' of the nominal robot is not driven in the simulator");
    s.joint_names.push_back(s.robot->joint_name(j));
    s.sim_joint.push_back(k);
  }
  for (const std::string& ee : sc.scoring.end_effectors) {
    const auto it = std::find(m.end_effector_names.begin(), m.end_effector_names.end(), ee);
    if (it == m.end_effector_names.end())
      throw InputError(sc.source + ": end effector '" + ee + "' is not simulated");
    s.sim_ee.push_back(int(it - m.end_effector_names.begin()));
  }
  return s;
}

class Run {
 public:
  Run(const Scenario& sc, const Setup& setup, Simulator& sim, DepthCamera& camera, int run,
      std::uint64_t seed, std::vector<MethodScores>& scores, const RunOptions& options,
      std::vector<KeptFrame>& frames)
      : sc_(sc),
        setup_(setup),
        sim_(sim),
        camera_(camera),
        options_(options),
        encoders_(setup.sim_model->joint_names, sc.encoders, stream_seed(seed, kEncoders)),
        depth_noise_(sc.depth_corruption, stream_seed(seed, kDepth)),
        physics_(sc, sim, commanded_motion(sc, *setup.sim_model, seed)),
        camera_poses_(setup.robot) {
    result_.run = run;
    result_.seed = seed;
    frames_timing_ = camera_frames(sc.camera_timing, sc.duration_s, stream_seed(seed, kFrames));
    const SimModel& m = *setup.sim_model;

    TrackingSetup tracking;
    tracking.robot = setup.robot;
    tracking.config = sc.tracker;
    tracking.config.source = sc.tracker_document.file;
    // The run's tracker stream; the configured particle_filter.seed picks
    // another one (1, the default, keeps it), so that a tracker seed set in
    // the scenario or its overrides changes the draws rather than being
    // silently replaced.
    tracking.config.seed = stream_seed(seed, kTracker) ^ (sc.tracker.seed - 1);
    tracking.config.asynchronous = options.realtime;
    tracking.methods = setup.methods;
    tracking.joint_names = m.joint_names;
    tracking.camera = reported_intrinsics(sc, camera_.intrinsics());
    const GroundTruth g0 = sim_.ground_truth();
    tracking.vision_only_start_rad.assign(g0.q.data(), g0.q.data() + g0.q.size());
    trackers_.emplace(tracking, result_, scores);
    if (options.sink)
      options.sink->begin_run({run, seed, stream_seed(seed, kTracker), m.joint_names,
                               tracking.camera, setup.joint_names, sc.scoring.end_effectors});
    if (run == 0) trackers_->keep_frames(options.frames_to_keep, sc.duration_s, frames);
  }

  RunResult execute() {
    const SimModel& m = *setup_.sim_model;
    const int n_sim = int(m.joint_names.size());
    const long steps = std::lround(sc_.duration_s * sc_.joint_rate_hz);
    const double period = physics_.joint_period_s();
    const long progress_every = std::max(1L, std::lround(sc_.joint_rate_hz));
    std::vector<double> readings(n_sim);
    std::size_t next_frame = 0;
    GroundTruth truth;
    DepthImage exact, robot_alone;
    if (options_.realtime) begin_recording(steps, n_sim);

    for (long n = 0; n <= steps; ++n) {
      const double t = double(n) * period;
      if (n > 0) physics_.advance_period();
      sim_.ground_truth(truth);

      // Encoders, then every method's joint update.
      encoders_.corrupt(
          t, n == 0 ? 0.0 : period, std::span<const double>(truth.q.data(), std::size_t(n_sim)),
          std::span<const double>(truth.actuator_torque.data(), std::size_t(n_sim)), readings);
      if (recording_)
        recording_->readings_rad.insert(recording_->readings_rad.end(), readings.begin(),
                                        readings.end());
      else
        joints(t, readings);

      // Camera captures at this step (the step nearest each capture time).
      bool frame_now = false;
      double occluded = std::numeric_limits<double>::quiet_NaN();
      while (next_frame < frames_timing_.size() &&
             frames_timing_[next_frame].stamp_s <= t + 0.5 * period) {
        const CameraFrame& f = frames_timing_[next_frame++];
        frame_now = true;
        ++result_.frames_captured;
        if (f.dropped) continue;
        physics_.place_occluders(t);
        camera_.render(sim_.data(), DepthContent::kScene, exact);
        if (!sc_.occluder_schedules.empty()) {
          // A second render, so only when something walks about.
          camera_.render(sim_.data(), DepthContent::kRobot, robot_alone);
          occluded = occluded_fraction(robot_alone, exact);
        }
        InFlight frame{t, t + (f.arrival_s - f.stamp_s), {}};
        depth_noise_.corrupt(exact, frame.image);
        if (options_.quantise_depth_mm) quantise_depth_mm(frame.image);
        in_flight_.push_back(std::move(frame));
      }

      // Deliveries: every frame that has arrived by now, in capture order.
      while (!in_flight_.empty() && in_flight_.front().arrival_s <= t + 1e-9) {
        if (recording_)
          recording_->deliveries.push_back({n, std::move(in_flight_.front())});
        else
          deliver(in_flight_.front(), t);
        in_flight_.pop_front();
      }

      const int every = sc_.scoring.every_n_joint_steps;
      if (frame_now || (every > 0 && n % every == 0)) {
        TruthSample sample = truth_sample(t, truth, frame_now, occluded);
        if (recording_)
          recording_->scored.push_back({n, std::move(sample)});
        else
          score(std::move(sample));
      }
      // Real time reports its progress as it replays.
      if (options_.progress && !recording_ && n % progress_every == 0 && n > 0)
        options_.progress({result_.run, 0, t, sc_.duration_s});
    }
    if (recording_) replay(steps, n_sim);
    trackers_->finish();
    for (std::size_t i = 0; i < result_.methods.size() && options_.realtime; ++i) {
      // End to end: from capture to delivery (the scenario's latency, and any
      // lag of the simulation behind the wall clock), then inside the tracker.
      const TrackerStats& st = result_.methods[i].stats;
      for (std::size_t k = 0; k < st.images.size(); ++k) {
        const ImageTiming& image = st.images[k];
        const auto it = std::lower_bound(
            delivered_.begin(), delivered_.end(), image.stamp_s,
            [](const std::pair<double, double>& d, double stamp) { return d.first < stamp; });
        if (it == delivered_.end() || it->first != image.stamp_s) continue;
        result_.methods[i].image_latency_ms.push_back(1e3 * (it->second - it->first) +
                                                      image.latency_ms);
      }
    }
    return std::move(result_);
  }

 private:
  // Reserves the recording of a real-time run, or refuses one that would
  // not fit in kMaxRecording_MB.
  void begin_recording(long steps, int n_sim) {
    const double pixels = double(camera_.intrinsics().width) * camera_.intrinsics().height;
    const double MB =
        (double(steps + 1) * n_sim * sizeof(double) +
         double(frames_timing_.size()) * (pixels * sizeof(float) + sizeof(InFlight))) /
        1e6;
    if (MB > kMaxRecording_MB)
      throw InputError(sc_.source + ": --realtime simulates a run before replaying it at the " +
                       "wall clock's pace, and this run's measurements would take " +
                       std::to_string(std::lround(MB)) + " MB (at most " +
                       std::to_string(std::lround(kMaxRecording_MB)) +
                       "): shorten duration_s or lower the camera's resolution");
    recording_.emplace();
    recording_->readings_rad.reserve(std::size_t(steps + 1) * std::size_t(n_sim));
  }

  // Feeds the recorded run to the trackers, each joint step when its
  // simulated time has passed on the wall clock since the replay began.
  void replay(long steps, int n_sim) {
    const double period = physics_.joint_period_s();
    const long progress_every = std::max(1L, std::lround(sc_.joint_rate_hz));
    std::size_t next_delivery = 0, next_scored = 0;
    wall_start_ = Clock::now();
    for (long n = 0; n <= steps; ++n) {
      const double t = double(n) * period;
      std::this_thread::sleep_until(wall_start_ + std::chrono::duration_cast<Clock::duration>(
                                                      std::chrono::duration<double>(t)));
      joints(t, std::span<const double>(recording_->readings_rad.data() + n * n_sim,
                                        std::size_t(n_sim)));
      for (; next_delivery < recording_->deliveries.size() &&
             recording_->deliveries[next_delivery].step == n;
           ++next_delivery)
        deliver(recording_->deliveries[next_delivery].frame, t);
      for (; next_scored < recording_->scored.size() && recording_->scored[next_scored].step == n;
           ++next_scored)
        score(std::move(recording_->scored[next_scored].truth));
      if (options_.progress && n % progress_every == 0 && n > 0)
        options_.progress({result_.run, 0, t, sc_.duration_s});
    }
    recording_.reset();
  }

  void joints(double t, std::span<const double> readings) {
    if (options_.sink) options_.sink->joints(result_.run, t, readings);
    trackers_->joints(t, readings);
  }

  void deliver(const InFlight& frame, double now) {
    if (options_.realtime)
      delivered_.emplace_back(frame.stamp_s,
                              std::chrono::duration<double>(Clock::now() - wall_start_).count());
    trackers_->image(frame.stamp_s, now, frame.image);
    if (options_.sink) options_.sink->image(result_.run, frame.stamp_s, now, frame.image);
  }

  TruthSample truth_sample(double t, const GroundTruth& g, bool camera_frame, double occluded) {
    const std::size_t nj = setup_.joint_names.size(), ne = setup_.sim_ee.size();
    TruthSample truth;
    truth.time_s = t;
    truth.camera_frame = camera_frame;
    truth.occluded_fraction = occluded;
    truth.angle_rad.resize(Eigen::Index(nj));
    truth.bias_rad.resize(Eigen::Index(nj));
    const std::span<const double> bias = encoders_.bias_rad();
    for (std::size_t j = 0; j < nj; ++j) {
      truth.angle_rad[j] = g.q[setup_.sim_joint[j]];
      truth.bias_rad[j] = bias[setup_.sim_joint[j]];
    }
    for (std::size_t e = 0; e < ne; ++e)
      truth.T_camera_ee.push_back(g.T_camera_ee[setup_.sim_ee[e]]);
    // The world frame is the robot's root link (simulator.h).
    truth.T_base_camera = g.T_world_camera;
    truth.camera_offset = camera_poses_.offset_to(truth.angle_rad, g.T_world_camera);
    return truth;
  }

  void score(TruthSample truth) {
    const TruthSample& scored = trackers_->score(std::move(truth), &camera_poses_, true, true);
    if (options_.sink) options_.sink->truth(result_.run, scored);
  }

  const Scenario& sc_;
  const Setup& setup_;
  Simulator& sim_;
  DepthCamera& camera_;
  const RunOptions& options_;
  EncoderCorruption encoders_;
  DepthCorruption depth_noise_;
  RunPhysics physics_;  // resets the simulator: before anything reads it
  CameraPoses camera_poses_;
  std::vector<CameraFrame> frames_timing_;
  RunResult result_;
  // Fills result_; after it, as it refers to it.
  std::optional<MethodTrackers> trackers_;
  std::deque<InFlight> in_flight_;
  std::optional<Recording> recording_;  // real time only, until replayed
  Clock::time_point wall_start_;
  // Real time: (stamp, wall time of delivery since wall_start_) per delivered image, in order.
  std::vector<std::pair<double, double>> delivered_;
};

}  // namespace

std::uint64_t run_seed(std::uint64_t seed, int run) {
  // 53 bits, so that JSON readers keep every digit.
  return splitmix64(splitmix64(seed) + std::uint64_t(run)) & ((std::uint64_t(1) << 53) - 1);
}

JointTrajectory run_trajectory(const Scenario& scenario, const SimModel& model, std::uint64_t seed,
                               int run) {
  return commanded_motion(scenario, model, run_seed(seed, run));
}

DrawnModelError run_robot(const Scenario& scenario, std::uint64_t seed, int run) {
  return run_model_error(scenario, stream_seed(run_seed(seed, run), kModel));
}

// Every joint and link model_mismatch.random may draw, changed at once by
// its largest draw, through the URDF rewriting the runs use: a joint whose
// origin has no translation to lengthen fails here, before any run, not in
// the run that first draws it.
void check_random_mismatch(const Scenario& sc, const SceneDescription& scene) {
  const RandomModelMismatch& r = sc.random_mismatch;
  UrdfPerturbation all = sc.perturbation;
  if (r.lengths > 0)
    for (const std::string& j : r.joints) all.origin_extension_m[j] += r.length_max_m;
  if (r.scales > 0)
    for (const std::string& l : r.links)
      all.link_scale.try_emplace(l, 1.0).first->second *= 1 + r.scale_max;
  try {
    perturbed_urdf_text(scene, scene.urdf_path, all);
  } catch (const InputError& e) {
    throw InputError(sc.source + ": key 'model_mismatch.random' cannot be drawn: " + e.what());
  }
}

ScenarioResult run_scenario(const Scenario& sc, const RunOptions& options) {
  const int runs = options.runs > 0 ? options.runs : sc.runs;
  if (options.runs < 0) throw InputError("runs must be >= 1");
  const std::uint64_t seed = options.seed >= 0 ? std::uint64_t(options.seed) : sc.seed;
  const std::vector<std::string> method_names =
      options.methods.empty() ? sc.methods : options.methods;
  for (std::size_t i = 0; i < method_names.size(); ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (method_names[i] == method_names[k])
        throw InputError("method '" + method_names[i] + "' is listed twice");

  const Setup setup = make_setup(sc, method_names);
  // One simulator and camera for every run, unless each run draws its robot.
  std::optional<Simulator> sim;
  std::optional<DepthCamera> camera;
  if (sc.random_mismatch.empty()) {
    sim.emplace(setup.sim_model);
    camera.emplace(setup.sim_model);
  }

  ScenarioResult result;
  result.scenario = sc.name;
  result.source = sc.source;
  result.recipe.scenario_file = sc.source;
  result.recipe.scenario_dir = sc.dir.string();
  result.recipe.overrides = sc.overrides;
  result.recipe.scenario_yaml = sc.resolved_yaml;
  result.recipe.tracker_yaml = YAML::Dump(sc.tracker_document.root) + "\n";
  result.recipe.seed = seed;
  result.recipe.runs = runs;
  result.recipe.methods = method_names;
  result.recipe.realtime = options.realtime;
  result.duration_s = sc.duration_s;
  result.joint_names = setup.joint_names;
  result.prismatic = prismatic_joints(*setup.robot, setup.joint_names);
  result.end_effectors = sc.scoring.end_effectors;
  result.scoring = sc.scoring.options;
  std::vector<MethodScores> scores;
  for (TrackingMethod m : setup.methods) {
    result.methods.push_back(method_name(m));
    scores.emplace_back(method_name(m), setup.joint_names, sc.scoring.end_effectors);
  }

  if (!sc.random_mismatch.empty()) check_random_mismatch(sc, setup.scene);
  for (int k = 0; k < runs; ++k) {
    const std::uint64_t seed_k = run_seed(seed, k);
    result.seeds.push_back(seed_k);
    RunOptions run_options = options;
    if (options.progress)
      run_options.progress = [&](const RunProgress& p) {
        options.progress({k, runs, p.time_s, p.duration_s});
      };
    if (sc.random_mismatch.empty()) {
      Run run(sc, setup, *sim, *camera, k, seed_k, scores, run_options, result.frames);
      result.runs.push_back(run.execute());
      continue;
    }
    // Another robot for this run: its own simulator model, simulator and
    // camera (same joints, links and end effectors, so setup's indices hold).
    DrawnModelError drawn = run_robot(sc, seed, k);
    Setup run_setup = setup;
    run_setup.sim_model = build_sim_model(setup.scene, drawn.perturbation);
    Simulator run_sim(run_setup.sim_model);
    DepthCamera run_camera(run_setup.sim_model);
    Run run(sc, run_setup, run_sim, run_camera, k, seed_k, scores, run_options, result.frames);
    result.runs.push_back(run.execute());
    result.runs.back().drawn_link_lengths_m = std::move(drawn.link_lengths_m);
    result.runs.back().drawn_shape_scales = std::move(drawn.shape_scales);
  }

  summarise_methods(result, scores, true);
  return result;
}

}  // namespace arttrack::sim
