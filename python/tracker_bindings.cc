// The tracker half of the Python module: RobotModel, TrackerConfig, Camera,
// Tracker and its estimate (tracker/include/arttrack/tracker/*.h).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/operators.h>
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack/tracker/tracker_config.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "arttrack/tracker/yaml_config.h"
#include "bindings.h"

namespace arttrack::python {
namespace {

using namespace pybind11::literals;

// A tracker configuration with the YAML document it was read from, so that
// overrides apply to the document (as --set does) and it reads back as text.
struct PyTrackerConfig {
  YamlDocument document;
  TrackerConfig config;

  static PyTrackerConfig from(YamlDocument document, const py::handle& overrides) {
    for (const std::string& assignment : override_assignments(overrides))
      apply_override(document, assignment);
    PyTrackerConfig out;
    out.config = tracker_config_from_yaml(document);
    out.document = std::move(document);
    return out;
  }
  std::string yaml() const {
    YAML::Emitter e;
    e << document.root;
    return std::string(e.c_str()) + "\n";
  }
};

// A YAML value as Python: maps as dicts, lists as lists, scalars as bool,
// int, float (.nan, .inf) or str, in that order of trying; null as None.
py::object to_python(const YAML::Node& node) {
  if (!node || node.IsNull()) return py::none();
  if (node.IsMap()) {
    py::dict d;
    for (const auto& kv : node) d[py::str(kv.first.Scalar())] = to_python(kv.second);
    return d;
  }
  if (node.IsSequence()) {
    py::list l;
    for (const auto& item : node) l.append(to_python(item));
    return l;
  }
  const std::string& s = node.Scalar();
  if (node.Tag() != "!") {  // quoted scalars stay text
    bool b = false;
    long long i = 0;
    double x = 0;
    if (YAML::convert<bool>::decode(node, b) && (s == "true" || s == "false")) return py::bool_(b);
    if (YAML::convert<long long>::decode(node, i)) return py::int_(i);
    if (YAML::convert<double>::decode(node, x)) return py::float_(x);
  }
  return py::str(s);
}

// One value of an override as YAML text (see override_assignments).
std::string yaml_text(const py::handle& v, bool top) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) {
    const double x = v.cast<double>();
    if (std::isnan(x)) return ".nan";
    if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
  }
  if (py::isinstance<py::str>(v)) {
    if (top) return v.cast<std::string>();  // YAML text, as --set takes it
    return py::module_::import("json").attr("dumps")(v).cast<std::string>();  // a quoted string
  }
  if (py::isinstance<py::dict>(v)) {
    std::string out = "{";
    for (const auto& [key, value] : v.cast<py::dict>())
      out += (out.size() > 1 ? ", " : "") + yaml_text(key, false) + ": " + yaml_text(value, false);
    return out + "}";
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::string out = "[";
    for (const py::handle item : v) out += (out.size() > 1 ? ", " : "") + yaml_text(item, false);
    return out + "]";
  }
  throw py::type_error("override value " + py::repr(v).cast<std::string>() +
                       ": expected str (YAML text), bool, int, float, list, tuple or dict");
}

// Row-major numpy copies of Eigen matrices, stacked: shape (n, R, C).
template <class Matrix>
py::array_t<double> stack(const std::vector<Matrix>& matrices, int rows, int cols) {
  py::array_t<double> out({py::ssize_t(matrices.size()), py::ssize_t(rows), py::ssize_t(cols)});
  auto a = out.mutable_unchecked<3>();
  for (std::size_t k = 0; k < matrices.size(); ++k)
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) a(py::ssize_t(k), r, c) = matrices[k](r, c);
  return out;
}

// The DOFs that are URDF joints, in DOF order.
std::vector<std::string> physical_joints(const RobotModel& r) {
  std::vector<std::string> out;
  for (int j = 0; j < r.num_joints(); ++j)
    if (!r.is_virtual_joint(j)) out.push_back(r.joint_name(j));
  return out;
}

py::dict chain_health_dict(const ChainHealth& c) {
  return py::dict("name"_a = c.name, "rendered_pixels"_a = c.rendered_pixels,
                  "explained_fraction"_a = c.explained_fraction,
                  "contradicted_fraction"_a = c.contradicted_fraction,
                  "abandoned_fraction"_a = c.abandoned_fraction,
                  "weakest_part_joint"_a = c.weakest_part_joint,
                  "weakest_part_explained_fraction"_a = c.weakest_part_explained_fraction,
                  "unconfirmed"_a = c.unconfirmed);
}

py::dict health_dict(const TrackingHealth& h) {
  py::list chains;
  for (const ChainHealth& c : h.chains) chains.append(chain_health_dict(c));
  py::list links;
  for (const TrackingHealth::LinkModelError& l : h.links)
    links.append(py::dict("link"_a = l.link, "shift_m"_a = l.shift_m, "images"_a = l.images));
  return py::dict(
      "state"_a = health_state_name(h.state), "image_stamp_s"_a = h.image_stamp_s,
      "whole"_a = chain_health_dict(h.whole), "chains"_a = chains,
      "acquisitions"_a = h.acquisitions, "chains_reacquired"_a = h.chains_reacquired,
      "refinements_accepted"_a = h.refinements_accepted,
      "unseen_priors_kept"_a = h.unseen_priors_kept,
      "images_with_unseen_motion"_a = h.images_with_unseen_motion,
      "hand_searches"_a = h.hand_searches, "hand_shifts_accepted"_a = h.hand_shifts_accepted,
      "last_acquisition_ms"_a = h.last_acquisition_ms, "model_error_std_m"_a = h.model_error_std_m,
      "links"_a = links,
      "encoder_noise_measured_rad"_a = py::array_t<double>(
          py::ssize_t(h.encoder_noise_measured_rad.size()), h.encoder_noise_measured_rad.data()),
      "weakest_part_explained_fraction"_a = h.weakest_part_explained_fraction(),
      "unconfirmed_chains"_a = h.unconfirmed_chains());
}

py::dict stats_dict(const TrackerStats& s) {
  const auto values = [&](double ImageTiming::*field) {
    const std::vector<double> v = s.images.values(field);
    return py::array_t<double>(py::ssize_t(v.size()), v.data());
  };
  return py::dict("joint_measurements"_a = s.joint_measurements,
                  "joint_measurements_dropped"_a = s.joint_measurements_dropped,
                  "images_received"_a = s.images_received, "images_applied"_a = s.images_applied,
                  "images_dropped_too_old"_a = s.images_dropped_too_old,
                  "images_dropped_backlog"_a = s.images_dropped_backlog,
                  "images_dropped_busy"_a = s.images_dropped_busy,
                  "images_dropped_bad_stamp"_a = s.images_dropped_bad_stamp,
                  "likelihood_evaluations"_a = s.likelihood_evaluations,
                  "last_evaluations_per_image"_a = s.last_evaluations_per_image,
                  "model_triangles"_a = s.model_triangles, "drawn_triangles"_a = s.drawn_triangles,
                  "mesh_error_bound_m"_a = s.mesh_error_bound_m, "mesh_error_m"_a = s.mesh_error_m,
                  "geometry_builds"_a = s.geometry_builds,
                  "image_stamp_s"_a = values(&ImageTiming::stamp_s),
                  "image_update_ms"_a = values(&ImageTiming::update_ms),
                  "image_refilter_ms"_a = values(&ImageTiming::refilter_ms),
                  "image_search_ms"_a = values(&ImageTiming::search_ms),
                  "image_latency_ms"_a = values(&ImageTiming::latency_ms));
}

// A depth image from a 2-D array: float32 (float64 is converted) in metres,
// or uint16 in millimetres (a count c is float(c * 1e-3) metres, as
// read_depth_png_mm reads a 16-bit PNG). Called without the GIL.
void fill_depth(const py::buffer_info& info, bool millimetres, DepthImage& out) {
  out.width = int(info.shape[1]);
  out.height = int(info.shape[0]);
  const std::size_t n = std::size_t(out.width) * std::size_t(out.height);
  out.depth_m.resize(n);
  if (millimetres) {
    const auto* p = static_cast<const std::uint16_t*>(info.ptr);
    for (std::size_t i = 0; i < n; ++i) out.depth_m[i] = float(p[i] * 1e-3);
  } else {
    const auto* p = static_cast<const float*>(info.ptr);
    std::copy(p, p + n, out.depth_m.begin());
  }
}

constexpr const char* kTrackerDoc =
    R"(The tracker: the public API of the method (docs/method.md "Overview";
Garcia Cifuentes et al. 2017). Feed it joint encoder readings and depth
images with their time stamps; read the estimate at any time: joint angles
and biases with standard deviations, the camera correction, and each end
effector's pose in the estimated camera frame.

Tracker(model, config, encoder_joints)

  model: RobotModel; config: TrackerConfig; encoder_joints: the order of the
  readings given to add_joint_measurement (every physical joint of the model
  exactly once, unless the method is vision_only, which takes none).
  Raises InputError naming an unknown, missing or repeated joint, an unknown
  end effector or block joint, or a bad configuration value.

Inside: one 2-state Kalman filter per joint updated at the encoder rate; each
depth image is applied at its own time stamp (minus the configured camera
delay) to the buffered belief of that time by a Coordinate Particle Filter
over the angle marginals, scored by the depth likelihood of the robot
rendered for each particle; the particles' moments are folded back into the
joint filters and the later joint readings are re-filtered. Beyond the paper
(full fusion): an annealed acquisition search at the first image,
re-acquisition when the health check says lost, a health verdict per image,
a Gauss-Newton refinement, and standard deviations from a full covariance
(tracker/include/arttrack/tracker/tracker.h says more).

Threads: in synchronous mode (the default, timing.asynchronous: false)
everything happens in the caller's thread and the numbers are a
deterministic function of the input. In asynchronous mode an image update
runs on a worker thread while joint updates go on; estimate() and the add_*
calls may be called from different Python threads (the GIL is released
during image updates).

Units: seconds, radians (metres for prismatic joints), depth in metres.)";

}  // namespace

std::vector<std::string> override_assignments(const py::handle& overrides) {
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  if (py::isinstance<py::dict>(overrides)) {
    for (const auto& [key, value] : overrides.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key))
        throw py::type_error("override key " + py::repr(key).cast<std::string>() +
                             ": expected a key path str, e.g. 'particle_filter.particles'");
      out.push_back(key.cast<std::string>() + "=" + yaml_text(value, true));
    }
    return out;
  }
  if (py::isinstance<py::str>(overrides))
    throw py::type_error(
        "overrides: expected a dict {key: value} or a list of 'key=value' strings, not one str");
  for (const py::handle item : overrides) {
    if (!py::isinstance<py::str>(item))
      throw py::type_error("overrides: list item " + py::repr(item).cast<std::string>() +
                           " is not a 'key=value' str");
    out.push_back(item.cast<std::string>());
  }
  return out;
}

void bind_tracker(py::module_& m) {
  // ---- RobotModel ----
  py::class_<RobotModel, std::shared_ptr<RobotModel>>(
      m, "RobotModel",
      "The robot's kinematic tree and link shapes, built once from a URDF and immutable "
      "afterwards.\n\n"
      "Degrees of freedom (DOFs) are the URDF's revolute, continuous and prismatic joints in "
      "depth-first tree order (siblings by joint name), then six virtual camera joints "
      "camera_offset_x, _y, _z (metres) and camera_offset_roll, _pitch, _yaw (radians) after the "
      "nominal camera frame, which absorb camera extrinsic and head kinematic error. URDF mimic "
      "joints follow their leader and are not DOFs."_doc)
      .def_static(
          "from_urdf_file",
          [](const std::string& path, const std::string& camera_frame,
             const std::vector<std::string>& mesh_search_paths, bool add_virtual_camera_joints) {
            RobotModelOptions options;
            options.camera_frame = camera_frame;
            options.mesh_search_paths = mesh_search_paths;
            options.add_virtual_camera_joints = add_virtual_camera_joints;
            return std::make_shared<RobotModel>(RobotModel::from_urdf_file(path, options));
          },
          "path"_a, "camera_frame"_a = "camera_optical_frame",
          "mesh_search_paths"_a = std::vector<std::string>{}, "add_virtual_camera_joints"_a = true,
          "Parses a URDF file. camera_frame: the URDF link of the nominal camera frame (optical "
          "convention: z forward, x right, y down). mesh_search_paths: folders that resolve "
          "relative and package://NAME/rest mesh paths (the URDF's own folder is searched "
          "first). Raises InputError naming the file (missing, malformed, a .xacro), a joint, a "
          "mesh and its link, or the camera frame (absent)."_doc)
      .def_property_readonly(
          "joint_names", [](const RobotModel& r) { return r.joint_names(); },
          "DOF names in the order of a configuration vector, virtual camera joints last."_doc)
      .def_property_readonly(
          "physical_joint_names", &physical_joints,
          "The DOFs that are URDF joints (what encoders read), in DOF order."_doc)
      .def_property_readonly("num_joints", &RobotModel::num_joints,
                             "Number of DOFs, virtual camera joints included."_doc)
      .def_property_readonly(
          "link_names",
          [](const RobotModel& r) {
            std::vector<std::string> out;
            for (int l = 0; l < r.num_links(); ++l) out.push_back(r.link_name(l));
            return out;
          },
          "Links in topological order (the URDF root first)."_doc)
      .def(
          "joint_limits",
          [](const RobotModel& r, const std::string& joint) {
            const int dof = r.joint_index(joint);
            return py::make_tuple(r.joint_lower(dof), r.joint_upper(dof));
          },
          "joint"_a,
          "(lower, upper) position limits of a DOF, radians or metres; -inf, inf for continuous "
          "and virtual joints. Raises InputError for a name that is not a DOF."_doc)
      .def_property_readonly("source", &RobotModel::source,
                             "Where the model came from (\"URDF file 'x'\"), for messages."_doc)
      .def("__repr__", [](const RobotModel& r) {
        return "<arttrack.RobotModel " + r.source() + ", " + std::to_string(r.num_joints()) +
               " DOFs>";
      });

  // ---- TrackerConfig ----
  py::class_<PyTrackerConfig>(
      m, "TrackerConfig",
      "Configuration of a Tracker: which of the paper's four methods (encoders_only, "
      "camera_offset_only, full_fusion, vision_only), the noise of every joint, the depth "
      "model, the particle filter, the delay buffer. The keys are those of "
      "tracker/config/default.yaml, which lists and documents every one (YAML uses degrees "
      "where a key says _deg).\n\n"
      "TrackerConfig(overrides=None): the shipped defaults (tracker/config/default.yaml).\n"
      "TrackerConfig.from_yaml_file(path, overrides=None): a YAML file (extends: followed).\n\n"
      "overrides: a dict {key path: value} applied in order, or a list of 'key=value' "
      "strings; key paths as `arttrack run --set` and a scenario's tracker_overrides write "
      "them (particle_filter.particles, joints.per_joint.elbow.bias_decay_per_s, "
      "particle_filter.blocks[0].joints). A str value is YAML text, as after the = of --set; "
      "bool, int, float, list and dict values are written as YAML. Unknown keys, wrong types "
      "and values out of range raise InputError naming the key."_doc)
      .def(py::init([](const py::object& overrides) {
             return PyTrackerConfig::from(default_tracker_document(), overrides);
           }),
           "overrides"_a = py::none(), "The shipped defaults with `overrides` applied."_doc)
      .def_static(
          "from_yaml_file",
          [](const std::string& path, const py::object& overrides) {
            return PyTrackerConfig::from(load_yaml_file(path), overrides);
          },
          "path"_a, "overrides"_a = py::none(),
          "Reads a tracker configuration file (keys not given keep the in-class defaults; to "
          "start from the shipped ones, `extends` them) and applies `overrides`."_doc)
      .def(
          "with_overrides",
          [](const PyTrackerConfig& c, const py::object& overrides) {
            return PyTrackerConfig::from({YAML::Clone(c.document.root), c.document.file},
                                         overrides);
          },
          "overrides"_a, "A copy with `overrides` applied to this configuration's document."_doc)
      .def(
          "__getitem__",
          [](const PyTrackerConfig& c, const std::string& key) {
            const std::optional<YAML::Node> node = find_key(c.document.root, key);
            if (!node) throw py::key_error(key);
            return to_python(*node);
          },
          "key"_a,
          "The value at a key path as the document holds it (YAML units: degrees where the key "
          "says _deg), e.g. config['particle_filter.particles']. KeyError when absent (the "
          "in-class default applies)."_doc)
      .def_property_readonly(
          "method",
          [](const PyTrackerConfig& c) { return std::string(method_name(c.config.method)); },
          "The tracking method: encoders_only, camera_offset_only, full_fusion or vision_only."_doc)
      .def_property_readonly(
          "camera_frame", [](const PyTrackerConfig& c) { return c.config.camera_frame; },
          "Nominal camera frame in the URDF (optical convention)."_doc)
      .def_property_readonly(
          "end_effectors", [](const PyTrackerConfig& c) { return c.config.end_effectors; },
          "Links whose pose in the estimated camera frame the tracker reports."_doc)
      .def_property_readonly(
          "source", [](const PyTrackerConfig& c) { return c.document.file; },
          "The file it was read from, named in messages."_doc)
      .def_property_readonly("yaml", &PyTrackerConfig::yaml,
                             "The configuration as a YAML document (overrides applied)."_doc)
      .def("__repr__", [](const PyTrackerConfig& c) {
        return "<arttrack.TrackerConfig " + c.document.file + ", method " +
               method_name(c.config.method) + ">";
      });

  // ---- Camera ----
  py::class_<CameraIntrinsics>(
      m, "Camera",
      "Pinhole intrinsics in pixels. Pixel (u, v) covers [u, u+1) x [v, v+1); a point (x, y, z) "
      "in the optical frame (z forward, x right, y down; metres) projects to "
      "(fx x / z + cx, fy y / z + cy).\n\n"
      "Camera(width, height, fx, fy, cx, cy): focal lengths and principal point in pixels."_doc)
      .def(py::init([](int width, int height, double fx, double fy, double cx, double cy) {
             return CameraIntrinsics{width, height, fx, fy, cx, cy};
           }),
           "width"_a, "height"_a, "fx"_a, "fy"_a, "cx"_a, "cy"_a)
      .def_static("from_vertical_fov", &CameraIntrinsics::from_vertical_fov, "width"_a, "height"_a,
                  "fovy_rad"_a,
                  "Square pixels and a centred principal point from a vertical field of view "
                  "(radians)."_doc)
      .def("scaled_to", &CameraIntrinsics::scaled_to, "width"_a, "height"_a,
           "The same camera at another resolution."_doc)
      .def("problem", &CameraIntrinsics::problem,
           "The first field outside the limits of a usable camera (field of view of each axis "
           "in [1, 170] degrees, principal point inside the image), as 'fx: ...'; '' when "
           "usable."_doc)
      .def_readwrite("width", &CameraIntrinsics::width, "pixels"_doc)
      .def_readwrite("height", &CameraIntrinsics::height, "pixels"_doc)
      .def_readwrite("fx", &CameraIntrinsics::fx, "focal length, pixels"_doc)
      .def_readwrite("fy", &CameraIntrinsics::fy, "focal length, pixels"_doc)
      .def_readwrite("cx", &CameraIntrinsics::cx, "principal point, pixels"_doc)
      .def_readwrite("cy", &CameraIntrinsics::cy, "principal point, pixels"_doc)
      .def(py::self == py::self)
      .def("__repr__", [](const CameraIntrinsics& c) {
        return "<arttrack.Camera " + std::to_string(c.width) + "x" + std::to_string(c.height) +
               " fx " + std::to_string(c.fx) + " fy " + std::to_string(c.fy) + " cx " +
               std::to_string(c.cx) + " cy " + std::to_string(c.cy) + ">";
      });

  // ---- Estimate ----
  py::class_<TrackerEstimate>(
      m, "Estimate",
      "What the tracker believes at one time (Tracker.estimate()). Its arrays are read-only (copy "
      "them to change them)."_doc)
      .def_readonly("time_s", &TrackerEstimate::time_s, "Time of the newest joint reading, s."_doc)
      .def_readonly("joint_names", &TrackerEstimate::joint_names,
                    "Physical joints in the model's DOF order (virtual joints excluded): the "
                    "order of the angle and bias arrays."_doc)
      .def_readonly("angle_rad", &TrackerEstimate::angle_rad,
                    "Joint angles, rad (m if prismatic)."_doc)
      .def_readonly("angle_std_rad", &TrackerEstimate::angle_std_rad,
                    "Their standard deviations, rad."_doc)
      .def_readonly("bias_rad", &TrackerEstimate::bias_rad,
                    "Encoder biases (reading minus true angle), rad; 0 where not estimated."_doc)
      .def_readonly("bias_std_rad", &TrackerEstimate::bias_std_rad,
                    "Their standard deviations, rad."_doc)
      .def_readonly(
          "camera_offset", &TrackerEstimate::camera_offset,
          "The camera correction (virtual camera joints): x, y, z (m), roll, pitch, "
          "yaw (rad); T_nominal_corrected = Trans(x, y, z) Rx(roll) Ry(pitch) Rz(yaw)."_doc)
      .def_readonly("camera_offset_std", &TrackerEstimate::camera_offset_std,
                    "Its standard deviations, m and rad."_doc)
      .def_property_readonly(
          "T_camera_ee",
          [](const TrackerEstimate& e) {
            std::vector<Eigen::Matrix4d> poses;
            for (const Eigen::Isometry3d& T : e.T_camera_ee) poses.push_back(T.matrix());
            return stack(poses, 4, 4);
          },
          "Pose of each configured end effector in the estimated (corrected) camera frame, "
          "shape (n, 4, 4), homogeneous transforms with translations in metres, in "
          "TrackerConfig.end_effectors order."_doc)
      .def_property_readonly(
          "T_camera_ee_covariance",
          [](const TrackerEstimate& e) { return stack(e.T_camera_ee_covariance, 6, 6); },
          "Their uncertainty, shape (n, 6, 6): covariance of (position m, rotation vector rad), "
          "both in the estimated camera frame, from the DOFs' covariance through the "
          "kinematics' Jacobian (first order)."_doc)
      .def_property_readonly(
          "ee_image_correction",
          [](const TrackerEstimate& e) { return stack(e.ee_image_correction, 6, 1); },
          "The end-effector fit's share of T_camera_ee, shape (n, 6, 1): per end effector, "
          "the rigid motion in its own axes (translation m, then rotation vector rad) from "
          "where the estimated angles' kinematics put it to the pose reported; 0 without "
          "the fit (end_effector_fit)."_doc)
      .def_property_readonly(
          "health", [](const TrackerEstimate& e) { return health_dict(e.health); },
          "How well the newest applied image agrees with the estimate, a dict: state "
          "('no_image', 'tracking', 'lost'), image_stamp_s, whole and chains (per kinematic "
          "chain: name, rendered_pixels, explained_fraction, contradicted_fraction, "
          "abandoned_fraction, weakest_part_joint, weakest_part_explained_fraction, "
          "unconfirmed), acquisitions, chains_reacquired, refinements_accepted, "
          "unseen_priors_kept, images_with_unseen_motion, hand_searches, "
          "hand_shifts_accepted, "
          "last_acquisition_ms, model_error_std_m (m), links (per link with geometry: link, "
          "shift_m, the surface shift the images pin, NaN before one does, and images), "
          "encoder_noise_measured_rad (per physical joint, each encoder's white noise as "
          "its readings show it; NaN without encoder or in the first 0.1 s), "
          "weakest_part_explained_fraction, "
          "unconfirmed_chains. Fractions are NaN without a verdict (fewer than "
          "health.min_pixels pixels)."_doc);

  // ---- Tracker ----
  py::class_<Tracker>(m, "Tracker", kTrackerDoc)
      .def(py::init([](std::shared_ptr<RobotModel> model, const PyTrackerConfig& config,
                       const std::vector<std::string>& encoder_joints) {
             return std::make_unique<Tracker>(std::move(model), config.config, encoder_joints);
           }),
           "model"_a, "config"_a, "encoder_joints"_a)
      .def(
          "set_initial_configuration",
          [](Tracker& t, const std::vector<std::string>& joints,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& angles_rad) {
            t.set_initial_configuration(joints,
                                        {angles_rad.data(), std::size_t(angles_rad.size())});
          },
          "joints"_a, "angles_rad"_a,
          "Vision only needs a starting configuration (physical joint names and their angles, "
          "rad); the other methods start from the first encoder reading. Joints not named start "
          "at 0 (or at the nearest limit)."_doc)
      .def(
          "add_joint_measurement",
          [](Tracker& t, double time_s,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& angles_rad) {
            t.add_joint_measurement(time_s, {angles_rad.data(), std::size_t(angles_rad.size())});
          },
          "time_s"_a, "angles_rad"_a,
          "One encoder reading per encoder joint, radians (a 1-D array or sequence in "
          "encoder_joints order), taken at time_s (s). Raises InputError for a time going "
          "backwards, a non-finite time or a wrong count. A reading that is not finite or lies "
          "further than input_checks.joint_limit_margin_deg outside its joint's limits drops "
          "the whole measurement (stats()['joint_measurements_dropped'])."_doc)
      .def(
          "add_depth_image",
          [](Tracker& t, double stamp_s, const py::array& depth, const CameraIntrinsics& camera) {
            if (depth.ndim() != 2)
              throw py::type_error("depth: expected a 2-D array (height, width), got " +
                                   std::to_string(depth.ndim()) + " dimensions");
            py::array image = depth;
            const bool millimetres = depth.dtype().is(py::dtype::of<std::uint16_t>());
            if (!millimetres) {
              if (depth.dtype().kind() != 'f')
                throw py::type_error(
                    "depth: expected float32 metres or uint16 millimetres, got dtype " +
                    py::str(depth.dtype()).cast<std::string>());
              image = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(depth);
            } else {
              image = py::array_t<std::uint16_t, py::array::c_style>::ensure(depth);
            }
            const py::buffer_info info = image.request();
            py::gil_scoped_release release;
            DepthImage d;
            fill_depth(info, millimetres, d);
            t.add_depth_image(stamp_s, d, camera);
          },
          "stamp_s"_a, "depth"_a, "camera"_a,
          "A depth image stamped at capture time (s), with the camera's intrinsics. depth: a 2-D "
          "array (height, width) of float32 metres along the optical axis (0 = no return; "
          "float64 is converted) or of uint16 millimetres (as a 16-bit depth PNG holds them; 0 = "
          "no return). Raises InputError for a size that does not match the intrinsics, a "
          "negative or non-finite depth (naming the pixel), or a time stamp earlier than the "
          "previous image's; TypeError for another dtype. An image stamped after the newest "
          "joint reading waits until the joints catch up; a stamp further than "
          "input_checks.max_image_clock_offset_s from the newest joint reading drops the image. "
          "Releases the GIL while it copies and applies the image."_doc)
      .def("prepare_camera", &Tracker::prepare_camera, "camera"_a,
           py::call_guard<py::gil_scoped_release>(),
           "Optional, before streaming: builds the simplified meshes and renderers for this "
           "camera (full resolution, as the images will come) now rather than at the first "
           "image, which on a robot of published meshes holds up the first images of a live "
           "stream for seconds. Raises InputError for unusable intrinsics."_doc)
      .def("wait_until_idle", &Tracker::wait_until_idle, py::call_guard<py::gil_scoped_release>(),
           "Asynchronous mode: blocks until no image update is running or waiting to run. "
           "Synchronous mode: returns at once."_doc)
      .def("estimate", py::overload_cast<>(&Tracker::estimate, py::const_),
           "The current belief (after the newest joint reading or image): an Estimate."_doc)
      .def(
          "stats", [](const Tracker& t) { return stats_dict(t.stats()); },
          "Counters and timings, a dict: joint_measurements, joint_measurements_dropped, "
          "images_received, images_applied, images_dropped_too_old, images_dropped_backlog, "
          "images_dropped_busy, images_dropped_bad_stamp, likelihood_evaluations, "
          "last_evaluations_per_image, model_triangles, drawn_triangles, mesh_error_bound_m, "
          "mesh_error_m, geometry_builds, and per applied image (the newest 16384) arrays "
          "image_stamp_s, "
          "image_update_ms, image_refilter_ms, image_search_ms, image_latency_ms (wall times, "
          "ms)."_doc)
      .def_property_readonly(
          "joint_names", [](const Tracker& t) { return physical_joints(t.model()); },
          "Physical joints in the model's DOF order (the order of Estimate's arrays)."_doc);
}

}  // namespace arttrack::python
