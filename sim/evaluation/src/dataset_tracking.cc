#include "arttrack/sim/dataset_tracking.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/method_trackers.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config_yaml.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using text::shortest_number;

TrackResult track_dataset(const Dataset& d, const TrackOptions& options,
                          std::ostream* estimate_csv) {
  TrackResult out;
  auto warn = [&](const std::string& w) {
    out.warnings.push_back(w);
    if (options.warn) options.warn(w);
  };

  // The nominal robot, and the joints of joints.csv against its joints.
  RobotModelOptions ro;
  ro.camera_frame = d.camera.frame;
  ro.mesh_search_paths = d.mesh_search_paths;
  const auto robot =
      std::make_shared<const RobotModel>(RobotModel::from_urdf_file(d.urdf.string(), ro));
  const fs::path joints_csv = d.dir / "joints.csv";
  std::vector<std::string> model_joints;
  for (int j = 0; j < robot->num_joints(); ++j)
    if (!robot->is_virtual_joint(j)) model_joints.push_back(robot->joint_name(j));
  for (const std::string& name : d.joint_names)
    if (std::find(model_joints.begin(), model_joints.end(), name) == model_joints.end())
      throw InputError(joints_csv.string() + ":1: joint '" + name + "' is not a movable joint of " +
                       d.urdf.string());
  for (const std::string& name : model_joints)
    if (std::find(d.joint_names.begin(), d.joint_names.end(), name) == d.joint_names.end())
      throw InputError(joints_csv.string() + ":1: has no column for joint '" + name + "' of " +
                       d.urdf.string());
  for (const std::string& ee : d.truth_end_effectors) {
    try {
      robot->link_index(ee);
    } catch (const InputError& e) {
      throw InputError((d.dir / "ground_truth.csv").string() + ":1: end effector '" + ee +
                       "': " + e.what());
    }
  }
  // Per model joint: its column in joints.csv (and in the truth rows).
  std::vector<std::size_t> column_of(model_joints.size());
  for (std::size_t j = 0; j < model_joints.size(); ++j)
    column_of[j] =
        std::size_t(std::find(d.joint_names.begin(), d.joint_names.end(), model_joints[j]) -
                    d.joint_names.begin());

  // The tracker configuration.
  TrackerConfig base;
  {
    const std::optional<fs::path> file =
        options.tracker_config ? options.tracker_config : d.tracker_file;
    base = file ? load_tracker_config(file->string()) : default_tracker_config();
  }
  base.camera_frame = d.camera.frame;
  if (d.has_truth()) base.end_effectors = d.truth_end_effectors;
  if (d.camera.delay_s) base.camera_delay_s = *d.camera.delay_s;
  base.asynchronous = false;
  // Image and joint clocks apart (another epoch or unit) would have the
  // tracker drop every image: refused, naming the first such row.
  const double joints_from_s = d.joint_time_s.front(), joints_to_s = d.joint_time_s.back();
  for (const DatasetFrame& f : d.frames)
    if (!(f.stamp_s >= joints_from_s - base.max_image_clock_offset_s &&
          f.stamp_s <= joints_to_s + base.max_image_clock_offset_s))
      throw InputError(f.where + ": image stamped " + shortest_number(f.stamp_s) +
                       " s is more than input_checks.max_image_clock_offset_s = " +
                       shortest_number(base.max_image_clock_offset_s) + " s outside the " +
                       shortest_number(joints_from_s) + " .. " + shortest_number(joints_to_s) +
                       " s of " + joints_csv.string() + ": the image and joint clocks differ");

  // The methods.
  std::vector<std::string> names = options.methods.empty() ? d.methods : options.methods;
  if (names.empty())
    for (const std::string& m : all_method_names())
      if (m != method_name(TrackingMethod::kVisionOnly) || d.truth_has_angles) names.push_back(m);
  std::vector<TrackingMethod> methods;
  for (std::size_t i = 0; i < names.size(); ++i) {
    methods.push_back(parse_method(names[i], "methods"));
    for (std::size_t k = 0; k < i; ++k)
      if (names[k] == names[i]) throw InputError("method '" + names[i] + "' is listed twice");
    if (methods.back() == TrackingMethod::kVisionOnly && !d.truth_has_angles)
      throw InputError(d.dir.string() +
                       ": vision_only starts from the true configuration, and the dataset has "
                       "no ground_truth.csv with joint angles");
  }
  if (methods.empty()) throw InputError("no method to run");

  // The result skeleton, as the runner fills it.
  ScenarioResult& r = out.result;
  r.scenario = d.name;
  r.source = d.dir.string();
  double last_s = d.joint_time_s.back();
  if (d.has_truth()) last_s = std::max(last_s, d.truth.back().time_s);
  r.duration_s = d.duration_s ? *d.duration_s : last_s;
  r.seeds = {d.seed ? *d.seed : std::uint64_t(base.seed)};
  r.joint_names = model_joints;
  r.prismatic = prismatic_joints(*robot, model_joints);
  r.end_effectors = base.end_effectors;
  r.scoring = d.scoring;
  r.scoring.validate();
  RunResult run;
  run.seed = r.seeds[0];
  std::vector<MethodScores> scores;
  for (TrackingMethod m : methods) {
    r.methods.push_back(method_name(m));
    scores.emplace_back(method_name(m), model_joints, base.end_effectors);
  }
  TrackingSetup setup;
  setup.robot = robot;
  setup.config = base;
  setup.methods = methods;
  setup.joint_names = d.joint_names;
  setup.camera = d.camera.intrinsics;
  if (d.has_truth()) {  // vision only starts from the first row's angles
    const Eigen::VectorXd& q0 = d.truth.front().angle_rad;
    setup.vision_only_start_rad.assign(q0.data(), q0.data() + q0.size());
  }
  MethodTrackers trackers(setup, run, scores);
  trackers.keep_frames(options.frames_to_keep, r.duration_s, r.frames);
  if (estimate_csv) trackers.write_estimates_to(*estimate_csv);

  const std::size_t nj = model_joints.size(), n_rows = d.joint_time_s.size();
  const std::size_t ncol = d.joint_names.size();
  std::size_t ji = 0, fi = 0, ti = 0;
  // An estimate row waiting for the images that arrive at its time.
  std::optional<double> pending_row;

  auto score = [&](const TruthSample& row) {
    TruthSample truth = row;
    truth.angle_rad.resize(Eigen::Index(nj));
    truth.bias_rad.resize(Eigen::Index(nj));
    for (std::size_t j = 0; j < nj; ++j) {
      truth.angle_rad[j] = row.angle_rad[column_of[j]];
      truth.bias_rad[j] = row.bias_rad[column_of[j]];
    }
    // No camera truth in a dataset: the camera is not scored.
    trackers.score(std::move(truth), nullptr, d.truth_has_angles, d.truth_has_biases);
  };

  auto deliver = [&](const DatasetFrame& f) {
    std::string problem;
    const std::optional<DepthImage> image = read_dataset_frame(d, f, &problem);
    if (!image) {
      ++out.frames_missing;
      warn(problem + "; frame skipped");
      return;
    }
    trackers.image(f.stamp_s, f.arrival_s, *image);
  };

  // Joints, images and truth rows merged in time order; at equal times
  // joints, then images, then the estimate is read (as the runner does).
  for (;;) {
    const double tj = ji < n_rows ? d.joint_time_s[ji] : kInf;
    const double tf = fi < d.frames.size() ? d.frames[fi].arrival_s : kInf;
    const double tt = ti < d.truth.size() ? d.truth[ti].time_s : kInf;
    const double next = std::min({tj, tf, tt});
    if (pending_row && (next > *pending_row || next == kInf)) {
      if (!(tt == *pending_row)) trackers.write_estimates(*pending_row);
      pending_row.reset();
    }
    if (next == kInf) break;
    if (tj == next) {
      trackers.joints(tj, std::span<const double>(&d.joint_readings_rad[ji * ncol], ncol));
      ++ji;
      if (options.estimate_every_n_joints > 0 && (ji - 1) % options.estimate_every_n_joints == 0)
        pending_row = tj;
    } else if (tf == next) {
      deliver(d.frames[fi]);
      ++run.frames_captured;
      ++fi;
      if (!d.has_truth() && ji > 0) pending_row = tf;
    } else {
      if (ji == 0) {
        ++out.truth_rows_skipped;
        warn((d.dir / "ground_truth.csv").string() + ": row at " + shortest_number(tt) +
             " s comes before the first joint reading; not scored");
      } else {
        score(d.truth[ti]);
      }
      ++ti;
    }
  }
  if (d.frames.empty()) warn(d.dir.string() + ": no depth images (depth/ is empty or missing)");
  trackers.finish();
  r.runs.push_back(std::move(run));
  summarise_methods(r, scores, d.has_truth());
  return out;
}

}  // namespace arttrack::sim
