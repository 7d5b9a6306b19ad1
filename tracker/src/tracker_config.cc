#include "arttrack/tracker/tracker_config.h"

#include <cmath>
#include <limits>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/tracker_config_yaml.h"

namespace arttrack {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Joint filter keys; `base` supplies the values of keys not given.
JointFilterParams read_joint_params(const ConfigNode& node, const JointFilterParams& base) {
  JointFilterParams p = base;
  p.encoder_noise_rad =
      node.number("encoder_noise_deg", base.encoder_noise_rad / kDeg, 0, 90) * kDeg;
  p.angle_diffusion_rad_per_sqrt_s =
      node.number("angle_diffusion_deg_per_sqrt_s", base.angle_diffusion_rad_per_sqrt_s / kDeg, 0,
                  1e5) *
      kDeg;
  p.bias_diffusion_rad_per_sqrt_s = node.number("bias_diffusion_deg_per_sqrt_s",
                                                base.bias_diffusion_rad_per_sqrt_s / kDeg, 0, 1e5) *
                                    kDeg;
  p.bias_decay_per_s = node.number("bias_decay_per_s", base.bias_decay_per_s, 1e-12, 1 - 1e-12);
  p.estimate_bias = node.get<bool>("estimate_bias", base.estimate_bias);
  return p;
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
  throw InputError(context + ": unknown method '" + name +
                   "' (expected encoders_only, camera_offset_only, full_fusion or vision_only)");
}

void TrackerConfig::validate(const std::string& context) const {
  auto fail = [&](const std::string& what) { throw InputError(context + ": " + what); };
  if (camera_frame.empty()) fail("camera_frame is empty");
  depth_model.validate(context);
  if (particle_filter.num_particles < 1) fail("particle_filter.particles must be at least 1");
  if (!(particle_filter.max_kl_divergence >= 0)) fail("particle_filter.max_kl_divergence < 0");
  if (!(particle_filter.proposal_scale > 0)) fail("particle_filter.proposal_scale must be > 0");
  if (threads < 0 || threads > kMaxWorkerThreads)
    fail("particle_filter.threads = " + std::to_string(threads) + " must be in [0, " +
         std::to_string(kMaxWorkerThreads) + "]");
  if (!(camera_delay_s >= 0) || !std::isfinite(camera_delay_s))
    fail("timing.camera_delay_s must be a finite number >= 0");
  if (buffer_capacity < 2) fail("timing.buffer_capacity must be at least 2");
  if (max_pending_images < 1) fail("timing.max_pending_images must be at least 1");
  if (!(joint_limit_margin_rad >= 0) || !std::isfinite(joint_limit_margin_rad))
    fail("input_checks.joint_limit_margin_deg must be a finite number >= 0");
  if (!(max_image_clock_offset_s > 0) || !std::isfinite(max_image_clock_offset_s))
    fail("input_checks.max_image_clock_offset_s must be a finite number > 0");
  if (!(vision_only_angle_diffusion_rad_per_sqrt_s >= 0))
    fail("vision_only.angle_diffusion_deg_per_sqrt_s < 0");
  if (render_cylinder_segments != 0 && !(render_cylinder_segments >= 3))
    fail("render.cylinder_segments must be 0 (the model's) or at least 3");
  if (render_sphere_segments != 0 && !(render_sphere_segments >= 4))
    fail("render.sphere_segments must be 0 (the model's) or at least 4");
  if (!(likelihood_exponent > 0 && likelihood_exponent <= 1))
    fail("particle_filter.likelihood_exponent must be in (0, 1]");
  if (refinement_min_pixels < 1) fail("refinement.min_pixels must be >= 1");
  if (!(image_information_scale > 0 && image_information_scale <= 1))
    fail("uncertainty.image_information_scale must be in (0, 1]");
  if (acquisition.passes < 1 || acquisition.passes > 10)
    fail("acquisition.passes must be in [1, 10]");
  if (!(acquisition.coarse_noise_std_m >= depth_model.noise_std_m &&
        acquisition.coarse_noise_std_m <= 0.5))
    fail("acquisition.coarse_noise_std_m must be in [depth_model.noise_std_m, 0.5]");
  if (!(acquisition.proposal_shrink > 0 && acquisition.proposal_shrink <= 1))
    fail("acquisition.proposal_shrink must be in (0, 1]");
  if (!(acquisition.period_s >= 0) || !std::isfinite(acquisition.period_s))
    fail("acquisition.period_s must be a finite number >= 0");
  if (!(acquisition.bias_std_rad > 0) || !std::isfinite(acquisition.bias_std_rad))
    fail("acquisition.bias_std_deg must be positive");
  if (!(acquisition.accept_margin_nats >= 0)) fail("acquisition.accept_margin_nats must be >= 0");
  if (acquisition.searches < 1 || acquisition.searches > 100)
    fail("acquisition.searches must be in [1, 100]");
  if (!(health.explained_m > 0) || !(health.contradicted_m > 0))
    fail("health.explained_m and health.contradicted_m must be positive");
  if (!(health.lost_contradicted_fraction >= 0 && health.lost_contradicted_fraction <= 1))
    fail("health.lost_contradicted_fraction must be in [0, 1]");
  if (!(health.lost_abandoned_fraction >= 0 && health.lost_abandoned_fraction <= 1))
    fail("health.lost_abandoned_fraction must be in [0, 1]");
  if (health.lost_after_images < 1 || health.min_pixels < 1)
    fail("health.lost_after_images and health.min_pixels must be at least 1");
  for (const auto& b : blocks) {
    if (b.name.empty()) fail("particle_filter.blocks: a block has no name");
    if (b.joints.empty()) fail("particle_filter.blocks: block '" + b.name + "' has no joints");
  }
}

TrackerConfig tracker_config_from_yaml(const YamlDocument& doc) {
  TrackerConfig c;
  c.source = doc.file;
  const ConfigNode root = ConfigNode::root(doc);
  c.method = parse_method(root.choice("method", "full_fusion", all_method_names()), doc.file);
  c.camera_frame = root.get<std::string>("camera_frame", c.camera_frame);
  c.end_effectors = root.get<std::vector<std::string>>("end_effectors", c.end_effectors);

  const ConfigNode joints = root.child("joints");
  c.joint_defaults = read_joint_params(joints.child("defaults"), c.joint_defaults);
  const ConfigNode per_joint = joints.child("per_joint");
  for (const std::string& name : per_joint.keys())
    c.joint_overrides[name] = read_joint_params(per_joint.child(name), c.joint_defaults);

  const ConfigNode cam = root.child("camera_offset");
  c.camera_translation.diffusion_per_sqrt_s = cam.number(
      "translation_diffusion_m_per_sqrt_s", c.camera_translation.diffusion_per_sqrt_s, 0, 10);
  c.camera_translation.initial_std =
      cam.number("translation_initial_std_m", c.camera_translation.initial_std, 0, 10);
  c.camera_rotation.diffusion_per_sqrt_s =
      cam.number("rotation_diffusion_deg_per_sqrt_s", c.camera_rotation.diffusion_per_sqrt_s / kDeg,
                 0, 1e4) *
      kDeg;
  c.camera_rotation.initial_std =
      cam.number("rotation_initial_std_deg", c.camera_rotation.initial_std / kDeg, 0, 180) * kDeg;

  const ConfigNode vision = root.child("vision_only");
  c.vision_only_angle_diffusion_rad_per_sqrt_s =
      vision.number("angle_diffusion_deg_per_sqrt_s",
                    c.vision_only_angle_diffusion_rad_per_sqrt_s / kDeg, 0, 1e5) *
      kDeg;
  c.vision_only_initial_std_rad =
      vision.number("initial_std_deg", c.vision_only_initial_std_rad / kDeg, 0, 180) * kDeg;

  const ConfigNode dm = root.child("depth_model");
  DepthModelParams& d = c.depth_model;
  d.occluder_model =
      dm.choice("occluder_model",
                d.occluder_model == OccluderModel::kTruncated ? "truncated" : "independent",
                {"independent", "truncated"}) == "truncated"
          ? OccluderModel::kTruncated
          : OccluderModel::kIndependent;
  d.outlier_weight = dm.number("outlier_weight", d.outlier_weight, 1e-9, 1);
  d.noise_std_m = dm.number("noise_std_m", d.noise_std_m, 1e-6, 1);
  d.noise_quadratic_per_m = dm.number("noise_quadratic_per_m", d.noise_quadratic_per_m, 0, 1);
  d.max_range_m = dm.number("max_range_m", d.max_range_m, 0.1, 100);
  d.occluder_decay_per_m = dm.number("occluder_decay_per_m", d.occluder_decay_per_m, 1e-6, 100);
  d.occlusion_prior = dm.number("occlusion_prior", d.occlusion_prior, 0, 1);
  d.width = int(dm.number("width", d.width, 4, 4096));
  d.height = int(dm.number("height", d.height, 3, 4096));

  const ConfigNode render = root.child("render");
  c.render_cylinder_segments =
      int(render.number("cylinder_segments", c.render_cylinder_segments, 0, 1024));
  c.render_sphere_segments =
      int(render.number("sphere_segments", c.render_sphere_segments, 0, 1024));

  const ConfigNode pf = root.child("particle_filter");
  c.particle_filter.num_particles =
      int(pf.number("particles", c.particle_filter.num_particles, 1, 1e6));
  c.particle_filter.max_kl_divergence =
      pf.number("max_kl_divergence", c.particle_filter.max_kl_divergence, 0, kInf);
  c.particle_filter.proposal_scale =
      pf.number("proposal_scale", c.particle_filter.proposal_scale, 1e-6, 1e6);
  c.particle_filter.bandwidth_factor =
      pf.number("bandwidth_factor", c.particle_filter.bandwidth_factor, 0, 10);
  c.likelihood_exponent = pf.number("likelihood_exponent", c.likelihood_exponent, 1e-3, 1);
  c.seed = pf.get<unsigned long long>("seed", c.seed);
  c.threads = int(pf.number("threads", c.threads, 0, kMaxWorkerThreads));
  for (const ConfigNode& b : pf.list("blocks")) {
    c.blocks.push_back(
        {b.required<std::string>("name"), b.required<std::vector<std::string>>("joints")});
  }

  const ConfigNode uncertainty = root.child("uncertainty");
  c.image_information_scale =
      uncertainty.number("image_information_scale", c.image_information_scale, 1e-6, 1);
  c.discount_correlated_residuals =
      uncertainty.get<bool>("discount_correlated_residuals", c.discount_correlated_residuals);
  const ConfigNode refinement = root.child("refinement");
  c.refine_mean = refinement.get<bool>("enabled", c.refine_mean);
  c.refinement_min_pixels = int(refinement.number("min_pixels", c.refinement_min_pixels, 1, 1e7));

  const ConfigNode acq = root.child("acquisition");
  TrackerConfig::Acquisition& a = c.acquisition;
  a.passes = int(acq.number("passes", a.passes, 1, 10));
  a.coarse_noise_std_m = acq.number("coarse_noise_std_m", a.coarse_noise_std_m, 1e-4, 0.5);
  a.proposal_shrink = acq.number("proposal_shrink", a.proposal_shrink, 0.05, 1);
  a.period_s = acq.number("period_s", a.period_s, 0, 1e6);
  a.bias_std_rad = acq.number("bias_std_deg", a.bias_std_rad / kDeg, 0.1, 180) * kDeg;
  a.accept_margin_nats = acq.number("accept_margin_nats", a.accept_margin_nats, 0, 1e6);
  a.searches = int(acq.number("searches", a.searches, 1, 100));

  const ConfigNode health = root.child("health");
  TrackerConfig::Health& h = c.health;
  h.explained_m = health.number("explained_m", h.explained_m, 1e-4, 1);
  h.contradicted_m = health.number("contradicted_m", h.contradicted_m, 1e-4, 1);
  h.lost_contradicted_fraction =
      health.number("lost_contradicted_fraction", h.lost_contradicted_fraction, 0, 1);
  h.lost_abandoned_fraction =
      health.number("lost_abandoned_fraction", h.lost_abandoned_fraction, 0, 1);
  h.lost_after_images = int(health.number("lost_after_images", h.lost_after_images, 1, 1e6));
  h.min_pixels = int(health.number("min_pixels", h.min_pixels, 1, 1e7));

  const ConfigNode timing = root.child("timing");
  c.camera_delay_s = timing.number("camera_delay_s", c.camera_delay_s, 0, 10);
  c.buffer_capacity = int(timing.number("buffer_capacity", c.buffer_capacity, 2, 1e7));
  c.max_pending_images = int(timing.number("max_pending_images", c.max_pending_images, 1, 1000));
  c.asynchronous = timing.get<bool>("asynchronous", c.asynchronous);

  const ConfigNode checks = root.child("input_checks");
  c.joint_limit_margin_rad =
      checks.number("joint_limit_margin_deg", c.joint_limit_margin_rad / kDeg, 0, 3600) * kDeg;
  c.max_image_clock_offset_s =
      checks.number("max_image_clock_offset_s", c.max_image_clock_offset_s, 1e-3, 1e6);

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
