#include "arttrack/sim/dataset.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <sstream>

#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using text::shortest_number;

namespace {

[[noreturn]] void fail_time_order(const text::CsvReader& csv, double t, double previous) {
  csv.fail("time stamp " + shortest_number(t) + " s is " +
           (t == previous ? "repeated" : "out of order") + " (the previous row's is " +
           shortest_number(previous) + " s)");
}

// ---- the parts of a dataset ----

DatasetCamera read_camera_yaml(const fs::path& path) {
  if (!fs::is_regular_file(path)) throw InputError(path.string() + ": camera file not found");
  const YamlDocument doc = load_yaml_file(path.string());
  const ConfigNode n = ConfigNode::root(doc);
  DatasetCamera c;
  for (const char* key : {"width", "height"}) {
    // The frames are depth PNGs, which are read up to kMaxDepthPngSide.
    const double v = n.required_number(key, 1, kMaxDepthPngSide);
    if (v != std::floor(v)) n.fail(key, "must be a whole number of pixels");
    (std::string(key) == "width" ? c.intrinsics.width : c.intrinsics.height) = int(v);
  }
  c.intrinsics.fx = n.required_number("fx", 1e-6, 1e9);
  c.intrinsics.fy = n.required_number("fy", 1e-6, 1e9);
  c.intrinsics.cx = n.required_number("cx", -1e9, 1e9);
  c.intrinsics.cy = n.required_number("cy", -1e9, 1e9);
  if (const std::string p = c.intrinsics.problem(); !p.empty()) {
    const auto colon = p.find(':');
    n.fail(p.substr(0, colon), p.substr(colon + 2));
  }
  c.frame = n.get<std::string>("frame", c.frame);
  if (n.has("delay_s")) c.delay_s = n.number("delay_s", 0, 0, 10);
  c.depth_unit_m = n.number("depth_unit_m", c.depth_unit_m, 1e-9, 1);
  n.finish();
  return c;
}

void read_robot(const fs::path& dir, const std::optional<fs::path>& urdf_override, Dataset& d) {
  if (urdf_override) {
    d.urdf = *urdf_override;
  } else if (fs::is_regular_file(dir / "robot.urdf")) {
    d.urdf = dir / "robot.urdf";
  } else if (fs::is_regular_file(dir / "robot.yaml")) {
    const YamlDocument doc = load_yaml_file((dir / "robot.yaml").string());
    const ConfigNode n = ConfigNode::root(doc);
    const fs::path urdf = n.required<std::string>("urdf");
    d.urdf = urdf.is_absolute() ? urdf : dir / urdf;
    const ConfigNode packages = n.child("packages");
    for (const std::string& name : packages.keys()) {
      const fs::path p = packages.required<std::string>(name);
      d.mesh_search_paths.push_back((p.is_absolute() ? p : dir / p).string());
    }
    n.finish();
  } else {
    throw InputError(dir.string() + ": dataset has neither robot.urdf nor robot.yaml");
  }
  if (!fs::is_regular_file(d.urdf)) throw InputError(d.urdf.string() + ": URDF not found");
}

void read_joints(const fs::path& path, Dataset& d) {
  if (!fs::is_regular_file(path)) throw InputError(path.string() + ": joint readings not found");
  text::CsvReader csv(path, text::CsvSpace::kTrim);
  std::vector<std::string> header, row;
  if (!csv.next(header)) csv.fail("is empty (expected a header time_s,<joint names...>)");
  if (header[0] != "time_s") csv.fail("the first column must be time_s, not '" + header[0] + "'");
  std::set<std::string> seen;
  for (std::size_t i = 1; i < header.size(); ++i) {
    if (header[i].empty()) csv.fail("column " + std::to_string(i + 1) + " has no joint name");
    if (!seen.insert(header[i]).second) csv.fail("joint '" + header[i] + "' is listed twice");
    d.joint_names.push_back(header[i]);
  }
  if (d.joint_names.empty()) csv.fail("names no joint");
  while (csv.next(row)) {
    csv.expect_width(row, header.size());
    const double t = csv.finite(row, 0, header);
    if (!d.joint_time_s.empty() && !(t > d.joint_time_s.back()))
      fail_time_order(csv, t, d.joint_time_s.back());
    d.joint_time_s.push_back(t);
    for (std::size_t i = 1; i < row.size(); ++i)
      d.joint_readings_rad.push_back(csv.finite(row, i, header));
  }
  if (d.joint_time_s.empty()) throw InputError(path.string() + ": has no readings");
}

// The joints of joints.csv against the URDF's, before the ground truth
// (whose columns are checked against joints.csv) can blame itself for them.
// track_dataset checks them against the tracker's model in full.
void check_joint_columns(const fs::path& path, const Dataset& d) {
  const UrdfSummary urdf = read_urdf_summary(d.urdf);
  for (const std::string& name : d.joint_names)
    if (!urdf.has_joint(name))
      throw InputError(path.string() + ":1: joint '" + name + "' is not a joint of " +
                       d.urdf.string());
  for (const std::string& name : urdf.movable_joints)
    if (std::find(d.joint_names.begin(), d.joint_names.end(), name) == d.joint_names.end())
      throw InputError(path.string() + ":1: has no column for joint '" + name + "' of " +
                       d.urdf.string());
}

void read_frames(const fs::path& depth_dir, Dataset& d) {
  if (!fs::is_directory(depth_dir)) return;
  const fs::path index = depth_dir / "index.csv";
  if (fs::is_regular_file(index)) {
    text::CsvReader csv(index, text::CsvSpace::kTrim);
    std::vector<std::string> header, row;
    if (!csv.next(header) || header != std::vector<std::string>{"stamp_s", "arrival_s", "file"})
      csv.fail("the header must be stamp_s,arrival_s,file");
    while (csv.next(row)) {
      csv.expect_width(row, 3);
      DatasetFrame f;
      f.stamp_s = csv.finite(row, 0, header);
      f.arrival_s = csv.finite(row, 1, header);
      if (row[2].empty()) csv.fail("no file named");
      f.file = depth_dir / row[2];
      f.where = csv.where();
      if (f.arrival_s < f.stamp_s) csv.fail("arrives before its time stamp");
      if (!d.frames.empty()) {
        const DatasetFrame& p = d.frames.back();
        if (f.arrival_s < p.arrival_s)
          csv.fail("rows must be in arrival order: arrives before the previous row");
        if (!(f.stamp_s > p.stamp_s)) fail_time_order(csv, f.stamp_s, p.stamp_s);
      }
      d.frames.push_back(std::move(f));
    }
    return;
  }
  // No index: every PNG named by its stamp, arriving when captured.
  for (const auto& entry : fs::directory_iterator(depth_dir)) {
    if (entry.path().extension() != ".png") continue;
    double stamp = 0;
    if (!text::parse_number(entry.path().stem().string(), stamp))
      throw InputError(entry.path().string() +
                       ": a depth file name must be its time stamp in seconds (e.g. "
                       "000012.345678.png), or depth/index.csv must list the files");
    d.frames.push_back({stamp, stamp, entry.path(), entry.path().string()});
  }
  std::sort(d.frames.begin(), d.frames.end(),
            [](const DatasetFrame& a, const DatasetFrame& b) { return a.stamp_s < b.stamp_s; });
  for (std::size_t i = 1; i < d.frames.size(); ++i)
    if (d.frames[i].stamp_s == d.frames[i - 1].stamp_s)
      throw InputError(d.frames[i].file.string() + ": same time stamp as " +
                       d.frames[i - 1].file.string());
}

void read_truth(const fs::path& path, Dataset& d) {
  if (!fs::is_regular_file(path)) return;
  text::CsvReader csv(path, text::CsvSpace::kTrim);
  std::vector<std::string> header, row;
  if (!csv.next(header)) csv.fail("is empty (expected a header starting with time_s)");
  // What each column holds.
  enum Kind { kTime, kCameraFrame, kOccluded, kAngle, kBias, kPose };
  struct Column {
    Kind kind;
    int index = 0;  // joint (joint_names order), end effector, or pose component
    int component = 0;
  };
  std::vector<Column> columns;
  std::map<std::string, int> joint_of;
  for (std::size_t j = 0; j < d.joint_names.size(); ++j) joint_of[d.joint_names[j]] = int(j);
  std::vector<int> angle_seen(d.joint_names.size(), 0), bias_seen(d.joint_names.size(), 0);
  std::vector<std::vector<int>> pose_seen;
  std::set<std::string> names;
  bool has_time = false;
  for (const std::string& h : header) {
    if (!names.insert(h).second) csv.fail("column '" + h + "' appears twice");
    auto ends_with = [&](const char* s) {
      const std::size_t n = std::strlen(s);
      return h.size() > n && h.compare(h.size() - n, n, s) == 0;
    };
    if (h == "time_s") {
      columns.push_back({kTime});
      has_time = true;
    } else if (h == "camera_frame") {
      columns.push_back({kCameraFrame});
    } else if (h == "occluded_fraction") {
      columns.push_back({kOccluded});
    } else if (joint_of.count(h)) {
      columns.push_back({kAngle, joint_of[h]});
      angle_seen[joint_of[h]] = 1;
    } else if (ends_with("_bias") && joint_of.count(h.substr(0, h.size() - 5))) {
      const int j = joint_of[h.substr(0, h.size() - 5)];
      columns.push_back({kBias, j});
      bias_seen[j] = 1;
    } else {
      int component = -1;
      for (int c = 0; c < 7; ++c)
        if (ends_with(text::kPoseSuffixes[c])) component = c;
      // "_qx" also ends in "_x": the longest suffix wins.
      for (int c = 3; c < 7; ++c)
        if (ends_with(text::kPoseSuffixes[c])) component = c;
      if (component < 0)
        csv.fail("column '" + h +
                 "' is not time_s, camera_frame, occluded_fraction, a joint of joints.csv (J or "
                 "J_bias) or an end-effector pose component (E_x, E_y, E_z, E_qw, E_qx, E_qy, "
                 "E_qz)");
      const std::string ee = h.substr(0, h.size() - std::strlen(text::kPoseSuffixes[component]));
      auto it = std::find(d.truth_end_effectors.begin(), d.truth_end_effectors.end(), ee);
      if (it == d.truth_end_effectors.end()) {
        d.truth_end_effectors.push_back(ee);
        pose_seen.emplace_back(7, 0);
        it = d.truth_end_effectors.end() - 1;
      }
      const int e = int(it - d.truth_end_effectors.begin());
      columns.push_back({kPose, e, component});
      pose_seen[e][component] = 1;
    }
  }
  if (!has_time) csv.fail("has no time_s column");
  for (std::size_t e = 0; e < pose_seen.size(); ++e)
    for (int c = 0; c < 7; ++c)
      if (!pose_seen[e][c])
        csv.fail("end effector '" + d.truth_end_effectors[e] + "' has no column '" +
                 d.truth_end_effectors[e] + text::kPoseSuffixes[c] + "'");
  if (d.truth_end_effectors.empty())
    csv.fail("has no end-effector pose columns (E_x, E_y, E_z, E_qw, E_qx, E_qy, E_qz)");
  auto all_or_none = [&](const std::vector<int>& seen, const char* suffix) {
    const bool any = std::find(seen.begin(), seen.end(), 1) != seen.end();
    for (std::size_t j = 0; j < seen.size() && any; ++j)
      if (!seen[j])
        csv.fail("has columns for some joints of joints.csv but not '" + d.joint_names[j] + suffix +
                 "' (give every joint or none)");
    return any;
  };
  d.truth_has_angles = all_or_none(angle_seen, "");
  d.truth_has_biases = all_or_none(bias_seen, "_bias");

  const std::size_t nj = d.joint_names.size(), ne = d.truth_end_effectors.size();
  std::vector<double> pose(7 * ne);
  while (csv.next(row)) {
    csv.expect_width(row, header.size());
    TruthSample s;
    s.camera_frame = true;
    s.angle_rad = Eigen::VectorXd::Constant(Eigen::Index(nj), kNaN);
    s.bias_rad = Eigen::VectorXd::Constant(Eigen::Index(nj), kNaN);
    for (std::size_t i = 0; i < row.size(); ++i) {
      const Column& c = columns[i];
      switch (c.kind) {
        case kTime:
          s.time_s = csv.finite(row, i, header);
          break;
        case kCameraFrame: {
          const double v = csv.number(row, i, header);
          if (v != 0 && v != 1) csv.fail("column 'camera_frame' must be 0 or 1");
          s.camera_frame = v == 1;
          break;
        }
        case kOccluded:
          s.occluded_fraction = csv.number(row, i, header);
          break;
        case kAngle:
          s.angle_rad[c.index] = csv.finite(row, i, header);
          break;
        case kBias:
          s.bias_rad[c.index] = csv.finite(row, i, header);
          break;
        case kPose:
          pose[7 * c.index + c.component] = csv.finite(row, i, header);
          break;
      }
    }
    if (!d.truth.empty() && !(s.time_s > d.truth.back().time_s))
      fail_time_order(csv, s.time_s, d.truth.back().time_s);
    for (std::size_t e = 0; e < ne; ++e) {
      const double* p = &pose[7 * e];
      Eigen::Quaterniond q(p[3], p[4], p[5], p[6]);
      if (std::abs(q.norm() - 1.0) > 1e-3)
        csv.fail("the quaternion of '" + d.truth_end_effectors[e] + "' is not a unit one (norm " +
                 shortest_number(q.norm()) + ")");
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = q.normalized().toRotationMatrix();
      T.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
      s.T_camera_ee.push_back(T);
    }
    d.truth.push_back(std::move(s));
  }
}

void read_dataset_yaml(const fs::path& path, Dataset& d) {
  if (!fs::is_regular_file(path)) return;
  const YamlDocument doc = load_yaml_file(path.string());
  const ConfigNode n = ConfigNode::root(doc);
  d.name = n.get<std::string>("name", d.name);
  // Informational: where it was exported from (the scenario resolved).
  n.get<std::string>("source", "");
  n.get<std::string>("version", "");
  n.get<std::vector<std::string>>("overrides", {});
  n.get<std::string>("scenario", "");
  if (n.has("seed")) {
    const double seed = n.number("seed", 0, 0, 9007199254740992.0);
    if (seed != std::floor(seed)) n.fail("seed", "must be a whole number");
    d.seed = n.required<std::uint64_t>("seed");
  }
  if (n.has("duration_s")) d.duration_s = n.number("duration_s", 0, 1e-9, 1e9);
  d.methods = n.get<std::vector<std::string>>("methods", {});
  for (const std::string& m : d.methods) parse_method(m, path.string() + ": key 'methods'");
  read_scoring_options(n.child("scoring"), d.scoring);
  n.finish();
}

}  // namespace

Dataset load_dataset(const fs::path& dir, const std::optional<fs::path>& urdf_override) {
  if (!fs::is_directory(dir)) throw InputError(dir.string() + ": dataset folder not found");
  Dataset d;
  d.dir = dir;
  const fs::path absolute = fs::absolute(dir).lexically_normal();
  d.name = (absolute.has_filename() ? absolute : absolute.parent_path()).filename().string();
  d.camera = read_camera_yaml(dir / "camera.yaml");
  read_robot(dir, urdf_override, d);
  read_joints(dir / "joints.csv", d);
  check_joint_columns(dir / "joints.csv", d);
  read_frames(dir / "depth", d);
  read_truth(dir / "ground_truth.csv", d);
  read_dataset_yaml(dir / "dataset.yaml", d);
  if (fs::is_regular_file(dir / "tracker.yaml")) d.tracker_file = dir / "tracker.yaml";
  return d;
}

std::optional<DepthImage> read_dataset_frame(const Dataset& dataset, const DatasetFrame& frame,
                                             std::string* problem) {
  const std::string name = frame.file.string();
  if (!fs::is_regular_file(frame.file)) {
    if (problem) *problem = name + ": depth image missing (listed at " + frame.where + ")";
    return std::nullopt;
  }
  DepthImage image;
  try {
    image = read_depth_png_mm(frame.file);
  } catch (const InputError& e) {
    if (problem) *problem = e.what();
    return std::nullopt;
  }
  const CameraIntrinsics& K = dataset.camera.intrinsics;
  if (image.width != K.width || image.height != K.height)
    throw InputError(name + ": image is " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " pixels, camera.yaml says " +
                     std::to_string(K.width) + "x" + std::to_string(K.height));
  // The unit, judged by the median valid count: a scene is between 2 cm and
  // 20 m away; metres written as integers give counts of a few units.
  std::vector<float> valid;
  for (float z : image.depth_m)
    if (z > 0) valid.push_back(z);
  const double unit_scale = dataset.camera.depth_unit_m / 1e-3;
  if (!valid.empty()) {
    auto mid = valid.begin() + std::ptrdiff_t(valid.size() / 2);
    std::nth_element(valid.begin(), mid, valid.end());
    const double counts = std::round(double(*mid) * 1000.0);
    const double median_m = counts * dataset.camera.depth_unit_m;
    if (median_m < 0.02 || median_m > 20.0) {
      std::ostringstream os;
      os << name << ": the median valid depth is " << counts << " counts, " << median_m
         << " m at depth_unit_m " << dataset.camera.depth_unit_m
         << "; expected a 16-bit PNG of depths in units of depth_unit_m (millimetres by "
            "default: a median between "
         << std::lround(0.02 / dataset.camera.depth_unit_m) << " and "
         << std::lround(20.0 / dataset.camera.depth_unit_m)
         << " counts); metres written as integers or a wrong depth_unit_m in camera.yaml?";
      throw InputError(os.str());
    }
  }
  if (unit_scale != 1.0)
    for (float& z : image.depth_m) z = float(z * unit_scale);
  return image;
}

}  // namespace arttrack::sim
