#include "arttrack/sim/method_trackers.h"

#include <chrono>

#include "arttrack/sim/internal/text_format.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"

namespace arttrack::sim {
namespace {

using Clock = std::chrono::steady_clock;

void write_estimate_header(std::ostream& out, const RobotModel& robot,
                           const std::vector<std::string>& end_effectors) {
  out << "time_s,method";
  for (int j = 0; j < robot.num_joints(); ++j) {
    if (robot.is_virtual_joint(j)) continue;
    const std::string& name = robot.joint_name(j);
    out << ',' << name << "_rad," << name << "_std_rad," << name << "_bias_rad," << name
        << "_bias_std_rad";
  }
  out << ",cam_x_m,cam_y_m,cam_z_m,cam_roll_rad,cam_pitch_rad,cam_yaw_rad";
  for (const std::string& e : end_effectors)
    for (const char* s : text::kPoseSuffixes) out << ',' << e << s;
  out << '\n';
}

void write_estimate_row(std::ostream& out, double t, const std::string& method,
                        const TrackerEstimate& e) {
  using text::shortest_number;
  out << shortest_number(t) << ',' << method;
  for (Eigen::Index j = 0; j < e.angle_rad.size(); ++j)
    out << ',' << shortest_number(e.angle_rad[j]) << ',' << shortest_number(e.angle_std_rad[j])
        << ',' << shortest_number(e.bias_rad[j]) << ',' << shortest_number(e.bias_std_rad[j]);
  for (int k = 0; k < 6; ++k) out << ',' << shortest_number(e.camera_offset[k]);
  for (const Eigen::Isometry3d& T : e.T_camera_ee) out << text::pose_fields(T);
  out << '\n';
}

}  // namespace

MethodTrackers::MethodTrackers(const TrackingSetup& setup, RunResult& run,
                               std::vector<MethodScores>& scores)
    : setup_(setup), run_(run), scores_(scores) {
  for (std::size_t i = 0; i < setup_.methods.size(); ++i) {
    TrackerConfig config = setup_.config;
    config.method = setup_.methods[i];
    trackers_.push_back(std::make_unique<Tracker>(setup_.robot, config, setup_.joint_names));
    // The camera is known before the stream (as a driver's camera info is):
    // the meshes are simplified now, not at the first image of a live run.
    trackers_.back()->prepare_camera(setup_.camera);
    if (config.method == TrackingMethod::kVisionOnly)
      trackers_.back()->set_initial_configuration(setup_.joint_names, setup_.vision_only_start_rad);
    MethodRun mr;
    mr.method = method_name(config.method);
    run_.methods.push_back(std::move(mr));
    scores_[i].begin_run();
  }
}

void MethodTrackers::keep_frames(int count, double duration_s, std::vector<KeptFrame>& frames) {
  keep_stamps_s_.clear();
  for (int k = 1; k <= count; ++k) keep_stamps_s_.push_back(duration_s * k / (count + 1));
  frames_ = &frames;
}

void MethodTrackers::write_estimates_to(std::ostream& estimate_csv) {
  estimate_csv_ = &estimate_csv;
  write_estimate_header(estimate_csv, *setup_.robot, setup_.config.end_effectors);
}

void MethodTrackers::joints(double time_s, std::span<const double> readings_rad) {
  joints_seen_ = true;
  for (std::size_t i = 0; i < trackers_.size(); ++i) {
    if (setup_.methods[i] == TrackingMethod::kVisionOnly) continue;
    const auto start = Clock::now();
    trackers_[i]->add_joint_measurement(time_s, readings_rad);
    run_.methods[i].joint_update_us.push_back(
        std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
}

void MethodTrackers::image(double stamp_s, double arrival_s, const DepthImage& image) {
  for (auto& tracker : trackers_) tracker->add_depth_image(stamp_s, image, setup_.camera);
  ++run_.frames_delivered;
  if (keep_stamps_s_.empty() || stamp_s < keep_stamps_s_.front() || !joints_seen_) return;
  keep_stamps_s_.erase(keep_stamps_s_.begin());
  keep(stamp_s, arrival_s, image);
}

void MethodTrackers::keep(double stamp_s, double arrival_s, const DepthImage& image) {
  KeptFrame kept;
  kept.run = run_.run;
  kept.stamp_s = stamp_s;
  kept.arrival_s = arrival_s;
  kept.observed = image;
  const int m = render_method(setup_.methods);
  if (m >= 0) {
    const TrackerEstimate e = trackers_[m]->estimate();
    const RobotModel& robot = *setup_.robot;
    Eigen::VectorXd q(robot.num_joints());
    q.head(e.angle_rad.size()) = e.angle_rad;
    q.tail<6>() = e.camera_offset;
    KinematicsState state(robot);
    forward_kinematics(robot, q, state);
    DepthRenderer renderer(robot, setup_.camera);
    renderer.render(state, kept.estimate);
    kept.estimate_method = method_name(setup_.methods[m]);
  }
  frames_->push_back(std::move(kept));
}

const TruthSample& MethodTrackers::score(TruthSample truth, CameraPoses* camera, bool angles_known,
                                         bool biases_known) {
  ScoredSample scored;
  std::vector<bool> in_view;
  for (const Eigen::Isometry3d& T : truth.T_camera_ee)
    in_view.push_back(in_camera_view(T.translation(), setup_.camera));
  for (std::size_t i = 0; i < trackers_.size(); ++i) {
    const TrackerEstimate est = trackers_[i]->estimate();
    if (estimate_csv_)
      write_estimate_row(*estimate_csv_, truth.time_s, run_.methods[i].method, est);
    run_.methods[i].samples.push_back(
        score_estimate(est, truth, camera, angles_known, biases_known, scored));
    scored.end_effector_in_view = in_view;
    scores_[i].add(scored);
  }
  run_.truth.push_back(std::move(truth));
  return run_.truth.back();
}

void MethodTrackers::write_estimates(double time_s) {
  if (!estimate_csv_) return;
  for (std::size_t i = 0; i < trackers_.size(); ++i)
    write_estimate_row(*estimate_csv_, time_s, run_.methods[i].method, trackers_[i]->estimate());
}

void MethodTrackers::finish() {
  for (std::size_t i = 0; i < trackers_.size(); ++i) {
    trackers_[i]->wait_until_idle();  // asynchronous: the last image
    run_.methods[i].stats = trackers_[i]->stats();
  }
}

int render_method(const std::vector<TrackingMethod>& methods) {
  for (std::size_t i = 0; i < methods.size(); ++i)
    if (methods[i] == TrackingMethod::kFullFusion) return int(i);
  for (std::size_t i = 0; i < methods.size(); ++i)
    if (methods[i] != TrackingMethod::kEncodersOnly) return int(i);
  return -1;
}

EstimateSample score_estimate(const TrackerEstimate& est, const TruthSample& truth,
                              CameraPoses* camera, bool angles_known, bool biases_known,
                              ScoredSample& scored) {
  const std::size_t nj = std::size_t(est.angle_rad.size()), ne = truth.T_camera_ee.size();
  EstimateSample s;
  s.angle_rad = est.angle_rad;
  s.angle_std_rad = est.angle_std_rad;
  s.bias_rad = est.bias_rad;
  s.bias_std_rad = est.bias_std_rad;
  s.camera_offset = est.camera_offset;
  s.camera_offset_std = est.camera_offset_std;
  s.T_camera_ee = est.T_camera_ee;
  s.health = est.health;
  scored = ScoredSample{};
  scored.time_s = truth.time_s;
  for (std::size_t e = 0; e < ne; ++e) {
    s.ee_error.push_back(pose_error(est.T_camera_ee[e], truth.T_camera_ee[e]));
    s.ee_error_vector.push_back(pose_error_vector(est.T_camera_ee[e], truth.T_camera_ee[e]));
    s.ee_correction.push_back(e < est.ee_image_correction.size()
                                  ? est.ee_image_correction[e]
                                  : Eigen::Matrix<double, 6, 1>::Zero());
    if (est.T_camera_ee_covariance.size() != ne) continue;
    s.ee_std.push_back(est.T_camera_ee_covariance[e].diagonal().cwiseMax(0.0).cwiseSqrt());
    const PoseErrorVector &error = s.ee_error_vector.back(), &std = s.ee_std.back();
    scored.end_effector_error.insert(scored.end_effector_error.end(), error.begin(), error.end());
    scored.end_effector_std.insert(scored.end_effector_std.end(), std.begin(), std.end());
  }
  scored.end_effectors = s.ee_error;
  auto per_joint = [nj](const Eigen::VectorXd& v) {
    return std::vector<double>(v.data(), v.data() + nj);
  };
  if (angles_known) {
    scored.angle_error_rad = per_joint(est.angle_rad - truth.angle_rad);
    scored.angle_std_rad = per_joint(est.angle_std_rad);
  }
  if (biases_known) {
    scored.bias_error_rad = per_joint(est.bias_rad - truth.bias_rad);
    scored.bias_std_rad = per_joint(est.bias_std_rad);
  }
  if (camera && truth.T_base_camera) {
    s.camera_error =
        pose_error(camera->camera(est.angle_rad, est.camera_offset), *truth.T_base_camera);
    scored.camera = s.camera_error;
    const CameraOffset error = est.camera_offset - truth.camera_offset;
    scored.camera_offset_error.assign(error.data(), error.data() + 6);
    scored.camera_offset_std.assign(est.camera_offset_std.data(), est.camera_offset_std.data() + 6);
  }
  return s;
}

void summarise_methods(ScenarioResult& result, const std::vector<MethodScores>& scores,
                       bool summarise) {
  const MethodScores* reference = nullptr;
  for (const MethodScores& s : scores)
    if (s.method() == method_name(TrackingMethod::kEncodersOnly)) reference = &s;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    MethodResult r{result.methods[i], scores[i], {}, {}, {}, {}, {}};
    if (summarise)
      r.summary = scores[i].summary(result.scoring, reference == &scores[i] ? nullptr : reference);
    std::vector<double> joint_us, image_ms, latency_ms;
    long long evaluations = 0, images = 0;
    for (const RunResult& run : result.runs) {
      const MethodRun& mr = run.methods[i];
      latency_ms.insert(latency_ms.end(), mr.image_latency_ms.begin(), mr.image_latency_ms.end());
      joint_us.insert(joint_us.end(), mr.joint_update_us.begin(), mr.joint_update_us.end());
      const std::vector<double> update_ms = mr.stats.images.values(&ImageTiming::update_ms);
      image_ms.insert(image_ms.end(), update_ms.begin(), update_ms.end());
      evaluations += mr.stats.likelihood_evaluations;
      images += mr.stats.images_applied;
    }
    r.timing.joint_update_us = percentiles(joint_us);
    r.timing.image_update_ms = percentiles(image_ms);
    r.timing.evaluations_per_image = images ? double(evaluations) / double(images) : 0.0;
    if (result.recipe.realtime) r.timing.image_latency_ms = percentiles(latency_ms);
    r.links = link_model_fits(result.runs, i);
    r.counts = health_counts(result.runs, i);
    r.encoder_noise_rad = encoder_noise_medians_rad(result.runs, i);
    result.method_results.push_back(std::move(r));
  }
}

}  // namespace arttrack::sim
