// Datasets: export a scenario, track the dataset, compare with the runner.
//   - quantise_depth_mm is exactly a 16-bit millimetre PNG round trip;
//   - round trip: export + track gives bit for bit the estimates of
//     run_scenario with the same seed when the runner's trackers also get
//     millimetre depths (RunOptions::quantise_depth_mm), and the same scores;
//     encoders only (which ignores images) also equals the plain run;
//   - estimate.csv rows hold the same numbers as the scored estimates;
//   - bad data: missing or unreadable frames are counted warnings and
//     tracking goes on; joints.csv out of order or repeated, joints the URDF
//     lacks or the reverse, images of the wrong size or unit, bad index and
//     ground-truth files are errors naming the file (and line or item).
#include "arttrack/sim/dataset.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "../error_of.h"
#include "arttrack/sim/dataset_tracking.h"
#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/run_outputs.h"
#include "arttrack/tracker/error.h"
#include "same_tracking.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

using arttrack::test_support::error_of;

namespace fs = std::filesystem;

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string l; std::getline(s, l);) lines.push_back(l);
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string f; std::getline(s, f, ',');) out.push_back(f);
  return out;
}

#define EXPECT_ERROR_HAS(message, part) \
  EXPECT_NE(std::string(message).find(part), std::string::npos) << (message)

TEST(Dataset, QuantiseDepthMmIsThePngRoundTrip) {
  const test::TestDir dir("dataset_quantise");
  DepthImage image(64, 32);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> depth(0.0, 70.0);
  for (float& z : image.depth_m) z = float(depth(rng));
  // Ties at half millimetres, no return, out of range, invalid values.
  const float special[] = {0.f,   0.0005f, 0.0015f, 1.2345f,  2.0005f, 65.535f, 65.6f,
                           100.f, -1.f,    NAN,     INFINITY, 1e-7f,   0.4995f, 3.f};
  for (std::size_t i = 0; i < std::size(special); ++i) image.depth_m[i] = special[i];
  write_depth_png_mm(dir.path() / "d.png", image);
  const DepthImage read = read_depth_png_mm(dir.path() / "d.png");
  DepthImage quantised = image;
  quantise_depth_mm(quantised);
  ASSERT_EQ(read.depth_m.size(), quantised.depth_m.size());
  for (std::size_t i = 0; i < read.depth_m.size(); ++i)
    ASSERT_EQ(read.depth_m[i], quantised.depth_m[i])
        << "pixel " << i << " depth " << image.depth_m[i];
  EXPECT_EQ(quantised.depth_m[3], float(1235 * 1e-3));
  EXPECT_EQ(quantised.depth_m[6], float(65535 * 1e-3));  // clamped
  EXPECT_EQ(quantised.depth_m[8], 0.f);
  EXPECT_EQ(quantised.depth_m[9], 0.f);
}

// One exported dataset shared by the tests (a copy per test that damages it).
class DatasetTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TestDir("dataset_suite");
    scenario_file_ = dir_->write("scenario.yaml", test::kMeasuredScenario);
    summary_ = export_scenario(scenario_file_, {}, 17, dir_->path() / "exported");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  // A fresh copy of the exported dataset, to damage.
  static fs::path copy(const std::string& name) {
    const fs::path to = dir_->path() / name;
    fs::remove_all(to);
    fs::copy(exported(), to, fs::copy_options::recursive);
    return to;
  }
  static fs::path exported() { return dir_->path() / "exported"; }
  // Tracks a dataset with encoders only (fast); returns the error or "".
  static std::string track_error(const fs::path& dataset,
                                 std::vector<std::string> methods = {"encoders_only"}) {
    return error_of([&] {
      TrackOptions o;
      o.methods = methods;
      track_dataset(load_dataset(dataset), o, nullptr);
    });
  }

  static test::TestDir* dir_;
  static fs::path scenario_file_;
  static ExportSummary summary_;
};
test::TestDir* DatasetTest::dir_ = nullptr;
fs::path DatasetTest::scenario_file_;
ExportSummary DatasetTest::summary_;

TEST_F(DatasetTest, ExportWritesTheStreamTheTrackersGet) {
  EXPECT_EQ(summary_.joint_rows, 1501);  // 1 kHz over [0, 1.5] s
  EXPECT_EQ(summary_.frames_captured, 46);
  EXPECT_LT(summary_.frames_delivered, summary_.frames_captured);  // drops
  EXPECT_GT(summary_.frames_delivered, 30);
  const Dataset d = load_dataset(exported());
  EXPECT_EQ(d.name, "scenario");
  EXPECT_EQ(d.joint_time_s.size(), 1501u);
  EXPECT_EQ(d.joint_time_s[1], 0.001);
  ASSERT_EQ(int(d.frames.size()), summary_.frames_delivered);
  bool late = false;
  for (const DatasetFrame& f : d.frames) {
    EXPECT_TRUE(fs::is_regular_file(f.file)) << f.file;
    EXPECT_GE(f.arrival_s, f.stamp_s + 0.0);
    late = late || f.arrival_s > f.stamp_s + 0.03;
  }
  EXPECT_TRUE(late);
  EXPECT_EQ(d.camera.intrinsics.width, 80);
  EXPECT_EQ(d.camera.intrinsics.height, 60);
  // The focal length the camera reports (focal_error 0.02), not the one it
  // images with: what the trackers got.
  EXPECT_NEAR(d.camera.intrinsics.fx,
              1.02 * CameraIntrinsics::from_vertical_fov(80, 60, 50 * kRadPerDeg).fx, 1e-9);
  EXPECT_EQ(d.camera.frame, "camera_optical_frame");
  ASSERT_EQ(d.seed, run_seed(17, 0));
  EXPECT_EQ(d.truth_end_effectors, (std::vector<std::string>{"left_ee", "right_ee"}));
  EXPECT_TRUE(d.truth_has_angles);
  EXPECT_TRUE(d.truth_has_biases);
  EXPECT_EQ(d.scoring.converged_after_s, 0.5);
  ASSERT_TRUE(d.tracker_file.has_value());
  EXPECT_NE(read_text(*d.tracker_file).find("particles: 10"), std::string::npos);
  // The frames are named by their stamps.
  EXPECT_EQ(d.frames[0].file.filename(), "000000.000000.png");
}

TEST_F(DatasetTest, TrackingTheExportGivesTheRunsNumbers) {
  const Scenario scenario = load_scenario(scenario_file_);
  RunOptions ro;
  ro.seed = 17;
  ro.quantise_depth_mm = true;  // what the PNGs hold
  const ScenarioResult run = run_scenario(scenario, ro);

  const Dataset dataset = load_dataset(exported());
  std::ostringstream estimate_csv;
  const TrackResult tracked = track_dataset(dataset, {}, &estimate_csv);
  const ScenarioResult& t = tracked.result;
  EXPECT_EQ(tracked.frames_missing, 0);
  EXPECT_TRUE(tracked.warnings.empty());
  ASSERT_EQ(t.methods, run.methods);
  EXPECT_EQ(t.joint_names, run.joint_names);
  EXPECT_EQ(t.end_effectors, run.end_effectors);
  EXPECT_EQ(t.seeds, run.seeds);
  EXPECT_EQ(t.duration_s, run.duration_s);
  ASSERT_EQ(t.runs.size(), 1u);
  const RunResult& a = run.runs[0];
  const RunResult& b = t.runs[0];
  EXPECT_EQ(b.frames_delivered, a.frames_delivered);

  ASSERT_EQ(b.truth.size(), a.truth.size());
  std::size_t non_frame = 0;
  for (std::size_t i = 0; i < a.truth.size(); ++i) {
    EXPECT_EQ(b.truth[i].time_s, a.truth[i].time_s);
    EXPECT_EQ(b.truth[i].camera_frame, a.truth[i].camera_frame);
    non_frame += !a.truth[i].camera_frame;
    EXPECT_EQ(b.truth[i].angle_rad, a.truth[i].angle_rad);
    EXPECT_EQ(b.truth[i].bias_rad, a.truth[i].bias_rad);
    for (std::size_t e = 0; e < a.truth[i].T_camera_ee.size(); ++e)
      EXPECT_TRUE(b.truth[i].T_camera_ee[e].isApprox(a.truth[i].T_camera_ee[e], 1e-14));
  }
  EXPECT_GT(non_frame, 5u);  // every 70 joint steps too

  // Bit for bit: the same inputs in the same order. The truth went through
  // a quaternion: errors within rounding.
  test::expect_same_tracking(run, t, 1e-13, 1e-12);
  // Image methods did use the images.
  EXPECT_GT(b.methods[2].stats.images_applied, 30);

  // The image-methods' trajectories are not trivially equal to the plain run
  // (millimetre depths change the likelihoods); encoders only ignores images
  // and equals it exactly.
  RunOptions plain;
  plain.seed = 17;
  plain.methods = {"encoders_only"};
  const ScenarioResult unquantised = run_scenario(scenario, plain);
  for (std::size_t i = 0; i < a.truth.size(); ++i)
    ASSERT_EQ(unquantised.runs[0].methods[0].samples[i].angle_rad,
              b.methods[0].samples[i].angle_rad);

  // estimate.csv: a header, then one row per method at every truth row,
  // with the scored estimates' numbers.
  const std::vector<std::string> rows = lines_of(estimate_csv.str());
  ASSERT_EQ(rows.size(), 1 + a.truth.size() * a.methods.size());
  const std::vector<std::string> header = split(rows[0]);
  const std::size_t nj = t.joint_names.size();
  ASSERT_EQ(header.size(), 2 + 4 * nj + 6 + 7 * 2);
  EXPECT_EQ(header[2], t.joint_names[0] + "_rad");
  EXPECT_EQ(header[2 + 4 * nj], "cam_x_m");
  EXPECT_EQ(header.back(), "right_ee_qz");
  for (std::size_t i = 0; i < a.truth.size(); i += 7) {
    for (std::size_t m = 0; m < a.methods.size(); ++m) {
      const std::vector<std::string> f = split(rows[1 + i * a.methods.size() + m]);
      ASSERT_EQ(f.size(), header.size());
      EXPECT_EQ(std::stod(f[0]), a.truth[i].time_s);
      EXPECT_EQ(f[1], a.methods[m].method);
      const EstimateSample& s = b.methods[m].samples[i];
      for (std::size_t j = 0; j < nj; ++j) {
        EXPECT_EQ(std::stod(f[2 + 4 * j]), s.angle_rad[j]);
        EXPECT_EQ(std::stod(f[4 + 4 * j]), s.bias_rad[j]);
      }
      for (int k = 0; k < 6; ++k) EXPECT_EQ(std::stod(f[2 + 4 * nj + k]), s.camera_offset[k]);
      const Eigen::Vector3d p = s.T_camera_ee[1].translation();
      EXPECT_EQ(std::stod(f[2 + 4 * nj + 6 + 7]), p.x());
      EXPECT_EQ(std::stod(f[2 + 4 * nj + 6 + 9]), p.z());
    }
  }

  // The outputs of arttrack run can be written from it.
  write_run_outputs(dir_->path() / "tracked_out", t);
  EXPECT_TRUE(fs::is_regular_file(dir_->path() / "tracked_out" / "summary.json"));
}

TEST_F(DatasetTest, MissingAndUnreadableFramesAreCountedAndTrackingGoesOn) {
  const fs::path d = copy("missing_frames");
  const Dataset before = load_dataset(d);
  fs::remove(before.frames[3].file);
  write_text(before.frames[7].file, "not a png");
  const Dataset dataset = load_dataset(d);
  TrackOptions o;
  o.methods = {"encoders_only", "full_fusion"};
  o.frames_to_keep = 0;
  int warned = 0;
  o.warn = [&](const std::string&) { ++warned; };
  const TrackResult r = track_dataset(dataset, o, nullptr);
  EXPECT_EQ(r.frames_missing, 2);
  EXPECT_EQ(warned, 2);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_ERROR_HAS(r.warnings[0], before.frames[3].file.string());
  EXPECT_ERROR_HAS(r.warnings[0], "missing");
  EXPECT_ERROR_HAS(r.warnings[1], before.frames[7].file.string());
  EXPECT_EQ(r.result.runs[0].frames_delivered, int(before.frames.size()) - 2);
  EXPECT_EQ(r.result.runs[0].methods[1].stats.images_received, int(before.frames.size()) - 2);
  EXPECT_EQ(r.result.runs[0].truth.size(), std::size_t(summary_.truth_rows));
}

TEST_F(DatasetTest, JointTimeStampsOutOfOrderOrRepeatedAreErrorsWithLine) {
  const fs::path d = copy("joint_order");
  const fs::path csv = d / "joints.csv";
  std::vector<std::string> lines = lines_of(read_text(csv));
  std::vector<std::string> swapped = lines;
  std::swap(swapped[10], swapped[11]);  // file lines 11 and 12
  write_text(csv, join_lines(swapped));
  std::string e = error_of([&] { load_dataset(d); });
  EXPECT_ERROR_HAS(e, csv.string() + ":12:");
  EXPECT_ERROR_HAS(e, "out of order");

  std::vector<std::string> repeated = lines;
  repeated.insert(repeated.begin() + 21, lines[20]);  // line 21 again as line 22
  write_text(csv, join_lines(repeated));
  e = error_of([&] { load_dataset(d); });
  EXPECT_ERROR_HAS(e, csv.string() + ":22:");
  EXPECT_ERROR_HAS(e, "repeated");

  std::vector<std::string> bad = lines;
  bad[5] = bad[5].substr(0, bad[5].rfind(',')) + ",abc";
  write_text(csv, join_lines(bad));
  e = error_of([&] { load_dataset(d); });
  EXPECT_ERROR_HAS(e, csv.string() + ":6:");
  EXPECT_ERROR_HAS(e, "'abc' is not a number");

  bad = lines;
  bad[8] += ",0.5";
  write_text(csv, join_lines(bad));
  EXPECT_ERROR_HAS(error_of([&] { load_dataset(d); }), csv.string() + ":9:");
}

// Image stamps on another clock than the joints' (here a million seconds
// later) would be dropped one by one: tracking refuses them, naming the row.
TEST_F(DatasetTest, ImageAndJointClocksApartAreAnErrorNamingTheRow) {
  const fs::path d = copy("clocks_apart");
  const fs::path index = d / "depth" / "index.csv";
  std::vector<std::string> lines = lines_of(read_text(index));
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> f = split(lines[i]);
    lines[i] = std::to_string(std::stod(f[0]) + 1e6) + "," + std::to_string(std::stod(f[1]) + 1e6) +
               "," + f[2];
  }
  write_text(index, join_lines(lines));
  const std::string e = track_error(d);
  EXPECT_ERROR_HAS(e, index.string() + ":2:");
  EXPECT_ERROR_HAS(e, "input_checks.max_image_clock_offset_s");
  EXPECT_ERROR_HAS(e, "clocks differ");
}

// dataset.yaml records what reproduces the export: the program's version, the
// overrides and the resolved scenario.
TEST_F(DatasetTest, DatasetYamlRecordsTheResolvedScenario) {
  const YAML::Node meta = YAML::LoadFile((exported() / "dataset.yaml").string());
  EXPECT_EQ(meta["version"].as<std::string>(), ARTTRACK_VERSION);
  EXPECT_TRUE(meta["overrides"].IsSequence());
  const YAML::Node scenario = YAML::Load(meta["scenario"].as<std::string>());
  EXPECT_EQ(scenario["name"].as<std::string>(), load_dataset(exported()).name);
  EXPECT_TRUE(scenario["scene"].IsDefined());
}

TEST_F(DatasetTest, JointsOfTheCsvAndTheUrdfMustMatch) {
  const fs::path d = copy("joint_names");
  const fs::path csv = d / "joints.csv";
  // The ground truth (with the right joints) is kept: the error must blame
  // joints.csv, not a column of ground_truth.csv.
  const std::string text = read_text(csv);
  const std::size_t header_end = text.find('\n');
  const std::string header = text.substr(0, header_end);

  // A joint the URDF lacks.
  std::string renamed = header;
  renamed.replace(renamed.find("left_arm_joint_2"), 16, "left_arm_joint_9");
  write_text(csv, renamed + text.substr(header_end));
  std::string e = track_error(d);
  EXPECT_ERROR_HAS(e, "'left_arm_joint_9'");
  EXPECT_ERROR_HAS(e, csv.string() + ":1:");
  EXPECT_ERROR_HAS(e, "robot.urdf");
  EXPECT_EQ(e.find("ground_truth.csv"), std::string::npos) << e;

  // A joint of the URDF without a column: drop the last column everywhere.
  std::string dropped;
  for (const std::string& l : lines_of(text)) dropped += l.substr(0, l.rfind(',')) + "\n";
  write_text(csv, dropped);
  const std::string last = header.substr(header.rfind(',') + 1);
  e = track_error(d);
  EXPECT_ERROR_HAS(e, "no column for joint '" + last + "'");
  EXPECT_ERROR_HAS(e, csv.string() + ":1:");
  EXPECT_EQ(e.find("ground_truth.csv"), std::string::npos) << e;

  // A joint listed twice.
  std::string twice = header;
  twice.replace(twice.find("left_arm_joint_2"), 16, "left_arm_joint_1");
  write_text(csv, twice + text.substr(header_end));
  EXPECT_ERROR_HAS(error_of([&] { load_dataset(d); }), "'left_arm_joint_1' is listed twice");
}

TEST_F(DatasetTest, ImagesOfTheWrongSizeAreErrorsNamingTheFile) {
  const fs::path d = copy("wrong_size");
  const Dataset before = load_dataset(d);
  write_depth_png_mm(before.frames[4].file, DepthImage(40, 30, 1.5f));
  const std::string e = track_error(d);
  EXPECT_ERROR_HAS(e, before.frames[4].file.string());
  EXPECT_ERROR_HAS(e, "40x30");
  EXPECT_ERROR_HAS(e, "80x60");
}

TEST_F(DatasetTest, DepthInTheWrongUnitIsAnErrorSayingWhatWasExpected) {
  const fs::path d = copy("wrong_unit");
  const Dataset before = load_dataset(d);
  // Metres written as integers: 1 and 2 "millimetres".
  DepthImage metres(80, 60, 0.001f);
  for (int u = 0; u < 40; ++u) metres.at(u, 10) = 0.002f;
  write_depth_png_mm(before.frames[2].file, metres);
  std::string e = track_error(d);
  EXPECT_ERROR_HAS(e, before.frames[2].file.string());
  EXPECT_ERROR_HAS(e, "expected");
  EXPECT_ERROR_HAS(e, "millimetres");

  // Tenths of millimetres in a file that says millimetres: 30 m.
  const Dataset again = load_dataset(copy("wrong_unit_far"));
  write_depth_png_mm(again.frames[2].file, DepthImage(80, 60, 30.0f));
  e = track_error(again.dir);
  EXPECT_ERROR_HAS(e, again.frames[2].file.string());
  EXPECT_ERROR_HAS(e, "30000 counts");

  // The same file is right with depth_unit_m 0.0001 (3 m).
  std::string camera = read_text(again.dir / "camera.yaml");
  camera.replace(camera.find("depth_unit_m: 0.001"), 19, "depth_unit_m: 0.0001");
  write_text(again.dir / "camera.yaml", camera);
  const Dataset tenths = load_dataset(again.dir);
  std::string problem;
  const auto image = read_dataset_frame(tenths, tenths.frames[2], &problem);
  ASSERT_TRUE(image.has_value()) << problem;
  EXPECT_NEAR(image->at(5, 5), 3.0f, 1e-6);
}

TEST_F(DatasetTest, BadIndexTruthAndCameraFilesAreNamed) {
  const fs::path d = copy("bad_files");
  const fs::path index = d / "depth" / "index.csv";
  const std::string index_text = read_text(index);
  std::vector<std::string> lines = lines_of(index_text);
  std::swap(lines[3], lines[4]);
  write_text(index, join_lines(lines));
  EXPECT_ERROR_HAS(error_of([&] { load_dataset(d); }), index.string() + ":5:");
  lines = lines_of(index_text);
  std::vector<std::string> f = split(lines[2]);
  lines[2] = f[0] + "," + std::to_string(std::stod(f[0]) - 0.01) + "," + f[2];
  write_text(index, join_lines(lines));
  std::string e = error_of([&] { load_dataset(d); });
  EXPECT_ERROR_HAS(e, index.string() + ":3:");
  EXPECT_ERROR_HAS(e, "before its time stamp");
  write_text(index, index_text);

  const fs::path truth = d / "ground_truth.csv";
  const std::string truth_text = read_text(truth);
  write_text(truth, "time_s,left_ee_x,elbow_angle\n");
  e = error_of([&] { load_dataset(d); });
  EXPECT_ERROR_HAS(e, truth.string() + ":1:");
  EXPECT_ERROR_HAS(e, "'elbow_angle'");
  write_text(truth, "time_s,left_ee_x,left_ee_y,left_ee_z,left_ee_qw,left_ee_qx,left_ee_qy\n");
  EXPECT_ERROR_HAS(error_of([&] { load_dataset(d); }), "no column 'left_ee_qz'");
  lines = lines_of(truth_text);
  std::swap(lines[2], lines[3]);
  write_text(truth, join_lines(lines));
  EXPECT_ERROR_HAS(error_of([&] { load_dataset(d); }), truth.string() + ":4:");
  write_text(truth, truth_text);

  const fs::path camera = d / "camera.yaml";
  const std::string camera_text = read_text(camera);
  std::string no_fx = camera_text;
  no_fx.erase(no_fx.find("fx:"), no_fx.find('\n', no_fx.find("fx:")) - no_fx.find("fx:") + 1);
  write_text(camera, no_fx);
  e = error_of([&] { load_dataset(d); });
  EXPECT_ERROR_HAS(e, camera.string());
  EXPECT_ERROR_HAS(e, "'fx'");
  // Values that parse but make every image meaningless name their field.
  const auto with_value = [&](const std::string& key, const std::string& value) {
    std::string text = camera_text;
    const auto at = text.find("\n" + key + ":") + 1;
    text.replace(at, text.find('\n', at) - at, key + ": " + value);
    return text;
  };
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"fx", "1e-6"},
           {"fy", "1e9"},
           {"cx", "1e9"},
           {"cy", "-5"},
           {"width", "100000"}}) {  // larger than any depth PNG read (kMaxDepthPngSide)
    write_text(camera, with_value(key, value));
    e = error_of([&] { load_dataset(d); });
    EXPECT_ERROR_HAS(e, camera.string());
    EXPECT_ERROR_HAS(e, "'" + key + "'");
  }
  write_text(camera, camera_text);

  fs::remove(d / "robot.urdf");
  EXPECT_ERROR_HAS(error_of([&] { load_dataset(d); }), "neither robot.urdf nor robot.yaml");
  // robot.yaml pointing at a URDF elsewhere works.
  fs::copy_file(exported() / "robot.urdf", dir_->path() / "elsewhere.urdf",
                fs::copy_options::overwrite_existing);
  write_text(d / "robot.yaml", "urdf: ../elsewhere.urdf\n");
  EXPECT_EQ(load_dataset(d).urdf, d / "../elsewhere.urdf");
}

TEST_F(DatasetTest, WithoutIndexOrTruthFramesAreNamedByStampAndEstimatesFollowArrivals) {
  const fs::path d = copy("no_index");
  const Dataset before = load_dataset(d);
  fs::remove(d / "depth" / "index.csv");
  fs::remove(d / "ground_truth.csv");
  const Dataset dataset = load_dataset(d);
  ASSERT_EQ(dataset.frames.size(), before.frames.size());
  for (std::size_t i = 0; i < dataset.frames.size(); ++i) {
    // Stamps from the names (microseconds), arriving when captured.
    EXPECT_NEAR(dataset.frames[i].stamp_s, before.frames[i].stamp_s, 5e-7);
    EXPECT_EQ(dataset.frames[i].arrival_s, dataset.frames[i].stamp_s);
  }
  EXPECT_FALSE(dataset.has_truth());
  EXPECT_ERROR_HAS(track_error(d, {"vision_only"}), "vision_only");

  std::ostringstream csv;
  TrackOptions o;
  o.methods = {"encoders_only", "camera_offset_only"};
  const TrackResult r = track_dataset(dataset, o, &csv);
  EXPECT_TRUE(r.result.runs[0].truth.empty());
  // One row per method at every arrival.
  EXPECT_EQ(lines_of(csv.str()).size(), 1 + 2 * dataset.frames.size());
  EXPECT_EQ(r.result.runs[0].methods[1].stats.images_received, int(dataset.frames.size()));

  write_text(d / "depth" / "frame_a.png", "x");
  const std::string e = error_of([&] { load_dataset(d); });
  EXPECT_ERROR_HAS(e, "frame_a.png");
  EXPECT_ERROR_HAS(e, "time stamp");
}

}  // namespace
}  // namespace arttrack::sim
