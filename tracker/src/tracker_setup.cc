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
  for (const auto& [name, o] : config.joint_overrides)
    if (std::find(phys_names.begin(), phys_names.end(), name) == phys_names.end())
      throw InputError(config.source + ": joints.per_joint: unknown joint '" + name + "'");
  std::vector<JointFilterParams> phys_params;
  for (int j = 0; j < n_phys; ++j) {
    JointFilterParams p = joint_filter_params(*model, config, j);
    // Camera offset only and vision only estimate no bias; encoders only
    // keeps the defaults' bias prior in its angles' spread (but not an
    // override's).
    if (config.method == TrackingMethod::kCameraOffsetOnly ||
        config.method == TrackingMethod::kVisionOnly ||
        (config.method != TrackingMethod::kFullFusion &&
         config.joint_overrides.count(model->joint_name(j))))
      p.estimate_bias = false;
    // Vision only: no encoder between images, the motion diffuses at
    // vision_only's rate (a prismatic joint's scaled as an angle's is).
    if (config.method == TrackingMethod::kVisionOnly)
      p.angle_diffusion_rad_per_sqrt_s =
          model->joint_type(j) == JointType::kPrismatic
              ? p.angle_diffusion_rad_per_sqrt_s *
                    config.vision_only_angle_diffusion_rad_per_sqrt_s /
                    config.joint_defaults.angle_diffusion_rad_per_sqrt_s
              : config.vision_only_angle_diffusion_rad_per_sqrt_s;
    phys_params.push_back(p);
  }
  std::vector<VirtualJointParams> virtual_params;
  for (int k = 0; k < 6; ++k) virtual_params.push_back(config.camera_joint_params(k));
  filter_model =
      std::make_unique<JointFilterModel>(phys_names, phys_params, virtual_names, virtual_params);
  bias_estimated.assign(n_phys, 0);
  for (int j = 0; j < n_phys; ++j) bias_estimated[j] = phys_params[j].estimate_bias;
}

JointFilterParams joint_filter_params(const RobotModel& model, const TrackerConfig& config,
                                      int dof) {
  const std::string& name = model.joint_name(dof);
  const bool prismatic = model.joint_type(dof) == JointType::kPrismatic;
  const JointFilterParams& defaults =
      prismatic ? config.prismatic_joint_defaults : config.joint_defaults;
  const auto it = config.joint_overrides.find(name);
  if (it == config.joint_overrides.end()) return defaults;
  const JointFilterOverride& o = it->second;
  if (o.linear && *o.linear != prismatic) {
    const JointNoiseKeys& keys = joint_noise_keys(prismatic);
    throw InputError(config.source + ": joints.per_joint." + name + ": '" + name + "' is " +
                     (prismatic ? "a prismatic joint: its keys are in metres ("
                                : "a revolute joint: its keys are in degrees (") +
                     keys.encoder_noise + ", " + keys.motion_diffusion + ", " +
                     keys.bias_diffusion + ")");
  }
  return o.over(defaults);
}

bool is_camera_block(const SamplingBlock& block, const RobotModel& model) {
  return std::all_of(block.coordinates.begin(), block.coordinates.end(),
                     [&](int j) { return model.is_virtual_joint(j); });
}

int blocks_sampled_per_image(const std::vector<SamplingBlock>& blocks, const RobotModel& model,
                             const TrackerConfig& config) {
  const int all = int(blocks.size());
  if (config.method != TrackingMethod::kFullFusion) return all;
  const int camera = int(std::count_if(blocks.begin(), blocks.end(), [&](const SamplingBlock& b) {
    return is_camera_block(b, model);
  }));
  return all - camera + std::min(camera, config.camera_blocks_per_image);
}

CoordinateParticleFilterParams particle_filter_params(const TrackerConfig& config, int num_blocks) {
  CoordinateParticleFilterParams params = config.particle_filter;
  if (config.method != TrackingMethod::kFullFusion) {
    params.bandwidth_factor = 0;
  } else if (num_blocks > 0) {
    params.num_particles =
        std::max(params.num_particles, (config.min_evaluations + num_blocks - 1) / num_blocks);
  }
  return params;
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
      return joint_filter_params(model, config, dof).estimate_bias;
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
