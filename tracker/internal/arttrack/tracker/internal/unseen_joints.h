// The joints an image cannot see keep their prior through it (full fusion
// with particle_filter.keep_unseen_prior; docs/method.md, "Joints out of
// view"). A state of the reported covariance whose DOF moves no link the
// camera sees at the image's prior mean, or whose links it sees at fewer
// than particle_filter.unseen_below_pixels pixels there with one of them on
// the view's border or behind a nearer surface, and that no explained pixel
// depends on at the particle filter's mean either, gets its joint's prior
// back: mean and variance, angle and bias, as the joint filter predicted
// them to the image's time. Each link is rendered alone, at the
// likelihood's resolution; a pixel of it is seen where the image has a
// return no more than health.explained_m in front of it. Behind a nearer
// surface (a panel, a person, the robot's other arm) or where the camera
// has no return, the image does not see the link.
//
// Why: out of view, the image says only where such a chain is not. The
// particle filter's draws that bring it into view are contradicted and the
// others score alike, so its moments are the prior cut off at the view's
// edge: a mean pushed away from the view and a variance cut to a fraction.
// Every image repeats that same evidence, so the mean walks away by a
// tenth of a degree or more per image, and the joint filter reads the walk
// as encoder bias: on paper/in_out_in__constant_bias the hidden hand was
// lost (over 2 cm for over a second) in a third of the runs
// (docs/accuracy.md, "The hidden arm keeps its prior"). The pixel model
// counts each image's absence as new and independent evidence; it is
// neither. A filter mean that brings the chain into view where the image
// explains it (some explained pixel depends on the DOF) is positive
// evidence and is kept, so a chain coming back into view is followed.
// A chain at the view's edge, a pixel or two in view at the prior, is the
// same case: the filter pushed it out of view in one image, by up to three
// prior sds with its variance cut to a sixth, and the chain came back into
// view that far off (docs/accuracy.md, "A chain at the view's edge"). A
// chain small in the image but wholly inside it is seen, however few its
// pixels. A chain behind an occluder is the same case again: the draws that
// bring it out past the occluder's edge are contradicted and the others
// score alike, so the filter walked an arm behind a panel 6-11 degrees per
// joint in a second, its variance cut to a tenth, and the hand was lost
// for 3.5 s (docs/accuracy.md, "An arm behind a panel keeps its prior").
//
// Setup: per state, the links its DOF moves (links_affecting_depth).
// Workspace: the prior's kinematics and joints, each link's render, the
// states found unseen. Allocation-free after the first image at a given
// likelihood size. Internal to the tracker (tracker/internal: not
// installed). Not thread-safe: the image thread's.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/internal/gaussian_fold.h"
#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/kinematics.h"

namespace arttrack {

class UnseenJoints {
 public:
  // `state_dofs`: the reported covariance's states' DOFs, in its order.
  UnseenJoints(const TrackerSetup& setup, std::vector<int> state_dofs);

  // Full fusion with keep_unseen_prior.
  bool on() const { return on_; }

  // Before the image's particle filter: keeps `prior` (every joint) and
  // finds the states none of whose links `observed` (the image at the
  // likelihood's resolution, `renderer`'s camera) sees a pixel of at the
  // prior's mean, or fewer than unseen_below_pixels with one on the view's
  // border or behind a nearer surface. Returns how many.
  int find(const JointBelief& prior, DepthRenderer& renderer, const DepthImage& observed);

  // After the image's information at the filter's mean
  // (`pixels_per_state`, ImageInformation::pixels_per_dof, in the states'
  // order): each state find() found that no explained pixel depends on gets
  // its joint's prior back in `belief`. Returns how many joints moved back.
  int keep_priors(std::span<const int> pixels_per_state, JointBelief& belief) const;

 private:
  // The pixels of link_image_ within `rect` that `observed` sees, and
  // whether one of them is on the view's border or one drawn is behind a
  // nearer surface.
  void count_seen(const PixelRect& rect, const DepthImage& observed, int& seen,
                  char& at_edge) const;

  // Setup.
  bool on_ = false;
  int below_pixels_ = 1;    // TrackerConfig::unseen_below_pixels
  float nearer_m_ = 0.01f;  // health.explained_m: a surface nearer hides the link
  const RobotModel* model_;
  std::vector<int> state_dofs_;
  std::vector<LinkSet> state_links_;
  // Workspace.
  KinematicsState kinematics_;
  Eigen::VectorXd q_;
  std::vector<AngleBiasGaussian> prior_;  // per DOF
  LinkSet one_link_;
  std::vector<int> link_pixels_;    // per link: pixels seen at the prior mean
  std::vector<char> link_at_edge_;  // per link: some at the view's or an occluder's edge
  DepthImage link_image_;
  std::vector<char> unseen_;  // per state
};

}  // namespace arttrack
