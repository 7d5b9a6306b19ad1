#include "arttrack/sim/scenario.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <tuple>
#include <type_traits>

#include "arttrack/sim/internal/config_geometry.h"
#include "arttrack/sim/search_paths.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "arttrack/tracker/units.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

// Runs `f`; an InputError from a struct's own validation is re-thrown naming
// the scenario file and the key path of `n`.
template <class F>
void checked(const ConfigNode& n, F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    n.fail("", std::string("is invalid: ") + e.what());
  }
}

// A whole number in [min, max].
long long integer(const ConfigNode& n, const std::string& key, long long fallback, double min,
                  double max) {
  const double v = n.number(key, double(fallback), min, max);
  if (v != std::floor(v)) n.fail(key, "must be a whole number");
  return (long long)v;
}

// A list of finite numbers scaled by `scale` (e.g. degrees to radians).
std::vector<double> numbers(const ConfigNode& n, const std::string& key, double scale) {
  if (!n.has(key)) return {};
  std::vector<double> v;
  try {
    v = n.required<std::vector<double>>(key);
  } catch (const InputError&) {
    n.fail(key, "must be a list of numbers");
  }
  for (double& x : v) {
    if (!std::isfinite(x)) n.fail(key, "must hold finite numbers");
    x *= scale;
  }
  return v;
}

// A pose from `<xyz_key>: [x, y, z]` (m) and `rpy_deg: [r, p, y]`.
Eigen::Isometry3d pose(const ConfigNode& n, const std::string& xyz_key) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = vec<3>(n, xyz_key, Eigen::Vector3d::Zero());
  T.linear() = rpy_matrix(kRadPerDeg * vec<3>(n, "rpy_deg", Eigen::Vector3d::Zero()));
  return T;
}

// A path named in the scenario: relative to it, else to a search folder
// (search_paths.h).
fs::path resolve_path(const ConfigNode& n, const std::string& key, const fs::path& fallback,
                      const fs::path& dir) {
  std::error_code ec;  // a name too long for the system is no file, not an exception
  const fs::path p = n.has(key) ? fs::path(n.required<std::string>(key)) : fallback;
  if (p.is_absolute()) {
    if (!fs::exists(p, ec)) n.fail(key, "= " + quote_value(p.string()) + ": no such file");
    return p;
  }
  if (fs::exists(dir / p, ec)) return fs::weakly_canonical(dir / p);
  if (const std::optional<fs::path> found = find_in_search_dirs(p))
    return fs::weakly_canonical(*found);
  n.fail(key, "= " + quote_value(p.string()) + ": no such file next to the scenario (in " +
                  dir.string() + ") or in the search folders (" + search_dirs_text() + ")");
}

// `joints: [names or groups]`, expanded. Empty when absent and !required.
std::vector<std::string> joint_list(const ConfigNode& n, const Scenario& s, bool required) {
  if (!n.has("joints")) {
    if (required) n.fail("joints", "is required but missing");
    return {};
  }
  std::vector<std::string> names;
  try {
    names = n.required<std::vector<std::string>>("joints");
  } catch (const InputError&) {
    n.fail("joints", "must be a list of joint or group names");
  }
  if (names.empty()) n.fail("joints", "must name at least one joint or group");
  std::vector<std::string> out;
  for (const std::string& name : names) {
    const std::vector<std::string> joints =
        expand_joint_group(name, s.urdf.movable_joints, s.scene.joint_groups);
    if (joints.empty()) {
      std::string groups = "all";
      for (const auto& [group, members] : s.scene.joint_groups) groups += ", " + group;
      n.fail("joints", "names " + quote_value(name) + ", which is neither a movable joint of " +
                           s.urdf.path.string() + " nor a group of them (" + groups +
                           "; groups are declared in the scene's robot.groups)");
    }
    out.insert(out.end(), joints.begin(), joints.end());
  }
  return out;
}

// The scene's joint groups must name movable joints of its URDF, and no
// group may shadow a joint.
void check_joint_groups(const Scenario& s) {
  for (const auto& [group, members] : s.scene.joint_groups) {
    const std::string key = s.scene.source + ": key 'robot.groups." + group + "'";
    if (s.urdf.has_joint(group))
      throw InputError(key + " is also a joint of " + s.urdf.path.string() +
                       ": give the group another name");
    for (const std::string& j : members)
      if (s.urdf.movable_index(j) < 0)
        throw InputError(key + " names " + quote_value(j) + ", which is not a movable joint of " +
                         s.urdf.path.string());
  }
}

// The home configuration the scene starts in, clamped into the limits.
std::vector<double> home_configuration(const Scenario& s) {
  std::vector<double> home;
  for (std::size_t i = 0; i < s.urdf.movable_joints.size(); ++i) {
    const auto it = s.scene.initial_joints_rad.find(s.urdf.movable_joints[i]);
    const double q = it == s.scene.initial_joints_rad.end() ? 0.0 : it->second;
    home.push_back(
        std::clamp(q, s.urdf.movable_limits[i].lower_rad, s.urdf.movable_limits[i].upper_rad));
  }
  return home;
}

// A motion group's joints: its keys are in degrees, so a prismatic joint
// (metres) in one is an error, not a finger moved 15 "degrees" = 0.26 m.
std::vector<std::string> motion_joints(const ConfigNode& n, const Scenario& s) {
  std::vector<std::string> joints = joint_list(n, s, true);
  for (const std::string& j : joints)
    if (s.urdf.is_prismatic(j))
      n.fail("joints", "includes the prismatic joint " + quote_value(j) +
                           " (metres) and motion keys are in degrees: motion moves revolute "
                           "joints only; leave it out of the group");
  return joints;
}

void read_motion(const ConfigNode& m, const UrdfSummary& urdf, Scenario& s) {
  // Each part on its own trajectory, so that an error names its key.
  const std::vector<double> home = home_configuration(s);
  auto check = [&](const ConfigNode& n, const auto& part) {
    checked(n, [&] {
      JointTrajectory t(urdf.movable_joints, home, urdf.movable_limits);
      if constexpr (std::is_same_v<std::decay_t<decltype(part)>, RandomMotion>) {
        std::mt19937_64 rng(0);
        t.add(part, rng);
      } else {
        t.add(part);
      }
    });
  };
  for (const ConfigNode& n : m.list("sinusoids")) {
    SinusoidMotion p;
    p.joints = motion_joints(n, s);
    p.amplitude_rad =
        kRadPerDeg * n.number("amplitude_deg", p.amplitude_rad / kRadPerDeg, -360, 360);
    p.frequency_hz = n.number("frequency_hz", p.frequency_hz, 1e-6, 100);
    p.phase_rad = kRadPerDeg * n.number("phase_deg", 0, -1e4, 1e4);
    p.centre_rad = numbers(n, "centre_deg", kRadPerDeg);
    p.fade_in_s = n.number("fade_in_s", p.fade_in_s, 0, 1e6);
    check(n, p);
    s.sinusoids.push_back(p);
  }
  for (const ConfigNode& n : m.list("waypoints")) {
    WaypointMotion p;
    p.joints = motion_joints(n, s);
    p.times_s = numbers(n, "times_s", 1.0);
    if (!n.has("times_s")) n.fail("times_s", "is required but missing");
    if (!n.has("positions_deg")) n.fail("positions_deg", "is required but missing");
    try {
      p.positions_rad = n.required<std::vector<std::vector<double>>>("positions_deg");
    } catch (const InputError&) {
      n.fail("positions_deg", "must be a list of lists of numbers (one list per time)");
    }
    for (auto& row : p.positions_rad)
      for (double& x : row) x *= kRadPerDeg;
    check(n, p);
    s.waypoints.push_back(p);
  }
  for (const ConfigNode& n : m.list("random")) {
    RandomMotion p;
    p.joints = motion_joints(n, s);
    p.amplitude_rad =
        kRadPerDeg * n.number("amplitude_deg", p.amplitude_rad / kRadPerDeg, 1e-6, 360);
    p.speed_scale = n.number("speed_scale", p.speed_scale, 1e-6, 1e3);
    p.base_speed_rad_per_s = kRadPerDeg * n.number("base_speed_deg_per_s",
                                                   p.base_speed_rad_per_s / kRadPerDeg, 1e-6, 1e5);
    p.margin_rad = kRadPerDeg * n.number("margin_deg", p.margin_rad / kRadPerDeg, 0, 360);
    p.num_components = int(integer(n, "components", p.num_components, 1, 1000));
    p.fade_in_s = n.number("fade_in_s", p.fade_in_s, 0, 1e6);
    check(n, p);
    s.random.push_back(p);
  }
  for (const ConfigNode& n : m.list("out_of_view")) {
    OutOfViewMotion p;
    p.joints = motion_joints(n, s);
    if (!n.has("out_of_view_deg")) n.fail("out_of_view_deg", "is required but missing");
    p.out_of_view_rad = numbers(n, "out_of_view_deg", kRadPerDeg);
    p.leave_s = n.number("leave_s", p.leave_s, 0, 1e6);
    p.return_s = n.number("return_s", p.return_s, 0, 1e6);
    p.move_duration_s = n.number("move_duration_s", p.move_duration_s, 1e-6, 1e6);
    check(n, p);
    s.out_of_view.push_back(p);
  }
}

void read_loads(const ConfigNode& root, const UrdfSummary& urdf, Scenario& s) {
  for (const ConfigNode& n : root.list("loads")) {
    LinkLoad l;
    l.link = n.required<std::string>("link");
    if (!urdf.has_link(l.link))
      n.fail("link", "= " + quote_value(l.link) + " is not a link of " + urdf.path.string());
    l.mass_kg = n.required_number("mass_kg", 1e-6, 1e4);
    l.start_s = n.required_number("start_s", 0, 1e6);
    l.end_s = n.required_number("end_s", 0, 1e6);
    l.ramp_s = n.number("ramp_s", l.ramp_s, 0, 1e6);
    if (l.end_s < l.start_s + 2 * l.ramp_s)
      n.fail("end_s", "must be at least start_s + 2 ramp_s (time to ramp in and out)");
    s.loads.push_back(l);
  }
}

// An encoder group's keys come in the units of the joints they corrupt:
// degrees for revolute and continuous joints, metres for prismatic ones (a
// gripper's fingers). A group that names both kinds is split in two; a
// prismatic joint in a group whose keys are all in degrees is an error, not
// a finger read 0.057 "degrees" = 1 mm off.
constexpr const char* kEncoderDegreeKeys[] = {
    "offset_deg", "step_amplitude_deg", "compliance_deg_per_Nm", "noise_deg", "resolution_deg"};
constexpr const char* kEncoderMetreKeys[] = {"offset_m", "step_amplitude_m", "compliance_m_per_N",
                                             "noise_m", "resolution_m"};

// The first of `keys` that n sets, or nullptr.
template <std::size_t N>
const char* first_key_set(const ConfigNode& n, const char* const (&keys)[N]) {
  for (const char* key : keys)
    if (n.has(key)) return key;
  return nullptr;
}

void read_encoders(const ConfigNode& root, const UrdfSummary& urdf, Scenario& s) {
  for (const ConfigNode& n : root.list("encoders")) {
    const std::vector<std::string> named = joint_list(n, s, false);
    std::vector<std::string> revolute, prismatic;
    for (const std::string& j : named.empty() ? urdf.movable_joints : named)
      (urdf.is_prismatic(j) ? prismatic : revolute).push_back(j);
    const char* degree_key = first_key_set(n, kEncoderDegreeKeys);
    const char* metre_key = first_key_set(n, kEncoderMetreKeys);
    if (!prismatic.empty() && degree_key && !metre_key) {
      std::string metre_keys;
      for (const char* key : kEncoderMetreKeys)
        metre_keys += (metre_keys.empty() ? "" : ", ") + std::string(key);
      n.fail("joints", "includes the prismatic joint " + quote_value(prismatic.front()) +
                           " (metres) and the group's keys are in degrees (" + degree_key +
                           "): give its corruption in metres (" + metre_keys +
                           "; 0 for none) or leave it out of the group");
    }
    if (metre_key && prismatic.empty())
      n.fail(metre_key, "is in metres, for prismatic joints, and the group has none");
    if (degree_key && revolute.empty())
      n.fail(degree_key, "is in degrees, for revolute joints, and the group has none");

    EncoderGroupCorruption g;
    g.step_period_s = n.number("step_period_s", g.step_period_s, 1e-6, 1e6);
    g.step_ramp_time_s = n.number("step_ramp_time_s", g.step_ramp_time_s, 0, 1e6);
    g.stretch_time_constant_s =
        n.number("stretch_time_constant_s", g.stretch_time_constant_s, 0, 1e6);
    EncoderGroupCorruption metres = g;
    g.offset_rad = kRadPerDeg * n.number("offset_deg", 0, -360, 360);
    g.step_amplitude_rad = kRadPerDeg * n.number("step_amplitude_deg", 0, -360, 360);
    g.compliance_rad_per_Nm = kRadPerDeg * n.number("compliance_deg_per_Nm", 0, 0, 1e3);
    g.noise_sigma_rad = kRadPerDeg * n.number("noise_deg", 0, 0, 360);
    g.resolution_rad = kRadPerDeg * n.number("resolution_deg", 0, 0, 360);
    metres.offset_rad = n.number("offset_m", 0, -10, 10);
    metres.step_amplitude_rad = n.number("step_amplitude_m", 0, -10, 10);
    metres.compliance_rad_per_Nm = n.number("compliance_m_per_N", 0, 0, 1);
    metres.noise_sigma_rad = n.number("noise_m", 0, 0, 10);
    metres.resolution_rad = n.number("resolution_m", 0, 0, 10);
    checked(n, [&] {
      g.validate();
      metres.validate();
    });
    if (prismatic.empty()) {
      g.joints = named;  // empty: every joint, all revolute
      s.encoders.groups.push_back(g);
      continue;
    }
    if (!revolute.empty()) {
      g.joints = revolute;
      s.encoders.groups.push_back(g);
    }
    metres.joints = prismatic;
    s.encoders.groups.push_back(metres);
  }
  // Cross-group rules (one step, stretch or quantisation per joint).
  try {
    EncoderCorruption(urdf.movable_joints, s.encoders, 0);
  } catch (const InputError& e) {
    root.fail("encoders", std::string("is invalid: ") + e.what());
  }
}

void read_camera(const ConfigNode& n, Scenario& s) {
  SceneDescription& sc = s.scene;
  sc.width = int(integer(n, "width", sc.width, 8, 8192));
  sc.height = int(integer(n, "height", sc.height, 8, 8192));
  sc.fovy_rad = kRadPerDeg * n.number("fovy_deg", sc.fovy_rad / kRadPerDeg, 1, 170);
  sc.near_m = n.number("near_m", sc.near_m, 1e-3, 100);
  sc.far_m = n.number("far_m", sc.far_m, 1e-2, 1000);
  if (sc.far_m <= sc.near_m) n.fail("far_m", "must be larger than near_m");

  CameraTiming& t = s.camera_timing;
  t.rate_hz = n.number("rate_hz", t.rate_hz, 1e-3, 1e4);
  t.first_frame_s = n.number("first_frame_s", t.first_frame_s, 0, 1e6);
  t.latency_s = n.number("latency_s", t.latency_s, 0, 100);
  t.jitter_s = n.number("jitter_s", t.jitter_s, 0, 100);
  t.jitter = n.choice("jitter", "gaussian", {"gaussian", "uniform"}) == "gaussian"
                 ? CameraTiming::Jitter::kGaussian
                 : CameraTiming::Jitter::kUniform;
  t.drop_probability = n.number("drop_probability", t.drop_probability, 0, 0.999);

  DepthCorruptionParams& d = s.depth_corruption;
  d.depth_scale_error = n.number("depth_scale_error", d.depth_scale_error, -0.2, 0.2);
  s.focal_error = n.number("focal_error", s.focal_error, -0.2, 0.2);
  d.noise_sigma0_m = n.number("noise_sigma0_m", d.noise_sigma0_m, 0, 10);
  d.noise_sigma_quadratic_per_m =
      n.number("noise_quadratic_per_m", d.noise_sigma_quadratic_per_m, 0, 10);
  d.baseline_focal_m_px = n.number("baseline_focal_m_px", d.baseline_focal_m_px, 0, 1e6);
  d.disparity_step_px = n.number("disparity_step_px", d.disparity_step_px, 1e-6, 100);
  d.dropout_probability = n.number("dropout_probability", d.dropout_probability, 0, 1);
  d.edge_jump_m = n.number("edge_jump_m", d.edge_jump_m, 1e-6, 100);
  d.edge_dropout_probability =
      n.number("edge_dropout_probability", d.edge_dropout_probability, 0, 1);
  d.max_range_m = n.number("max_range_m", d.max_range_m, 1e-3, kInf);
  d.min_range_m = n.number("min_range_m", d.min_range_m, 0, 1e3);
  checked(n, [&] {
    t.validate();
    d.validate();
  });
}

// `key: [min, max]`, 0 <= min <= max <= `limit`.
std::pair<double, double> draw_range(const ConfigNode& n, const std::string& key, double limit) {
  const std::vector<double> v = numbers(n, key, 1.0);
  if (v.size() != 2 || v[0] < 0 || v[0] > v[1] || v[1] > limit) {
    std::ostringstream range;
    range << "must be [min, max] with 0 <= min <= max <= " << limit;
    n.fail(key, range.str());
  }
  return {v[0], v[1]};
}

// model_mismatch.random (RandomModelMismatch): joints by name (a fixed
// mount too) or movable group, links by name; the counts at most the
// candidates.
void read_random_mismatch(const ConfigNode& n, Scenario& s) {
  RandomModelMismatch& r = s.random_mismatch;
  for (const std::string& name : n.get<std::vector<std::string>>("joints", {})) {
    std::vector<std::string> joints =
        s.urdf.has_joint(name)
            ? std::vector<std::string>{name}
            : expand_joint_group(name, s.urdf.movable_joints, s.scene.joint_groups);
    if (joints.empty())
      n.fail("joints", "names " + quote_value(name) + ", which is neither a joint of " +
                           s.urdf.path.string() + " nor a group of its movable joints");
    for (const std::string& j : joints)
      if (std::find(r.joints.begin(), r.joints.end(), j) == r.joints.end()) r.joints.push_back(j);
  }
  for (const std::string& link : n.get<std::vector<std::string>>("links", {})) {
    if (!s.urdf.has_link(link))
      n.fail("links", "names " + quote_value(link) + ", no link of " + s.urdf.path.string());
    if (std::find(r.links.begin(), r.links.end(), link) == r.links.end()) r.links.push_back(link);
  }
  r.lengths = int(integer(n, "lengths", 0, 0, double(r.joints.size())));
  r.scales = int(integer(n, "scales", 0, 0, double(r.links.size())));
  if (r.lengths > 0) {
    if (!n.has("length_m")) n.fail("length_m", "is required when lengths > 0");
    std::tie(r.length_min_m, r.length_max_m) = draw_range(n, "length_m", 0.1);
  }
  if (r.scales > 0) {
    if (!n.has("scale")) n.fail("scale", "is required when scales > 0");
    std::tie(r.scale_min, r.scale_max) = draw_range(n, "scale", 0.5);
  }
}

void read_miscalibration(const ConfigNode& root, const UrdfSummary& urdf, Scenario& s) {
  const ConfigNode m = root.child("miscalibration");
  UrdfPerturbation& p = s.perturbation;
  p.camera_link = s.scene.camera_link;
  p.camera_mount = s.scene.camera_mount;
  if (m.has("camera_offset")) {
    const ConfigNode c = m.child("camera_offset");
    p.T_nominal_true_camera = pose(c, "xyz_m");
  }
  const ConfigNode head = m.child("head_error");
  for (const std::string& joint : head.keys()) {
    const ConfigNode j = head.child(joint);
    if (!urdf.has_joint(joint)) head.fail(joint, "names no joint of " + urdf.path.string());
    JointOriginChange c;
    c.joint = joint;
    c.T_old_new = pose(j, "xyz_m");
    c.R_axis = rpy_matrix(kRadPerDeg * vec<3>(j, "axis_tilt_deg", Eigen::Vector3d::Zero()));
    p.joint_changes.push_back(c);
  }

  const ConfigNode mm = root.child("model_mismatch");
  const ConfigNode lengths = mm.child("link_lengths_m");
  for (const std::string& joint : lengths.keys()) {
    if (!urdf.has_joint(joint)) lengths.fail(joint, "names no joint of " + urdf.path.string());
    p.origin_extension_m[joint] = lengths.required_number(joint, -10, 10);
  }
  const ConfigNode shapes = mm.child("shape_scale");
  for (const std::string& link : shapes.keys()) {
    if (!urdf.has_link(link)) shapes.fail(link, "names no link of " + urdf.path.string());
    p.link_scale[link] = shapes.required_number(link, 1e-3, 1e3);
  }
  if (mm.has("random")) read_random_mismatch(mm.child("random"), s);
}

OccluderSpec::Type occluder_type(const std::string& type) {
  return type == "box"        ? OccluderSpec::Type::kBox
         : type == "cylinder" ? OccluderSpec::Type::kCylinder
                              : OccluderSpec::Type::kPerson;
}

Eigen::Vector3d occluder_size(const ConfigNode& n, OccluderSpec::Type type) {
  switch (type) {
    case OccluderSpec::Type::kBox: {
      if (!n.has("size_m")) n.fail("size_m", "is required for a box");
      const Eigen::Vector3d size = vec<3>(n, "size_m", Eigen::Vector3d::Zero());
      if ((size.array() <= 0).any()) n.fail("size_m", "must hold positive sizes");
      return size;
    }
    case OccluderSpec::Type::kCylinder:
      return {n.required_number("radius_m", 1e-4, 100), n.required_number("length_m", 1e-4, 100),
              0};
    case OccluderSpec::Type::kPerson:
      return {n.required_number("height_m", 0.1, 5), 0, 0};
  }
  return Eigen::Vector3d::Zero();
}

// Keyframes of a sweep: back and forth between two poses at constant speed.
std::vector<OccluderKeyframe> sweep(const ConfigNode& n) {
  if (!n.has("from")) n.fail("from", "is required but missing");
  if (!n.has("to")) n.fail("to", "is required but missing");
  const Eigen::Isometry3d A = pose(n.child("from"), "position_m");
  const Eigen::Isometry3d B = pose(n.child("to"), "position_m");
  const double start = n.number("start_s", 0, 0, 1e6);
  const double duration = n.required_number("duration_s", 1e-3, 1e6);
  const int passes = int(integer(n, "passes", 1, 1, 10000));
  const double pause = n.number("pause_s", 0, 0, 1e6);
  std::vector<OccluderKeyframe> k{{start, A}};
  double t = start;
  for (int i = 0; i < passes; ++i) {
    if (i > 0 && pause > 0) k.push_back({t += pause, k.back().T_world_occluder});
    k.push_back({t += duration, i % 2 == 0 ? B : A});
  }
  return k;
}

void read_occluders(const ConfigNode& root, Scenario& s) {
  for (const ConfigNode& n : root.list("occluders")) {
    const std::string name = n.required<std::string>("name");
    int index = -1;
    for (size_t i = 0; i < s.scene.occluders.size(); ++i)
      if (s.scene.occluders[i].name == name) index = int(i);
    if (index >= 0 && (n.has("type") || n.has("size_m") || n.has("radius_m") || n.has("height_m") ||
                       n.has("rgba")))
      n.fail("name",
             "= " + quote_value(name) + " is an occluder of the scene: give only its schedule");
    if (index < 0) {
      for (const auto& shape : s.scene.shapes)
        if (shape.name == name)
          n.fail("name", "= " + quote_value(name) + " is already a scene object");
      OccluderSpec o;
      o.name = name;
      o.type = occluder_type(n.choice("type", "box", {"box", "cylinder", "person"}));
      o.size_m = occluder_size(n, o.type);
      if (n.has("rgba")) {
        const Eigen::Vector4d c = vec<4>(n, "rgba", Eigen::Vector4d::Ones());
        if ((c.array() < 0).any() || (c.array() > 1).any())
          n.fail("rgba", "must hold numbers in [0, 1]");
        o.rgba = c.cast<float>();
      }
      index = int(s.scene.occluders.size());
      s.scene.occluders.push_back(o);
    }
    OccluderSchedule sched;
    sched.occluder = index;
    if (n.has("keyframes") == n.has("sweep"))
      n.fail("keyframes", "or 'sweep' must be given, not both or neither");
    if (n.has("sweep")) {
      sched.keyframes = sweep(n.child("sweep"));
    } else {
      for (const ConfigNode& k : n.list("keyframes")) {
        const double t = k.required_number("time_s", 0, 1e6);
        if (!sched.keyframes.empty() && t <= sched.keyframes.back().time_s)
          k.fail("time_s", "must be later than the previous keyframe's");
        sched.keyframes.push_back({t, pose(k, "position_m")});
      }
      if (sched.keyframes.empty()) n.fail("keyframes", "must list at least one keyframe");
    }
    s.scene.occluders[index].T_world_occluder = sched.keyframes.front().T_world_occluder;
    s.occluder_schedules.push_back(sched);
  }
}

void read_scoring(const ConfigNode& n, Scenario& s) {
  ScenarioScoring& sc = s.scoring;
  read_scoring_options(n, sc.options);
  sc.every_n_joint_steps = int(integer(n, "every_n_joint_steps", 0, 0, 1e9));
  sc.end_effectors = n.get<std::vector<std::string>>("end_effectors", s.scene.end_effector_links);
  if (sc.end_effectors.empty()) n.fail("end_effectors", "must name at least one link");
  for (const std::string& ee : sc.end_effectors)
    if (!s.urdf.has_link(ee))
      n.fail("end_effectors",
             "names " + quote_value(ee) + ", which is not a link of " + s.urdf.path.string());
  // The simulator reports the scored end effectors too.
  for (const std::string& ee : sc.end_effectors)
    if (std::find(s.scene.end_effector_links.begin(), s.scene.end_effector_links.end(), ee) ==
        s.scene.end_effector_links.end())
      s.scene.end_effector_links.push_back(ee);
}

// `simulated_urdf` / `tracker_urdf`: another URDF of the scene's robot (a
// calibrated description against the nominal one), with the same movable
// joints as the scene's URDF; empty (the scene's URDF) if absent.
fs::path read_robot_urdf(const ConfigNode& root, const std::string& key, const fs::path& dir,
                         const Scenario& s) {
  if (!root.has(key)) return {};
  const fs::path path = resolve_path(root, key, "", dir);
  UrdfSummary other;
  try {
    other = read_urdf_summary(path);
  } catch (const InputError& e) {
    root.fail(key, e.what());
  }
  const auto differ = [&](const UrdfSummary& a, const UrdfSummary& b) {
    for (const std::string& j : a.movable_joints)
      if (b.movable_index(j) < 0)
        root.fail(key, "= '" + path.string() + "': movable joint '" + j + "' of " +
                           a.path.string() + " is not a movable joint of " + b.path.string() +
                           " (both URDFs must have the same movable joints)");
  };
  differ(s.urdf, other);
  differ(other, s.urdf);
  return path;
}

// The tracker configuration: the scenario's `tracker` file (default: the
// built-in tracker/config/default.yaml), the scene's robot-specific
// tracker_overrides over it, the scenario's tracker_overrides over those; or,
// for a rerun, `resolved` (the configuration a run recorded) as it is.
void read_tracker(const ConfigNode& root, const fs::path& dir, const YamlDocument* resolved,
                  Scenario& s) {
  fs::path file;
  YamlDocument document;
  if (resolved) {
    s.tracker_file = root.get<std::string>("tracker", "");  // named only
  } else if (root.has("tracker")) {
    file = resolve_path(root, "tracker", "", dir);
    document = load_yaml_file(file.string());
  } else {
    document = default_tracker_document();
  }
  const ConfigNode over = root.child("tracker_overrides");
  for (const std::string& key : over.keys())
    s.tracker_overrides.emplace_back(key, over.flow_text(key));
  if (!resolved) return set_tracker_document(s, document, file);
  // A rerun's configuration has every override in it already.
  s.tracker_document = *resolved;
  s.tracker = tracker_config_from_yaml(s.tracker_document);
  s.tracker.camera_frame = s.scene.camera_link;
  s.tracker.end_effectors = s.scoring.end_effectors;
}

}  // namespace

void set_tracker_document(Scenario& s, const YamlDocument& document, const fs::path& file) {
  s.tracker_file = file;
  s.tracker_document = {YAML::Clone(document.root), document.file};
  YamlDocument& doc = s.tracker_document;
  for (const auto& [key, value] : s.scene.tracker_overrides) {
    try {
      apply_override(doc, key + "=" + value);
    } catch (const InputError& e) {
      throw InputError(s.scene.source + ": key 'robot.tracker_overrides." + key +
                       "' cannot be applied: " + e.what());
    }
  }
  for (const auto& [key, value] : s.tracker_overrides) {
    try {
      apply_override(doc, key + "=" + value);
    } catch (const InputError& e) {
      throw ConfigKeyError(s.source, "tracker_overrides." + key,
                           std::string("cannot be applied: ") + e.what());
    }
  }
  try {
    s.tracker = tracker_config_from_yaml(doc);
  } catch (const ConfigKeyError& e) {
    // Name where the bad key was set: the scenario's tracker_overrides win
    // over the scene's, which win over the tracker file (which the error
    // names already).
    const auto sets = [&](const std::string& key) {
      return e.key() == key || e.key().starts_with(key + ".") || e.key().starts_with(key + "[");
    };
    for (const auto& [key, value] : s.tracker_overrides)
      if (sets(key)) throw ConfigKeyError(s.source, "tracker_overrides." + e.key(), e.problem());
    for (const auto& [key, value] : s.scene.tracker_overrides)
      if (sets(key))
        throw ConfigKeyError(s.scene.source, "robot.tracker_overrides." + e.key(), e.problem());
    throw;
  }
  // The tracker's nominal camera is the simulated camera's link.
  s.tracker.camera_frame = s.scene.camera_link;
  s.tracker.end_effectors = s.scoring.end_effectors;
}

std::vector<std::string> expand_joint_group(
    const std::string& name, const std::vector<std::string>& joints,
    const std::map<std::string, std::vector<std::string>>& groups) {
  if (name == "all") return joints;
  if (const auto it = groups.find(name); it != groups.end()) return it->second;
  if (std::find(joints.begin(), joints.end(), name) != joints.end()) return {name};
  return {};
}

Eigen::Isometry3d OccluderSchedule::pose_at(double t_s) const {
  if (t_s <= keyframes.front().time_s) return keyframes.front().T_world_occluder;
  if (t_s >= keyframes.back().time_s) return keyframes.back().T_world_occluder;
  const auto it =
      std::upper_bound(keyframes.begin(), keyframes.end(), t_s,
                       [](double t, const OccluderKeyframe& k) { return t < k.time_s; });
  const OccluderKeyframe& b = *it;
  const OccluderKeyframe& a = *(it - 1);
  const double x = (t_s - a.time_s) / (b.time_s - a.time_s);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() =
      (1 - x) * a.T_world_occluder.translation() + x * b.T_world_occluder.translation();
  T.linear() = Eigen::Quaterniond(a.T_world_occluder.linear())
                   .slerp(x, Eigen::Quaterniond(b.T_world_occluder.linear()))
                   .toRotationMatrix();
  return T;
}

double LinkLoad::weight(double t_s) const {
  auto ramp = [](double x) { return 0.5 - 0.5 * std::cos(M_PI * std::clamp(x, 0.0, 1.0)); };
  if (t_s <= start_s || t_s >= end_s) return 0;
  if (ramp_s <= 0) return 1;
  return std::min(ramp((t_s - start_s) / ramp_s), ramp((end_s - t_s) / ramp_s));
}

JointTrajectory make_trajectory(const Scenario& s, const std::vector<std::string>& joint_names,
                                const std::vector<JointLimit>& limits,
                                const std::vector<double>& home_rad, std::mt19937_64& rng) {
  std::vector<double> home = home_rad;
  for (size_t i = 0; i < home.size(); ++i)
    home[i] = std::clamp(home[i], limits[i].lower_rad, limits[i].upper_rad);
  JointTrajectory trajectory(joint_names, home, limits);
  for (const auto& p : s.sinusoids) trajectory.add(p);
  for (const auto& p : s.waypoints) trajectory.add(p);
  for (const auto& p : s.random) trajectory.add(p, rng);
  for (const auto& p : s.out_of_view) trajectory.add(p);
  return trajectory;
}

Scenario scenario_from_yaml(const YamlDocument& doc, const fs::path& dir,
                            const YamlDocument* tracker) {
  const ConfigNode root = ConfigNode::root(doc);
  Scenario s;
  s.source = doc.file;
  s.dir = dir;
  s.name = root.get<std::string>("name", fs::path(doc.file).stem().string());
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos)
    root.fail("name", "must be a non-empty name without slashes");
  // The document as read, for the run's record; written out once every key
  // checked out (a 1 MB hostile value took yaml-cpp's emitter half a second
  // before the error that refuses it).
  YAML::Node resolved = YAML::Clone(doc.root);
  resolved["name"] = s.name;  // a rerun's document has another file name

  if (!root.has("scene")) root.fail("scene", "is required but missing");
  s.scene_file = resolve_path(root, "scene", "", dir);
  s.scene = load_scene(s.scene_file);
  s.urdf = read_urdf_summary(s.scene.urdf_path);
  check_joint_groups(s);
  if (s.scene.camera_mount) {  // the link the mount adds
    s.urdf.link_names.push_back(s.scene.camera_link);
    s.urdf.joint_names.push_back(s.scene.camera_link + "_mount");
  }
  s.simulated_urdf_path = read_robot_urdf(root, "simulated_urdf", dir, s);
  s.tracker_urdf_path = read_robot_urdf(root, "tracker_urdf", dir, s);

  s.duration_s = root.number("duration_s", s.duration_s, 1e-3, 1e6);
  s.seed = (std::uint64_t)integer(root, "seed", (long long)s.seed, 0, 9007199254740992.0);
  s.runs = int(integer(root, "runs", s.runs, 1, 1e5));
  s.joint_rate_hz = root.number("joint_rate_hz", s.joint_rate_hz, 1, 1e5);

  s.methods = root.get<std::vector<std::string>>("methods", all_method_names());
  if (s.methods.empty()) root.fail("methods", "must name at least one method");
  std::set<std::string> seen;
  for (const std::string& m : s.methods) {
    parse_method(m, doc.file + ": key 'methods'");
    if (!seen.insert(m).second) root.fail("methods", "lists " + quote_value(m) + " twice");
  }

  read_camera(root.child("camera"), s);
  read_motion(root.child("motion"), s.urdf, s);
  read_loads(root, s.urdf, s);
  read_encoders(root, s.urdf, s);
  read_miscalibration(root, s.urdf, s);
  read_occluders(root, s);
  read_scoring(root.child("scoring"), s);
  read_tracker(root, dir, tracker, s);

  // The motion as a whole.
  std::mt19937_64 rng(s.seed);
  checked(root.child("motion"), [&] {
    make_trajectory(s, s.urdf.movable_joints, s.urdf.movable_limits, home_configuration(s), rng);
  });

  root.finish();
  s.resolved_yaml = YAML::Dump(resolved) + "\n";
  return s;
}

Scenario load_scenario(const fs::path& path, const std::vector<std::string>& overrides) {
  YamlDocument doc = load_yaml_file(path.string());
  // A name names one file: it is not inherited through `extends`.
  if (doc.root["name"] && !YAML::LoadFile(path.string())["name"]) doc.root.remove("name");
  for (const std::string& o : overrides) {
    try {
      apply_override(doc, o);
    } catch (const InputError& e) {
      throw InputError(path.string() + ": " + e.what());
    }
  }
  Scenario s = scenario_from_yaml(doc, fs::absolute(path).parent_path());
  s.overrides = overrides;
  return s;
}

void read_scoring_options(const ConfigNode& n, ScoringOptions& o) {
  o.converged_after_s = n.number("converged_after_s", o.converged_after_s, 0, 1e9);
  o.convergence_threshold_m =
      n.number("convergence_threshold_m", o.convergence_threshold_m, 1e-12, 1e3);
  o.lost_threshold_m = n.number("lost_threshold_m", o.lost_threshold_m, 1e-12, 1e3);
  o.lost_after_s = n.number("lost_after_s", o.lost_after_s, 1e-9, 1e9);
}

fs::path default_scenario_path() {
  return find_default_file("scenarios/default.yaml", "default scenario");
}

CameraIntrinsics reported_intrinsics(const Scenario& scenario, const CameraIntrinsics& rendered) {
  CameraIntrinsics reported = rendered;
  reported.fx *= 1 + scenario.focal_error;
  reported.fy *= 1 + scenario.focal_error;
  return reported;
}

DrawnModelError run_model_error(const Scenario& scenario, std::uint64_t seed) {
  DrawnModelError out;
  out.perturbation = scenario.perturbation;
  const RandomModelMismatch& r = scenario.random_mismatch;
  if (r.empty()) return out;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // `count` of `candidates`, in their order, then per one a size and a sign.
  const auto draw = [&](const std::vector<std::string>& candidates, int count, double lo, double hi,
                        auto&& apply) {
    std::vector<std::size_t> chosen(candidates.size());
    std::iota(chosen.begin(), chosen.end(), std::size_t(0));
    std::shuffle(chosen.begin(), chosen.end(), rng);
    chosen.resize(std::size_t(count));
    std::sort(chosen.begin(), chosen.end());
    for (std::size_t i : chosen) {
      const double size = lo + (hi - lo) * unit(rng);
      apply(candidates[i], unit(rng) < 0.5 ? -size : size);
    }
  };
  draw(r.joints, r.lengths, r.length_min_m, r.length_max_m, [&](const std::string& j, double d) {
    out.link_lengths_m[j] = d;
    out.perturbation.origin_extension_m[j] += d;
  });
  draw(r.links, r.scales, r.scale_min, r.scale_max, [&](const std::string& l, double d) {
    out.shape_scales[l] = 1 + d;
    out.perturbation.link_scale.try_emplace(l, 1.0).first->second *= 1 + d;
  });
  return out;
}

}  // namespace arttrack::sim
