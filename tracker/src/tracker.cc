#include "arttrack/tracker/tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <limits>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "arttrack/tracker/belief_buffer.h"
#include "arttrack/tracker/coordinate_particle_filter.h"
#include "arttrack/tracker/depth_likelihood.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/gaussian_fold.h"
#include "arttrack/tracker/hypothesis_evaluator.h"
#include "arttrack/tracker/image_information.h"
#include "arttrack/tracker/internal/acquisition.h"
#include "arttrack/tracker/internal/estimate_report.h"
#include "arttrack/tracker/internal/image_filter.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/joint_filter.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/mesh_simplify.h"
#include "arttrack/tracker/posterior_covariance.h"
#include "arttrack/tracker/worker_pool.h"
#include "health_check.h"
#include "mean_refinement.h"

namespace arttrack {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNoTime = -std::numeric_limits<double>::infinity();

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The belief as a flat vector for the buffer: five arrays of n.
void save_belief(const JointBelief& b, std::span<double> out) {
  const size_t n = b.mean_a.size();
  std::copy(b.mean_a.begin(), b.mean_a.end(), out.begin());
  std::copy(b.mean_b.begin(), b.mean_b.end(), out.begin() + n);
  std::copy(b.var_a.begin(), b.var_a.end(), out.begin() + 2 * n);
  std::copy(b.cov_ab.begin(), b.cov_ab.end(), out.begin() + 3 * n);
  std::copy(b.var_b.begin(), b.var_b.end(), out.begin() + 4 * n);
}

void load_belief(std::span<const double> in, JointBelief& b) {
  const size_t n = b.mean_a.size();
  std::copy(in.begin(), in.begin() + n, b.mean_a.begin());
  std::copy(in.begin() + n, in.begin() + 2 * n, b.mean_b.begin());
  std::copy(in.begin() + 2 * n, in.begin() + 3 * n, b.var_a.begin());
  std::copy(in.begin() + 3 * n, in.begin() + 4 * n, b.cov_ab.begin());
  std::copy(in.begin() + 4 * n, in.begin() + 5 * n, b.var_b.begin());
}

struct PendingImage {
  double stamp_s;
  double apply_time_s;  // stamp minus the camera delay
  DepthImage image;     // subsampled to the likelihood's resolution
  CameraIntrinsics camera;
  Clock::time_point received;  // add_depth_image was called
};

}  // namespace

struct Tracker::Impl {
  Impl(std::shared_ptr<const RobotModel> m, const TrackerConfig& c,
       const std::vector<std::string>& encoder_joints);
  ~Impl();

  // What the model and configuration decide once (tracker_setup.h), and
  // the names the members below read it by.
  const TrackerSetup setup;
  const std::shared_ptr<const RobotModel>& model = setup.model;
  const TrackerConfig& config = setup.config;
  const int n = setup.n, n_phys = setup.n_phys;
  const std::vector<int>& encoder_dof = setup.encoder_dof;
  const std::vector<int>& ee_links = setup.ee_links;
  const bool use_encoders = setup.use_encoders, use_images = setup.use_images;
  const std::unique_ptr<const JointFilterModel>& filter_model = setup.filter_model;
  const std::vector<char>& bias_estimated = setup.bias_estimated;  // per physical DOF

  // All members below `mutex` are guarded by it, except the image-update
  // machinery, which only the thread doing the update touches.

  mutable std::mutex mutex;
  std::condition_variable wake, idle;
  bool initialized = false;
  double time_s = kNoTime;
  JointBelief belief;
  std::vector<double> readings_bank;  // newest readings, DOF order (physical)
  std::unique_ptr<BeliefBuffer> buffer;
  double image_time_s = kNoTime;      // time of the newest applied image
  std::vector<double> image_state;    // belief right after it
  std::vector<double> state_scratch;  // the belief flattened for the buffer
  double last_stamp_s = kNoTime;
  std::deque<PendingImage> pending;
  bool updating = false;  // an asynchronous image update is running
  bool stop = false;
  TrackerStats stats;
  mutable EstimateReport report{setup};  // estimate()'s (estimate_report.h)

  // Image update machinery (one update at a time): the image's particle
  // filter and the robot it draws (image_filter.h), the searches
  // (acquisition.h), the health check and the counts that trigger them.
  std::unique_ptr<ImageFilter> image_filter;
  std::unique_ptr<Acquisition> acquisition;
  std::vector<double> prior_std;
  std::thread worker;
  std::vector<double> reading_at_t;  // encoder readings at the image's time (DOF order)
  int images_seen = 0;
  std::optional<HealthCheck> health_check;
  TrackingHealth health;            // the image thread's
  TrackingHealth published_health;  // guarded by mutex
  Eigen::VectorXd check_q;

  // The reported uncertainty (posterior_covariance.h): the image thread's,
  // and the copy estimate() reads (guarded by mutex).
  PosteriorCovariance covariance, published_covariance;
  std::unique_ptr<ImageInformation> information;
  // uncertainty.model_error: the link shifts' variance averaged over images.
  double model_error_var_m2 = 0, model_error_time_s = 0;
  bool model_error_started = false;
  Eigen::MatrixXd consider_cross;
  Eigen::VectorXd covariance_start;
  std::vector<char> reopened;      // per DOF: re-acquisition moved it at this image
  bool refine_on = false;          // the Gauss-Newton refinement of the mean (full fusion)
  std::vector<double> prior_mean;  // the image's prior mean, before the particle filter
  std::optional<MeanRefinement> refinement;
  Eigen::VectorXd refine_x;
  std::vector<double> refine_spread;

  void update_covariance(JointBelief& belief, double time_s);
  bool refine(JointBelief& belief, const Eigen::MatrixXd& information,
              const Eigen::VectorXd& gradient);

  bool applicable(const PendingImage& p) const {
    return !use_encoders || (initialized && p.apply_time_s <= time_s);
  }
  void apply_pending_locked(std::unique_lock<std::mutex>& lock);
  void apply_image(PendingImage image, std::unique_lock<std::mutex>& lock);
  void worker_loop();
};

Tracker::Impl::Impl(std::shared_ptr<const RobotModel> m, const TrackerConfig& c,
                    const std::vector<std::string>& encoder_joints)
    : setup(std::move(m), c, encoder_joints) {
  belief = initial_joint_belief(*filter_model, std::vector<double>(n_phys, 0.0));
  readings_bank.assign(n_phys, 0.0);
  buffer = std::make_unique<BeliefBuffer>(n_phys, 5 * n, config.buffer_capacity);
  image_state.assign(5 * n, 0.0);
  state_scratch.assign(5 * n, 0.0);
  if (!use_encoders) {
    // Vision only starts from a given configuration (set_initial_configuration).
    for (int j = 0; j < n_phys; ++j) {
      belief.mean_a[j] = std::clamp(0.0, model->joint_lower(j), model->joint_upper(j));
      belief.var_a[j] = config.vision_only_initial_std_rad * config.vision_only_initial_std_rad;
      belief.mean_b[j] = belief.cov_ab[j] = belief.var_b[j] = 0;
    }
    initialized = true;
  }

  if (use_images) {
    image_filter = std::make_unique<ImageFilter>(setup);
    prior_std.assign(n, 0.0);

    health_check.emplace(*model, n_phys, config.health, config.depth_model.max_range_m);
    health = health_check->initial_health();
    check_q = Eigen::VectorXd::Zero(n);
    acquisition = std::make_unique<Acquisition>(setup);
    // The reported covariance's states: every DOF the particle filter samples,
    // but the encoder joints whose bias is not estimated (their encoder says
    // their angle).
    std::vector<char> sampled(n, 0);
    for (const SamplingBlock& b : image_filter->filter().blocks())
      for (int j : b.coordinates) sampled[j] = 1;
    std::vector<PosteriorCovariance::State> states;
    std::vector<int> dofs;
    for (int j = 0; j < n; ++j) {
      if (!sampled[j]) continue;
      if (j < n_phys && use_encoders) {
        if (!bias_estimated[j]) continue;
        states.push_back({j, PosteriorCovariance::Kind::kBias,
                          filter_model->bias_decay_rate_per_s()[j],
                          filter_model->bias_rate_var()[j]});
      } else {
        states.push_back(
            {j, PosteriorCovariance::Kind::kAngle, 0.0, filter_model->angle_rate_var()[j]});
      }
      dofs.push_back(j);
    }
    ImageInformationParams information_params;
    information_params.link_shifts = config.model_error;
    const int num_consider = config.model_error ? 3 * int(model->links_with_geometry().size()) : 0;
    covariance = PosteriorCovariance(std::move(states), num_consider);
    published_covariance = covariance;
    information = std::make_unique<ImageInformation>(std::move(dofs), information_params);
    covariance_start.resize(covariance.size());
    reopened.assign(n, 0);
    refine_on = config.method == TrackingMethod::kFullFusion && config.refine_mean;
    prior_mean.assign(n, 0.0);
    Eigen::VectorXd refine_var_q = Eigen::VectorXd::Zero(covariance.size());
    for (int i = 0; i < covariance.size(); ++i) {
      const auto& st = covariance.states()[std::size_t(i)];
      if (st.kind == PosteriorCovariance::Kind::kBias)
        refine_var_q[i] = filter_model->encoder_var_rad2()[st.dof];
    }
    refinement.emplace(std::move(refine_var_q), config.refinement_min_pixels,
                       config.likelihood_exponent);
    refine_x.resize(covariance.size());
    refine_spread.resize(std::size_t(covariance.size()));
    if (config.asynchronous) worker = std::thread([this] { worker_loop(); });
  }
}

Tracker::Impl::~Impl() {
  if (worker.joinable()) {
    {
      std::lock_guard lock(mutex);
      stop = true;
    }
    wake.notify_all();
    worker.join();
  }
}

// Synchronous mode: applies every image that has become applicable, in order.
void Tracker::Impl::apply_pending_locked(std::unique_lock<std::mutex>& lock) {
  if (config.asynchronous) {
    if (!pending.empty() && applicable(pending.front())) wake.notify_all();
    return;
  }
  while (!pending.empty() && applicable(pending.front())) {
    PendingImage next = std::move(pending.front());
    pending.pop_front();
    apply_image(std::move(next), lock);
  }
}

void Tracker::Impl::apply_image(PendingImage image, std::unique_lock<std::mutex>& lock) {
  const auto start = Clock::now();
  const double t = image.apply_time_s;
  // The prior at the image's time: the newest belief at or before it,
  // predicted forward. An image applied at or after the buffered entry
  // supersedes the entry's belief.
  JointBelief prior = belief;
  double base_time;
  if (use_encoders) {
    const int i = buffer->last_at_or_before(t);
    if (i < 0) {
      ++stats.images_dropped_too_old;
      return;
    }
    if (image_time_s >= buffer->time(i)) {
      load_belief(image_state, prior);
      base_time = image_time_s;
    } else {
      load_belief(buffer->state(i), prior);
      base_time = buffer->time(i);
    }
  } else {
    base_time = time_s == kNoTime ? t : time_s;
  }
  predict_joints(*filter_model, t - base_time, prior);

  // The particle filter runs without the lock in asynchronous mode, so joint
  // readings keep coming in.
  for (int j = 0; j < n; ++j) prior_std[j] = std::sqrt(std::max(0.0, prior.var_a[j]));
  std::copy(prior.mean_a.begin(), prior.mean_a.end(), prior_mean.begin());
  // The encoder readings at the image's time (DOF order), for acquisitions.
  reading_at_t.clear();  // keeps its capacity: no allocation after the first image
  if (acquisition->on()) {
    const int i = buffer->last_at_or_before(t);
    if (i >= 0) {
      const auto m = buffer->measurement(i);
      reading_at_t.assign(m.begin(), m.end());
    }
  }
  if (config.asynchronous) lock.unlock();
  const DepthLikelihood& likelihood = image_filter->likelihood();
  const CameraIntrinsics camera =
      subsampled_intrinsics(image.camera, likelihood.width(), likelihood.height());
  if (image_filter->set_image(image.image, camera))
    acquisition->draw(image_filter->geometry().drawn_model());
  double search_ms = 0;
  const bool first = images_seen++ == 0;
  if (acquisition->on() && first) {
    search_ms = acquisition->acquire_first(*image_filter, image.image, prior_std, t, prior, health);
  } else {
    image_filter->run(prior.mean_a, prior_std, prior.mean_a, prior_std);
    fold_angle_posteriors(image_filter->filter().mean(), image_filter->filter().variance(), prior);
  }
  HealthCheck& check = *health_check;
  if (acquisition->on() && !first && !reading_at_t.empty()) {
    const SearchKind kind = acquisition->due_search(check, t);
    if (kind != SearchKind::kNone) {
      acquisition->reacquire(kind, *image_filter, image.image, check, reading_at_t, t, prior,
                             health, reopened);
      search_ms = health.last_acquisition_ms;
    }
  }
  update_covariance(prior, t);
  check.update(prior.mean_a, image.image, image.stamp_s, image_filter->geometry().renderer(),
               health);
  if (config.asynchronous) lock.lock();
  published_health = health;
  published_covariance = covariance;

  // Re-filter the joint readings after the image (paper Sec. IV-C).
  const auto refilter_start = Clock::now();
  image_time_s = t;
  save_belief(prior, image_state);
  if (use_encoders) {
    const int i = buffer->last_at_or_before(t);
    if (i < 0) {  // the buffer moved past the image while it was being applied
      ++stats.images_dropped_too_old;
      return;
    }
    double previous = t;
    for (int k = i + 1; k < buffer->size(); ++k) {
      filter_joints(*filter_model, buffer->time(k) - previous, buffer->measurement(k), prior);
      save_belief(prior, buffer->mutable_state(k));
      previous = buffer->time(k);
    }
    // Bring the belief to the newest reading's time (it equals t when no
    // reading came after the image).
    if (previous < time_s) predict_joints(*filter_model, time_s - previous, prior);
  } else {
    time_s = t;
  }
  belief = prior;
  ++stats.images_applied;
  const int evaluations = image_filter->filter().num_evaluations();
  const RenderGeometry& geometry = image_filter->geometry();
  stats.last_evaluations_per_image = evaluations;
  stats.likelihood_evaluations += evaluations;
  stats.model_triangles = model->num_drawn_triangles();
  stats.drawn_triangles = geometry.drawn_model().num_drawn_triangles();
  stats.mesh_error_bound_m = std::max(0.0, geometry.error_bound_m());
  stats.mesh_error_m = geometry.error_m();
  stats.images.add({image.stamp_s, ms_since(start), ms_since(refilter_start), search_ms,
                    ms_since(image.received)});
}

// The reported covariance after an image at time_s (belief: after its
// fold-back). It starts from the prior's angle variances at the first image;
// a chain that re-acquisition moved starts again from the broad prior it was
// searched with.
void Tracker::Impl::update_covariance(JointBelief& belief, double time_s) {
  if (covariance.size() == 0) return;
  const auto& states = covariance.states();
  if (!covariance.started()) {
    for (int i = 0; i < covariance.size(); ++i) {
      const double sd = prior_std[states[std::size_t(i)].dof];
      covariance_start[i] = sd * sd;
    }
    covariance.reset(covariance_start, time_s);
  } else {
    covariance.predict_to(time_s);
  }
  const double var_b = config.acquisition.bias_std_rad * config.acquisition.bias_std_rad;
  bool any_reopened = false;
  for (int i = 0; i < covariance.size(); ++i) {
    const int dof = states[std::size_t(i)].dof;
    if (reopened[dof]) covariance.restart_state(i, var_b);
    any_reopened = any_reopened || reopened[dof];
    reopened[dof] = 0;
  }
  for (int j = 0; j < n; ++j) check_q[j] = belief.mean_a[j];
  const Eigen::MatrixXd& info =
      information->compute(image_filter->geometry().renderer(), {check_q.data(), std::size_t(n)},
                           image_filter->likelihood());
  if (refine_on && !any_reopened && information->pixels_used() > 0)
    health.refinements_accepted += refine(belief, info, information->gradient());
  const double discount =
      config.discount_correlated_residuals ? information->effective_pixel_fraction() : 1.0;
  if (!config.model_error) {
    covariance.update(info, config.image_information_scale * discount);
    return;
  }
  // The link shifts' variance, averaged over time (one image's estimate is noisy).
  const double sample = information->link_shift_variance_m2();
  // From 0, so that the first images (the estimate still converging, its
  // residuals large) weigh one image's share each.
  const double dt = model_error_started ? std::max(0.0, time_s - model_error_time_s) : 1.0 / 30;
  const double keep = std::exp(-dt / config.model_error_time_constant_s);
  model_error_var_m2 = keep * model_error_var_m2 + (1 - keep) * sample;
  model_error_time_s = time_s;
  model_error_started = true;
  health.model_error_std_m = std::sqrt(model_error_var_m2);
  const double std_m = std::max(health.model_error_std_m, config.model_error_min_std_m);
  consider_cross = information->shift_cross_information() * std_m;
  covariance.update(info, consider_cross, config.image_information_scale * discount);
}

// The mean refinement (mean_refinement.h): the full step or its half when
// it raises the target, prior x likelihood^beta, with the exact pixel model.
bool Tracker::Impl::refine(JointBelief& belief, const Eigen::MatrixXd& information,
                           const Eigen::VectorXd& gradient) {
  const auto& states = covariance.states();
  const int m = covariance.size();
  for (int i = 0; i < m; ++i) {
    const int dof = states[std::size_t(i)].dof;
    refine_x[i] = belief.mean_a[dof] - prior_mean[dof];  // theta - mu
    refine_spread[std::size_t(i)] = prior_std[dof];
  }
  if (!refinement->solve(covariance.nominal_angle_covariance(), refine_x, information, gradient,
                         this->information->pixels_per_dof(), refine_spread))
    return false;
  const Eigen::VectorXd& step = refinement->step();
  auto target = [&](double fraction) {
    for (int j = 0; j < n; ++j) check_q[j] = belief.mean_a[j];
    for (int i = 0; i < m; ++i) check_q[states[std::size_t(i)].dof] += fraction * step[i];
    return refinement->log_prior(fraction) + image_filter->score({check_q.data(), std::size_t(n)});
  };
  const double current = target(0);
  double best = current, best_fraction = 0;
  for (double fraction : {1.0, 0.5}) {
    const double value = target(fraction);
    if (value > best) {
      best = value;
      best_fraction = fraction;
    }
  }
  if (best_fraction == 0) return false;
  for (int i = 0; i < m; ++i) {
    const int dof = states[std::size_t(i)].dof;
    belief.set_joint(
        dof, fold_angle_marginal(belief.joint(dof), belief.mean_a[dof] + best_fraction * step[i],
                                 belief.var_a[dof]));
  }
  return true;
}

void Tracker::Impl::worker_loop() {
  std::unique_lock lock(mutex);
  while (true) {
    wake.wait(lock, [&] { return stop || (!pending.empty() && applicable(pending.front())); });
    if (stop) return;
    // Only the newest applicable image is worth the work; older ones that
    // piled up while an update ran are dropped.
    while (pending.size() > 1 && applicable(pending[1])) {
      pending.pop_front();
      ++stats.images_dropped_busy;
    }
    PendingImage next = std::move(pending.front());
    pending.pop_front();
    updating = true;
    apply_image(std::move(next), lock);
    updating = false;
    idle.notify_all();
  }
}

Tracker::Tracker(std::shared_ptr<const RobotModel> model, const TrackerConfig& config,
                 const std::vector<std::string>& encoder_joints)
    : impl_(std::make_unique<Impl>(std::move(model), config, encoder_joints)) {}

Tracker::~Tracker() = default;

const RobotModel& Tracker::model() const { return *impl_->model; }
const TrackerConfig& Tracker::config() const { return impl_->config; }

void Tracker::set_initial_configuration(const std::vector<std::string>& joints,
                                        std::span<const double> angles_rad) {
  Impl& s = *impl_;
  if (joints.size() != angles_rad.size())
    throw InputError("initial configuration: " + std::to_string(joints.size()) + " names but " +
                     std::to_string(angles_rad.size()) + " angles");
  std::lock_guard lock(s.mutex);
  for (size_t k = 0; k < joints.size(); ++k) {
    const int dof = s.model->joint_index(joints[k]);
    if (!std::isfinite(angles_rad[k]))
      throw InputError("initial configuration: joint '" + joints[k] + "' is not finite");
    if (!s.use_encoders) s.belief.mean_a[dof] = angles_rad[k];
  }
}

void Tracker::add_joint_measurement(double time_s, std::span<const double> angles_rad) {
  Impl& s = *impl_;
  std::unique_lock lock(s.mutex);
  if (!s.use_encoders) return;  // vision only ignores the encoders
  if (int(angles_rad.size()) != int(s.encoder_dof.size()))
    throw InputError("joint measurement at " + std::to_string(time_s) + " s has " +
                     std::to_string(angles_rad.size()) + " values, expected " +
                     std::to_string(s.encoder_dof.size()));
  if (!std::isfinite(time_s)) throw InputError("joint measurement time stamp is not finite");
  if (s.initialized && time_s < s.time_s) {
    std::ostringstream os;
    os.precision(9);
    os << "joint measurement time stamp goes backwards: " << time_s << " s after " << s.time_s
       << " s";
    throw InputError(os.str());
  }
  // One broken reading (1e300, NaN, a wrapped angle) would poison its
  // joint's filter for the rest of the run: the measurement is dropped.
  const double margin = s.config.joint_limit_margin_rad;
  for (size_t k = 0; k < angles_rad.size(); ++k) {
    const int dof = s.encoder_dof[k];
    if (!(angles_rad[k] >= s.model->joint_lower(dof) - margin &&
          angles_rad[k] <= s.model->joint_upper(dof) + margin) ||
        !std::isfinite(angles_rad[k])) {
      ++s.stats.joint_measurements_dropped;
      return;
    }
  }
  for (size_t k = 0; k < angles_rad.size(); ++k) s.readings_bank[s.encoder_dof[k]] = angles_rad[k];
  if (!s.initialized) {
    s.belief = initial_joint_belief(*s.filter_model, s.readings_bank);
    s.initialized = true;
  } else {
    filter_joints(*s.filter_model, time_s - s.time_s, s.readings_bank, s.belief);
  }
  s.time_s = time_s;
  save_belief(s.belief, s.state_scratch);
  s.buffer->push(time_s, s.readings_bank, s.state_scratch);
  ++s.stats.joint_measurements;
  s.apply_pending_locked(lock);
}

void Tracker::add_depth_image(double stamp_s, const DepthImage& image,
                              const CameraIntrinsics& camera) {
  const auto received = Clock::now();
  Impl& s = *impl_;
  std::ostringstream where;
  where.precision(9);
  where << "depth image stamped " << stamp_s << " s";
  if (!std::isfinite(stamp_s)) {
    std::lock_guard lock(s.mutex);
    ++s.stats.images_received;
    ++s.stats.images_dropped_bad_stamp;
    return;
  }
  if (image.width != camera.width || image.height != camera.height ||
      image.depth_m.size() != size_t(image.width) * image.height || image.width <= 0)
    throw InputError(where.str() + ": image is " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " but the intrinsics say " +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height));
  if (!(camera.fx > 0 && camera.fy > 0))
    throw InputError(where.str() + ": focal lengths must be positive");
  // One branch-free pass over the pixels (it vectorises), then the first bad
  // pixel for the message only when there is one.
  int valid = 1;
  const float* depth = image.depth_m.data();
  for (std::size_t i = 0; i < image.depth_m.size(); ++i)
    valid &= int(depth[i] >= 0.f) & int(depth[i] <= std::numeric_limits<float>::max());
  for (int v = 0; v < image.height && !valid; ++v)
    for (int u = 0; u < image.width; ++u) {
      const float z = image.at(u, v);
      if (!(z >= 0) || !std::isfinite(z)) {
        std::ostringstream os;
        os << where.str() << ": pixel (" << u << ", " << v << ") has depth " << z
           << " (expected metres >= 0, 0 for no return)";
        throw InputError(os.str());
      }
    }
  // Only the likelihood's resolution is kept: the likelihood would subsample
  // to it anyway, and a 640x480 copy per image is 64 times the memory.
  const int W = s.config.depth_model.width, H = s.config.depth_model.height;
  DepthImage kept;
  if (s.use_images)
    kept = image.width == W && image.height == H ? image : subsample_depth(image, W, H);

  std::unique_lock lock(s.mutex);
  // An image a clock apart from the joints' (a stamp in another epoch or
  // unit) would wait forever or be applied to a belief of another time.
  if (s.use_encoders && s.initialized &&
      !(std::abs(stamp_s - s.time_s) <= s.config.max_image_clock_offset_s)) {
    ++s.stats.images_received;
    ++s.stats.images_dropped_bad_stamp;
    return;
  }
  if (stamp_s < s.last_stamp_s) {
    std::ostringstream os;
    os.precision(9);
    os << where.str() << " comes after one stamped " << s.last_stamp_s
       << " s: image time stamps go backwards";
    throw InputError(os.str());
  }
  s.last_stamp_s = stamp_s;
  ++s.stats.images_received;
  if (!s.use_images) return;
  s.pending.push_back(
      {stamp_s, stamp_s - s.config.camera_delay_s, std::move(kept), camera, received});
  while (int(s.pending.size()) > s.config.max_pending_images) {
    s.pending.pop_front();
    ++s.stats.images_dropped_backlog;
  }
  s.apply_pending_locked(lock);
}

void Tracker::wait_until_idle() {
  Impl& s = *impl_;
  if (!s.config.asynchronous || !s.worker.joinable()) return;
  std::unique_lock lock(s.mutex);
  s.idle.wait(
      lock, [&] { return !s.updating && (s.pending.empty() || !s.applicable(s.pending.front())); });
}

TrackerEstimate Tracker::estimate() const {
  const Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  if (!s.initialized) throw InputError("tracker estimate asked for before any joint measurement");
  TrackerEstimate e;
  s.report.fill(s.belief, s.readings_bank, s.time_s, s.published_covariance, e);
  e.health = s.published_health;
  return e;
}

double TrackingHealth::weakest_part_explained_fraction() const {
  double weakest = std::numeric_limits<double>::quiet_NaN();
  for (const ChainHealth& c : chains)
    if (c.weakest_part_explained_fraction < weakest || std::isnan(weakest))
      weakest = c.weakest_part_explained_fraction;
  return weakest;
}

int TrackingHealth::unconfirmed_chains() const {
  return int(std::count_if(chains.begin(), chains.end(),
                           [](const ChainHealth& c) { return c.unconfirmed; }));
}

const char* health_state_name(TrackingHealth::State state) {
  switch (state) {
    case TrackingHealth::State::kNoImage:
      return "no_image";
    case TrackingHealth::State::kTracking:
      return "tracking";
    case TrackingHealth::State::kLost:
      return "lost";
  }
  return "unknown";
}

TrackerStats Tracker::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

}  // namespace arttrack
