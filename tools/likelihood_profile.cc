// likelihood_profile DATASET --series TIMESERIES.csv --time T [--run K] [--method M]
//
// Does the image prefer the estimate to the truth, and which links say so?
// A diagnostic for the testbed (it needs the truth): for the depth image of
// an exported dataset (`arttrack export`) nearest time T, and the row nearest
// the image's stamp of an `arttrack run` of the same scenario and seed (its
// run K, default 0: the run export writes; method M, default full_fusion),
// it evaluates the tracker's pixel likelihood (the dataset's tracker.yaml:
// depth model, resolution, geometry) at states on the straight line from the
// true state q_t (angles and camera offset) to the estimate q_e,
// q(alpha) = q_t + alpha (q_e - q_t), and prints
//   - log p(image | q(alpha)) - log p(image | q_t) for alpha from -1 to 2,
//     moving every DOF, the camera offset alone, the joints alone;
//   - that difference at alpha = 1 split by link, over the pixels both
//     states cover (interior) and the others (silhouette);
//   - the Fisher information along the line at the estimate (visible branch,
//     interior pixels within 3 sigma, as image_information.h counts it) and
//     each link's pull there, d/dalpha of its pixels' log-likelihood.
// A likelihood that rises from alpha = 0 to 1 prefers the estimate: the
// error is the model's (or the image's), not the filter's. docs/accuracy.md
// "Known gaps" (stop 37) has an example.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "arttrack/sim/dataset.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"
#include "arttrack/tracker/tracker_config_yaml.h"

namespace arttrack {
namespace {

namespace fs = std::filesystem;

struct Args {
  std::string dataset, series, method = "full_fusion";
  double time_s = 0;
  int run = 0;
};

// The camera offset's columns in timeseries.csv, in the virtual joints' order.
constexpr const char* kCameraColumns[6] = {"x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"};

// The row of `run` and `method` nearest `time_s`: its true and estimated
// state in `model`'s DOF order (a DOF without columns is an error).
void read_states(const fs::path& series, const Args& args, double time_s, const RobotModel& model,
                 Eigen::VectorXd& truth, Eigen::VectorXd& estimate, double& row_time_s) {
  sim::text::CsvReader csv(series, sim::text::CsvSpace::kVerbatim);
  std::vector<std::string> header, fields, best;
  if (!csv.next(header)) csv.fail("empty file");
  auto column = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    throw InputError(series.string() + ": no column '" + name + "'");
  };
  const std::size_t time_col = column("time_s"), run_col = column("run"),
                    method_col = column("method");
  double best_distance = INFINITY;
  while (csv.next(fields)) {
    csv.expect_width(fields, header.size());
    if (fields[run_col] != std::to_string(args.run) || fields[method_col] != args.method) continue;
    const double t = csv.finite(fields, time_col, header);
    if (std::abs(t - time_s) < best_distance) best_distance = std::abs(t - time_s), best = fields;
  }
  if (best.empty())
    throw InputError(series.string() + ": no row of run " + std::to_string(args.run) +
                     " and method '" + args.method + "'");
  auto value = [&](const std::string& name) {
    const std::size_t i = column(name);
    char* end = nullptr;
    const double v = std::strtod(best[i].c_str(), &end);
    if (best[i].empty() || *end != 0 || !std::isfinite(v))
      throw InputError(series.string() + ": column '" + name + "' is '" + best[i] +
                       "' at the row nearest " + std::to_string(time_s) + " s, not a number");
    return v;
  };
  row_time_s = value("time_s");
  const int n = model.num_joints(), first_camera = n - 6;  // the virtual camera joints
  truth.resize(n);
  estimate.resize(n);
  for (int i = 0; i < n; ++i) {
    if (i >= first_camera) {
      const std::string suffix = kCameraColumns[i - first_camera];
      truth[i] = value("cam_true_" + suffix);
      estimate[i] = value("cam_" + suffix);
    } else {
      truth[i] = value(model.joint_name(i) + "_true_rad");
      estimate[i] = value(model.joint_name(i) + "_est_rad");
    }
  }
}

void run(const Args& args) {
  const sim::Dataset dataset = sim::load_dataset(args.dataset);
  if (dataset.frames.empty()) throw InputError(args.dataset + ": no depth images");
  const TrackerConfig config = dataset.tracker_file
                                   ? load_tracker_config(dataset.tracker_file->string())
                                   : default_tracker_config();
  RobotModelOptions options;
  options.mesh_search_paths = dataset.mesh_search_paths;
  options.camera_frame = dataset.camera.frame;
  const RobotModel full = RobotModel::from_urdf_file(dataset.urdf.string(), options);
  if (full.num_joints() < 6 || !full.is_virtual_joint(full.num_joints() - 6))
    throw InputError(dataset.urdf.string() + ": no camera frame '" + options.camera_frame + "'");

  // The image nearest the time asked.
  const sim::DatasetFrame* frame = &dataset.frames.front();
  for (const sim::DatasetFrame& f : dataset.frames)
    if (std::abs(f.stamp_s - args.time_s) < std::abs(frame->stamp_s - args.time_s)) frame = &f;
  std::string problem;
  const std::optional<DepthImage> image = sim::read_dataset_frame(dataset, *frame, &problem);
  if (!image) throw InputError(problem);

  Eigen::VectorXd q_t, q_e;
  double row_time_s = 0;
  read_states(args.series, args, frame->stamp_s, full, q_t, q_e, row_time_s);

  // What the tracker draws, at the likelihood's resolution.
  const DepthModelParams& depth_model = config.depth_model;
  const CameraIntrinsics camera =
      subsampled_intrinsics(dataset.camera.intrinsics, depth_model.width, depth_model.height);
  const RobotModel model =
      full.with_simplified_meshes(config.geometry.error_bound_m(camera), nullptr,
                                  config.geometry.nearest_range_m, config.geometry.coarser_levels);
  DepthLikelihood likelihood(depth_model);
  likelihood.set_observation(*image);
  DepthRenderer renderer(model, camera);
  KinematicsState state(model);
  const int n = model.num_joints(), first_camera = n - 6;

  // The rendered depth at q, and which link each pixel shows (-1: none).
  auto render = [&](const Eigen::VectorXd& q, DepthImage& depth, std::vector<int>* label) {
    forward_kinematics(model, q, state);
    renderer.render(state, depth);
    if (!label) return;
    label->assign(depth.depth_m.size(), -1);
    DepthImage one;
    for (int l : model.links_with_geometry()) {
      LinkSet alone(std::size_t(model.num_links()), false);
      alone[std::size_t(l)] = true;
      renderer.render_links(state, alone, one);
      for (std::size_t i = 0; i < depth.depth_m.size(); ++i)
        if (one.depth_m[i] > 0 && one.depth_m[i] == depth.depth_m[i]) (*label)[i] = l;
    }
  };
  DepthImage depth;
  auto log_likelihood = [&](const Eigen::VectorXd& q) {
    render(q, depth, nullptr);
    return likelihood.log_ratio(depth);
  };
  auto along = [&](double alpha) { return Eigen::VectorXd(q_t + alpha * (q_e - q_t)); };

  std::printf("image %s (stamp %.3f s), estimate and truth of %s run %d at %.3f s\n",
              frame->file.filename().string().c_str(), frame->stamp_s, args.method.c_str(),
              args.run, row_time_s);
  std::printf(
      "estimate - truth, camera offset: x %+.2f y %+.2f z %+.2f mm, roll %+.3f pitch "
      "%+.3f yaw %+.3f deg\n",
      1e3 * (q_e[first_camera] - q_t[first_camera]),
      1e3 * (q_e[first_camera + 1] - q_t[first_camera + 1]),
      1e3 * (q_e[first_camera + 2] - q_t[first_camera + 2]),
      (q_e[first_camera + 3] - q_t[first_camera + 3]) * 180 / M_PI,
      (q_e[first_camera + 4] - q_t[first_camera + 4]) * 180 / M_PI,
      (q_e[first_camera + 5] - q_t[first_camera + 5]) * 180 / M_PI);
  const double at_truth = log_likelihood(q_t);
  std::printf("\nlog-likelihood at q(alpha) minus at the truth, nats\n");
  std::printf("%6s %12s %14s %12s\n", "alpha", "every DOF", "camera alone", "joints alone");
  for (double alpha : {-1.0, -0.5, 0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0}) {
    const Eigen::VectorXd q = along(alpha);
    Eigen::VectorXd camera_only = q_t, joints_only = q;
    camera_only.tail(6) = q.tail(6);
    joints_only.tail(6) = q_t.tail(6);
    std::printf("%6.2f %12.2f %14.2f %12.2f\n", alpha, log_likelihood(q) - at_truth,
                log_likelihood(camera_only) - at_truth, log_likelihood(joints_only) - at_truth);
  }

  // Per link: the estimate's pixels against the truth's.
  DepthImage truth_depth, estimate_depth;
  std::vector<int> truth_label, estimate_label;
  render(q_t, truth_depth, &truth_label);
  render(q_e, estimate_depth, &estimate_label);
  auto pixel_term = [&](std::size_t i, float r) {
    const double z = likelihood.observed_depth_m(int(i));
    return z > 0 && r > 0 ? likelihood.log_ratio_pixel(z, r) : 0.0;
  };
  struct Share {
    double interior = 0, silhouette = 0;
    int interior_pixels = 0, silhouette_pixels = 0;
  };
  std::map<int, Share> shares;
  for (std::size_t i = 0; i < truth_depth.depth_m.size(); ++i) {
    const double d =
        pixel_term(i, estimate_depth.depth_m[i]) - pixel_term(i, truth_depth.depth_m[i]);
    if (d == 0) continue;
    const int link = truth_label[i] >= 0 ? truth_label[i] : estimate_label[i];
    Share& s = shares[link];
    if (truth_depth.depth_m[i] > 0 && estimate_depth.depth_m[i] > 0) {
      s.interior += d, ++s.interior_pixels;
    } else {
      s.silhouette += d, ++s.silhouette_pixels;
    }
  }

  // At the estimate: the Fisher information along the line and each link's pull.
  const double h = 0.05;
  DepthImage plus, minus;
  std::vector<int> plus_label, minus_label;
  render(along(1 + h), plus, &plus_label);
  render(along(1 - h), minus, &minus_label);
  double fisher = 0;
  int fisher_pixels = 0;
  std::map<int, double> pulls;
  for (std::size_t i = 0; i < plus.depth_m.size(); ++i) {
    const double z = likelihood.observed_depth_m(int(i));
    if (!(z > 0)) continue;
    const int link = estimate_label[i] >= 0 ? estimate_label[i]
                     : plus_label[i] >= 0   ? plus_label[i]
                                            : minus_label[i];
    pulls[link] += (pixel_term(i, plus.depth_m[i]) - pixel_term(i, minus.depth_m[i])) / (2 * h);
    const double r = estimate_depth.depth_m[i], sigma = likelihood.noise_std_at_m(z);
    if (!(r > 0 && plus.depth_m[i] > 0 && minus.depth_m[i] > 0)) continue;
    if (std::abs(z - r) > 3 * sigma || std::abs(plus.depth_m[i] - r) > 3 * sigma ||
        std::abs(minus.depth_m[i] - r) > 3 * sigma)
      continue;
    const double slope = (plus.depth_m[i] - minus.depth_m[i]) / (2 * h) / sigma;
    fisher += slope * slope;
    ++fisher_pixels;
  }
  std::printf(
      "\nper link: log-likelihood at the estimate minus at the truth (interior: pixels "
      "both cover), and its pull at the estimate, nats per unit alpha\n");
  std::printf("%-24s %10s %7s %11s %7s %10s\n", "link", "interior", "pixels", "silhouette",
              "pixels", "pull");
  for (const int l : model.links_with_geometry()) {
    const Share s = shares.count(l) ? shares[l] : Share{};
    const double pull = pulls.count(l) ? pulls[l] : 0.0;
    if (s.interior_pixels + s.silhouette_pixels == 0 && pull == 0) continue;
    std::printf("%-24s %+10.2f %7d %+11.2f %7d %+10.2f\n", model.link(l).name.c_str(), s.interior,
                s.interior_pixels, s.silhouette, s.silhouette_pixels, pull);
  }
  std::printf(
      "\nFisher information along the line at the estimate: %.1f per unit alpha^2 over %d "
      "pixels (one image's standard deviation along it: %.3f of the line)\n",
      fisher, fisher_pixels, fisher > 0 ? 1 / std::sqrt(fisher) : INFINITY);
}

}  // namespace
}  // namespace arttrack

int main(int argc, char** argv) {
  arttrack::Args args;
  CLI::App app{
      "Does the image prefer the estimate to the truth? The tracker's depth likelihood "
      "along the line from the true state to an estimate, split by link"};
  app.add_option("dataset", args.dataset, "Dataset folder written by arttrack export")->required();
  app.add_option("--series", args.series,
                 "timeseries.csv of arttrack run of the same scenario and seed")
      ->required();
  app.add_option("--time", args.time_s, "Seconds: the image nearest this time")->required();
  app.add_option("--run", args.run, "Run of the series (default 0: the run export writes)");
  app.add_option("--method", args.method, "Method of the series (default full_fusion)");
  CLI11_PARSE(app, argc, argv);
  if (!std::isfinite(args.time_s) || args.time_s < 0) {
    std::cerr << "likelihood_profile: usage error: --time " << args.time_s
              << " is not a number of seconds >= 0\n";
    return 2;
  }
  try {
    arttrack::run(args);
  } catch (const std::exception& e) {
    std::cerr << "likelihood_profile: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
