// The tracker's setup: what the robot model, the configuration and the
// encoders' order decide once, before any measurement, and nothing changes
// afterwards (Pinocchio's Model; each component's per-run workspace is its
// Data). Tracker's constructor builds it, and the image update's components
// (image_update.h) read it.
//
// Internal to the tracker (tracker/internal: not installed).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack {

struct TrackerSetup {
  // Validates `config` first (TrackerConfig::validate), then the model (its
  // six virtual camera joints), the encoder order (every physical joint
  // exactly once, none virtual; not read for vision_only), the end effectors
  // and the per-joint filter parameters. Throws InputError naming the item.
  TrackerSetup(std::shared_ptr<const RobotModel> model, const TrackerConfig& config,
               const std::vector<std::string>& encoder_joints);

  std::shared_ptr<const RobotModel> model;
  TrackerConfig config;
  int n = 0;                         // DOFs: physical then virtual (the model's order = the bank's)
  int n_phys = 0;                    // physical joints
  bool use_encoders = true;          // not vision_only
  bool use_images = true;            // not encoders_only
  std::vector<int> encoder_dof;      // reading index -> DOF
  std::vector<int> ee_links;         // config.end_effectors' links
  std::vector<char> bias_estimated;  // per physical DOF, after the method's rules
  // The joint filters' noises in DOF order, with the method's rules applied:
  // camera_offset_only and vision_only estimate no bias; vision_only's
  // angles diffuse at vision_only_angle_diffusion_rad_per_sqrt_s.
  std::unique_ptr<const JointFilterModel> filter_model;
};

}  // namespace arttrack
