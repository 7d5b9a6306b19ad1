// The tracker: the public API of the method (docs/method.md "Overview";
// Garcia Cifuentes et al. 2017). Feed it joint encoder readings and depth
// images with their time stamps; read the estimate at any time: joint angles
// and biases with standard deviations, the camera correction, and each end
// effector's pose in the estimated camera frame.
//
// Inside: one 2-state Kalman filter per joint (joint_filter.h) updated at the
// encoder rate; each depth image is applied at its own time stamp (minus the
// configured camera delay) to the buffered belief of that time by a
// Coordinate Particle Filter over the angle marginals, scored by the depth
// likelihood of the robot rendered for each particle; the particles'
// moments are folded back into the joint filters and the later joint
// readings are re-filtered (belief_buffer.h).
//
// Beyond the paper (full fusion; docs/method.md "Beyond the paper";
// docs/accuracy.md has the measurements):
// - Acquisition. The paper's CPF starts at the prior mean and moment-matches
//   a few particles, so at the first image a joint can settle in a wrong
//   mode (e.g. a wrist folded out of view, which scores better than an arm
//   slightly misaligned) and its collapsed variance never lets it leave. At
//   the first image the tracker runs an annealed search instead: CPF passes
//   over the same image with a coarse-to-fine depth noise (a wide noise gives
//   a nearly aligned arm credit, so the search has a basin to follow), each
//   pass proposing around the previous one, the last targeting the filter's
//   prior exactly (importance-corrected). It runs acquisition.searches
//   times with independent draws; the result the image plus the prior
//   prefer is kept (one search lands in a wrong mode now and then).
// - Re-acquisition (augmented MCL). When the health check says lost (and,
//   if acquisition.period_s > 0, periodically), the prior of every joint
//   whose bias is estimated is re-opened around the encoder reading with a
//   broad bias and searched the same way; each chain the health check found
//   poor (every chain, for the periodic search) takes the result when the
//   image plus that prior prefer it: a chain whose encoder bias jumped comes
//   back, a chain out of view keeps what the encoders say.
// - Health. After each image the robot is rendered at the estimate's mean
//   and compared with the image: the share of its pixels the camera sees
//   through (contradicted) or confirms (explained), whole and per chain, and
//   the share of the pixels a chain explained at its last good image that
//   the image still shows unchanged but the render no longer explains
//   (abandoned: an estimate that left a robot that did not move, e.g. after
//   an encoder slip, to where nothing contradicts it). A contradicted or
//   abandoned share above its threshold for a few images is "lost".
// - Refinement (refinement.enabled). After the particles, one
//   Gauss-Newton step on the depth
//   residuals with the full prior covariance (DART's local refinement),
//   taken only if it raises the exact target: it moves the mean along the
//   ridge between the camera's pose and the arms' biases, where the
//   coordinate-wise particles lag. Each state moves at most the particles'
//   spread, or its reported standard deviation while the step is longer
//   than refinement.widen_beyond_sigma of them (the mean still converging).
//   With refinement.unseen_information_ratio (0.01 by default), along a
//   direction that moves no surface (the motion field's information below
//   that fraction of the prior's and of the central differences': arm7's
//   camera orbiting its round base with joint 1 turning back) the step is
//   the prior's alone; the central differences read edges as information
//   there.
// - Joints out of view (particle_filter.keep_unseen_prior). A joint none of
//   whose links the camera draws at the image's prior mean (or fewer than
//   particle_filter.unseen_below_pixels, at the view's edge), and that no
//   explained pixel depends on at the particles' mean, keeps its prior
//   through the image: the particles would read "not in view" as new
//   evidence at every image and walk a hidden arm away from the view.
// - Reported uncertainty. The standard deviations of the biases, angles and
//   camera offsets are the marginals of a full covariance updated with each
//   image's Gauss-Newton information (posterior_covariance.h,
//   image_information.h), not the particle filter's collapsed moments; each
//   image counts as many independent pixels as its residuals' correlation
//   and size say it is worth (uncertainty.discount_correlated_residuals).
//   While a bias's or the camera offset's mean still moves, its reported
//   variance also takes that motion (uncertainty.mean_lag_scale,
//   mean_lag.h): the estimate itself is not changed by it.
// - End-effector fit (end_effector_fit.enabled; full fusion). The robot is
//   not its URDF: the angles that fit every link's pixels leave the hand a
//   few millimetres and degrees from where its own pixels put it. After
//   each image, a rigid motion of each end effector's end link (with the
//   links below it) is fitted to the residuals, on the image at
//   end_effector_fit.resolution_factor times the likelihood's resolution
//   (at most the image's own); averaged over time, it
//   corrects the end effectors' reported poses (ee_image_correction), and
//   their positions' covariance is the fits' (their scatter about the
//   average, plus the links' shape error, at
//   uncertainty.model_error_unpinned_scale times it along the direction
//   the fits determine least, and the shift each fitted link's learned
//   scale moves the fit by: end_effector_fit.link_scales), not the
//   angles'. The angles, biases and
//   their covariance are the filter's, unchanged. Each fit is also
//   searched along that direction with the whole pixel likelihood, which
//   sees a hand reaching past the model's silhouette
//   (end_effector_fit.axis_search_range_m, 1 cm; 0: not searched).
// - An optional floor on the moment-matched variance
//   (CoordinateParticleFilterParams::bandwidth_factor, off by default).
//
// Threads: in synchronous mode everything happens in the caller's thread and
// the numbers are a deterministic function of the input. In asynchronous
// mode an image update runs on a worker thread while joint updates go on;
// estimate() and the add_* calls may be called from different threads.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack {

// How well the newest applied image agrees with the estimate: the robot
// rendered at the estimate's mean, compared pixel by pixel with the image
// (TrackerConfig::Health). Fractions are of the rendered pixels that have a
// valid observed depth; NaN when there are fewer than min_pixels of them
// (e.g. the robot out of view: no verdict, not a failure).
//
// The render alone cannot see an estimate that left the robot it had found
// (an arm folded out of view or behind something is contradicted nowhere).
// So the tracker keeps, per chain, the pixels its render explained at the
// last image where the chain was not poor; `abandoned_fraction` is the
// share of them whose observed depth is still the same (the robot it
// explained is still there) but that the chain's render no longer explains.
// A real motion changes the image at those pixels; an estimate that moved
// while the robot did not leaves them abandoned. NaN before a chain has
// min_pixels such pixels.
struct ChainHealth {
  std::string name;         // the chain's first joint, e.g. "left_arm_joint_1"
  int rendered_pixels = 0;  // with a valid observed depth
  double explained_fraction = std::numeric_limits<double>::quiet_NaN();
  double contradicted_fraction = std::numeric_limits<double>::quiet_NaN();
  double abandoned_fraction = std::numeric_limits<double>::quiet_NaN();
  // The chain's least confirmed part: of the subtrees its joints move (the
  // links after each joint but the first), the one whose visible pixels
  // (rendered alone, not behind another rendered link, with a valid
  // observed depth) the image explains least, if it has min_pixels of them.
  // A hand that the first search put in a wrong mode hides behind the real
  // arm (the image is in front of it everywhere): nothing contradicts it and
  // the chain as a whole is still 95% explained, but its hand is explained
  // nowhere. Below Health::unconfirmed_explained_fraction the chain is
  // unconfirmed: it is searched again (not "lost": an occluded hand is
  // unconfirmed too, and the search only takes what the image prefers and
  // confirms).
  // weakest_part_joint: the model's DOF index of the part's first joint,
  // -1 with a NaN fraction when no part has enough visible pixels.
  int weakest_part_joint = -1;
  double weakest_part_explained_fraction = std::numeric_limits<double>::quiet_NaN();
  bool unconfirmed = false;
};
struct TrackingHealth {
  enum class State { kNoImage, kTracking, kLost };
  State state = State::kNoImage;
  double image_stamp_s = std::numeric_limits<double>::quiet_NaN();
  ChainHealth whole;                // every link
  std::vector<ChainHealth> chains;  // per kinematic chain below the root
  int acquisitions = 0;             // annealed searches run so far
  int chains_reacquired = 0;        // chains that took a search's result
  int refinements_accepted = 0;     // Gauss-Newton steps taken (tracker.h)
  // Joints an image could not see whose particle-filter step was undone
  // (particle_filter.keep_unseen_prior), summed over images: a chain out
  // of view or behind an occluder is where its encoders and learned biases
  // put it.
  int unseen_priors_kept = 0;
  // Images whose refinement step found a motion of the states that moves no
  // surface the camera sees (refinement.unseen_information_ratio), summed:
  // along it the step follows the prior, and so does the estimate. A robot
  // whose base link is round about its first joint (a camera orbit with that
  // joint turning back) shows one on every image (arm7); the dual arm on
  // about a third of its images (directions its images barely pin).
  int images_with_unseen_motion = 0;
  double last_acquisition_ms = 0;  // wall time of the newest search
  // The end-effector fit's search along each hand (end_effector_fit.
  // axis_search_range_m): fitted hands searched so far, and the searches
  // whose shift along the hand beat the fit's own pose. A share accepted
  // near 1 says a hand is longer or shorter along itself than its URDF (or
  // its mesh larger or smaller than the real hand): ee_image_correction
  // says by how much.
  int hand_searches = 0;
  int hand_shifts_accepted = 0;
  // How far the robot's links seem to be from the model's: the standard
  // deviation of a link's surface shift the residuals show (uncertainty.
  // model_error), metres; 0 when the model fits the images (or it is off).
  double model_error_std_m = 0;
  // The same per link, to find the links that do not fit: one per link
  // with geometry (RobotModel::links_with_geometry order) with
  // uncertainty.model_error, none without. `shift_m` is the size of the
  // link's surface shift the residuals show along the directions the images
  // pin (the DOFs cannot absorb them), averaged like model_error_std_m over
  // the images that pin some; NaN until one does. A length error along the
  // chain that the joints take up does not show (docs/accuracy.md).
  // `scale`: how much larger the link's geometry seems than the model's, a
  // fraction about the link frame's origin (0.05: 5% larger; a mesh
  // exported at the wrong scale, a cover), fitted beside the shifts in
  // each image that shows the link (ImageInformation::LinkScaleFit) and
  // averaged over uncertainty.model_error_learned_time_constant_s, each
  // image weighted by its fit's precision; NaN until 30 images have sized
  // it (a link seen in a few images reads too noisily to name). Where to
  // look, not a measurement: a link beside a scaled link or a wrong length
  // can read a few percent, and a link whose geometry's centre lies far
  // from its origin reads part of its scale as a shift (docs/accuracy.md,
  // stop 86). With end_effector_fit.link_scales (the default) the scales
  // of the end-effector fits' links widen the hands' reported positions
  // (the realistic dual arm's hands, 4% off their meshes, read +3.1% and
  // -2.9%; stop 99).
  struct LinkModelError {
    std::string link;
    double shift_m = std::numeric_limits<double>::quiet_NaN();
    int images = 0;  // that pinned some direction of it
    double scale = std::numeric_limits<double>::quiet_NaN();
    int scale_images = 0;  // that sized it
  };
  std::vector<LinkModelError> links;
  // Each encoder's white noise as its readings show it (the scatter of
  // four consecutive readings about their parabola, averaged over the last
  // 2 s; a bias cancels): per physical joint in DOF order, rad (m for
  // a prismatic joint); NaN for a joint without encoder or before about
  // 0.1 s of readings. A measured noise well above the configured
  // encoder_noise says the configuration is too optimistic; with
  // encoder_noise.from_readings the tracker weighs the readings by it
  // (TrackerConfig::EncoderNoise; docs/accuracy.md, "Encoders noisier than
  // configured").
  std::vector<double> encoder_noise_measured_rad;

  // The lowest ChainHealth::weakest_part_explained_fraction over the chains
  // (NaN when no chain has a part with a verdict), and how many chains are
  // unconfirmed.
  double weakest_part_explained_fraction() const;
  int unconfirmed_chains() const;
};
const char* health_state_name(TrackingHealth::State state);

// What the tracker believes at one time.
struct TrackerEstimate {
  double time_s = 0;
  // Physical joints in the model's DOF order (virtual joints excluded).
  std::vector<std::string> joint_names;
  Eigen::VectorXd angle_rad, angle_std_rad;
  Eigen::VectorXd bias_rad, bias_std_rad;  // 0 where biases are not estimated
  // Virtual camera joints: x, y, z (m), roll, pitch, yaw (rad); see robot_model.h.
  Eigen::Matrix<double, 6, 1> camera_offset = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> camera_offset_std = Eigen::Matrix<double, 6, 1>::Zero();
  // Pose of each configured end effector in the estimated (corrected) camera
  // frame, in TrackerConfig::end_effectors order.
  std::vector<Eigen::Isometry3d> T_camera_ee;
  // Their uncertainty: covariance of (position m, rotation vector rad, both
  // in the estimated camera frame), from the DOFs' covariance through the
  // kinematics' Jacobian (first order; the biases' and camera offsets' full
  // covariance after the first image, posterior_covariance.h); with the
  // end-effector fit, the position's is the fits' where they have a say
  // (their scatter and the links' shape error, widened along the direction
  // they determine least, and the fitted links' learned scales' shift of
  // them, "End-effector fit" above).
  std::vector<Eigen::Matrix<double, 6, 6>> T_camera_ee_covariance;
  // The end-effector fit's share of T_camera_ee ("End-effector fit" above):
  // per end effector, the rigid motion in its own axes (translation m, then
  // rotation vector rad) from where the estimated angles' kinematics put it
  // to the pose reported. Zero without the fit. How far the URDF's
  // kinematics are from the hand the camera sees; while no image shows the
  // hand it fades back to zero over end_effector_fit.time_constant_s.
  std::vector<Eigen::Matrix<double, 6, 1>> ee_image_correction;
  TrackingHealth health;
};

// Timings of one applied image update.
struct ImageTiming {
  double stamp_s = 0;      // the image's time stamp
  double update_ms = 0;    // wall time of the update
  double refilter_ms = 0;  // of which: re-filtering the buffered joints
  // Of which: the acquisition or re-acquisition search run at this image (0
  // when none ran). Images without one are the steady state.
  double search_ms = 0;
  // Wall time from its add_depth_image call until the estimate includes it
  // (waiting included).
  double latency_ms = 0;
};

// The timings of the most recent kCapacity applied images (oldest first) and
// the count and sums of all of them: fixed-size storage whatever the run time.
// A tracker fed 30 images a second keeps the last 9 minutes; shorter runs
// keep every image, so their percentiles are those of all images.
class ImageTimings {
 public:
  static constexpr std::size_t kCapacity = 16384;

  void add(const ImageTiming& t) {
    if (ring_.size() < kCapacity) {
      if (ring_.empty()) ring_.reserve(kCapacity);  // once: no growth later
      ring_.push_back(t);
    } else {
      ring_[std::size_t(total_ % kCapacity)] = t;
    }
    ++total_;
    sum_update_ms_ += t.update_ms;
    sum_refilter_ms_ += t.refilter_ms;
  }
  // Images kept, min(total(), kCapacity).
  std::size_t size() const { return ring_.size(); }
  bool empty() const { return ring_.empty(); }
  // Images ever added.
  long long total() const { return total_; }
  // The k-th oldest image kept, k < size().
  const ImageTiming& operator[](std::size_t k) const {
    return ring_.size() < kCapacity ? ring_[k] : ring_[std::size_t((total_ + k) % kCapacity)];
  }
  // Means over all images ever added (0 without any).
  double mean_update_ms() const { return total_ ? sum_update_ms_ / double(total_) : 0.0; }
  double mean_refilter_ms() const { return total_ ? sum_refilter_ms_ / double(total_) : 0.0; }
  // One field of the images kept, oldest first.
  std::vector<double> values(double ImageTiming::*field) const {
    std::vector<double> out(size());
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = (*this)[k].*field;
    return out;
  }

 private:
  std::vector<ImageTiming> ring_;
  long long total_ = 0;
  double sum_update_ms_ = 0, sum_refilter_ms_ = 0;
};

// Counters and timings, for reports and benchmarks. Fixed size (timings:
// ImageTimings::kCapacity images at most), whatever the run time.
struct TrackerStats {
  int joint_measurements = 0;  // filtered
  // Not filtered: a reading not finite or further than
  // TrackerConfig::joint_limit_margin_rad outside its joint's limits.
  int joint_measurements_dropped = 0;
  int images_received = 0;
  int images_applied = 0;
  int images_dropped_too_old = 0;  // older than the belief buffer reaches
  int images_dropped_backlog = 0;  // too many waiting for the joints to catch up
  int images_dropped_busy = 0;     // asynchronous: arrived while an update ran and a newer one came
  // Stamp not finite or further than TrackerConfig::max_image_clock_offset_s
  // from the newest joint measurement (counted as received too).
  int images_dropped_bad_stamp = 0;
  long long likelihood_evaluations = 0;
  int last_evaluations_per_image = 0;
  // The geometry the image updates draw (TrackerConfig::geometry), known from
  // prepare_camera or the first image on: triangles of the model as loaded
  // and as drawn (the cylinders' and spheres' tessellations excluded: they
  // are drawn exactly), the error the simplification was allowed and the
  // largest it reports, and how many times the simplified model was built
  // (once, unless the images' intrinsics change its error bound).
  int model_triangles = 0;
  int drawn_triangles = 0;
  double mesh_error_bound_m = 0;
  double mesh_error_m = 0;
  int geometry_builds = 0;
  ImageTimings images;  // of the applied images
};

// The Coordinate Particle Filter's sampling blocks for `config` on `model`,
// in visiting order: TrackerConfig::blocks by name, or by default one block
// per physical joint whose bias is estimated (every physical joint for
// vision_only), from the hand to the root of each chain, then one per
// virtual camera joint; camera_offset_only keeps only the virtual joints,
// encoders_only has none. Joints in no block follow their encoders. Throws
// InputError naming a block and its unknown joint.
std::vector<SamplingBlock> sampling_blocks(const RobotModel& model, const TrackerConfig& config);

// Whether every coordinate of `block` is a virtual camera joint of `model`.
bool is_camera_block(const SamplingBlock& block, const RobotModel& model);

// The blocks an image update samples: `blocks` (sampling_blocks()), of
// which full fusion samples at most config.camera_blocks_per_image camera
// blocks (is_camera_block()) per image.
int blocks_sampled_per_image(const std::vector<SamplingBlock>& blocks, const RobotModel& model,
                             const TrackerConfig& config);

// The particle filter's settings for `num_blocks` sampling blocks sampled
// per image (blocks_sampled_per_image()):
// config.particle_filter, with full fusion's particles per block raised to
// ceil(config.min_evaluations / num_blocks) when that is more, and no
// bandwidth floor for the other methods.
CoordinateParticleFilterParams particle_filter_params(const TrackerConfig& config, int num_blocks);

// The joint filter parameters `config` gives the physical joint `dof` of
// `model`, before the method's rules: the defaults of its kind
// (prismatic_joint_defaults for a prismatic joint, in metres, joint_defaults
// otherwise) with its joints.per_joint override. Throws InputError naming
// the joint when the override's units are not its joint's (metres for a
// revolute joint, degrees for a prismatic one).
JointFilterParams joint_filter_params(const RobotModel& model, const TrackerConfig& config,
                                      int dof);

class Tracker {
 public:
  // `encoder_joints`: the order of the readings given to add_joint_measurement
  // (every physical joint of the model exactly once, unless the method is
  // vision_only, which takes none). Throws InputError naming an unknown,
  // missing or repeated joint, an unknown end effector or block joint, or a
  // bad configuration value (TrackerConfig::validate, checked first).
  Tracker(std::shared_ptr<const RobotModel> model, const TrackerConfig& config,
          const std::vector<std::string>& encoder_joints);
  ~Tracker();
  Tracker(const Tracker&) = delete;
  Tracker& operator=(const Tracker&) = delete;

  // Vision only needs a starting configuration (physical joint name -> rad);
  // the other methods start from the first encoder reading. Joints not named
  // start at 0 (or at the nearest limit).
  void set_initial_configuration(const std::vector<std::string>& joints,
                                 std::span<const double> angles_rad);

  // One encoder reading per encoder joint, radians, taken at time_s. Throws
  // InputError for a time going backwards, a non-finite time or a wrong
  // count. A reading that is not finite or lies further than
  // TrackerConfig::joint_limit_margin_rad outside its joint's limits drops the
  // whole measurement (TrackerStats::joint_measurements_dropped): the joints
  // are not filtered at time_s.
  void add_joint_measurement(double time_s, std::span<const double> angles_rad);

  // A depth image (metres, 0 = no return) stamped at capture time, with the
  // camera's intrinsics. Throws InputError for a size that does not match the
  // intrinsics, a negative or non-finite depth (naming the pixel), or a time
  // stamp earlier than the previous image's. An image stamped after the newest
  // joint reading waits until the joints catch up. A stamp that is not finite
  // or lies further than TrackerConfig::max_image_clock_offset_s from the
  // newest joint reading drops the image (TrackerStats::images_dropped_bad_stamp).
  void add_depth_image(double stamp_s, const DepthImage& image, const CameraIntrinsics& camera);

  // Optional, before streaming: builds what the image updates draw the robot
  // with for this camera (full resolution, as the images will come): each
  // link mesh simplified to the likelihood's resolution (TrackerConfig::
  // geometry) and the renderers. Otherwise the first image does it, and a
  // robot of published meshes (330 000 triangles: about 2 s on one core)
  // then holds up the first images of a live stream. An image whose
  // intrinsics differ builds it again. Waits for a running image update.
  // Throws InputError for unusable intrinsics (CameraIntrinsics::problem).
  void prepare_camera(const CameraIntrinsics& camera);

  // Asynchronous mode: blocks until no image update is running or waiting to
  // run (that can run). Synchronous mode: returns at once.
  void wait_until_idle();

  // The current belief (after the newest joint reading or image). Holds the
  // tracker's lock while it computes (a joint update waits for it): about
  // 5 us of CPU on the dual arm (build/bench_tracker_update, BM_Estimate),
  // so a controller may poll it at the encoders' rate.
  TrackerEstimate estimate() const;
  // The same into `out`, reusing its storage: once `out` has held this
  // tracker's estimate, filling it again allocates nothing (a controller's
  // loop that polls at the encoders' rate need not touch the heap).
  void estimate(TrackerEstimate& out) const;
  TrackerStats stats() const;

  const RobotModel& model() const;
  const TrackerConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace arttrack
