// The camera offset's random walk as the joints that carry the camera move
// (VirtualJointParams::motion_diffusion_per_sqrt_rad).
//
// The six virtual joints correct the camera frame the URDF gives. On a
// camera carried by joints (a pan-tilt head) that correction is not a
// constant: an axis a degree or two off, or an origin a few millimetres
// off, turns and moves the true camera against the model's as the head
// turns, by an amount that grows with how far it turned, not with how much
// time passed. The paper's head (paper/base/apollo.yaml: axes tilted by 1.5
// and 2.5 degrees) moves the true offset 0.5-0.8 degrees over its range.
// With only the time diffusion the estimate lags it: on the exact-depth
// both_fast file, whose head moves three times as fast, the offset's roll
// and y stayed 0.2 degrees and 1.3 mm off, against standard deviations of
// 0.1 degrees and 0.8 mm (docs/accuracy.md, "The camera that turns with
// the head").
//
// So at each image every virtual joint's variance grows by
//   sigma_m^2 * sum over the carrying joints j of max(0, |dq_j| - sqrt(2) sigma_q,j),
// dq_j the change of joint j's estimated angle since the previous image,
// less what two readings' encoder noise sigma_q,j moves it by (a still
// head adds next to nothing). A camera fixed in the world, or carried by no
// joint the tracker knows, gets nothing, and so does vision only (no
// encoder measures the head's travel apart from the images).
//
// Setup: the model and the filters' noises. Workspace: the carrying joints'
// angles at the previous image. Allocation-free after construction.
#pragma once

#include <span>
#include <vector>

#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack {

class CameraCarrierMotion {
 public:
  // The physical DOFs whose motion moves the nominal camera frame (the
  // ancestors of model.nominal_camera_link(), mimics included), and the
  // virtual joints' sigma_m^2 from `config` (translation, then rotation).
  CameraCarrierMotion(const RobotModel& model, const JointFilterModel& filters,
                      const TrackerConfig& config);

  // Whether any virtual joint can grow: a carrying joint, a sigma_m > 0 and
  // a method with encoders (not vision only).
  bool on() const { return on_; }
  const std::vector<int>& carrying_dofs() const { return carrying_dofs_; }

  // At an image: the angle means (DOF order) at its time; fills `added_var`
  // (DOF order, the model's size) with each DOF's variance to add, 0 but for
  // the virtual joints, and returns the carrying joints' travel counted
  // since the previous call, rad (metres for a prismatic one). The first
  // call counts none.
  double added_variance(std::span<const double> mean_a, std::span<double> added_var);

 private:
  std::vector<int> carrying_dofs_;
  std::vector<double> noise_allowance_;  // sqrt(2) sigma_q per carrying DOF
  std::vector<double> rate_var_;         // sigma_m^2 per DOF (0 but virtual joints)
  std::vector<double> previous_;         // the carrying DOFs' angles at the last call
  bool started_ = false;
  bool on_ = false;
};

}  // namespace arttrack
