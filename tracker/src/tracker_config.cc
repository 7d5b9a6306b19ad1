#include "arttrack/tracker/tracker_config.h"

#include <initializer_list>
#include <string>
#include <variant>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/mesh_simplify.h"
#include "arttrack/tracker/internal/worker_pool.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "arttrack/tracker/units.h"
#include "config_range.h"

namespace arttrack {
namespace {

// A number of a section by its key: a whole number for an int field; `unit`:
// one unit of the key in the field's units (kRadPerDeg for a _deg key held in rad).
struct NumberKey {
  const char* key;
  std::variant<double*, int*> field;
  double unit = 1.0;
};

// Reads the keys given (the others keep their fields' values); the ranges
// are validate's.
void read_numbers(const ConfigNode& node, std::initializer_list<NumberKey> keys) {
  for (const NumberKey& k : keys) {
    if (double* const* d = std::get_if<double*>(&k.field))
      **d = node.number(k.key, **d / k.unit) * k.unit;
    else
      *std::get<int*>(k.field) = node.whole_number(k.key, *std::get<int*>(k.field));
  }
}

// Joint filter keys, in degrees or (`linear`, a prismatic joint's) metres;
// `base` supplies the values of keys not given.
JointFilterParams read_joint_params(const ConfigNode& node, const JointFilterParams& base,
                                    bool linear) {
  const JointNoiseKeys& keys = joint_noise_keys(linear);
  JointFilterParams p = base;
  read_numbers(node, {{keys.encoder_noise, &p.encoder_noise_rad, keys.unit},
                      {keys.motion_diffusion, &p.angle_diffusion_rad_per_sqrt_s, keys.unit},
                      {keys.bias_diffusion, &p.bias_diffusion_rad_per_sqrt_s, keys.unit},
                      {"bias_decay_per_s", &p.bias_decay_per_s}});
  p.estimate_bias = node.get<bool>("estimate_bias", base.estimate_bias);
  return p;
}

// A joints.per_joint entry: the keys it gives, in the units its keys say
// (degrees or metres, never both).
JointFilterOverride read_joint_override(const ConfigNode& node) {
  const auto given = [&](const JointNoiseKeys& keys) {
    for (const char* k : {keys.encoder_noise, keys.motion_diffusion, keys.bias_diffusion})
      if (node.has(k)) return k;
    return static_cast<const char*>(nullptr);
  };
  const char* angular = given(kRevoluteNoiseKeys);
  const char* linear = given(kPrismaticNoiseKeys);
  if (angular && linear)
    node.fail(linear, std::string("is in metres (a prismatic joint's) but ") + angular +
                          " is in degrees (a revolute joint's): one joint is one or the other");
  JointFilterOverride o;
  if (angular || linear) o.linear = linear != nullptr;
  const JointNoiseKeys& keys = joint_noise_keys(linear != nullptr);
  const std::pair<const char*, std::optional<double>*> fields[] = {
      {keys.encoder_noise, &o.encoder_noise},
      {keys.motion_diffusion, &o.motion_diffusion_per_sqrt_s},
      {keys.bias_diffusion, &o.bias_diffusion_per_sqrt_s}};
  for (const auto& [key, field] : fields)
    if (node.has(key)) *field = node.number(key, 0.0) * keys.unit;
  if (node.has("bias_decay_per_s")) o.bias_decay_per_s = node.number("bias_decay_per_s", 0.0);
  if (node.has("estimate_bias")) o.estimate_bias = node.get<bool>("estimate_bias", true);
  return o;
}

}  // namespace

const char* method_name(TrackingMethod method) {
  switch (method) {
    case TrackingMethod::kEncodersOnly:
      return "encoders_only";
    case TrackingMethod::kCameraOffsetOnly:
      return "camera_offset_only";
    case TrackingMethod::kFullFusion:
      return "full_fusion";
    case TrackingMethod::kVisionOnly:
      return "vision_only";
  }
  return "?";
}

const std::vector<std::string>& all_method_names() {
  static const std::vector<std::string> names = {"encoders_only", "camera_offset_only",
                                                 "full_fusion", "vision_only"};
  return names;
}

TrackingMethod parse_method(const std::string& name, const std::string& context) {
  for (TrackingMethod m : {TrackingMethod::kEncodersOnly, TrackingMethod::kCameraOffsetOnly,
                           TrackingMethod::kFullFusion, TrackingMethod::kVisionOnly}) {
    if (name == method_name(m)) return m;
  }
  throw InputError(context + ": unknown method " + quote_value(name) +
                   " (expected encoders_only, camera_offset_only, full_fusion or vision_only)");
}

double TrackerConfig::Geometry::error_bound_m(const CameraIntrinsics& likelihood_camera) const {
  return max_error_px > 0 ? mesh_error_bound_m(likelihood_camera, max_error_px, nearest_range_m)
                          : 0.0;
}

const VirtualJointParams& TrackerConfig::camera_joint_params(int k) const {
  if (k < 0 || k >= 6)
    throw InputError("virtual camera joint " + std::to_string(k) + ": expected 0 to 5");
  return k < 3 ? camera_translation : camera_rotation;
}

// Every range of the configuration, in the YAML's keys and units; the
// structs' own validate functions hold theirs (depth model, joint filters,
// particle filter).
void TrackerConfig::validate(const std::string& source) const {
  const auto check = [&](const std::string& key, double value, const ConfigRange& range,
                         double unit = 1.0) { check_range(source, key, value, range, unit); };
  using R = ConfigRange;
  if (camera_frame.empty()) fail_key(source, "camera_frame", "is empty");

  joint_defaults.validate(source, "joints.defaults.");
  prismatic_joint_defaults.validate(source, "joints.prismatic_defaults.", true);
  // Each override over the defaults of its units (both when it gave only
  // unit-free keys): what the joints it may be for will run with.
  for (const auto& [name, o] : joint_overrides) {
    const std::string prefix = "joints.per_joint." + name + ".";
    if (!o.linear.value_or(false)) o.over(joint_defaults).validate(source, prefix);
    if (o.linear.value_or(true)) o.over(prismatic_joint_defaults).validate(source, prefix, true);
  }
  check("encoder_smoothing.rate_diffusion_deg_per_s_per_sqrt_s",
        encoder_smoothing.rate_diffusion_rad_per_s_per_sqrt_s, R::open_closed(0, 1e5), kRadPerDeg);
  check("camera_offset.translation_diffusion_m_per_sqrt_s", camera_translation.diffusion_per_sqrt_s,
        R::closed(0, 10));
  check("camera_offset.translation_initial_std_m", camera_translation.initial_std,
        R::open_closed(0, 10));
  check("camera_offset.rotation_diffusion_deg_per_sqrt_s", camera_rotation.diffusion_per_sqrt_s,
        R::closed(0, 1e4), kRadPerDeg);
  check("camera_offset.rotation_initial_std_deg", camera_rotation.initial_std,
        R::open_closed(0, 180), kRadPerDeg);
  check("camera_offset.translation_diffusion_m_per_sqrt_rad",
        camera_translation.motion_diffusion_per_sqrt_rad, R::closed(0, 10));
  check("camera_offset.rotation_diffusion_deg_per_sqrt_rad",
        camera_rotation.motion_diffusion_per_sqrt_rad, R::closed(0, 1e4), kRadPerDeg);
  check("vision_only.angle_diffusion_deg_per_sqrt_s", vision_only_angle_diffusion_rad_per_sqrt_s,
        R::closed(0, 1e5), kRadPerDeg);
  check("vision_only.initial_std_deg", vision_only_initial_std_rad, R::closed(0, 180), kRadPerDeg);

  depth_model.validate(source, "depth_model.");
  check("geometry.max_error_px", geometry.max_error_px, R::closed(0, 4));
  check("geometry.nearest_range_m", geometry.nearest_range_m, R::closed(0.01, 100));
  check("geometry.coarser_levels", geometry.coarser_levels, R::closed(0, 8));

  particle_filter.validate(source, "particle_filter.");
  check("particle_filter.likelihood_exponent", likelihood_exponent, R::closed(1e-3, 1));
  check("particle_filter.threads", threads, R::closed(0, kMaxWorkerThreads));
  check("particle_filter.min_evaluations", min_evaluations, R::closed(0, 1000000));
  check("particle_filter.camera_blocks_per_image", camera_blocks_per_image, R::closed(1, 6));
  check("particle_filter.unseen_below_pixels", unseen_below_pixels, R::closed(1, 1000000));
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const std::string key = "particle_filter.blocks[" + std::to_string(i) + "]";
    if (blocks[i].name.empty()) fail_key(source, key + ".name", "is empty");
    if (blocks[i].joints.empty())
      fail_key(source, key + ".joints", "is empty (block '" + blocks[i].name + "')");
  }

  check("uncertainty.image_information_scale", image_information_scale, R::closed(1e-6, 1));
  check("uncertainty.model_error_time_constant_s", model_error_time_constant_s,
        R::closed(1e-3, 1e4));
  check("uncertainty.model_error_min_std_m", model_error_min_std_m, R::closed(0, 0.1));
  check("uncertainty.model_error_unpinned_scale", model_error_unpinned_scale, R::closed(1, 10));
  check("uncertainty.model_error_learned_time_constant_s", model_error_learned_time_constant_s,
        R::closed(1e-3, 1e4));
  check("uncertainty.model_error_learned_max_std_m", model_error_learned_max_std_m,
        R::closed(1e-6, 0.1));
  check("uncertainty.link_length_std_m", link_length_std_m, R::closed(0, 0.1));
  check("uncertainty.depth_scale_std", depth_scale_std, R::closed(0, 0.1));
  check("uncertainty.mean_lag_scale", mean_lag_scale, R::closed(0, 100));
  check("uncertainty.mean_lag_time_constant_s", mean_lag_time_constant_s, R::closed(0.5, 1e4));
  check("refinement.min_pixels", refinement_min_pixels, R::closed(1, 1e7));
  check("refinement.widen_beyond_sigma", refinement_widen_beyond_sigma, R::closed(0, 100));
  check("refinement.unseen_information_ratio", refinement_unseen_information_ratio,
        R::closed(0, 1));
  check("end_effector_fit.time_constant_s", end_effector_fit.time_constant_s, R::closed(1e-3, 1e4));
  check("end_effector_fit.max_std_m", end_effector_fit.max_std_m, R::closed(1e-6, 1));
  check("end_effector_fit.resolution_factor", end_effector_fit.resolution_factor, R::closed(1, 8));
  check("end_effector_fit.axis_search_range_m", end_effector_fit.axis_search_range_m,
        R::closed(0, 0.05));

  const Acquisition& a = acquisition;
  check("acquisition.passes", a.passes, R::closed(1, 10));
  // The search anneals from the coarse noise down to the pixel model's.
  R coarse = R::closed(depth_model.noise_std_m, 0.5);
  coarse.lo_key = "depth_model.noise_std_m";
  check("acquisition.coarse_noise_std_m", a.coarse_noise_std_m, coarse);
  if (a.passes > 1) {
    // The first search pass's likelihood must be a valid depth model too.
    DepthModelParams coarsest = depth_model;
    coarsest.noise_std_m = a.coarse_noise_std_m;
    try {
      coarsest.validate(source, "depth_model.");
    } catch (const ConfigKeyError& e) {
      fail_key(source, "acquisition.coarse_noise_std_m",
               "= " + std::to_string(a.coarse_noise_std_m) +
                   " as the depth noise of the first search pass: " + e.key() + " " + e.problem());
    }
  }
  check("acquisition.proposal_shrink", a.proposal_shrink, R::closed(0.05, 1));
  check("acquisition.period_s", a.period_s, R::closed(0, 1e6));
  check("acquisition.bias_std_deg", a.bias_std_rad, R::closed(0.1, 180), kRadPerDeg);
  check("acquisition.accept_margin_nats", a.accept_margin_nats, R::closed(0, 1e6));
  check("acquisition.searches", a.searches, R::closed(1, 100));

  const Health& h = health;
  check("health.explained_m", h.explained_m, R::closed(1e-4, 1));
  check("health.contradicted_m", h.contradicted_m, R::closed(1e-4, 1));
  check("health.lost_contradicted_fraction", h.lost_contradicted_fraction, R::closed(0, 1));
  check("health.lost_abandoned_fraction", h.lost_abandoned_fraction, R::closed(0, 1));
  check("health.unconfirmed_explained_fraction", h.unconfirmed_explained_fraction, R::closed(0, 1));
  check("health.occluder_gap_m", h.occluder_gap_m, R::closed(1e-3, 10));
  check("health.lost_after_images", h.lost_after_images, R::closed(1, 1e6));
  check("health.min_pixels", h.min_pixels, R::closed(1, 1e7));

  check("timing.camera_delay_s", camera_delay_s, R::closed(0, 10));
  check("timing.buffer_capacity", buffer_capacity, R::closed(2, 1e7));
  check("timing.max_pending_images", max_pending_images, R::closed(1, 1000));

  check("input_checks.joint_limit_margin_deg", joint_limit_margin_rad, R::closed(0, 3600),
        kRadPerDeg);
  check("input_checks.max_image_clock_offset_s", max_image_clock_offset_s, R::closed(1e-3, 1e6));
}

TrackerConfig tracker_config_from_yaml(const YamlDocument& doc) {
  TrackerConfig c;
  c.source = doc.file;
  const ConfigNode root = ConfigNode::root(doc);
  c.method = parse_method(root.choice("method", "full_fusion", all_method_names()), doc.file);
  c.camera_frame = root.get<std::string>("camera_frame", c.camera_frame);
  c.end_effectors = root.get<std::vector<std::string>>("end_effectors", c.end_effectors);

  const ConfigNode joints = root.child("joints");
  c.joint_defaults = read_joint_params(joints.child("defaults"), c.joint_defaults, false);
  c.prismatic_joint_defaults =
      read_joint_params(joints.child("prismatic_defaults"), c.prismatic_joint_defaults, true);
  const ConfigNode per_joint = joints.child("per_joint");
  for (const std::string& name : per_joint.keys())
    c.joint_overrides[name] = read_joint_override(per_joint.child(name));

  const ConfigNode smoothing = root.child("encoder_smoothing");
  c.encoder_smoothing.enabled = smoothing.get<bool>("enabled", c.encoder_smoothing.enabled);
  read_numbers(smoothing, {{"rate_diffusion_deg_per_s_per_sqrt_s",
                            &c.encoder_smoothing.rate_diffusion_rad_per_s_per_sqrt_s, kRadPerDeg}});
  c.encoder_noise.from_readings =
      root.child("encoder_noise").get<bool>("from_readings", c.encoder_noise.from_readings);

  read_numbers(
      root.child("camera_offset"),
      {{"translation_diffusion_m_per_sqrt_s", &c.camera_translation.diffusion_per_sqrt_s},
       {"translation_initial_std_m", &c.camera_translation.initial_std},
       {"rotation_diffusion_deg_per_sqrt_s", &c.camera_rotation.diffusion_per_sqrt_s, kRadPerDeg},
       {"rotation_initial_std_deg", &c.camera_rotation.initial_std, kRadPerDeg},
       {"translation_diffusion_m_per_sqrt_rad",
        &c.camera_translation.motion_diffusion_per_sqrt_rad},
       {"rotation_diffusion_deg_per_sqrt_rad", &c.camera_rotation.motion_diffusion_per_sqrt_rad,
        kRadPerDeg}});
  read_numbers(root.child("vision_only"),
               {{"angle_diffusion_deg_per_sqrt_s", &c.vision_only_angle_diffusion_rad_per_sqrt_s,
                 kRadPerDeg},
                {"initial_std_deg", &c.vision_only_initial_std_rad, kRadPerDeg}});

  const ConfigNode dm = root.child("depth_model");
  DepthModelParams& d = c.depth_model;
  d.occluder_model =
      dm.choice("occluder_model",
                d.occluder_model == OccluderModel::kTruncated ? "truncated" : "independent",
                {"independent", "truncated"}) == "truncated"
          ? OccluderModel::kTruncated
          : OccluderModel::kIndependent;
  read_numbers(dm, {{"outlier_weight", &d.outlier_weight},
                    {"noise_std_m", &d.noise_std_m},
                    {"noise_quadratic_per_m", &d.noise_quadratic_per_m},
                    {"max_range_m", &d.max_range_m},
                    {"occluder_decay_per_m", &d.occluder_decay_per_m},
                    {"occlusion_prior", &d.occlusion_prior},
                    {"width", &d.width},
                    {"height", &d.height}});

  read_numbers(root.child("geometry"), {{"max_error_px", &c.geometry.max_error_px},
                                        {"nearest_range_m", &c.geometry.nearest_range_m},
                                        {"coarser_levels", &c.geometry.coarser_levels}});
  c.geometry.open_parts_both_sides =
      root.child("geometry").get<bool>("open_parts_both_sides", c.geometry.open_parts_both_sides);

  const ConfigNode pf = root.child("particle_filter");
  read_numbers(pf, {{"particles", &c.particle_filter.num_particles},
                    {"max_kl_divergence", &c.particle_filter.max_kl_divergence},
                    {"proposal_scale", &c.particle_filter.proposal_scale},
                    {"no_evidence_nats", &c.particle_filter.no_evidence_nats},
                    {"bandwidth_factor", &c.particle_filter.bandwidth_factor},
                    {"block_moments_below_nats", &c.particle_filter.block_moments_below_nats},
                    {"min_evaluations", &c.min_evaluations},
                    {"camera_blocks_per_image", &c.camera_blocks_per_image},
                    {"likelihood_exponent", &c.likelihood_exponent},
                    {"unseen_below_pixels", &c.unseen_below_pixels},
                    {"threads", &c.threads}});
  c.seed = pf.get<unsigned long long>("seed", c.seed);
  c.keep_unseen_prior = pf.get<bool>("keep_unseen_prior", c.keep_unseen_prior);
  for (const ConfigNode& b : pf.list("blocks")) {
    c.blocks.push_back(
        {b.required<std::string>("name"), b.required<std::vector<std::string>>("joints")});
  }

  const ConfigNode uncertainty = root.child("uncertainty");
  read_numbers(uncertainty,
               {{"image_information_scale", &c.image_information_scale},
                {"model_error_time_constant_s", &c.model_error_time_constant_s},
                {"model_error_min_std_m", &c.model_error_min_std_m},
                {"model_error_unpinned_scale", &c.model_error_unpinned_scale},
                {"model_error_learned_time_constant_s", &c.model_error_learned_time_constant_s},
                {"model_error_learned_max_std_m", &c.model_error_learned_max_std_m},
                {"link_length_std_m", &c.link_length_std_m},
                {"depth_scale_std", &c.depth_scale_std},
                {"mean_lag_scale", &c.mean_lag_scale},
                {"mean_lag_time_constant_s", &c.mean_lag_time_constant_s}});
  c.discount_correlated_residuals =
      uncertainty.get<bool>("discount_correlated_residuals", c.discount_correlated_residuals);
  c.pixel_noise_after_fit = uncertainty.get<bool>("pixel_noise_after_fit", c.pixel_noise_after_fit);
  c.model_error = uncertainty.get<bool>("model_error", c.model_error);
  c.model_error_learned_shifts =
      uncertainty.get<bool>("model_error_learned_shifts", c.model_error_learned_shifts);
  c.model_error_unpinned_scale_on_learned = uncertainty.get<bool>(
      "model_error_unpinned_scale_on_learned", c.model_error_unpinned_scale_on_learned);
  const ConfigNode refinement = root.child("refinement");
  c.refine_mean = refinement.get<bool>("enabled", c.refine_mean);
  read_numbers(refinement, {{"min_pixels", &c.refinement_min_pixels},
                            {"widen_beyond_sigma", &c.refinement_widen_beyond_sigma},
                            {"unseen_information_ratio", &c.refinement_unseen_information_ratio}});
  TrackerConfig::EndEffectorFitConfig& fit = c.end_effector_fit;
  const ConfigNode end_effector_fit = root.child("end_effector_fit");
  fit.enabled = end_effector_fit.get<bool>("enabled", fit.enabled);
  fit.link_scales = end_effector_fit.get<bool>("link_scales", fit.link_scales);
  read_numbers(end_effector_fit, {{"time_constant_s", &fit.time_constant_s},
                                  {"max_std_m", &fit.max_std_m},
                                  {"resolution_factor", &fit.resolution_factor},
                                  {"axis_search_range_m", &fit.axis_search_range_m}});

  TrackerConfig::Acquisition& a = c.acquisition;
  const ConfigNode acquisition = root.child("acquisition");
  read_numbers(acquisition, {{"passes", &a.passes},
                             {"coarse_noise_std_m", &a.coarse_noise_std_m},
                             {"proposal_shrink", &a.proposal_shrink},
                             {"period_s", &a.period_s},
                             {"bias_std_deg", &a.bias_std_rad, kRadPerDeg},
                             {"accept_margin_nats", &a.accept_margin_nats},
                             {"searches", &a.searches}});
  a.search_camera = acquisition.get<bool>("search_camera", a.search_camera);
  TrackerConfig::Health& h = c.health;
  read_numbers(root.child("health"),
               {{"explained_m", &h.explained_m},
                {"contradicted_m", &h.contradicted_m},
                {"lost_contradicted_fraction", &h.lost_contradicted_fraction},
                {"lost_abandoned_fraction", &h.lost_abandoned_fraction},
                {"unconfirmed_explained_fraction", &h.unconfirmed_explained_fraction},
                {"occluder_gap_m", &h.occluder_gap_m},
                {"lost_after_images", &h.lost_after_images},
                {"min_pixels", &h.min_pixels}});

  const ConfigNode timing = root.child("timing");
  read_numbers(timing, {{"camera_delay_s", &c.camera_delay_s},
                        {"buffer_capacity", &c.buffer_capacity},
                        {"max_pending_images", &c.max_pending_images}});
  c.asynchronous = timing.get<bool>("asynchronous", c.asynchronous);

  read_numbers(root.child("input_checks"),
               {{"joint_limit_margin_deg", &c.joint_limit_margin_rad, kRadPerDeg},
                {"max_image_clock_offset_s", &c.max_image_clock_offset_s}});

  root.finish();
  c.validate(doc.file);
  return c;
}

TrackerConfig load_tracker_config(const std::string& path) {
  return tracker_config_from_yaml(load_yaml_file(path));
}

YamlDocument default_tracker_document() {
  return load_yaml_string(default_tracker_config_yaml(), kDefaultTrackerConfigName);
}

TrackerConfig default_tracker_config() {
  return tracker_config_from_yaml(default_tracker_document());
}

}  // namespace arttrack
