// The testbed half of the Python module: the library functions the
// arttrack program's run, render, export and track commands call
// (tools/arttrack_*.cc), with the same checks of their arguments
// (tools/commands.h) and the same outputs (sim/run_outputs.h).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "arttrack/sim/dataset.h"
#include "arttrack/sim/dataset_tracking.h"
#include "arttrack/sim/depth_png.h"
#include "arttrack/sim/run_outputs.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/sim/scene_render.h"
#include "arttrack/tracker/error.h"
#include "bindings.h"
#include "commands.h"

namespace arttrack::python {
namespace {

namespace fs = std::filesystem;
using namespace pybind11::literals;

// The `methods` argument: None (the scenario's or dataset's), a list of
// names or one comma-separated str, checked as --methods is.
std::vector<std::string> method_list(const py::handle& methods) {
  if (methods.is_none()) return {};
  std::string text;
  if (py::isinstance<py::str>(methods)) {
    text = methods.cast<std::string>();
  } else {
    bool first = true;
    for (const py::handle m : methods)
      text += (first ? "" : ",") + m.cast<std::string>(), first = false;
  }
  if (const std::string problem = cli::comma_list()(text); !problem.empty())
    throw cli::UsageError("methods: " + problem);
  std::vector<std::string> out = cli::split_commas(text);
  for (const std::string& m : out) parse_method(m, "methods");
  return out;
}

long long seed_of(const std::optional<long long>& seed) {
  if (seed && *seed < 0) throw cli::UsageError("seed: must be >= 0");
  return seed.value_or(-1);
}

py::array_t<float> depth_array(const DepthImage& d) {
  py::array_t<float> out({py::ssize_t(d.height), py::ssize_t(d.width)});
  std::copy(d.depth_m.begin(), d.depth_m.end(), out.mutable_data());
  return out;
}

// A table's columns as a dict {name: 1-D array}: float64 for numbers, str
// arrays for text.
py::dict columns_dict(const std::vector<sim::TimeseriesColumn>& columns) {
  const py::object array = py::module_::import("numpy").attr("array");
  py::dict out;
  for (const sim::TimeseriesColumn& c : columns) {
    if (c.is_text)
      out[py::str(c.name)] = array(py::cast(c.text), "dtype"_a = "str");
    else
      out[py::str(c.name)] = py::array_t<double>(py::ssize_t(c.numbers.size()), c.numbers.data());
  }
  return out;
}

// estimate.csv (track_dataset's) as columns: `method` text, the rest numbers.
std::vector<sim::TimeseriesColumn> csv_columns(const std::string& text) {
  std::vector<sim::TimeseriesColumn> columns;
  std::istringstream in(text);
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string field;
    for (std::size_t c = 0; std::getline(fields, field, ','); ++c) {
      if (header) {
        columns.push_back({field, {}, {}, field == "method"});
      } else if (columns[c].is_text) {
        columns[c].text.push_back(field);
      } else {
        columns[c].numbers.push_back(std::stod(field));
      }
    }
    header = false;
  }
  return columns;
}

// What run_scenario and track_dataset return for a ScenarioResult.
py::dict result_dict(const sim::ScenarioResult& result, const std::vector<fs::path>& written) {
  py::dict out;
  out["summary"] = py::module_::import("json").attr("loads")(sim::summary_json(result));
  out["timeseries"] = columns_dict(sim::timeseries_table(result).columns);
  std::vector<std::string> files;
  for (const fs::path& f : written) files.push_back(f.string());
  out["files"] = files;
  return out;
}

}  // namespace

void bind_testbed(py::module_& m) {
  m.def(
      "run_scenario",
      [](const std::optional<std::string>& scenario, const py::object& overrides,
         std::optional<long long> seed, std::optional<int> runs, const py::object& methods,
         const std::optional<std::string>& out, bool force) {
        const std::vector<std::string> assignments = override_assignments(overrides);
        sim::RunOptions options;
        options.methods = method_list(methods);
        options.seed = seed_of(seed);
        if (runs && *runs < 1) throw cli::UsageError("runs: must be >= 1");
        if (runs && *runs > cli::kMaxRuns)
          throw cli::UsageError("runs: must be at most " + std::to_string(cli::kMaxRuns));
        options.runs = runs.value_or(0);
        sim::ScenarioResult result;
        std::vector<fs::path> written;
        {
          py::gil_scoped_release release;
          const sim::Scenario s = sim::load_scenario(
              scenario ? fs::path(*scenario) : sim::default_scenario_path(), assignments);
          if (out) cli::check_fresh_output(*out, {"summary.json", "timeseries.csv"}, force);
          result = sim::run_scenario(s, options);
          if (out) written = sim::write_run_outputs(*out, result);
        }
        return result_dict(result, written);
      },
      "scenario"_a = py::none(), "overrides"_a = py::none(), "seed"_a = py::none(),
      "runs"_a = py::none(), "methods"_a = py::none(), "out"_a = py::none(), "force"_a = false,
      R"(Runs a scenario as `arttrack run` does: simulates the robot, tracks it with each
method, scores the estimates against the ground truth.

scenario: a scenario YAML (default scenarios/default.yaml). overrides: scenario
keys as --set takes them (a dict {key: value} or a list of 'key=value'; e.g.
{'duration_s': 2, 'encoders[0].offset_deg': 5}). seed: the scenario seed the
runs' seeds derive from (>= 0; default the scenario's). runs: number of runs
(1 to 100000; default the scenario's). methods: a list of encoders_only,
camera_offset_only, full_fusion, vision_only (default the scenario's).
out: also write summary.json, timeseries.csv, report.html and frames/ there
(a folder holding a previous run's outputs needs force=True).

Returns a dict: 'summary' (summary.json as a dict: per method the
end-effector errors in m and rad, convergence time in s, consistency, timings),
'timeseries' (timeseries.csv's columns in its order: {name: 1-D array}, one
row per run, scored instant and method; float64 but for 'method' and
'health_state', str; the same values as the file, to the bit) and 'files'
(those written). Raises InputError (bad scenario, key or value), UsageError
(runs, seed, methods, out without force). The GIL is released while it runs.)");

  m.def(
      "render_scene",
      [](const std::optional<std::string>& scene, double time_s, std::optional<long long> seed) {
        const long long s = seed_of(seed);
        sim::SceneRender r;
        {
          py::gil_scoped_release release;
          r = sim::render_scene(scene ? fs::path(*scene) : sim::default_scene_path(), time_s, s);
        }
        py::dict joint_angles;
        for (std::size_t j = 0; j < r.joint_names.size(); ++j)
          joint_angles[py::str(r.joint_names[j])] = r.joint_angle_rad[j];
        return py::dict(
            "scene_depth"_a = depth_array(r.scene_depth),
            "robot_depth"_a = depth_array(r.robot_depth),
            "model_depth"_a = depth_array(r.model_depth), "camera"_a = r.camera,
            "time_s"_a = r.time_s, "joint_angles"_a = joint_angles, "scene_file"_a = r.scene_file,
            "simulated_urdf"_a = r.simulated_urdf, "model_mismatch"_a = r.model_mismatch,
            "model_triangles"_a = r.model_triangles, "drawn_triangles"_a = r.drawn_triangles);
      },
      "scene"_a = py::none(), "time_s"_a = 0.0, "seed"_a = py::none(),
      R"(Renders a scene as `arttrack render` does: simulates it to time_s (s, in
[0, 3600]) and renders its depth camera. A scene holds the home pose; a
scenario's is its first run's (seed: the scenario's if None) at the joint step
nearest time_s, simulated as run_scenario simulates it (its motion, loads and
occluders) on the robot that run simulates (its model_mismatch, head error and
camera miscalibration).

scene: a scene YAML or a scenario naming one (default models/scene_default.yaml).
Returns a dict: 'scene_depth' (MuJoCo's depth of the whole scene), 'robot_depth'
(of the robot alone), 'model_depth' (the tracker's render of the robot at the
true angles from the true camera with the geometry it draws: where it differs
from robot_depth, the model error), each a float32 array (height, width) of
metres along the optical axis, 0 = no return; 'camera' (Camera), 'time_s',
'joint_angles' ({joint: the simulated robot's true angle then, rad}),
'scene_file', 'simulated_urdf', 'model_mismatch' (how the simulated robot
differs from the tracker's, or 'none'), 'model_triangles', 'drawn_triangles'.
Raises InputError. The GIL is released while it runs.)");

  m.def(
      "export_dataset",
      [](const std::string& scenario, const std::string& out, const py::object& overrides,
         std::optional<long long> seed, bool force) {
        const std::vector<std::string> assignments = override_assignments(overrides);
        const long long s = seed_of(seed);
        if (out.empty()) throw cli::UsageError("out: must not be empty");
        sim::ExportSummary e;
        {
          py::gil_scoped_release release;
          cli::check_fresh_output(out, {"dataset.yaml", "joints.csv"}, force);
          e = sim::export_scenario(scenario, assignments, s, out);
        }
        return py::dict("run_seed"_a = e.run_seed, "joint_rows"_a = e.joint_rows,
                        "frames_captured"_a = e.frames_captured,
                        "frames_delivered"_a = e.frames_delivered, "truth_rows"_a = e.truth_rows);
      },
      "scenario"_a, "out"_a, "overrides"_a = py::none(), "seed"_a = py::none(), "force"_a = false,
      R"(Simulates run 0 of a scenario and writes it as a dataset into the folder
`out`, as `arttrack export` does (docs/datasets.md): joints.csv (s, rad),
depth/*.png (16-bit millimetres) with depth/index.csv (stamps and arrival
times, s), ground_truth.csv, camera.yaml, robot.urdf, tracker.yaml,
dataset.yaml. overrides and seed as run_scenario. Returns a dict: run_seed,
joint_rows, frames_captured, frames_delivered, truth_rows. Raises InputError,
UsageError (seed, a folder holding a dataset without force=True). The GIL is
released while it runs.)");

  m.def(
      "track_dataset",
      [](const std::string& dataset, const std::optional<std::string>& config,
         const std::optional<std::string>& urdf, const py::object& methods, int every,
         const std::optional<std::string>& out, bool force) {
        if (every < 0) throw cli::UsageError("every: must be >= 0");
        sim::TrackOptions options;
        options.methods = method_list(methods);
        if (config) options.tracker_config = *config;
        options.estimate_every_n_joints = every;
        sim::TrackResult r;
        std::ostringstream estimate;
        std::vector<fs::path> written;
        bool has_truth = false;
        {
          py::gil_scoped_release release;
          const sim::Dataset d =
              sim::load_dataset(dataset, urdf ? std::optional<fs::path>(*urdf) : std::nullopt);
          if (out) cli::check_fresh_output(*out, {"estimate.csv", "summary.json"}, force);
          r = sim::track_dataset(d, options, &estimate);
          has_truth = d.has_truth();
          if (out && has_truth) written = sim::write_run_outputs(*out, r.result);
        }
        py::dict result = has_truth ? result_dict(r.result, written) : py::dict();
        if (!has_truth) {
          result["summary"] = py::none();
          result["timeseries"] = py::dict();
        }
        result["estimate"] = columns_dict(csv_columns(estimate.str()));
        result["frames_missing"] = r.frames_missing;
        result["warnings"] = r.warnings;
        return result;
      },
      "dataset"_a, "config"_a = py::none(), "urdf"_a = py::none(), "methods"_a = py::none(),
      "every"_a = 0, "out"_a = py::none(), "force"_a = false,
      R"(Tracks a dataset folder as `arttrack track` does: per method one synchronous
tracker fed the joint readings and depth images in arrival order.

config: a tracker YAML (default: the dataset's tracker.yaml, else the shipped
defaults). urdf: the nominal robot (default the dataset's). methods: as
run_scenario (default the dataset's, else all it allows). every: also an
estimate row every N joint readings. out: also write summary.json,
timeseries.csv, report.html and frames/ there when the dataset has ground truth.

Returns a dict: 'estimate' (estimate.csv's columns: time_s, method, per joint
J_rad, J_std_rad, J_bias_rad, J_bias_std_rad, the camera correction cam_x_m ...
cam_yaw_rad, per end effector E_x, E_y, E_z (m), E_qw, E_qx, E_qy, E_qz), and
with ground truth 'summary' and 'timeseries' as run_scenario (else None and
{}); 'frames_missing', 'warnings', 'files'. Raises InputError. The GIL is
released while it runs.)");

  m.def(
      "read_depth_png",
      [](const std::string& path) {
        DepthImage d;
        {
          py::gil_scoped_release release;
          d = sim::read_depth_png_mm(path);
        }
        return depth_array(d);
      },
      "path"_a,
      "Reads a 16-bit depth PNG in millimetres (a dataset's depth/*.png) as a float32 array "
      "(height, width) of metres, 0 = no return. Raises InputError naming the file."_doc);

  m.def(
      "default_scenario_path", [] { return sim::default_scenario_path().string(); },
      "The scenario `arttrack run` runs without one (scenarios/default.yaml of the source tree)."_doc);
}

}  // namespace arttrack::python
