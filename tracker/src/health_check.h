// The estimate's health check (TrackingHealth, tracker.h; docs/accuracy.md,
// "The failure, and what the tracker does about it", item 3): the robot
// rendered at the estimate and compared with the observed image at the
// likelihood's resolution, whole, per kinematic chain and per chain part,
// and the counts of poor and unconfirmed images that trigger the tracker's
// searches (re-acquisition, confirming searches).
//
// A rendered depth r explains an observed z when |z - r| <= explained_m, and
// is contradicted when z > r + contradicted_m (the camera sees through it).
// A chain is poor when more than lost_contradicted_fraction of its pixels
// are contradicted or more than lost_abandoned_fraction of the pixels it
// explained at its last good image still show the same depth but are no
// longer explained by it. A chain part (the links after one of its joints
// but the first) is unconfirmed when its visible pixels are explained below
// unconfirmed_explained_fraction; pixels with another link in front, or an
// observed surface more than occluder_gap_m in front, give it no verdict.
//
// Internal to the tracker (not installed). Not thread-safe: the image
// thread's.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack {

class HealthCheck {
 public:
  // The chains are the model's physical DOFs (the first num_physical)
  // grouped by their top-most physical ancestor DOF: for the dual arm, the
  // head and each arm. max_range_m: observed depths beyond it are invalid.
  HealthCheck(const RobotModel& model, int num_physical, const TrackerConfig::Health& params,
              double max_range_m);

  // A TrackingHealth with one named ChainHealth per chain (by its root
  // joint) and the whole robot named "all", nothing assessed yet.
  TrackingHealth initial_health() const;

  // Physical DOFs per chain, and per chain its parts: (joint, the links it
  // moves) for each of its joints but the root.
  const std::vector<std::vector<int>>& chains() const { return chains_; }
  const std::vector<std::pair<int, LinkSet>>& parts(std::size_t chain) const {
    return parts_[chain];
  }

  // Assesses the robot at q (every DOF) against `observed`, drawn by
  // `renderer` at observed's size: fills `health` (whole, chains, state,
  // image_stamp_s) and counts poor and unconfirmed images.
  void update(std::span<const double> q, const DepthImage& observed, double stamp_s,
              DepthRenderer& renderer, TrackingHealth& health);

  // Whether the image supports the robot at q for chain c: its parts have a
  // verdict, and none is unconfirmed or its weakest part is explained more
  // than `weakest_before` (the estimate's, NaN: none). Changes no count.
  bool supports_chain(std::span<const double> q, std::size_t c, const DepthImage& observed,
                      DepthRenderer& renderer, double weakest_before);

  // What the last update() found, and the counts the searches use.
  bool chain_poor(std::size_t c) const { return chain_poor_[c] != 0; }
  // Images in a row chain c has been unconfirmed (0: confirmed).
  int unconfirmed_images(std::size_t c) const { return unconfirmed_images_[c]; }
  bool any_unconfirmed() const;
  // Images in a row with some chain poor.
  int poor_images() const { return poor_images_; }
  // Re-acquisitions since the last image with no chain poor.
  int failed_reacquisitions() const { return failed_reacquisitions_; }
  // Confirming searches since the last image with no chain unconfirmed.
  int failed_confirmations() const { return failed_confirmations_; }

  // A search of the unconfirmed chains ran: they start counting again.
  void confirming_search_ran();
  // A re-acquisition of the poor chains ran: the poor images start counting
  // again, and the failures go up until an image with no chain poor.
  void reacquisition_ran();

 private:
  // Rendered, explained and contradicted pixels of check_image_ (out).
  void assess(const DepthImage& observed, ChainHealth& out) const;
  // ChainHealth::weakest_part_* and unconfirmed of chain c, whose robot is
  // in kinematics_ and rendered whole in full_image_, and whose
  // rendered_pixels `out` has (overwrites image_).
  void assess_parts(std::size_t c, const DepthImage& observed, DepthRenderer& renderer,
                    ChainHealth& out);
  void set_configuration(std::span<const double> q);
  bool explains(float r, float z) const {
    return r > 0 && z > 0 && std::abs(z - r) <= params_.explained_m;
  }

  const RobotModel& model_;
  TrackerConfig::Health params_;
  float max_range_m_;
  std::vector<std::string> chain_names_;
  std::vector<std::vector<int>> chains_;
  std::vector<LinkSet> chain_links_;
  std::vector<std::vector<std::pair<int, LinkSet>>> parts_;
  // Per chain: the observed depth where its render was explained at its
  // last good image (0 elsewhere), at the likelihood's resolution.
  std::vector<std::vector<float>> explained_depth_m_;
  std::vector<char> chain_poor_;
  std::vector<int> unconfirmed_images_;
  int poor_images_ = 0;
  int failed_reacquisitions_ = 0;
  int failed_confirmations_ = 0;
  // Scratch.
  Eigen::VectorXd q_;
  KinematicsState kinematics_;
  DepthImage image_, full_image_;
};

}  // namespace arttrack
