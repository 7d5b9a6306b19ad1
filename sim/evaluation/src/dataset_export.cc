#include "arttrack/sim/dataset.h"

#include <tinyxml2.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using text::shortest_number;

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

}  // namespace arttrack::sim
