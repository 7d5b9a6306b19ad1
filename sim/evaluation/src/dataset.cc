#include "arttrack/sim/dataset.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/method_trackers.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using text::shortest_number;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

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

// ---- reading ----

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

// ---- writing ----

struct DatasetWriter::Files {
  std::ofstream joints, index, truth;
};

namespace {

std::ofstream open_for_writing(const fs::path& path) {
  std::ofstream out(path);
  if (!out) throw InputError(path.string() + ": cannot open for writing");
  return out;
}

// "000012.345678": the stamp in microseconds, sortable as text.
std::string stamp_file_name(double stamp_s) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%013.6f.png", stamp_s);
  return buf;
}

}  // namespace

DatasetWriter::DatasetWriter(const fs::path& dir) : dir_(dir), files_(std::make_unique<Files>()) {
  std::error_code ec;
  fs::create_directories(dir / "depth", ec);
  if (ec) throw InputError((dir / "depth").string() + ": cannot create: " + ec.message());
  // A previous export's frames would linger next to the new index.
  for (const auto& entry : fs::directory_iterator(dir / "depth"))
    if (entry.path().extension() == ".png") fs::remove(entry.path());
}

DatasetWriter::~DatasetWriter() = default;

void DatasetWriter::begin_run(const RunStart& start) {
  if (start.run != 0) return;
  start_ = start;
  files_->joints = open_for_writing(dir_ / "joints.csv");
  files_->joints << "time_s";
  for (const std::string& j : start.encoder_joints) files_->joints << ',' << j;
  files_->joints << '\n';
  files_->index = open_for_writing(dir_ / "depth" / "index.csv");
  files_->index << "stamp_s,arrival_s,file\n";
  files_->truth = open_for_writing(dir_ / "ground_truth.csv");
  std::ostream& t = files_->truth;
  t << "time_s,camera_frame,occluded_fraction";
  for (const std::string& j : start.truth_joints) t << ',' << j;
  for (const std::string& j : start.truth_joints) t << ',' << j << "_bias";
  for (const std::string& e : start.end_effectors)
    for (const char* s : text::kPoseSuffixes) t << ',' << e << s;
  t << '\n';
}

void DatasetWriter::joints(int run, double time_s, std::span<const double> readings_rad) {
  if (run != 0) return;
  std::ostream& out = files_->joints;
  out << shortest_number(time_s);
  for (double r : readings_rad) out << ',' << shortest_number(r);
  out << '\n';
  ++joint_rows_;
}

void DatasetWriter::image(int run, double stamp_s, double arrival_s, const DepthImage& image) {
  if (run != 0) return;
  const std::string file = stamp_file_name(stamp_s);
  write_depth_png_mm(dir_ / "depth" / file, image);
  files_->index << shortest_number(stamp_s) << ',' << shortest_number(arrival_s) << ',' << file
                << '\n';
  ++frames_;
}

void DatasetWriter::truth(int run, const TruthSample& truth) {
  if (run != 0) return;
  std::ostream& out = files_->truth;
  out << shortest_number(truth.time_s) << ',' << (truth.camera_frame ? 1 : 0) << ','
      << shortest_number(truth.occluded_fraction);
  for (Eigen::Index j = 0; j < truth.angle_rad.size(); ++j)
    out << ',' << shortest_number(truth.angle_rad[j]);
  for (Eigen::Index j = 0; j < truth.bias_rad.size(); ++j)
    out << ',' << shortest_number(truth.bias_rad[j]);
  for (const Eigen::Isometry3d& T : truth.T_camera_ee) out << text::pose_fields(T);
  out << '\n';
  ++truth_rows_;
}

void DatasetWriter::finish() {
  for (auto [file, name] :
       {std::pair{&files_->joints, "joints.csv"}, std::pair{&files_->index, "depth/index.csv"},
        std::pair{&files_->truth, "ground_truth.csv"}}) {
    if (!file->is_open()) continue;
    file->close();
    if (!*file) throw InputError((dir_ / name).string() + ": write failed");
  }
}

namespace {

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out = open_for_writing(path);
  out << text;
  out.close();
  if (!out) throw InputError(path.string() + ": write failed");
}

// The tracker's URDF (with the scene's camera mount) with every mesh copied into DIR/meshes/ and
// named relative to it, so that the dataset loads from anywhere.
void write_robot(const Scenario& sc, const fs::path& dir) {
  const std::string resolved = mounted_urdf_text(sc.scene, sc.tracker_urdf());
  tinyxml2::XMLDocument doc;
  if (doc.Parse(resolved.c_str(), resolved.size()) != tinyxml2::XML_SUCCESS)
    throw InputError(sc.tracker_urdf().string() + ": cannot parse the URDF");
  std::map<fs::path, std::string> copied;  // source -> name in meshes/
  std::set<std::string> used;
  std::vector<tinyxml2::XMLElement*> stack{doc.RootElement()};
  while (!stack.empty()) {
    tinyxml2::XMLElement* e = stack.back();
    stack.pop_back();
    for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) stack.push_back(c);
    if (std::string(e->Name()) != "mesh" || !e->Attribute("filename")) continue;
    const fs::path source = e->Attribute("filename");
    auto it = copied.find(source);
    if (it == copied.end()) {
      std::string name = source.filename().string();
      for (int k = 1; used.count(name); ++k)
        name = source.stem().string() + "_" + std::to_string(k) + source.extension().string();
      used.insert(name);
      fs::create_directories(dir / "meshes");
      std::error_code ec;
      fs::copy_file(source, dir / "meshes" / name, fs::copy_options::overwrite_existing, ec);
      if (ec) throw InputError(source.string() + ": cannot copy the mesh: " + ec.message());
      it = copied.emplace(source, name).first;
    }
    e->SetAttribute("filename", ("meshes/" + it->second).c_str());
  }
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  write_text(dir / "robot.urdf", printer.CStr());
}

// The scenario's tracker configuration as the runner builds it: its file
// with the scene's and the scenario's tracker_overrides, the scene's camera
// link, the scored end effectors and the run's tracker seed. The method is
// set per tracker.
std::string tracker_yaml(const Scenario& sc, unsigned long long tracker_seed) {
  YamlDocument doc{YAML::Clone(sc.tracker_document.root), sc.tracker_document.file};
  doc.root.remove("method");
  doc.root["camera_frame"] = sc.tracker.camera_frame;
  doc.root["end_effectors"] = sc.tracker.end_effectors;
  doc.root["particle_filter"]["seed"] = tracker_seed;
  doc.root["timing"]["asynchronous"] = false;
  tracker_config_from_yaml(doc);  // it must read back
  YAML::Emitter out;
  out << doc.root;
  return "# The tracker configuration of the exported run (" + doc.file +
         " with the scene's and the scenario's tracker_overrides and the run's seed); the "
         "method is set per tracker.\n" +
         out.c_str() + "\n";
}

}  // namespace

ExportSummary export_scenario(const fs::path& scenario_file,
                              const std::vector<std::string>& overrides, long long seed,
                              const fs::path& out_dir) {
  const Scenario sc = load_scenario(scenario_file, overrides);
  DatasetWriter writer(out_dir);
  RunOptions options;
  options.runs = 1;
  options.seed = seed;
  // Trackers do not change the measurements; the cheapest one runs.
  options.methods = {method_name(TrackingMethod::kEncodersOnly)};
  options.frames_to_keep = 0;
  options.sink = &writer;
  const ScenarioResult result = run_scenario(sc, options);
  writer.finish();

  const RunStart& start = writer.start();
  const CameraIntrinsics& K = start.camera;
  std::ostringstream camera;
  camera << "# Depth camera of the exported scenario: pinhole intrinsics (pixels), the URDF link\n"
            "# of its optical frame, the nominal delay the tracker assumes, metres per PNG count.\n"
         << "width: " << K.width << "\nheight: " << K.height << "\nfx: " << shortest_number(K.fx)
         << "\nfy: " << shortest_number(K.fy) << "\ncx: " << shortest_number(K.cx)
         << "\ncy: " << shortest_number(K.cy) << "\nframe: " << sc.scene.camera_link
         << "\ndelay_s: " << shortest_number(sc.tracker.camera_delay_s)
         << "\ndepth_unit_m: 0.001\n";
  write_text(out_dir / "camera.yaml", camera.str());
  write_robot(sc, out_dir);
  write_text(out_dir / "tracker.yaml", tracker_yaml(sc, start.tracker_seed));

  YAML::Emitter meta;
  meta << YAML::BeginMap << YAML::Key << "name" << YAML::Value << sc.name << YAML::Key << "source"
       << YAML::Value << sc.source << YAML::Key << "seed" << YAML::Value << start.seed << YAML::Key
       << "duration_s" << YAML::Value << shortest_number(sc.duration_s) << YAML::Key << "methods"
       << YAML::Value << YAML::Flow << sc.methods << YAML::Key << "scoring" << YAML::Value
       << YAML::BeginMap << YAML::Key << "converged_after_s" << YAML::Value
       << shortest_number(sc.scoring.options.converged_after_s) << YAML::Key
       << "convergence_threshold_m" << YAML::Value
       << shortest_number(sc.scoring.options.convergence_threshold_m) << YAML::Key
       << "lost_threshold_m" << YAML::Value << shortest_number(sc.scoring.options.lost_threshold_m)
       << YAML::Key << "lost_after_s" << YAML::Value
       << shortest_number(sc.scoring.options.lost_after_s) << YAML::EndMap << YAML::Key << "version"
       << YAML::Value << result.recipe.version << YAML::Key << "overrides" << YAML::Value
       << YAML::Flow << overrides << YAML::Key << "scenario" << YAML::Value << YAML::Literal
       << sc.resolved_yaml << YAML::EndMap;
  write_text(
      out_dir / "dataset.yaml",
      std::string("# Exported by arttrack export: run 0 of the scenario.\n") + meta.c_str() + "\n");

  ExportSummary summary;
  summary.run_seed = start.seed;
  summary.joint_rows = writer.joint_rows();
  summary.frames_captured = result.runs[0].frames_captured;
  summary.frames_delivered = writer.frames();
  summary.truth_rows = writer.truth_rows();
  return summary;
}

// ---- tracking ----

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
