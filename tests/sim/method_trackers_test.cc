// The tracking-and-scoring half of a run, on the small dual-arm robot:
//   - a run's measurements, recorded as its trackers receive them
//     (MeasurementSink) and fed again to a MethodTrackers built as the
//     runner builds its own, give the run's scored samples, tracker counts,
//     kept frames and summaries bit for bit: the runner is only the
//     simulator feeding this consumer (`arttrack track` feeds it from files;
//     the dataset tests check that round trip);
//   - estimate.csv gets a header and a row per method at every scored instant
//     and every write_estimates;
//   - an image before the first joint reading is delivered but not kept
//     (there is no estimate to render yet).
#include "arttrack/sim/method_trackers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <variant>

#include "arttrack/sim/urdf_perturbation.h"
#include "same_tracking.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

struct Joints {
  double time_s;
  std::vector<double> readings_rad;
};
struct Image {
  double stamp_s, arrival_s;
  DepthImage image;
};

// Run 0's stream, in the order the trackers got it.
class Recorder : public MeasurementSink {
 public:
  void begin_run(const RunStart& s) override {
    if (s.run == 0) start = s;
  }
  void joints(int run, double t, std::span<const double> r) override {
    if (run == 0) events.push_back(Joints{t, {r.begin(), r.end()}});
  }
  void image(int run, double stamp_s, double arrival_s, const DepthImage& image) override {
    if (run == 0) events.push_back(Image{stamp_s, arrival_s, image});
  }
  void truth(int run, const TruthSample& truth) override {
    if (run == 0) events.push_back(truth);
  }

  RunStart start;
  std::vector<std::variant<Joints, Image, TruthSample>> events;
};

// What the recorded stream gives when fed to a consumer built as the runner
// builds its own (nominal robot, the run's tracker seed, synchronous).
struct Replay {
  ScenarioResult result;
  std::string estimate_csv;
};

Replay replay(const Scenario& sc, const ScenarioResult& run, const Recorder& rec) {
  const RunStart& start = rec.start;
  TrackingSetup setup;
  setup.robot =
      std::make_shared<const RobotModel>(tracker_robot_model(sc.scene, sc.tracker_urdf()));
  setup.config = sc.tracker;
  setup.config.source = sc.tracker_document.file;
  setup.config.seed = start.tracker_seed;
  setup.config.asynchronous = false;
  for (const std::string& m : run.methods) setup.methods.push_back(parse_method(m, "test"));
  setup.joint_names = start.encoder_joints;
  setup.camera = start.camera;
  // Vision only's start: the truth at 0 s, from the truth's joint order.
  const auto is_truth = [](const auto& e) { return std::holds_alternative<TruthSample>(e); };
  const TruthSample& first =
      std::get<TruthSample>(*std::find_if(rec.events.begin(), rec.events.end(), is_truth));
  EXPECT_EQ(first.time_s, 0.0);
  for (const std::string& j : start.encoder_joints) {
    const auto it = std::find(start.truth_joints.begin(), start.truth_joints.end(), j);
    EXPECT_NE(it, start.truth_joints.end()) << j;
    setup.vision_only_start_rad.push_back(first.angle_rad[it - start.truth_joints.begin()]);
  }

  Replay out;
  ScenarioResult& r = out.result;
  r.methods = run.methods;
  r.scoring = run.scoring;
  r.runs.emplace_back();
  std::vector<MethodScores> scores;
  for (const std::string& m : r.methods)
    scores.emplace_back(m, start.truth_joints, start.end_effectors);
  std::ostringstream csv;
  CameraPoses camera(setup.robot);
  MethodTrackers trackers(setup, r.runs[0], scores);
  trackers.keep_frames(2, sc.duration_s, r.frames);
  trackers.write_estimates_to(csv);
  for (const auto& event : rec.events) {
    if (const auto* j = std::get_if<Joints>(&event)) trackers.joints(j->time_s, j->readings_rad);
    if (const auto* i = std::get_if<Image>(&event))
      trackers.image(i->stamp_s, i->arrival_s, i->image);
    if (const auto* t = std::get_if<TruthSample>(&event)) trackers.score(*t, &camera, true, true);
  }
  trackers.finish();
  summarise_methods(r, scores, true);
  out.estimate_csv = csv.str();
  return out;
}

TEST(MethodTrackers, ReplayingARunsMeasurementsGivesItsScoredSamples) {
  const test::TestDir dir("method_trackers_replay");
  const Scenario sc = load_scenario(dir.write("scenario.yaml", test::kMeasuredScenario));
  Recorder rec;
  RunOptions options;
  options.frames_to_keep = 2;
  options.sink = &rec;
  const ScenarioResult run = run_scenario(sc, options);
  ASSERT_TRUE(std::holds_alternative<Joints>(rec.events.at(0)));

  const Replay replayed = replay(sc, run, rec);
  const RunResult& a = run.runs[0];
  const RunResult& b = replayed.result.runs[0];
  EXPECT_EQ(b.frames_delivered, a.frames_delivered);
  ASSERT_EQ(b.truth.size(), a.truth.size());
  for (std::size_t i = 0; i < a.truth.size(); ++i) EXPECT_EQ(b.truth[i].time_s, a.truth[i].time_s);
  test::expect_same_tracking(run, replayed.result, 0, 0);
  for (std::size_t m = 0; m < a.methods.size(); ++m)
    for (std::size_t i = 0; i < a.methods[m].samples.size(); ++i)
      ASSERT_EQ(b.methods[m].samples[i].camera_error.translation_m,
                a.methods[m].samples[i].camera_error.translation_m);
  EXPECT_TRUE(b.methods[3].joint_update_us.empty());  // vision only gets no readings
  EXPECT_GT(b.methods[2].stats.images_applied, 10);

  ASSERT_EQ(replayed.result.frames.size(), 2u);
  ASSERT_EQ(run.frames.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(replayed.result.frames[k].stamp_s, run.frames[k].stamp_s);
    EXPECT_EQ(replayed.result.frames[k].estimate_method, "full_fusion");
    EXPECT_EQ(replayed.result.frames[k].estimate.depth_m, run.frames[k].estimate.depth_m);
  }

  // estimate.csv: the header, then a row per method and scored instant.
  const std::string& csv = replayed.estimate_csv;
  EXPECT_EQ(std::size_t(std::count(csv.begin(), csv.end(), '\n')),
            1 + a.truth.size() * a.methods.size());
  EXPECT_EQ(csv.rfind("time_s,method,", 0), 0u);
}

TEST(MethodTrackers, KeepsNoFrameBeforeTheFirstJointReadingAndWritesEstimateRows) {
  const test::TestDir dir("method_trackers_keep");
  const Scenario sc = load_scenario(dir.write("scenario.yaml", test::kMeasuredScenario));
  TrackingSetup setup;
  setup.robot =
      std::make_shared<const RobotModel>(tracker_robot_model(sc.scene, sc.tracker_urdf()));
  setup.config = sc.tracker;
  setup.methods = {TrackingMethod::kEncodersOnly, TrackingMethod::kFullFusion};
  for (int j = 0; j < setup.robot->num_joints(); ++j)
    if (!setup.robot->is_virtual_joint(j)) setup.joint_names.push_back(setup.robot->joint_name(j));
  setup.camera = CameraIntrinsics::from_vertical_fov(40, 30, 50 * M_PI / 180);
  RunResult run;
  std::vector<MethodScores> scores{{"encoders_only", setup.joint_names},
                                   {"full_fusion", setup.joint_names}};
  std::vector<KeptFrame> frames;
  std::ostringstream csv;
  MethodTrackers trackers(setup, run, scores);
  trackers.keep_frames(1, 0.0, frames);  // from 0 s on
  trackers.write_estimates_to(csv);

  const DepthImage empty(40, 30);
  trackers.image(0.0, 0.0, empty);  // no estimate yet: delivered, not kept
  EXPECT_EQ(run.frames_delivered, 1);
  EXPECT_TRUE(frames.empty());
  const std::vector<double> zero(setup.joint_names.size(), 0.0);
  trackers.joints(0.001, zero);
  trackers.image(0.0, 0.001, empty);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].arrival_s, 0.001);
  EXPECT_EQ(frames[0].estimate_method, "full_fusion");
  trackers.write_estimates(0.001);
  trackers.finish();
  EXPECT_EQ(run.methods[0].joint_update_us.size(), 1u);
  EXPECT_EQ(run.methods[1].stats.images_received, 2);
  const std::string text = csv.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3);  // header, two methods
  EXPECT_NE(text.find("\n0.001,encoders_only,"), std::string::npos);
  EXPECT_NE(text.find("\n0.001,full_fusion,"), std::string::npos);
}

}  // namespace
}  // namespace arttrack::sim
