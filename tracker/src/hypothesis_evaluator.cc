#include "arttrack/tracker/internal/hypothesis_evaluator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <string>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/worker_pool.h"

namespace arttrack {
namespace {

bool intersects(const PixelRect& a, const PixelRect& b) {
  return !a.empty() && !b.empty() && a.u0 < b.u1 && b.u0 < a.u1 && a.v0 < b.v1 && b.v0 < a.v1;
}

// log of a product of positive factors, renormalised by frexp every eight
// factors: the pixel ratios lie within about 1e-15..1e18 (depth_likelihood.cc),
// so eight quotients of them stay far inside the double range.
class LogProduct {
 public:
  void multiply(double factor) {
    product_ *= factor;
    if (++pending_ == 8) {
      int e;
      product_ = std::frexp(product_, &e);
      exponent_ += e;
      pending_ = 0;
    }
  }
  double log() const { return std::log(product_) + double(exponent_) * std::numbers::ln2; }

 private:
  double product_ = 1;
  long exponent_ = 0;
  int pending_ = 0;
};

}  // namespace

// Links that move rigidly together: those whose nearest movable joint at or
// above them is the same (or none: the root's group).
struct HypothesisEvaluator::Group {
  LinkSet links;
  std::vector<bool> depends_on;  // per DOF: the group's pose in the camera frame changes with it
  long long triangles = 0;
};

struct HypothesisEvaluator::BlockPlan {
  bool full = false;        // render and score every particle from scratch
  bool keep_cache = false;  // a later block is cached: keep rectangles and ratios up to date
  std::vector<int> moving, per_particle, common;  // group indices
};

// Per-worker scratch (the renderer holds per-vertex buffers).
struct HypothesisEvaluator::Workspace {
  Eigen::VectorXd q;
  KinematicsState kinematics;
  std::unique_ptr<DepthRenderer> renderer;
  DepthImage statics;  // other groups, valid inside the moving groups' old rectangle
  DepthImage moving;   // the moving groups alone, zero outside moving_dirty
  PixelRect moving_dirty;
  DepthImage image;  // reference mode
  // Changed or covered pixels of one evaluation.
  std::vector<int> pixel, covered_pixel;
  std::vector<float> depth, covered_depth, ratio;
  long long full = 0, cached = 0, held = 0, pixels = 0;
};

HypothesisEvaluator::HypothesisEvaluator(const RobotModel& model,
                                         const std::vector<SamplingBlock>& blocks, Mode mode,
                                         const RenderOptions& render_options)
    : model_(&model),
      mode_(mode),
      render_options_(render_options),
      all_links_(model.num_links(), true) {
  const int n = model.num_joints();
  const int camera = model.camera_link();
  std::vector<LinkSet> moved(n);
  for (int d = 0; d < n; ++d) moved[d] = model.links_moved_by(d);

  std::map<int, int> group_of_key;
  long long total_triangles = 0;
  for (int l : model.links_with_geometry()) {
    int key = l;
    // Up to the nearest link that moves on its own (a mimic follows its leader).
    while (model.link(key).dof < 0 && model.link(key).mimic_dof < 0 && model.link(key).parent >= 0)
      key = model.link(key).parent;
    auto [it, inserted] = group_of_key.emplace(key, int(groups_.size()));
    if (inserted) {
      Group g;
      g.links.assign(model.num_links(), false);
      g.depends_on.resize(n);
      for (int d = 0; d < n; ++d) g.depends_on[d] = moved[d][key] != moved[d][camera];
      groups_.push_back(std::move(g));
    }
    Group& g = groups_[it->second];
    g.links[l] = true;
    g.triangles += (long long)model.link(l).mesh.triangles.size();
    total_triangles += (long long)model.link(l).mesh.triangles.size();
  }

  std::vector<bool> sampled(n, false);
  for (const SamplingBlock& block : blocks) {
    for (int c : block.coordinates)
      if (c < 0 || c >= n)
        throw InputError("hypothesis evaluator: block '" + block.name + "' has coordinate " +
                         std::to_string(c) + " outside the model's " + std::to_string(n) +
                         " joints");
    BlockPlan plan;
    long long moving_triangles = 0;
    for (int g = 0; g < int(groups_.size()); ++g) {
      bool moves = false, differs = false;
      for (int c : block.coordinates) moves = moves || groups_[g].depends_on[c];
      for (int d = 0; d < n; ++d) differs = differs || (sampled[d] && groups_[g].depends_on[d]);
      if (moves) {
        plan.moving.push_back(g);
        moving_triangles += groups_[g].triangles;
      } else if (differs) {
        plan.per_particle.push_back(g);
      } else {
        plan.common.push_back(g);
      }
    }
    // Drawing most of the robot over a cache and scoring the changes costs
    // more than rendering and scoring it all (every pixel would change).
    plan.full = mode_ == Mode::kReference || 4 * moving_triangles > 3 * total_triangles;
    for (int c : block.coordinates) sampled[c] = true;
    plans_.push_back(std::move(plan));
  }
  bool later_cached = false;
  for (int k = int(plans_.size()) - 1; k >= 0; --k) {
    plans_[k].keep_cache = later_cached;
    later_cached = later_cached || !plans_[k].full;
  }
  prior_mean_ = Eigen::VectorXd::Zero(n);
}

HypothesisEvaluator::~HypothesisEvaluator() = default;

bool HypothesisEvaluator::renders_fully(int block) const { return plans_.at(block).full; }

void HypothesisEvaluator::begin_run(const CameraIntrinsics& camera,
                                    const DepthLikelihood& likelihood,
                                    std::span<const double> prior_mean) {
  ARTTRACK_CHECK_ARGUMENT(camera.width == likelihood.width() &&
                          camera.height == likelihood.height());
  ARTTRACK_CHECK_ARGUMENT(int(prior_mean.size()) == model_->num_joints());
  if (!(camera == camera_)) {
    camera_ = camera;
    num_particles_ = 0;  // buffers and renderers are rebuilt for the new camera
    workspaces_.clear();
  }
  likelihood_ = &likelihood;
  for (int j = 0; j < prior_mean_.size(); ++j) prior_mean_[j] = prior_mean[j];
  next_block_ = 0;
  prior_groups_rendered_ = false;
}

void HypothesisEvaluator::allocate(int num_particles, int num_workers) {
  if (num_particles == num_particles_ && int(workspaces_.size()) == num_workers) return;
  const int W = camera_.width, H = camera_.height;
  const int slots = 2 * num_particles + 1;
  num_particles_ = num_particles;
  base_ = 0;
  depth_.assign(slots, DepthImage(W, H));
  ratio_.assign(slots, std::vector<float>(std::size_t(W) * H, 1.f));
  rects_.assign(std::size_t(slots) * groups_.size(), PixelRect{});
  score_.assign(slots, 0.0);
  common_ = DepthImage(W, H);
  prior_group_depth_.assign(groups_.size(), DepthImage(W, H));
  prior_group_rect_.assign(groups_.size(), PixelRect{});
  prior_groups_rendered_ = false;
  workspaces_.clear();
  for (int w = 0; w < num_workers; ++w) {
    auto ws = std::make_unique<Workspace>();
    ws->q = Eigen::VectorXd::Zero(model_->num_joints());
    ws->kinematics = KinematicsState(*model_);
    // The other workers copy the first renderer's clusters instead of building them again.
    ws->renderer = w == 0 ? std::make_unique<DepthRenderer>(*model_, camera_, render_options_)
                          : std::make_unique<DepthRenderer>(*workspaces_[0]->renderer);
    ws->statics = ws->moving = ws->image = DepthImage(W, H);
    for (auto* v : {&ws->pixel, &ws->covered_pixel}) v->resize(std::size_t(W) * H);
    for (auto* v : {&ws->depth, &ws->covered_depth, &ws->ratio}) v->resize(std::size_t(W) * H);
    workspaces_.push_back(std::move(ws));
  }
}

// Sum of log(ratio) over the covered pixels of `rect`; stores each ratio
// in ratio_out (indexed by pixel) when given.
double HypothesisEvaluator::score_image(const DepthImage& depth, const PixelRect& rect,
                                        float* ratio_out, Workspace& w) const {
  int n = 0;
  for (int v = rect.v0; v < rect.v1; ++v) {
    const float* row = depth.depth_m.data() + std::size_t(v) * depth.width;
    for (int u = rect.u0; u < rect.u1; ++u) {
      if (row[u] > 0.f) {
        w.covered_pixel[n] = v * depth.width + u;
        w.covered_depth[n++] = row[u];
      }
    }
  }
  likelihood_->ratios(w.covered_pixel.data(), w.covered_depth.data(), n, w.ratio.data());
  LogProduct product;
  for (int k = 0; k < n; ++k) product.multiply(w.ratio[k]);
  if (ratio_out)
    for (int k = 0; k < n; ++k) ratio_out[w.covered_pixel[k]] = w.ratio[k];
  w.pixels += n;
  return product.log();
}

// Every group alone at the prior mean.
void HypothesisEvaluator::render_prior_groups() {
  Workspace& w = *workspaces_[0];
  forward_kinematics(*model_, prior_mean_, w.kinematics);
  for (std::size_t g = 0; g < groups_.size(); ++g)
    prior_group_rect_[g] =
        w.renderer->render_links(w.kinematics, groups_[g].links, prior_group_depth_[g]);
  prior_groups_rendered_ = true;
}

// The prior mean's image, rectangles and ratios in slot 2L: the parent of
// every particle at block 0.
void HypothesisEvaluator::render_reference_slot() {
  Workspace& w = *workspaces_[0];
  const int slot = 2 * num_particles_;
  const int G = int(groups_.size());
  DepthImage& image = depth_[slot];
  std::fill(image.depth_m.begin(), image.depth_m.end(), 0.f);
  PixelRect all;
  for (int g = 0; g < G; ++g) {
    merge_nearer(prior_group_depth_[g], prior_group_rect_[g], image);
    rects_[std::size_t(slot) * G + g] = prior_group_rect_[g];
    all = all.united(prior_group_rect_[g]);
  }
  score_[slot] = score_image(image, all, ratio_[slot].data(), w);
}

double HypothesisEvaluator::evaluate_full(const BlockPlan& plan, int slot,
                                          std::span<const double> x, Workspace& w) {
  for (int j = 0; j < w.q.size(); ++j) w.q[j] = x[j];
  forward_kinematics(*model_, w.q, w.kinematics);
  DepthImage& image = depth_[slot];
  std::fill(image.depth_m.begin(), image.depth_m.end(), 0.f);
  PixelRect all;
  if (plan.keep_cache) {
    const int G = int(groups_.size());
    for (int g = 0; g < G; ++g) {
      const PixelRect r = w.renderer->draw_links(w.kinematics, groups_[g].links, image);
      rects_[std::size_t(slot) * G + g] = r;
      all = all.united(r);
    }
  } else {
    all = w.renderer->draw_links(w.kinematics, all_links_, image);
  }
  ++w.full;
  score_[slot] = score_image(image, all, plan.keep_cache ? ratio_[slot].data() : nullptr, w);
  return score_[slot];
}

bool HypothesisEvaluator::holds_block(const ParticleBatch& batch) const {
  for (int c : batch.coordinates)
    for (int l = 0; l < batch.num_particles; ++l)
      if (!(batch.particle(l)[std::size_t(c)] == prior_mean_[c])) return false;
  return true;
}

// The particle's image is what evaluate_full would draw (a link drawn twice
// at one pose is drawn alike); its score is summed again from scratch over
// the same covered pixels in the same order, as evaluate_full sums it, so
// that the score is the same number.
double HypothesisEvaluator::rescore_held(const BlockPlan& plan, int slot, Workspace& w) {
  const PixelRect all{0, 0, camera_.width, camera_.height};
  score_[slot] = score_image(depth_[slot], all, plan.keep_cache ? ratio_[slot].data() : nullptr, w);
  return score_[slot];
}

double HypothesisEvaluator::evaluate_cached(const BlockPlan& plan, int slot,
                                            std::span<const double> x, Workspace& w) {
  for (int j = 0; j < w.q.size(); ++j) w.q[j] = x[j];
  forward_kinematics(*model_, w.q, w.kinematics);
  const int W = camera_.width;
  const int G = int(groups_.size());
  PixelRect* rects = rects_.data() + std::size_t(slot) * G;

  // Where the moving groups were: there the other groups are redrawn (the
  // common image, and per-particle groups that reach into it).
  PixelRect old;
  for (int g : plan.moving) old = old.united(rects[g]);
  if (!old.empty()) {
    for (int v = old.v0; v < old.v1; ++v) {
      const std::size_t i = std::size_t(v) * W + old.u0;
      std::memcpy(w.statics.depth_m.data() + i, common_.depth_m.data() + i,
                  sizeof(float) * old.width());
    }
    for (int g : plan.per_particle)
      if (intersects(rects[g], old))
        w.renderer->draw_links(w.kinematics, groups_[g].links, w.statics);
  }

  // The moving groups at their new pose, alone.
  for (int v = w.moving_dirty.v0; v < w.moving_dirty.v1; ++v)
    std::fill_n(w.moving.depth_m.data() + std::size_t(v) * W + w.moving_dirty.u0,
                w.moving_dirty.width(), 0.f);
  PixelRect now;
  for (int g : plan.moving) {
    rects[g] = w.renderer->draw_links(w.kinematics, groups_[g].links, w.moving);
    now = now.united(rects[g]);
  }
  w.moving_dirty = now;

  // New depth in both rectangles; collect the pixels that changed.
  float* depth = depth_[slot].depth_m.data();
  float* ratio = ratio_[slot].data();
  const PixelRect both = old.united(now);
  int changed = 0, covered = 0;
  for (int v = both.v0; v < both.v1; ++v) {
    const bool row_old = v >= old.v0 && v < old.v1;
    const bool row_now = v >= now.v0 && v < now.v1;
    for (int u = both.u0; u < both.u1; ++u) {
      const int i = v * W + u;
      const float s = row_old && u >= old.u0 && u < old.u1 ? w.statics.depth_m[i] : depth[i];
      const float m = row_now && u >= now.u0 && u < now.u1 ? w.moving.depth_m[i] : 0.f;
      const float d = m != 0.f && (s == 0.f || m < s) ? m : s;
      if (d != depth[i]) {
        w.pixel[changed] = i;
        w.depth[changed++] = d;
        if (d > 0.f) {
          w.covered_pixel[covered] = i;
          w.covered_depth[covered++] = d;
        }
      }
    }
  }
  likelihood_->ratios(w.covered_pixel.data(), w.covered_depth.data(), covered, w.ratio.data());
  LogProduct product;
  for (int k = 0, c = 0; k < changed; ++k) {
    const int i = w.pixel[k];
    const float new_ratio = w.depth[k] > 0.f ? w.ratio[c++] : 1.f;
    const float old_ratio = depth[i] > 0.f ? ratio[i] : 1.f;
    product.multiply(double(new_ratio) / double(old_ratio));
    depth[i] = w.depth[k];
    ratio[i] = new_ratio;
  }
  ++w.cached;
  w.pixels += covered;
  score_[slot] += product.log();
  return score_[slot];
}

void HypothesisEvaluator::evaluate(const ParticleBatch& batch, std::span<double> log_likelihood,
                                   WorkerPool& pool) {
  ARTTRACK_CHECK_ARGUMENT(likelihood_ && batch.block == next_block_ &&
                          batch.block < int(plans_.size()));
  ARTTRACK_CHECK_ARGUMENT(batch.dimension == model_->num_joints());
  next_block_ = batch.block + 1;
  const int L = batch.num_particles;
  allocate(L, pool.num_workers());

  if (mode_ == Mode::kReference) {
    pool.parallel_for(L, [&](int begin, int end, int worker) {
      Workspace& w = *workspaces_[worker];
      for (int l = begin; l < end; ++l) {
        const auto x = batch.particle(l);
        for (int j = 0; j < w.q.size(); ++j) w.q[j] = x[j];
        forward_kinematics(*model_, w.q, w.kinematics);
        const PixelRect rect = w.renderer->render(w.kinematics, w.image);
        log_likelihood[l] =
            rect.empty()
                ? 0.0
                : likelihood_->log_ratio(
                      w.image.depth_m.data() + std::size_t(rect.v0) * w.image.width + rect.u0,
                      w.image.width, rect);
        ++w.full;
      }
    });
  } else {
    const BlockPlan& plan = plans_[batch.block];
    bool resampled = batch.block == 0;
    for (int l = 0; l < L && !resampled; ++l) resampled = batch.parents[l] != l;
    // Resampled particles move to the other half of the slots (each copies
    // its parent's cache), so that no slot is read and written at once.
    const int source_base = base_;
    const int new_base = batch.block == 0 ? 0 : (resampled ? L - base_ : base_);
    // A held block leaves every particle as its parent was: its cache holds
    // the image, so nothing is drawn.
    const bool held = holds_block(batch);
    const bool uses_cache = !plan.full || held;
    if (uses_cache) {
      if (!prior_groups_rendered_) render_prior_groups();
      if (batch.block == 0) render_reference_slot();
    }
    if (!plan.full && !held) {
      // The common groups: their coordinates are unsampled, so every
      // particle has them at the prior mean.
      std::fill(common_.depth_m.begin(), common_.depth_m.end(), 0.f);
      for (int g : plan.common) merge_nearer(prior_group_depth_[g], prior_group_rect_[g], common_);
    }
    const int G = int(groups_.size());
    pool.parallel_for(L, [&](int begin, int end, int worker) {
      Workspace& w = *workspaces_[worker];
      for (int l = begin; l < end; ++l) {
        const int slot = new_base + l;
        if (uses_cache && resampled) {
          const int from = batch.block == 0 ? 2 * L : source_base + batch.parents[l];
          depth_[slot].depth_m = depth_[from].depth_m;  // same sizes: no allocation
          std::copy(ratio_[from].begin(), ratio_[from].end(), ratio_[slot].begin());
          std::copy_n(rects_.begin() + std::size_t(from) * G, G,
                      rects_.begin() + std::size_t(slot) * G);
          score_[slot] = score_[from];
        }
        if (held) {
          log_likelihood[l] = plan.full ? rescore_held(plan, slot, w) : score_[slot];
          ++w.held;
        } else {
          log_likelihood[l] = plan.full ? evaluate_full(plan, slot, batch.particle(l), w)
                                        : evaluate_cached(plan, slot, batch.particle(l), w);
        }
      }
    });
    base_ = new_base;
  }
  for (auto& w : workspaces_) {
    stats_.full_evaluations += w->full;
    stats_.cached_evaluations += w->cached;
    stats_.held_evaluations += w->held;
    stats_.pixels_scored += w->pixels;
    w->full = w->cached = w->held = w->pixels = 0;
  }
}

}  // namespace arttrack
