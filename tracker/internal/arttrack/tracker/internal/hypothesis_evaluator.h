// Scores the Coordinate Particle Filter's particles against one depth image:
// the robot rendered at each particle (depth_renderer.h), summed pixel
// log-likelihood ratios (depth_likelihood.h). The image update's hot loop.
//
// Cached mode (default) renders only what a block changes. Links are grouped
// by the nearest movable joint above them (a group moves rigidly); per block
// the groups are
//   moving:       their pose in the camera depends on the block's coordinates;
//   per-particle: on coordinates sampled by earlier blocks of this run;
//   common:       on neither, so identical for all particles (all unsampled
//                 coordinates sit at the prior mean); drawn once per block.
// The groups are rendered one by one at the prior mean once per run, and a
// block's common image is the nearest depth of its common groups' images.
// Each particle keeps its last full image, per-pixel ratios p(z|r)/p(z|inf)
// and per-group bounding rectangles (copied from its parent on resampling).
// Evaluating block k redraws, in the rectangle the moving groups covered, the
// other groups (common image, per-particle groups that reach into it), draws
// the moving groups at their new pose, and updates the score with the pixels
// whose depth changed: score = parent score + sum of log(new / old ratio).
// A block whose moving groups hold most of the triangles (it moves the camera,
// e.g. head or camera-offset joints) renders and scores particles from scratch.
// With the default hand-to-root blocks, arm blocks draw one subtree over the
// cache and only the head and camera blocks render everything.
// A held block (every particle has its coordinates at the prior mean: a
// search that holds the rest of the robot, acquisition.h) changes no
// particle: its score is the parent's, and a block that renders from
// scratch only sums its cached image again. Nothing is drawn, and the
// scores are the numbers drawing would give: in a search of one hand the
// held blocks were nine in ten of the evaluations.
//
// Scores use DepthLikelihood::ratios() (fast exp/erfc, each ratio rounded to
// float): every particle's score is the sum over its covered pixels of
// log(float ratio), within about 3e-7 per covered pixel of the exact
// DepthLikelihood::log_ratio(). Reference mode renders every particle from
// scratch and scores it with the exact log_ratio() (the slow, obvious
// evaluator, kept for tests and comparisons).
//
// Results depend only on the particles, never on how they are split across
// workers. Allocation-free after the first run at a given image size and
// particle count.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <span>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/internal/coordinate_particle_filter.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {

// Work counters, summed over runs.
struct HypothesisEvaluatorStats {
  long long full_evaluations = 0;    // particles rendered and scored from scratch
  long long cached_evaluations = 0;  // particles that drew only the moving groups
  long long held_evaluations = 0;    // particles of held blocks: nothing drawn
  long long pixels_scored = 0;       // pixel ratios computed (fast path)
};

class HypothesisEvaluator final : public LogLikelihoodEvaluator {
 public:
  enum class Mode { kCached, kReference };

  // `blocks`: the filter's sampling blocks in visiting order (coordinates are
  // DOF indices of `model`). The model must outlive the evaluator. Its
  // renderers draw with `render_options` (RenderGeometry::render_options()).
  HypothesisEvaluator(const RobotModel& model, const std::vector<SamplingBlock>& blocks,
                      Mode mode = Mode::kCached, const RenderOptions& render_options = {});
  ~HypothesisEvaluator() override;

  // Before each filter run: the camera at the likelihood's resolution (its
  // size must equal the likelihood's), the likelihood of the current image
  // (kept by pointer), and the prior mean every particle starts from (size
  // model.num_joints()).
  void begin_run(const CameraIntrinsics& camera, const DepthLikelihood& likelihood,
                 std::span<const double> prior_mean);

  // Log-likelihood (score, up to a constant) of every particle after
  // batch.block was perturbed; blocks must come in order 0, 1, ... after
  // begin_run().
  void evaluate(const ParticleBatch& batch, std::span<double> log_likelihood,
                WorkerPool& pool) override;

  Mode mode() const { return mode_; }
  // Whether block k renders every particle from scratch (always true in reference mode).
  bool renders_fully(int block) const;
  const HypothesisEvaluatorStats& stats() const { return stats_; }

 private:
  struct Group;
  struct BlockPlan;
  struct Workspace;

  void allocate(int num_particles, int num_workers);
  void render_prior_groups();
  void render_reference_slot();
  double evaluate_full(const BlockPlan& plan, int slot, std::span<const double> x, Workspace& w);
  double evaluate_cached(const BlockPlan& plan, int slot, std::span<const double> x, Workspace& w);
  // Whether every particle has the batch's coordinates at the prior mean.
  bool holds_block(const ParticleBatch& batch) const;
  double rescore_held(const BlockPlan& plan, int slot, Workspace& w);
  double score_image(const DepthImage& depth, const PixelRect& rect, float* ratio_out,
                     Workspace& w) const;

  const RobotModel* model_;
  Mode mode_;
  RenderOptions render_options_;
  std::vector<Group> groups_;
  std::vector<BlockPlan> plans_;
  LinkSet all_links_;

  CameraIntrinsics camera_;
  const DepthLikelihood* likelihood_ = nullptr;
  Eigen::VectorXd prior_mean_;
  int next_block_ = 0;

  // Per-particle caches: slots [0, L) and [L, 2L) alternate on resampling,
  // slot 2L holds the prior mean's image. Particle l lives in slot base_ + l.
  int num_particles_ = 0;
  int base_ = 0;
  std::vector<DepthImage> depth_;          // per slot: the full image
  std::vector<std::vector<float>> ratio_;  // per slot: p(z|r)/p(z|inf) where depth > 0
  std::vector<PixelRect> rects_;           // per slot x group: the group's pixels
  std::vector<double> score_;              // per slot
  // Each group alone at the prior mean (the common groups of every block are
  // there), rendered once per run, and the rectangle it covers.
  std::vector<DepthImage> prior_group_depth_;
  std::vector<PixelRect> prior_group_rect_;
  bool prior_groups_rendered_ = false;
  DepthImage common_;  // the current block's common groups: the nearest of their prior images
  std::vector<std::unique_ptr<Workspace>> workspaces_;
  HypothesisEvaluatorStats stats_;
};

}  // namespace arttrack
