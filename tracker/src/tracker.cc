#include "arttrack/tracker/tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <sstream>
#include <thread>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/belief_buffer.h"
#include "arttrack/tracker/internal/encoder_noise_meter.h"
#include "arttrack/tracker/internal/encoder_smoother.h"
#include "arttrack/tracker/internal/estimate_report.h"
#include "arttrack/tracker/internal/image_update.h"
#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "elapsed.h"

namespace arttrack {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNoTime = -std::numeric_limits<double>::infinity();
// TrackingHealth::encoder_noise_measured_rad's average: 2000 readings at 1 kHz.
constexpr double kEncoderNoiseTimeConstant_s = 2.0;

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
  double stamp_s = 0;
  double apply_time_s = 0;  // stamp minus the camera delay
  DepthImage image;         // subsampled to the likelihood's resolution
  DepthImage fit_image;     // to the end-effector fit's (empty: the likelihood's)
  CameraIntrinsics camera;
  Clock::time_point received;  // add_depth_image was called
};

}  // namespace

// The tracker: the inputs (checked, then filtered or queued), the threads
// and locks, and the estimate. An image's update is ImageUpdate's
// (image_update.h); what the model and configuration decide once is the
// TrackerSetup's (tracker_setup.h).
struct Tracker::Impl {
  Impl(std::shared_ptr<const RobotModel> m, const TrackerConfig& c,
       const std::vector<std::string>& encoder_joints);
  ~Impl();

  const TrackerSetup setup;

  // All members below `mutex` are guarded by it, except `images`,
  // `reading_at_t`, `applying` and `image_prior`, which only the thread
  // doing the update touches.
  mutable std::mutex mutex;
  std::condition_variable wake, idle;
  bool initialized = false;
  double time_s = kNoTime;
  JointBelief belief;
  std::vector<double> readings_bank;               // newest readings, DOF order (physical)
  std::unique_ptr<EncoderSmoother> smoother;       // config.encoder_smoothing; null: off
  std::unique_ptr<EncoderNoiseMeter> noise_meter;  // the raw readings'; null without encoders
  JointFilterModel joint_model;  // setup.filter_model's, with the encoders' noise as measured
  std::unique_ptr<BeliefBuffer> buffer;
  double image_time_s = kNoTime;      // time of the newest applied image
  std::vector<double> image_state;    // belief right after it
  std::vector<double> state_scratch;  // the belief flattened for the buffer
  double last_stamp_s = kNoTime;
  // The images waiting for the joints to reach their time, oldest first,
  // and entries done with, whose pixel storage the next images reuse (so an
  // image's queue entry allocates nothing once there are spares). Both are
  // reserved to max_pending_images + 1 and never grow past it.
  std::vector<PendingImage> pending, spare;
  bool updating = false;  // an asynchronous image update is running
  bool stop = false;
  TrackerStats stats;
  mutable EstimateReport report;  // estimate()'s (estimate_report.h)
  // The image thread's health and covariance, as estimate() reads them.
  TrackingHealth published_health;
  PosteriorCovariance published_covariance;
  std::vector<double> published_mean_lag_var;  // per state of published_covariance
  std::vector<EndEffectorFitEstimate> published_fits;

  // The image update (use_images; one update at a time), and the encoder
  // readings at the image's time (DOF order) its searches start from.
  std::unique_ptr<ImageUpdate> images;
  std::vector<double> reading_at_t;
  PendingImage applying;    // the image being applied, out of `pending`
  JointBelief image_prior;  // apply_image()'s belief, kept for its storage
  std::thread worker;

  bool applicable(const PendingImage& p) const {
    return !setup.use_encoders || (initialized && p.apply_time_s <= time_s);
  }
  // encoder_noise.from_readings: each encoder's sigma_q in the smoothing and
  // the joint filter from its measured noise (TrackerConfig::EncoderNoise).
  void weigh_readings_by_measured_noise();
  void apply_pending_locked(std::unique_lock<std::mutex>& lock);
  // Moves pending's oldest entry into `applying` and applies it.
  void apply_oldest_pending(std::unique_lock<std::mutex>& lock);
  void apply_image(const PendingImage& image, std::unique_lock<std::mutex>& lock);
  // Under the lock: pending's oldest entry, or `done`, becomes a spare.
  void drop_oldest_pending();
  void keep_as_spare(PendingImage& done);
  // TrackerStats' geometry fields from `images` (under the lock).
  void count_geometry();
  void worker_loop();
};

Tracker::Impl::Impl(std::shared_ptr<const RobotModel> m, const TrackerConfig& c,
                    const std::vector<std::string>& encoder_joints)
    : setup(std::move(m), c, encoder_joints), joint_model(*setup.filter_model), report(setup) {
  const int n = setup.n, n_phys = setup.n_phys;
  belief = initial_joint_belief(*setup.filter_model, std::vector<double>(n_phys, 0.0));
  readings_bank.assign(n_phys, 0.0);
  if (setup.use_encoders && setup.config.encoder_smoothing.enabled) {
    std::vector<char> revolute(std::size_t(n_phys), 0);
    for (int j = 0; j < n_phys; ++j)
      revolute[std::size_t(j)] = setup.model->joint_type(j) != JointType::kPrismatic;
    smoother = std::make_unique<EncoderSmoother>(
        setup.filter_model->encoder_var_rad2().first(std::size_t(n_phys)), revolute,
        setup.config.encoder_smoothing.rate_diffusion_rad_per_s_per_sqrt_s);
  }
  if (setup.use_encoders) {
    std::vector<char> has_encoder(std::size_t(n_phys), 0);
    for (int dof : setup.encoder_dof) has_encoder[std::size_t(dof)] = 1;
    noise_meter = std::make_unique<EncoderNoiseMeter>(has_encoder, kEncoderNoiseTimeConstant_s);
  }
  buffer = std::make_unique<BeliefBuffer>(n_phys, 5 * n, setup.config.buffer_capacity);
  pending.reserve(std::size_t(setup.config.max_pending_images) + 1);
  spare.reserve(std::size_t(setup.config.max_pending_images) + 1);
  image_state.assign(5 * n, 0.0);
  state_scratch.assign(5 * n, 0.0);
  if (!setup.use_encoders) {
    // Vision only starts from a given configuration (set_initial_configuration).
    const RobotModel& model = *setup.model;
    const double sd = setup.config.vision_only_initial_std_rad;
    for (int j = 0; j < n_phys; ++j) {
      belief.mean_a[j] = std::clamp(0.0, model.joint_lower(j), model.joint_upper(j));
      belief.var_a[j] = sd * sd;
      belief.mean_b[j] = belief.cov_ab[j] = belief.var_b[j] = 0;
    }
    initialized = true;
  }
  if (setup.use_images) {
    images = std::make_unique<ImageUpdate>(setup);
    published_covariance = images->covariance();
    published_mean_lag_var.assign(images->mean_lag_variance().begin(),
                                  images->mean_lag_variance().end());
    published_fits = images->end_effector_fits();
    if (setup.config.asynchronous) worker = std::thread([this] { worker_loop(); });
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
  if (setup.config.asynchronous) {
    if (!pending.empty() && applicable(pending.front())) wake.notify_all();
    return;
  }
  while (!pending.empty() && applicable(pending.front())) apply_oldest_pending(lock);
}

void Tracker::Impl::apply_oldest_pending(std::unique_lock<std::mutex>& lock) {
  // Out of the queue first: in asynchronous mode add_depth_image() changes
  // the queue while the image is applied.
  std::swap(applying, pending.front());
  pending.erase(pending.begin());
  apply_image(applying, lock);
  keep_as_spare(applying);
}

void Tracker::Impl::drop_oldest_pending() {
  keep_as_spare(pending.front());
  pending.erase(pending.begin());
}

void Tracker::Impl::keep_as_spare(PendingImage& done) {
  if (spare.size() < spare.capacity()) {
    spare.emplace_back();
    std::swap(spare.back(), done);
  }
}

void Tracker::Impl::weigh_readings_by_measured_noise() {
  // Not before the meter has settled (1 s at 1 kHz): earlier, an encoder as
  // noisy as configured crossed the tolerance at 0.13 s (realistic/arm seed 8).
  if (noise_meter->differences() < EncoderNoiseMeter::kSettledDifferences) return;
  constexpr double excess =
      TrackerConfig::kEncoderNoiseTolerance * TrackerConfig::kEncoderNoiseTolerance - 1;
  const std::span<const double> configured = setup.filter_model->encoder_var_rad2();
  for (int dof : setup.encoder_dof) {
    const double measured = noise_meter->noise_std(dof), c2 = configured[std::size_t(dof)];
    const double var =
        std::isfinite(measured) ? std::max(c2, measured * measured - excess * c2) : c2;
    if (var == joint_model.encoder_var_rad2()[std::size_t(dof)]) continue;
    if (smoother) smoother->set_encoder_var(dof, var);
    joint_model.set_encoder_var(dof, var);
  }
}

void Tracker::Impl::count_geometry() {
  const RenderGeometry& geometry = images->geometry();
  stats.model_triangles = setup.model->num_drawn_triangles();
  stats.drawn_triangles = geometry.drawn_model().num_drawn_triangles();
  stats.mesh_error_bound_m = std::max(0.0, geometry.error_bound_m());
  stats.mesh_error_m = geometry.error_m();
  stats.geometry_builds = images->geometry_builds();
}

void Tracker::Impl::apply_image(const PendingImage& image, std::unique_lock<std::mutex>& lock) {
  const auto start = Clock::now();
  const double t = image.apply_time_s;
  // The prior at the image's time: the newest belief at or before it,
  // predicted forward. An image applied at or after the buffered entry
  // supersedes the entry's belief.
  JointBelief& prior = image_prior;
  prior = belief;
  double base_time;
  if (setup.use_encoders) {
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
  predict_joints(*setup.filter_model, t - base_time, prior);

  // The encoder readings at the image's time (DOF order), for acquisitions.
  reading_at_t.clear();  // keeps its capacity: no allocation after the first image
  if (images->wants_readings()) {
    const int i = buffer->last_at_or_before(t);
    if (i >= 0) {
      const auto m = buffer->measurement(i);
      reading_at_t.assign(m.begin(), m.end());
    }
  }
  // The image update runs without the lock in asynchronous mode, so joint
  // readings keep coming in.
  if (setup.config.asynchronous) lock.unlock();
  const double search_ms = images->apply(image.image, image.fit_image, image.camera, image.stamp_s,
                                         t, reading_at_t, prior);
  if (setup.config.asynchronous) lock.lock();
  published_health = images->health();
  published_covariance = images->covariance();
  published_mean_lag_var.assign(images->mean_lag_variance().begin(),
                                images->mean_lag_variance().end());
  published_fits = images->end_effector_fits();

  // Re-filter the joint readings after the image (paper Sec. IV-C).
  const auto refilter_start = Clock::now();
  image_time_s = t;
  save_belief(prior, image_state);
  if (setup.use_encoders) {
    const int i = buffer->last_at_or_before(t);
    if (i < 0) {  // the buffer moved past the image while it was being applied
      ++stats.images_dropped_too_old;
      return;
    }
    double previous = t;
    for (int k = i + 1; k < buffer->size(); ++k) {
      filter_joints(joint_model, buffer->time(k) - previous, buffer->measurement(k), prior);
      save_belief(prior, buffer->mutable_state(k));
      previous = buffer->time(k);
    }
    // Bring the belief to the newest reading's time (it equals t when no
    // reading came after the image).
    if (previous < time_s) predict_joints(*setup.filter_model, time_s - previous, prior);
  } else {
    time_s = t;
  }
  belief = prior;
  ++stats.images_applied;
  const int evaluations = images->filter().filter().num_evaluations();
  stats.last_evaluations_per_image = evaluations;
  stats.likelihood_evaluations += evaluations;
  count_geometry();
  stats.images.add({image.stamp_s, ms_since(start), ms_since(refilter_start), search_ms,
                    ms_since(image.received)});
}

void Tracker::Impl::worker_loop() {
  std::unique_lock lock(mutex);
  while (true) {
    wake.wait(lock, [&] { return stop || (!pending.empty() && applicable(pending.front())); });
    if (stop) return;
    // Only the newest applicable image is worth the work; older ones that
    // piled up while an update ran are dropped.
    while (pending.size() > 1 && applicable(pending[1])) {
      drop_oldest_pending();
      ++stats.images_dropped_busy;
    }
    updating = true;
    apply_oldest_pending(lock);
    updating = false;
    idle.notify_all();
  }
}

Tracker::Tracker(std::shared_ptr<const RobotModel> model, const TrackerConfig& config,
                 const std::vector<std::string>& encoder_joints)
    : impl_(std::make_unique<Impl>(std::move(model), config, encoder_joints)) {}

Tracker::~Tracker() = default;

const RobotModel& Tracker::model() const { return *impl_->setup.model; }
const TrackerConfig& Tracker::config() const { return impl_->setup.config; }

void Tracker::set_initial_configuration(const std::vector<std::string>& joints,
                                        std::span<const double> angles_rad) {
  Impl& s = *impl_;
  if (joints.size() != angles_rad.size())
    throw InputError("initial configuration: " + std::to_string(joints.size()) + " names but " +
                     std::to_string(angles_rad.size()) + " angles");
  std::lock_guard lock(s.mutex);
  for (size_t k = 0; k < joints.size(); ++k) {
    const int dof = s.setup.model->joint_index(joints[k]);
    if (!std::isfinite(angles_rad[k]))
      throw InputError("initial configuration: joint '" + joints[k] + "' is not finite");
    if (!s.setup.use_encoders) s.belief.mean_a[dof] = angles_rad[k];
  }
}

void Tracker::add_joint_measurement(double time_s, std::span<const double> angles_rad) {
  Impl& s = *impl_;
  std::unique_lock lock(s.mutex);
  if (!s.setup.use_encoders) return;  // vision only ignores the encoders
  if (int(angles_rad.size()) != int(s.setup.encoder_dof.size()))
    throw InputError("joint measurement at " + std::to_string(time_s) + " s has " +
                     std::to_string(angles_rad.size()) + " values, expected " +
                     std::to_string(s.setup.encoder_dof.size()));
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
  const double margin = s.setup.config.joint_limit_margin_rad;
  for (size_t k = 0; k < angles_rad.size(); ++k) {
    const int dof = s.setup.encoder_dof[k];
    if (!(angles_rad[k] >= s.setup.model->joint_lower(dof) - margin &&
          angles_rad[k] <= s.setup.model->joint_upper(dof) + margin) ||
        !std::isfinite(angles_rad[k])) {
      ++s.stats.joint_measurements_dropped;
      return;
    }
  }
  for (size_t k = 0; k < angles_rad.size(); ++k)
    s.readings_bank[s.setup.encoder_dof[k]] = angles_rad[k];
  s.noise_meter->add(time_s, s.readings_bank);
  if (s.setup.config.encoder_noise.from_readings) s.weigh_readings_by_measured_noise();
  // Smoothed readings are what the filter, the buffer's re-filtering and
  // encoders only's report take (encoder_smoother.h).
  if (s.smoother) s.smoother->smooth(s.initialized ? time_s - s.time_s : 0.0, s.readings_bank);
  if (!s.initialized) {
    s.belief = initial_joint_belief(*s.setup.filter_model, s.readings_bank);
    s.initialized = true;
  } else {
    filter_joints(s.joint_model, time_s - s.time_s, s.readings_bank, s.belief);
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
  auto where = [&] {  // for messages only: an accepted image formats nothing
    std::ostringstream os;
    os.precision(9);
    os << "depth image stamped " << stamp_s << " s";
    return os.str();
  };
  if (!std::isfinite(stamp_s)) {
    std::lock_guard lock(s.mutex);
    ++s.stats.images_received;
    ++s.stats.images_dropped_bad_stamp;
    return;
  }
  if (image.width != camera.width || image.height != camera.height ||
      image.depth_m.size() != size_t(image.width) * image.height || image.width <= 0)
    throw InputError(where() + ": image is " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " but the intrinsics say " +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height));
  if (!(camera.fx > 0 && camera.fy > 0))
    throw InputError(where() + ": focal lengths must be positive");
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
        os << where() << ": pixel (" << u << ", " << v << ") has depth " << z
           << " (expected metres >= 0, 0 for no return)";
        throw InputError(os.str());
      }
    }
  // Only the likelihood's resolution is kept, and the end-effector fit's:
  // the likelihood would subsample to it anyway, and a 640x480 copy per
  // image is 64 times the memory (the fit's 160x120, 4 times).
  const int W = s.setup.config.depth_model.width, H = s.setup.config.depth_model.height;
  auto keep_at_size = [&](int width, int height, DepthImage& kept) {
    if (image.width == width && image.height == height)
      kept = image;
    else
      subsample_depth(image, width, height, kept);
  };
  PendingImage entry;  // a spare's storage, when there is one
  if (s.setup.use_images) {
    {
      std::lock_guard lock(s.mutex);
      if (!s.spare.empty()) {
        std::swap(entry, s.spare.back());
        s.spare.pop_back();
      }
    }
    keep_at_size(W, H, entry.image);
    // The end-effector fit's finer image, when the image has more pixels.
    int fit_W = 0, fit_H = 0;
    if (s.images->fit_image_size(image.width, image.height, fit_W, fit_H)) {
      keep_at_size(fit_W, fit_H, entry.fit_image);
    } else {
      entry.fit_image.width = entry.fit_image.height = 0;
      entry.fit_image.depth_m.clear();
    }
  }

  std::unique_lock lock(s.mutex);
  // An image a clock apart from the joints' (a stamp in another epoch or
  // unit) would wait forever or be applied to a belief of another time.
  if (s.setup.use_encoders && s.initialized &&
      !(std::abs(stamp_s - s.time_s) <= s.setup.config.max_image_clock_offset_s)) {
    ++s.stats.images_received;
    ++s.stats.images_dropped_bad_stamp;
    s.keep_as_spare(entry);
    return;
  }
  if (stamp_s < s.last_stamp_s) {
    std::ostringstream os;
    os.precision(9);
    os << where() << " comes after one stamped " << s.last_stamp_s
       << " s: image time stamps go backwards";
    throw InputError(os.str());
  }
  s.last_stamp_s = stamp_s;
  ++s.stats.images_received;
  if (!s.setup.use_images) return;
  entry.stamp_s = stamp_s;
  entry.apply_time_s = stamp_s - s.setup.config.camera_delay_s;
  entry.camera = camera;
  entry.received = received;
  s.pending.emplace_back();
  std::swap(s.pending.back(), entry);
  while (int(s.pending.size()) > s.setup.config.max_pending_images) {
    s.drop_oldest_pending();
    ++s.stats.images_dropped_backlog;
  }
  s.apply_pending_locked(lock);
}

void Tracker::prepare_camera(const CameraIntrinsics& camera) {
  if (const std::string problem = camera.problem(); !problem.empty())
    throw InputError("camera to prepare for: " + problem);
  Impl& s = *impl_;
  std::unique_lock lock(s.mutex);
  if (!s.images) return;
  // The worker draws with what this rebuilds, and only while `updating`
  // with the lock released; holding the lock keeps it from starting one.
  s.idle.wait(lock, [&] { return !s.updating; });
  s.images->prepare(camera);
  s.count_geometry();
}

void Tracker::wait_until_idle() {
  Impl& s = *impl_;
  if (!s.setup.config.asynchronous || !s.worker.joinable()) return;
  std::unique_lock lock(s.mutex);
  s.idle.wait(
      lock, [&] { return !s.updating && (s.pending.empty() || !s.applicable(s.pending.front())); });
}

TrackerEstimate Tracker::estimate() const {
  TrackerEstimate e;
  estimate(e);
  return e;
}

void Tracker::estimate(TrackerEstimate& e) const {
  const Impl& s = *impl_;
  std::lock_guard lock(s.mutex);
  if (!s.initialized) throw InputError("tracker estimate asked for before any joint measurement");
  s.report.fill(s.belief, s.readings_bank, s.time_s, s.published_covariance,
                s.published_mean_lag_var, s.published_fits, e);
  e.health = s.published_health;  // assigned element-wise: kept capacity is reused
  if (s.noise_meter) {
    e.health.encoder_noise_measured_rad.resize(std::size_t(s.setup.n_phys));
    for (int j = 0; j < s.setup.n_phys; ++j)
      e.health.encoder_noise_measured_rad[std::size_t(j)] = s.noise_meter->noise_std(j);
  }
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
