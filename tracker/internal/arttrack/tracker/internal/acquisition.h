// Acquisition and re-acquisition (docs/method.md, "Acquisition" and
// "Re-acquisition"; tracker.h): annealed coarse-to-fine searches over one
// image, from the encoders' configuration, at the first image, periodically
// (acquisition.period_s) and when the health check (health_check.h) finds a
// chain poor or unconfirmed.
//
// A search (Deutscher et al.'s annealing, as coarse-to-fine depth noise):
// passes - 1 particle filter passes over the same image, pass k targeting
// prior x likelihood_k, likelihood_k with a depth noise shrinking
// geometrically from acquisition.coarse_noise_std_m to the pixel model's,
// each proposing around the previous pass's mean with the prior's standard
// deviations times proposal_shrink^k; then the image's own filter
// (image_filter.h) runs a final pass that proposes from there but targets
// the prior exactly. acquisition.searches independent searches, the best by
// image plus prior. Full fusion only, with acquisition.passes > 1.
//
// Setup (AcquisitionSetup): the search blocks and pass likelihoods, from the
// model and configuration. Workspace (AcquisitionWorkspace): the search's
// own particle filter, proposals, results and the time of the last search.
// Internal to the tracker (tracker/internal: not installed). Not
// thread-safe: the image thread's.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "arttrack/tracker/internal/coordinate_particle_filter.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/internal/hypothesis_evaluator.h"
#include "arttrack/tracker/internal/image_filter.h"
#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/tracker.h"

namespace arttrack {

class HealthCheck;

struct AcquisitionSetup {
  explicit AcquisitionSetup(const TrackerSetup& setup);

  bool on = false;  // full fusion with acquisition.passes > 1
  const TrackerSetup& tracker;
  TrackerConfig::Acquisition params;
  // The searched DOFs, one block each: the physical joints whose bias is
  // estimated (root to hand), then the camera's.
  std::vector<SamplingBlock> blocks;
  // The pixel models of the search passes, coarse to fine (passes - 1).
  std::vector<DepthModelParams> pass_models;
  // Variance of a re-opened bias, (acquisition.bias_std_rad)^2.
  double reopened_bias_var_rad2 = 0;
};

struct AcquisitionWorkspace {
  explicit AcquisitionWorkspace(const AcquisitionSetup& setup);

  std::optional<CoordinateParticleFilter> cpf;  // the search passes' (when on)
  std::unique_ptr<HypothesisEvaluator> evaluator;
  std::vector<DepthLikelihood> likelihoods;  // setup.pass_models'
  // The proposal of the current pass, the re-opened prior, the chains'
  // candidate, and acquire()'s best search (mean and variance per DOF).
  std::vector<double> search_mean, search_std, open_mean, open_std, candidate;
  std::vector<double> found_mean, found_variance;
  std::vector<char> part_open;  // per DOF: searched by the current confirming search
  double last_search_s = -std::numeric_limits<double>::infinity();
};

// Which search an image is due (due_search()).
enum class SearchKind {
  kNone,
  kPoor,        // some chain poor: re-acquisition of the poor chains
  kConfirming,  // some chain unconfirmed long enough: its weakest part searched
  kPeriodic,    // acquisition.period_s since the last search
};

class Acquisition {
 public:
  explicit Acquisition(const TrackerSetup& setup);

  const AcquisitionSetup& setup() const { return setup_; }
  bool on() const { return setup_.on; }
  // Makes the search's evaluator for the image filter's drawn model (after
  // ImageFilter::set_image returned true).
  void draw(const RenderGeometry& geometry);

  // The first image (the prior is the encoders': bias prior around the
  // readings): searches the prior coarse to fine and folds the best search
  // into `belief` (fold_angle_posteriors). With acquisition.search_camera
  // false the camera is held at its prior: one image does not tell the
  // camera's roll and sideways shift from both arms' biases
  // (tracker_config.h), and the images after it do. Counts the search in
  // `health`; returns its time in ms.
  double acquire_first(ImageFilter& image, const DepthImage& observed,
                       std::span<const double> prior_std, double time_s, JointBelief& belief,
                       TrackingHealth& health);

  // The search an image after the first is due, from the health check's
  // counts. A re-acquisition that did not help (the chain still poor) is
  // retried after twice as many poor images each time, up to 16 times as
  // many: a tracker that stays lost (a wrong model, images that do not match
  // the joints) must not spend every image on searches. Unconfirmed chains
  // have a back-off of their own: an occluded hand stays unconfirmed, and
  // the search must not run at every image while it is hidden.
  SearchKind due_search(const HealthCheck& check, double time_s) const;

  // Augmented-MCL-style re-acquisition (Thrun et al., Probabilistic
  // Robotics): re-opens the prior of every joint whose bias is estimated to
  // the encoders' `reading` (DOF order) with a broad bias
  // (acquisition.bias_std_rad), searches it, and lets each chain take the
  // result when the image plus that prior prefer it by accept_margin_nats. A
  // chain that settled in a wrong mode gets out; one that is right keeps its
  // belief. Marks the DOFs it moved in `reopened`; counts in `health` and
  // `check`.
  void reacquire(SearchKind kind, ImageFilter& image, const DepthImage& observed,
                 HealthCheck& check, std::span<const double> reading, double time_s,
                 JointBelief& belief, TrackingHealth& health, std::vector<char>& reopened);

  // acquisition.searches independent searches from the prior N(mean,
  // stddev^2), each with its own random draws and a final pass that targets
  // the prior; leaves in found_mean and found_variance the final pass whose
  // mean the image plus the prior prefer. One search lands in a wrong mode
  // now and then (bias_jump, 8 seeds: a hand left 10 cm off for 3 s, an arm
  // 6 cm off from the first image, both rated "tracking"; docs/accuracy.md).
  void acquire(ImageFilter& image, const DepthImage& observed, std::span<const double> mean,
               std::span<const double> stddev);
  const AcquisitionWorkspace& workspace() const { return ws_; }

 private:
  // One annealed search: leaves in search_mean and search_std the proposal
  // of the final pass.
  void search(ImageFilter& image, const DepthImage& observed, std::span<const double> mean,
              std::span<const double> stddev);
  // A confirming search opens only each unconfirmed chain's weakest part.
  void open_weakest_parts(const HealthCheck& check, const TrackingHealth& health,
                          const JointBelief& belief);

  const AcquisitionSetup setup_;
  AcquisitionWorkspace ws_;
};

}  // namespace arttrack
