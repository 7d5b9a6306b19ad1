// The tracking-and-scoring half of a run: one Tracker per method, fed the
// same measurements in the same order, their estimates scored against the
// truth. Shared by the scenario runner (`arttrack run`, sweeps, tuning,
// bench) and dataset tracking (`arttrack track`), so that a simulated run and
// its exported dataset are fed, scored, rendered and written alike:
//
//   measurements (joint readings; depth images with stamp and arrival)
//     -> trackers -> estimates -> scored samples (RunResult, MethodScores),
//        kept frames, estimate.csv rows
//
// The producer (simulator or dataset) calls, per instant: joints(), then
// image() for each image that has arrived, then score() or
// write_estimates(); then finish() once at the end of the run. Over all runs,
// summarise_methods() turns the scores and timings into MethodResults.
#pragma once

#include <memory>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "arttrack/sim/run_result.h"
#include "arttrack/sim/scoring.h"
#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack::sim {

// What a run's trackers are built from.
struct TrackingSetup {
  std::shared_ptr<const RobotModel> robot;  // nominal, with virtual camera joints
  // The configuration of every tracker (seed, camera, synchronous or not);
  // its method is set per tracker.
  TrackerConfig config;
  std::vector<TrackingMethod> methods;
  std::vector<std::string> joint_names;  // order of the readings
  CameraIntrinsics camera;               // of the depth images
  // Vision only's initial configuration (its start is "given", as in the
  // paper), joint_names order, rad; unused without vision_only.
  std::vector<double> vision_only_start_rad;
};

// One run's trackers and what they give. Fills `run` (per method: samples,
// joint update times, stats; the truth; frames_delivered) and adds to
// `scores` (one per method, TrackingSetup::methods order; begin_run() is
// called on each), which must outlive this.
class MethodTrackers {
 public:
  MethodTrackers(const TrackingSetup& setup, RunResult& run, std::vector<MethodScores>& scores);

  // Keeps `count` depth frames for reports, evenly spread over the run: the
  // first image delivered that was captured at or after each of
  // duration_s * k / (count + 1), k = 1 .. count, with the estimate of
  // render_method() rendered right after it, appended to `frames`. Images
  // before the first joint reading are not kept (there is no estimate yet).
  void keep_frames(int count, double duration_s, std::vector<KeptFrame>& frames);
  // Writes estimate.csv (its header now, then rows at score() and
  // write_estimates()); see track_dataset in dataset_tracking.h for the columns.
  void write_estimates_to(std::ostream& estimate_csv);

  // Encoder readings taken at time_s (TrackingSetup::joint_names order, rad)
  // to every method but vision only; each call's wall time is recorded
  // (MethodRun::joint_update_us).
  void joints(double time_s, std::span<const double> readings_rad);
  // A depth image captured at stamp_s, given to every method at arrival_s.
  void image(double stamp_s, double arrival_s, const DepthImage& image);
  // Scores every method's estimate now against `truth` (score_estimate:
  // `camera` may be null, angles_known and biases_known as there; whether
  // each true end effector is in the images' view, in_camera_view), writes
  // their estimate.csv rows, appends the truth to the run and returns it.
  const TruthSample& score(TruthSample truth, CameraPoses* camera, bool angles_known,
                           bool biases_known);
  // Writes every method's estimate.csv row at time_s (no scoring).
  void write_estimates(double time_s);
  // Waits for asynchronous updates to end and records each method's stats.
  void finish();

 private:
  void keep(double stamp_s, double arrival_s, const DepthImage& image);

  TrackingSetup setup_;
  RunResult& run_;
  std::vector<MethodScores>& scores_;
  std::vector<std::unique_ptr<Tracker>> trackers_;
  std::vector<double> keep_stamps_s_;
  std::vector<KeptFrame>* frames_ = nullptr;
  std::ostream* estimate_csv_ = nullptr;
  bool joints_seen_ = false;
};

// The method whose estimate is rendered next to kept frames: full fusion,
// else the first method that uses images; -1 if none does.
int render_method(const std::vector<TrackingMethod>& methods);

// Scores one method's estimate against the truth at a scored instant: the
// sample kept in the run's results and the one its ErrorTrace gets. The
// truth's angles and biases are in the estimate's joint order;
// angles_known / biases_known say whether they are real (a dataset may lack
// them). `camera` (may be null: no camera scoring) is the tracker's nominal
// model; it is used only where the truth has a camera pose.
EstimateSample score_estimate(const TrackerEstimate& estimate, const TruthSample& truth,
                              CameraPoses* camera, bool angles_known, bool biases_known,
                              ScoredSample& scored);

// Fills result.method_results from the runs and `scores` (result.methods
// order): per method its scores, its summary (if `summarise`; against
// encoders only where it ran) and its timings pooled over the runs (image
// latencies if result.recipe.realtime).
void summarise_methods(ScenarioResult& result, const std::vector<MethodScores>& scores,
                       bool summarise);

}  // namespace arttrack::sim
