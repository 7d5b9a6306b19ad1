#include "fuzz_targets.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

#include "arttrack/sim/dataset.h"
#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scene.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/mesh_loader.h"
#include "arttrack/tracker/model_limits.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"
#include "error_of.h"
#include "mesh_convert.h"
#include "urdf_prepare.h"

namespace arttrack::fuzz {
namespace fs = std::filesystem;

namespace {

// A private folder that mirrors the shipped models/, scenarios/ and
// tracker/config/ (a symbolic link per entry), so that an input written into
// it finds the files its references name; removed at exit.
class Scratch {
 public:
  Scratch() {
    dir_ = fs::temp_directory_path() / ("arttrack_fuzz_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    const fs::path source(ARTTRACK_SOURCE_DIR);
    for (const char* folder : {"models", "scenarios", "tracker/config"}) {
      fs::create_directories(dir_ / folder);
      for (const auto& entry : fs::directory_iterator(source / folder))
        fs::create_symlink(entry.path(), dir_ / folder / entry.path().filename());
    }
    fs::create_directories(dir_ / "urdf_work");  // prepare_urdf's work folder
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

const fs::path& scratch() {
  static const Scratch s;
  return s.dir();
}

void write_file(const fs::path& path, std::string_view data) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(data.data(), std::streamsize(data.size()));
  if (!out) throw std::runtime_error("fuzz: cannot write " + path.string());
}

// Splits off the selector byte: the index of `tags` it names (its value
// modulo their number if it is none of them), and the rest.
std::size_t select(std::string_view& data, std::string_view tags) {
  if (data.empty()) return 0;
  const char c = data.front();
  data.remove_prefix(1);
  const std::size_t i = tags.find(c);
  return i != std::string_view::npos ? i : std::size_t((unsigned char)c) % tags.size();
}

}  // namespace

std::string urdf_one(std::string_view data) {
  const fs::path models = scratch() / "models";
  std::string error =
      test_support::error_of([&] { RobotModel::from_urdf_string(std::string(data), models); });
  const fs::path file = models / "fuzz_input.urdf";
  write_file(file, data);
  const std::string prepare_error = test_support::error_of([&] {
    sim::prepare_urdf(file, {{"arttrack_models", models}}, scratch() / "urdf_work");
  });
  return error.empty() ? prepare_error : error;
}

std::string mesh_one(std::string_view data) {
  static const char* const extensions[] = {".stl", ".obj", ".dae"};
  const fs::path file = scratch() / (std::string("fuzz_mesh") + extensions[select(data, "sod")]);
  write_file(file, data);
  const Eigen::Vector3d scale(1, -2, 0.5);  // a mirroring scale takes the winding path too
  const std::string error = test_support::error_of([&] { load_mesh(file.string(), scale); });
  const std::string convert_error = test_support::error_of([&] {
    sim::convert_mesh_to_binary_stl(file, scratch() / "fuzz_mesh_out", scale, "fuzz mesh",
                                    ModelLimits::kMaxMeshTriangles);
  });
  return error.empty() ? convert_error : error;
}

std::string yaml_one(std::string_view data) {
  const std::size_t kind = select(data, "TSC");
  const fs::path folder = scratch() / (kind == 0   ? "tracker/config"
                                       : kind == 1 ? "models"
                                                   : "scenarios");
  const fs::path file = folder / "fuzz_input.yaml";
  write_file(file, data);
  return test_support::error_of([&] {
    if (kind == 0) load_tracker_config(file.string());
    if (kind == 1) sim::load_scene(file);
    if (kind == 2) sim::load_scenario(file, {});
  });
}

std::string dataset_one(std::string_view data) {
  const fs::path dir = scratch() / "dataset";
  fs::remove_all(dir);
  fs::create_directories(dir / "depth");
  // The robot is not fuzzed: the loader checks joints.csv against it, so it is
  // the shipped robot the corpus' datasets were exported with.
  fs::copy_file(fs::path(ARTTRACK_SOURCE_DIR) / "models/dual_arm.urdf", dir / "robot.urdf");
  const char* const files[] = {"camera.yaml",     "joints.csv",   "ground_truth.csv",
                               "depth/index.csv", "dataset.yaml", "depth/a.png"};
  for (const char* name : files) {
    if (data.empty()) break;
    const bool last = std::string_view(name) == "depth/a.png";
    const std::size_t end = last ? std::string_view::npos : data.find(kDatasetSeparator);
    write_file(dir / name, data.substr(0, end));
    data.remove_prefix(end == std::string_view::npos ? data.size()
                                                     : end + kDatasetSeparator.size());
  }
  return test_support::error_of([&] {
    const sim::Dataset d = sim::load_dataset(dir);
    const std::size_t n = std::min<std::size_t>(d.frames.size(), 4);
    for (std::size_t i = 0; i < n; ++i) {
      std::string problem;
      sim::read_dataset_frame(d, d.frames[i], &problem);
    }
  });
}

std::string png_one(std::string_view data) {
  const fs::path file = scratch() / "fuzz_depth.png";
  write_file(file, data);
  return test_support::error_of([&] { sim::read_depth_png_mm(file); });
}

}  // namespace arttrack::fuzz
