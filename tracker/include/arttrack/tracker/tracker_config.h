// Configuration of a Tracker: which of the paper's four methods, the noise of
// every joint, the depth model, the particle filter, the delay buffer.
//
// Plain structs with in-class defaults, filled from YAML
// (tracker_config_yaml.h: this header needs no yaml-cpp) and checked once,
// by TrackerConfig::validate, which holds every range: the file reader calls
// it, and so does the Tracker for a configuration built in code. The shipped
// defaults are tracker/config/default.yaml, compiled into the library
// (default_tracker_config()); they name no joint or link of a particular
// robot. YAML uses degrees where it says `_deg`; the structs hold radians.
// The in-class defaults are the file's values, field by field (a default in
// radians is written as the file's degrees times kRadPerDeg, the same double
// the reader makes of it): DefaultConfigTest.TheShippedFileHoldsEveryInClassDefault.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_model_params.h"
#include "arttrack/tracker/joint_filter_params.h"
#include "arttrack/tracker/particle_filter_params.h"
#include "arttrack/tracker/units.h"

namespace arttrack {

// The four methods the paper compares (Sec. V-D, "Performance measures"), as
// configurations of one tracker (docs/method.md "The four methods").
enum class TrackingMethod {
  kEncodersOnly,      // forward kinematics of the raw encoder readings
  kCameraOffsetOnly,  // encoders taken as unbiased; images estimate the virtual camera joints
  kFullFusion,        // angles, biases and virtual camera joints from encoders and images
  kVisionOnly,        // no encoders: angles and camera joints from images alone
};

const char* method_name(TrackingMethod method);
// Parses "encoders_only", "camera_offset_only", "full_fusion", "vision_only";
// throws InputError naming `context` otherwise.
TrackingMethod parse_method(const std::string& name, const std::string& context);
const std::vector<std::string>& all_method_names();

struct TrackerConfig {
  // Where this configuration came from, for messages (the YAML file's path).
  std::string source = "tracker configuration";

  TrackingMethod method = TrackingMethod::kFullFusion;

  // Nominal camera frame in the URDF (optical convention).
  std::string camera_frame = "camera_optical_frame";
  // Links whose pose in the estimated camera frame the tracker reports (may
  // be none).
  std::vector<std::string> end_effectors;

  // Joint filters: defaults for every revolute or continuous joint (radians)
  // and for every prismatic one (metres: a gripper's fingers, a linear
  // axis), and per-joint overrides of some of them, keyed by joint name,
  // over the defaults of the joint's kind (joint_filter_params(); an
  // override's units must be its joint's). A prismatic joint's bias is not
  // estimated by default: its encoder reads the position itself, and a
  // millimetre is far below a pixel of the likelihood (1.5-2 cm at 80x60 and
  // 1 m); it follows its encoder and costs no particles.
  JointFilterParams joint_defaults;
  JointFilterParams prismatic_joint_defaults{1e-4, 1.0, 2e-4, 0.987, false};
  std::map<std::string, JointFilterOverride> joint_overrides;
  // Encoder smoothing (encoder_smoother.h): a constant-velocity Kalman
  // filter on each revolute encoder's readings, ahead of the joint filter.
  // Off, the joint filter takes each reading almost whole (its angle
  // diffusion follows any motion) and the angle carries the reading's white
  // noise between images: 0.057 degrees on every encoder took the dual
  // arm's realistic p75 from 4.0 to 6.3-6.7 mm (docs/accuracy.md, "Encoders
  // with noise"). On by default (stop 74): real encoders have noise, and
  // with exact readings it moved the paper's exact-depth files' p75 by
  // under 0.1 mm, up to 0.8 mm on the in/out/in and occlusion files (stop
  // 71); off, encoders only reports the raw readings.
  struct EncoderSmoothing {
    bool enabled = true;
    // sigma_v: the rate's diffusion (white acceleration), rad/s per
    // sqrt(s); in (0, 1e5] deg/s/sqrt(s). Smaller averages more readings
    // and lags more behind an accelerating joint.
    double rate_diffusion_rad_per_s_per_sqrt_s = 20 * kRadPerDeg;
  };
  EncoderSmoothing encoder_smoothing;
  // The encoders' noise as their readings show it (encoder_noise_meter.h;
  // TrackingHealth::encoder_noise_measured_rad, always measured). With
  // from_readings, an encoder whose measured noise m is over
  // kEncoderNoiseTolerance times its configured sigma_q is smoothed and
  // filtered as if its noise were sqrt(m^2 - (tolerance^2 - 1) sigma_q^2):
  // continuous, sigma_q at the tolerance and nearly m far above it; from the
  // meter's 1000th difference on (1 s at 1 kHz), when it is within a few
  // percent. Within the tolerance the configuration stands, so where it is
  // right nothing changes. Encoders 3.5 and 9 times noisier than configured
  // cost the realistic dual arm's hands 2.5 and 8.5 mm at p75 without it,
  // 1.1 and 2.6 with it, as much as configuring the true noise
  // (docs/accuracy.md, "Encoders noisier than configured"). Configured noise
  // larger than the readings' is kept: it is the user's statement of the
  // encoders' error.
  struct EncoderNoise {
    bool from_readings = true;
  };
  static constexpr double kEncoderNoiseTolerance = 1.25;
  EncoderNoise encoder_noise;
  // Virtual camera joints: translation (m) and rotation (rad) noise.
  VirtualJointParams camera_translation{0.002, 0.03, 0.0};
  VirtualJointParams camera_rotation{0.11 * kRadPerDeg, 1.7 * kRadPerDeg, 0.25 * kRadPerDeg};
  // The noise of the k-th virtual camera joint, k in [0, 6), in the model's
  // order: translation along x, y, z (camera_translation), then rotation
  // about x, y, z (camera_rotation). Throws InputError outside [0, 6).
  const VirtualJointParams& camera_joint_params(int k) const;

  // Vision only: how fast angles may wander between images (rad/sqrt(s)) and
  // the standard deviation of the given initial configuration (rad).
  double vision_only_angle_diffusion_rad_per_sqrt_s = 17.0 * kRadPerDeg;
  double vision_only_initial_std_rad = 1.1 * kRadPerDeg;

  DepthModelParams depth_model;
  // Geometry at the likelihood's resolution (mesh_simplify.h): when the
  // camera is known (Tracker::prepare_camera, else the first image) every
  // link mesh the tracker draws is simplified so that its surface moves at
  // most max_error_px of one pixel (at depth_model's resolution) at
  // nearest_range_m, the nearest range the camera sees the robot (a depth
  // camera's minimum range), with four
  // coarser levels of detail for links twice, 4, 8 and 16 times as far
  // (robot_model.h, Link::coarser_meshes). Cylinders and spheres are drawn
  // exactly whatever this says.
  struct Geometry {
    // In [0, 4]; 0 draws the full meshes.
    double max_error_px = 0.25;
    // In [0.01, 100] metres.
    double nearest_range_m = 0.3;
    // Levels of detail beyond the first, in [0, 8]: level k drawn from 2^k
    // times the nearest range (4: up to 16 times, 0.3 -> 4.8 m).
    int coarser_levels = 4;
    // Draw the links whose meshes have an open part (a border, an edge of
    // three triangles: robot_model.h, Link::mesh_parts) from both sides, as
    // a camera sees an open surface, instead of culling back faces as for
    // closed ones. Off: a crack or T-junction makes a mesh open, and both
    // sides cost up to 1.6 times as much; on when the camera sees into an
    // open shell (render and bench name the links).
    bool open_parts_both_sides = false;
    // The largest error the simplification may make for a camera at the
    // likelihood's resolution (mesh_error_bound_m(); 0: full meshes).
    double error_bound_m(const CameraIntrinsics& likelihood_camera) const;
  };
  Geometry geometry;
  CoordinateParticleFilterParams particle_filter;
  // Full fusion samples at least this many particles per image over the
  // blocks it samples per image (blocks_sampled_per_image() in tracker.h):
  // particles per block max(particle_filter.num_particles,
  // ceil(min_evaluations / blocks)) (particle_filter_params()). A 7-DoF arm
  // samples 7 joint blocks and 2 camera blocks: 45 particles; the dual arm
  // 14 and 2: 25. 0: exactly particle_filter.num_particles.
  int min_evaluations = 400;
  // Full fusion: how many of the camera blocks (blocks of virtual camera
  // joints only) an image update samples, in [1, 6]; the images take them
  // in turn, and the others keep their prior mean and variance for that
  // image (the refinement still moves every DOF). Each camera particle
  // redraws the whole robot, so the camera blocks were 44% of a mesh
  // robot's image update. min_evaluations counts the blocks sampled. 6:
  // every block each image, the paper's.
  int camera_blocks_per_image = 2;
  // Full fusion: a joint none of whose links the camera sees at an image's
  // prior mean (out of view, or behind a surface the image shows more than
  // health.explained_m nearer), and that no explained pixel depends on at
  // the particle filter's mean, keeps its prior through the image
  // (unseen_joints.h in the tracker's internals): the filter would
  // otherwise take the image's "not here" as evidence again at every image
  // and walk the hidden chain away from the view or behind the occluder
  // (docs/accuracy.md, "The hidden arm keeps its prior", "An arm behind a
  // panel keeps its prior"). false: the particle filter's moments, as the
  // paper.
  bool keep_unseen_prior = true;
  // With keep_unseen_prior: a joint whose links the camera sees at fewer
  // than this many pixels (at the likelihood's resolution) at the prior
  // mean, one of them on the view's border or one behind a nearer surface,
  // counts as unseen too. 1: only a chain wholly unseen. A chain at the
  // view's edge is seen by a pixel or two, which say mostly where it is
  // not: the particles' mean then pushes it out of view by degrees in one
  // image and their variance collapses (docs/accuracy.md, "A chain at the
  // view's edge").
  int unseen_below_pixels = 30;
  // Sampling blocks: named lists of joint names. Empty: one block per
  // physical joint whose bias is estimated (every physical joint for
  // vision_only; a joint whose bias is not estimated, like a mimic joint,
  // follows its encoder and costs no particles), ordered from the hand
  // towards the root (so that the links a block does not move are the same
  // for all particles within a chain), then one per virtual camera joint (a
  // joint six-dimensional camera block finds local optima); see
  // sampling_blocks() in tracker.h. camera_offset_only samples only the
  // virtual joints.
  struct Block {
    std::string name;
    std::vector<std::string> joints;
  };
  std::vector<Block> blocks;
  // Exponent beta in [1e-3, 1] on the image likelihood in the particle filter
  // (CoordinateParticleFilter::run): 1 counts every pixel as an independent
  // measurement; neighbouring pixels share model and calibration errors, so
  // fewer than that is honest.
  double likelihood_exponent = 1.0;
  // The reported uncertainty (posterior_covariance.h): an image's
  // information counts this much, in [1e-6, 1] (1: every explained pixel an
  // independent measurement).
  double image_information_scale = 1.0;
  // Also scale each image's information by how many independent pixels its
  // residuals are worth (ImageInformation::effective_pixel_fraction).
  bool discount_correlated_residuals = true;
  // With model_error: the reported covariance's pixel-noise term (the gain
  // times the pixels' noise, posterior_covariance.h) at the noise the
  // image's residuals show once the DOFs' fit is taken out
  // (ImageInformation::fitted_residual_factor; at most the weights'
  // noise), not at the noise the weights assume. The weights, and so the
  // means, are unchanged. The residuals before the fit also hold the
  // estimate's own error: with exact depth that is nearly all of them, and
  // the dual arms' exact-depth files were over the 2 sigma band's top;
  // under the realistic camera the term falls by about a fifth
  // (docs/accuracy.md, stop 93; the default since then).
  bool pixel_noise_after_fit = true;
  // The real robot is not its model: treat a shift of each link's surface
  // as an error shared by every image (consider states of the reported
  // covariance, posterior_covariance.h; link shifts, image_information.h),
  // with a standard deviation estimated from the images' residuals,
  // averaged over model_error_time_constant_s, and at least
  // model_error_min_std_m (a user who knows their URDF is off by about that);
  // and each curved link's bulge (its surface out along its normals, fitted
  // apart from the shifts) at the size its own images fit.
  // A shift one image does not pin (the DOFs absorb it: a link's length
  // along the chain) is taken model_error_unpinned_scale times that
  // estimate, and so is the hand's along the direction the
  // end-effector fit determines least (end_effector_fit.h), in [1, 10]:
  // the estimate comes from the links that fit.
  bool model_error = true;
  double model_error_time_constant_s = 2.0;
  double model_error_min_std_m = 0.0;
  double model_error_unpinned_scale = 3.0;
  // Also learn each link's shift over many poses, in the link's own axes
  // (learned_link_shifts.h: each image's shift fit summed over
  // model_error_learned_time_constant_s); where an axis is learned (the
  // sum's standard deviation under model_error_learned_max_std_m), the
  // shift's prior along it is at least the learned shift's size in the
  // camera offset's uncertainty (the joints' unpinned shifts are already
  // scaled: with it too they went over the 2 sigma band). A length
  // the joints take up shows over poses, not in one image: on the
  // realistic dual arm the camera's pitch is then within 2 sigma as often
  // as it claims (docs/accuracy.md, stop 59).
  bool model_error_learned_shifts = true;
  double model_error_learned_time_constant_s = 10.0;
  double model_error_learned_max_std_m = 0.001;
  // Whether the joints take the unpinned shifts of a link learned on all
  // three axes (as above) at model_error_unpinned_scale times the estimate
  // too (true, stops 42-90), or at the estimate plus the learned shift's
  // excess over it (false, the default since stop 91). The scale stands for
  // what is unknown of the shifts the joints take up unseen; of a learned
  // link the size is known. The camera offset keeps the scale either way.
  // On the realistic family false brings the sculpted dual arm's joints
  // into the 2 sigma band (99.7 -> 96.8%) with the means unchanged: the
  // refinement's step stays bounded by the scaled deviations (bounded by
  // the reported ones it lagged where a hand came back into view: stop 90;
  // ReportedCovariance::step_bound_covariance(), docs/accuracy.md, stop 91).
  bool model_error_unpinned_scale_on_learned = false;
  // The user's stated standard deviation of the URDF's link lengths, m, in
  // [0, 0.1]: each joint origin the camera does not hang from may be that
  // much longer or shorter along its translation, an error shared by every
  // image (one more consider state per joint, reported_covariance.h). The
  // joints and the camera offset absorb such an error, so the images
  // cannot size it (the link shifts above come from the residuals left
  // after that); only what the user knows of their robot can. 0: none.
  double link_length_std_m = 0.0;
  // The user's stated standard deviation of their depth camera's scale, a
  // fraction in [0, 0.1] (0.005: every return may be 0.5% long or short,
  // the same in every image): one more consider state
  // (reported_covariance.h) and, for the end-effector fit, that fraction of
  // the hand's distance along its line of sight (end_effector_fit.h). The
  // camera offset takes such an error up along the optical axis, so the
  // images cannot size it; only the camera's calibration can. 0: none.
  double depth_scale_std = 0.0;
  // Widen the reported variance of a bias or a camera offset while its
  // mean still moves (mean_lag.h): plus mean_lag_scale times the squared
  // difference of the mean's running averages over 0.2 s and over
  // mean_lag_time_constant_s. The report only; the estimate is the same.
  // Under model error the first images can put a mean on a wrong point of
  // a ridge, from which it slides back over seconds while its reported
  // standard deviation is already small (docs/accuracy.md, "The mean's lag
  // as uncertainty"). mean_lag_scale in [0, 100] (0: off),
  // mean_lag_time_constant_s in [0.5, 1e4].
  double mean_lag_scale = 2.0;
  double mean_lag_time_constant_s = 6.0;
  // Full fusion: one Gauss-Newton step on the mean after the particle
  // filter (tracker.h, "Refinement").
  bool refine_mean = true;
  // A DOF takes part in the step when at least this many explained pixels
  // depend on it.
  int refinement_min_pixels = 30;
  // When the step is longer than this many reported standard deviations
  // (its Mahalanobis length under the reported covariance: the mean is far
  // from where the image and the prior put it, as while it converges),
  // each state may move up to its reported standard deviation, not only the
  // particles' spread. 0: never.
  double refinement_widen_beyond_sigma = 2.0;
  // A direction of the states along which the image's motion-field
  // information (surface normals: what moving a surface shows) is below
  // this fraction both of the prior's and of the central differences'
  // information takes no image term in the step: along it the mean follows
  // the prior alone. Such a direction moves no surface (a camera orbiting
  // an axisymmetric base link while the joint that turns it turns back),
  // but the central differences, one DOF at a time, count each edge a DOF's
  // step moves across a pixel centre as a slope, and the DOFs' jumps fall on
  // different pixels, so they read information there. 0: off, the default
  // before stop 98 (arm7's exact-depth camera walked 35-71 mm along its
  // round base; docs/accuracy.md, "Directions that move no surface").
  double refinement_unseen_information_ratio = 0.01;
  // Full fusion: each end effector's pose where the images show its end
  // link (the nearest link with geometry at or above it), not only where
  // the joint estimate's kinematics put it (tracker.h, "End-effector fit";
  // end_effector_fit.h). Each image's rigid fit of that link counts when
  // its translation's standard deviation is below max_std_m; the fits are
  // averaged over time_constant_s. The fit sees the image at
  // resolution_factor times the likelihood's width and height (at most
  // the image's own): 1 is the likelihood's image (no extra cost), more
  // pixels show the hand's length and axis. axis_search_range_m: each
  // fit is also searched along the direction it determines least, the
  // whole pixel likelihood scored at shifts up to this far
  // (end_effector_axis_search.h); 0: not searched.
  struct EndEffectorFitConfig {
    bool enabled = true;
    double time_constant_s = 1.0;
    double max_std_m = 0.002;
    int resolution_factor = 2;
    double axis_search_range_m = 0.01;
    // Whether the reported position also takes the fit links' shape scales
    // the images learn (TrackingHealth::LinkModelError::scale): the shift a
    // link's scale moves its rigid fit by (end_effector_fit.h). The
    // default since stop 99 (docs/accuracy.md).
    bool link_scales = true;
  };
  EndEffectorFitConfig end_effector_fit;
  // Acquisition (tracker.h): an annealed, coarse-to-fine search from the
  // encoders' configuration, at the first image, periodically and when the
  // health check says the estimate is lost. Full fusion only.
  struct Acquisition {
    // Passes over one image: passes - 1 search passes, from a depth noise of
    // coarse_noise_std_m down to the pixel model's, then the final pass. 1
    // switches acquisition off (every image is one plain CPF run).
    int passes = 3;
    double coarse_noise_std_m = 0.05;
    // Proposal standard deviation of search pass k: the prior's times shrink^k.
    double proposal_shrink = 0.5;
    // A periodic search from the encoders every this many seconds (0: never).
    double period_s = 0.0;
    // Bias standard deviation of the re-opened prior a search starts from
    // (the encoders' reading, bias 0), rad.
    double bias_std_rad = 20 * kRadPerDeg;
    // A chain takes the search's result when it scores this many nats better
    // (log-likelihood ratio of the image plus log prior of the encoders).
    double accept_margin_nats = 5.0;
    // Independent searches per acquisition (first image, re-acquisition);
    // the one the image plus the prior prefer is used.
    int searches = 3;
    // Whether the first image's search moves the six camera joints too.
    // false: the camera starts at its prior (mean and standard deviation)
    // and the images after the first move it. One image does not tell the
    // camera's pose from the arms' biases: searched, the camera settled
    // anywhere along that ridge, and the images after it, counted as
    // evidence for that place, held it there with a standard deviation that
    // did not cover it. Held, the camera offset is within 2 sigma 90-98% of
    // the time on the exact-depth files where it was 70-86% searched, with
    // no run lost on the occlusion files (docs/accuracy.md, "The camera held
    // at the first image, again"; arm7's camera still drifts along its
    // ridge, later).
    bool search_camera = false;
  };
  Acquisition acquisition;
  // Health (TrackerEstimate::health): a rendered robot pixel is explained
  // when the observed depth is within explained_m of it, contradicted when
  // the camera sees more than contradicted_m behind it. An estimate whose
  // contradicted share exceeds lost_contradicted_fraction for lost_after_images
  // images in a row is lost (and triggers an acquisition).
  struct Health {
    double explained_m = 0.01;
    double contradicted_m = 0.02;
    double lost_contradicted_fraction = 0.25;
    double lost_abandoned_fraction = 0.25;  // ChainHealth::abandoned_fraction
    // A chain part whose visible pixels are explained below this share is
    // unconfirmed, and its chain searched again after lost_after_images
    // such images (ChainHealth::weakest_part_explained_fraction); a chain
    // nothing contradicts takes the search's result only if this check
    // then confirms it or finds it better explained. 0: off.
    double unconfirmed_explained_fraction = 0.5;
    // A part's pixel whose observed depth is more than this in front of
    // its render shows an occluder, not the robot (a panel held before the
    // arm): it gives the part no verdict. A hand in a wrong mode behind the
    // real arm has the real robot a few centimetres in front of it.
    double occluder_gap_m = 0.1;
    int lost_after_images = 3;
    int min_pixels = 20;  // fewer rendered pixels with a valid depth: no verdict
  };
  Health health;
  // Seed of the particle filter's random generator.
  unsigned long long seed = 1;
  // Worker threads for the image update (0: one per core).
  int threads = 0;

  // Constant camera delay, s: an image stamped t is applied at t - delay.
  double camera_delay_s = 0;
  // Joint measurements (and beliefs) kept for re-filtering after a delayed
  // image: images older than this are dropped and counted.
  int buffer_capacity = 2000;
  // Images stamped after the newest joint measurement wait for the joints;
  // beyond this many waiting, the oldest is dropped and counted.
  int max_pending_images = 4;
  // Asynchronous: image updates run on a worker thread while joint updates
  // go on (the paper's two filters). Synchronous: each image is applied when
  // it becomes applicable, in the caller's thread (deterministic).
  bool asynchronous = false;

  // Readings the tracker drops and counts (TrackerStats) instead of filtering:
  // a joint measurement with a reading further than joint_limit_margin_rad
  // outside its joint's limits (or not finite), and a depth image stamped
  // further than max_image_clock_offset_s from the newest joint measurement
  // (or not finite). Either would poison the filter for the rest of the run.
  double joint_limit_margin_rad = 30 * kRadPerDeg;
  double max_image_clock_offset_s = 10.0;

  // Like Ceres' Solver::Options::IsValid: checks every field against its
  // range (the only place the ranges are written), including the joint
  // defaults and per-joint overrides, the camera offset and the sub-structs
  // (DepthModelParams::validate, CoordinateParticleFilterParams::validate,
  // JointFilterParams::validate). Throws ConfigKeyError (error.h) naming
  // `source`, the key as the YAML writes it (e.g.
  // "joints.per_joint.l_elbow.bias_diffusion_deg_per_sqrt_s"), the value and
  // the allowed range, in the YAML's units (degrees for a `_deg` key).
  void validate(const std::string& source) const;
};

// The text of tracker/config/default.yaml as built into the library (every
// key, documented), and the configuration it gives. The name it goes by in
// messages: kDefaultTrackerConfigName.
const char* default_tracker_config_yaml();
TrackerConfig default_tracker_config();
inline constexpr const char* kDefaultTrackerConfigName = "tracker/config/default.yaml (built in)";

}  // namespace arttrack
