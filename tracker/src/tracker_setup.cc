#include "arttrack/tracker/internal/tracker_setup.h"

#include <algorithm>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/coordinate_particle_filter.h"
#include "arttrack/tracker/tracker.h"

namespace arttrack {
namespace {

// The configuration, validated before any member is built from it.
const TrackerConfig& validated(const TrackerConfig& config) {
  config.validate(config.source);
  return config;
}

}  // namespace

TrackerSetup::TrackerSetup(std::shared_ptr<const RobotModel> m, const TrackerConfig& c,
                           const std::vector<std::string>& encoder_joints)
    : model(std::move(m)), config(validated(c)) {
  n = model->num_joints();
  for (int j = 0; j < n; ++j)
    if (!model->is_virtual_joint(j)) ++n_phys;
  if (n - n_phys != 6)
    throw InputError(model->source() + ": the tracker needs the six virtual camera joints");
  use_encoders = config.method != TrackingMethod::kVisionOnly;
  use_images = config.method != TrackingMethod::kEncodersOnly;

  // Encoder order -> DOFs: every physical joint exactly once.
  if (use_encoders) {
    std::vector<int> seen(n_phys, 0);
    for (const std::string& name : encoder_joints) {
      const int dof = model->joint_index(name);
      if (model->is_virtual_joint(dof))
        throw InputError("encoder joint '" + name + "' is a virtual camera joint");
      if (seen[dof]++) throw InputError("encoder joint '" + name + "' is listed twice");
      encoder_dof.push_back(dof);
    }
    for (int j = 0; j < n_phys; ++j)
      if (!seen[j])
        throw InputError("no encoder reading for joint '" + model->joint_name(j) +
                         "' (every physical joint needs one, except for vision_only)");
  }
  for (const std::string& ee : config.end_effectors) ee_links.push_back(model->link_index(ee));

  // Joint filter bank in DOF order.
  std::vector<std::string> phys_names(model->joint_names().begin(),
                                      model->joint_names().begin() + n_phys);
  std::vector<std::string> virtual_names(model->joint_names().begin() + n_phys,
                                         model->joint_names().end());
  JointFilterParams defaults = config.joint_defaults;
  if (config.method == TrackingMethod::kCameraOffsetOnly) defaults.estimate_bias = false;
  if (config.method == TrackingMethod::kVisionOnly) {
    defaults.estimate_bias = false;
    defaults.angle_diffusion_rad_per_sqrt_s = config.vision_only_angle_diffusion_rad_per_sqrt_s;
  }
  auto overrides = config.joint_overrides;
  for (auto& [name, p] : overrides) {
    if (config.method != TrackingMethod::kFullFusion) p.estimate_bias = false;
    if (config.method == TrackingMethod::kVisionOnly)
      p.angle_diffusion_rad_per_sqrt_s = config.vision_only_angle_diffusion_rad_per_sqrt_s;
  }
  auto phys_params = per_joint_params(phys_names, defaults, overrides, config.source);
  std::vector<VirtualJointParams> virtual_params;
  for (int k = 0; k < 6; ++k)
    virtual_params.push_back(k < 3 ? config.camera_translation : config.camera_rotation);
  filter_model =
      std::make_unique<JointFilterModel>(phys_names, phys_params, virtual_names, virtual_params);
  bias_estimated.assign(n_phys, 0);
  for (int j = 0; j < n_phys; ++j) bias_estimated[j] = phys_params[j].estimate_bias;
}

std::vector<SamplingBlock> sampling_blocks(const RobotModel& model, const TrackerConfig& config) {
  std::vector<SamplingBlock> blocks;
  if (config.method == TrackingMethod::kEncodersOnly) return blocks;
  if (!config.blocks.empty()) {
    for (const auto& b : config.blocks) {
      SamplingBlock block{b.name, {}};
      for (const std::string& joint : b.joints) {
        try {
          block.coordinates.push_back(model.joint_index(joint));
        } catch (const InputError& e) {
          throw InputError(config.source + ": block '" + b.name + "': " + e.what());
        }
      }
      blocks.push_back(std::move(block));
    }
  } else {
    // One block per joint, virtual ones included. A single six-dimensional
    // camera block settles in local optima (a roll and pitch that mimic a
    // sideways shift; see TrackerTest.CameraOffsetOnlyRecoversAMiscalibratedCamera),
    // which coordinate-wise sampling avoids. A joint whose bias is not
    // estimated follows its encoder: sampling it would spend particles on
    // what the encoder already says (a humanoid's fingers, eyes and neck).
    const auto sampled = [&](int dof) {
      if (model.is_virtual_joint(dof) || config.method == TrackingMethod::kVisionOnly) return true;
      if (config.method != TrackingMethod::kFullFusion) return false;
      const auto it = config.joint_overrides.find(model.joint_name(dof));
      return it != config.joint_overrides.end() ? it->second.estimate_bias
                                                : config.joint_defaults.estimate_bias;
    };
    // Physical joints from the hand to the root of each chain (reverse
    // depth-first order), then the virtual ones.
    const int n = model.num_joints();
    for (int j = n - 1; j >= 0; --j)
      if (!model.is_virtual_joint(j) && sampled(j)) blocks.push_back({model.joint_name(j), {j}});
    for (int j = 0; j < n; ++j)
      if (model.is_virtual_joint(j)) blocks.push_back({model.joint_name(j), {j}});
  }
  if (config.method == TrackingMethod::kCameraOffsetOnly) {
    // Encoders are trusted: only the virtual joints are sampled.
    for (auto& b : blocks)
      std::erase_if(b.coordinates, [&](int j) { return !model.is_virtual_joint(j); });
    std::erase_if(blocks, [](const SamplingBlock& b) { return b.coordinates.empty(); });
  }
  return blocks;
}

}  // namespace arttrack
