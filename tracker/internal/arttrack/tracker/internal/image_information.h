// How much one depth image says about a configuration: the Gauss-Newton
// (Fisher) information of the pixel likelihood about a set of DOFs, at one
// configuration (docs/accuracy.md, "Consistency").
//
// The Coordinate Particle Filter gives a good mean but a poor covariance: a
// few particles per coordinate, weighted by a sharp likelihood, collapse to
// one, and coordinate-wise moments cannot show that the image pins some
// combinations of joints (the hand's pose in the camera) and leaves others
// almost free (the camera's pose against every arm's biases). This module
// gives the matrix a Laplace approximation needs instead. For the pixels
// where the robot rendered at q is seen (valid observed depth z within
// `inlier_sigmas` noise sigmas of the rendered depth r, and every
// perturbed render covering the pixel too), the visible branch of the pixel
// model is N(z; r(q), sigma(z)^2) (depth_likelihood.h), whose Fisher
// information is
//   I = sum_pixels  grad r(q) grad r(q)^T / sigma^2,
// grad r by central differences of the rendered depth, one DOF at a time
// (information_matrix(), gradient(): the refinement's), and, with
// params.motion_field, from the motion field (motion_field_information():
// the reported covariance's).
// Only interior pixels count: how the silhouette moves is not
// differentiable, so the edges' information is left out (the matrix errs on
// the side of less information). Occluded and unexplained pixels say
// nothing.
//
// Cost: the links drawn one by one at q, then per DOF 2 renders of the
// links it moves (over the others' images from the first pass: every link
// when it moves the camera) at the likelihood's resolution, the DOFs spread
// over a WorkerPool's workers when one is given (the same numbers on any
// count of workers). Allocation-free after the first call with a given
// image size, DOF set and worker count.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {

class WorkerPool;      // worker_pool.h
class SurfaceNormals;  // surface_normals.h

struct ImageInformationParams {
  // Central-difference steps: radians for revolute DOFs, metres for prismatic ones.
  double revolute_step_rad = 2e-3;
  double prismatic_step_m = 1e-3;
  // A pixel counts when |z - r| is below this many noise sigmas.
  double inlier_sigmas = 3;
  // Also compute how the image depends on a shift of each link's surface
  // (link shifts, below).
  bool link_shifts = false;
  // Also compute the information from the motion field
  // (motion_field_information(), below).
  bool motion_field = false;
  // Also compute how the image depends on the camera's depth scale
  // (depth_scale_cross_information(), below).
  bool depth_scale = false;
  // Also size the residuals' noise with the DOFs' fit taken out
  // (fitted_residual_factor(), below).
  bool fitted_residuals = false;
};

class ImageInformation {
 public:
  // `dofs`: the DOF indices of `renderer.model()` the matrix is about, in
  // its row order.
  ImageInformation(std::vector<int> dofs, const ImageInformationParams& params = {});
  ~ImageInformation();

  const std::vector<int>& dofs() const { return dofs_; }

  // The information matrix about dofs() of the likelihood's current
  // observation, at configuration q (size model.num_joints()). The renderer's
  // camera must have the likelihood's size. With `pool`, its workers share
  // the renders (worker 0, the caller, with `renderer`; the others with
  // renderers of their own, made at the first call and whenever the model
  // or camera changes). Returns a reference to an internal matrix, valid
  // until the next call.
  const Eigen::MatrixXd& compute(DepthRenderer& renderer, std::span<const double> q,
                                 const DepthLikelihood& likelihood, WorkerPool* pool = nullptr);

  // The matrix of the last compute().
  const Eigen::MatrixXd& information_matrix() const { return information_; }
  // The same information with d r / d q from the motion field (with
  // params.motion_field; else information_matrix()): each pixel's surface
  // point X, in camera axes, moves with DOF k by the sum over the joints k
  // drives (a mimic with its multiplier) of a x (X - o) (revolute; a for
  // prismatic; a, o the joint's axis and origin), counted when the joint
  // moves the pixel's link and not the camera, negated when it moves the
  // camera and not the link; the rendered depth at the pixel changes by
  // j . dX, j the link-shift vector below (from the rendered depth's
  // slopes), over the same pixels; rather j = n / n . (x, y, 1) from the
  // surface's normal n, and 0 beyond 76 degrees from facing the camera, on
  // a cylinder or sphere (RoundShape, drawn exactly: its own normal) and on
  // a mesh (the smooth surface it approximates, surface_normals.h): slopes
  // between pixels are chords of the curve, and a shape turned about its
  // own axis seemed to move (arm7's round base, docs/accuracy.md stop 44;
  // the sculpted arm7's mesh base, stop 45). It is one linear map
  // for every DOF: a motion that moves no surface relative to the camera
  // changes no pixel.
  // Central differences are not: where one surface steps in front of
  // another by less than inlier_sigmas (a finger before the hand, a link
  // before the next), a DOF's step moves the edge across a pixel centre and
  // the difference counts the step as a slope, and the steps of DOFs whose
  // motions cancel (arm7's camera turned about its round base with the
  // first joint turned back) do not cancel. Measured on an arm7 image: 696
  // per unit along that motion from central differences, 7 from the
  // rendered depth's change along it. The reported covariance uses this;
  // the refinement's Gauss-Newton step keeps the central differences
  // (information_matrix(), gradient()), with which it is more accurate.
  const Eigen::MatrixXd& motion_field_information() const {
    return params_.motion_field ? field_information_ : information_;
  }
  // The same gradient as gradient() with d r / d q from the motion field
  // (with params.motion_field; else gradient()): it has no component along
  // a motion that moves no surface, where gradient()'s central differences
  // may (above). Computed on the call from the last compute()'s motion
  // field and residuals, so images that do not ask for it do not pay for
  // it; allocation-free after the first call with a given DOF count.
  const Eigen::VectorXd& motion_field_gradient() const;
  // The Gauss-Newton gradient of the last compute(): sum over the same
  // pixels of grad r (z - r) / sigma^2 (the log-likelihood's gradient of the
  // visible branch), in dofs() order.
  const Eigen::VectorXd& gradient() const { return gradient_; }
  // Pixels that contributed to the last compute(), in all and per DOF (those
  // whose depth the DOF changes).
  int pixels_used() const { return pixels_used_; }
  const std::vector<int>& pixels_per_dof() const { return pixels_per_dof_; }

  // How many independent measurements the last compute()'s pixels are worth,
  // as a fraction of pixels_used(), from their normalised residuals u = (z -
  // r) / sigma: the pixel model takes every u as independent N(0, 1), but an
  // estimate off by more than the noise (or a model that differs from the
  // robot) leaves residuals that are larger and that neighbouring pixels
  // share. With rho_x, rho_y the correlations of horizontally and vertically
  // adjacent residuals (each clamped to [0, 0.99]), ess = (1 - rho_x) / (1 +
  // rho_x) * (1 - rho_y) / (1 + rho_y) the effective sample size of a
  // separable first-order autoregressive field per pixel, and s^2 their mean
  // square, a least-squares estimate from residuals of that size and
  // correlation varies s^2 / ess times as much as the pixel model says:
  //   fraction = min(1, ess / s^2),
  // never more than the model's independent pixels. Residuals much smaller
  // than sigma count as little as their size: with exact depth they are a
  // tenth of sigma and correlated 0.8 (ess 0.01), and the fraction with
  // max(1, s^2) for s^2 (stop 37 and before) kept 1% of the pixels, the
  // reported standard deviations about ten times the errors. 1 when no
  // pixel was used.
  double effective_pixel_fraction() const { return effective_pixel_fraction_; }
  // The same residuals with the DOFs' least-squares fit taken out (with
  // params.fitted_residuals; else 1): e = u - G x, x = (G^T G)^-1 G^T u,
  // G the motion field's d r / d q (the finite differences' without
  // params.motion_field). A residual the DOFs explain is the estimate's
  // own error, not the pixels' noise: the fraction above counts both
  // (with exact depth its residuals are the estimate's error, correlated
  // 0.8; with it fitted out they are a twentieth of sigma and correlated
  // 0.1). With rho_x', rho_y' and ess' from e as above and s'^2 = e^T e /
  // (pixels_used() - DOFs), the noise the pixels put into a fit is
  //   factor = s'^2 / ess'
  // times the pixel model's (the sandwich of a least-squares fit). 1 when
  // no pixel was used, the pixels do not outnumber the DOFs, or the fit
  // is not finite.
  double fitted_residual_factor() const { return fitted_residual_factor_; }

  // Link shifts (with params.link_shifts): the real robot's links are not
  // the model's (lengths, shapes, simplified meshes), and the error is the
  // same in every image. Its first-order effect is modelled as a shift t_l
  // of each link's surface, in camera axes: the rendered depth at pixel
  // (u, v) of link l becomes r(u - du, v - dv) + t_z with du = fx (t_x - x
  // t_z) / r, dv = fy (t_y - y t_z) / r, x = (u - cx) / fx, y = (v - cy) /
  // fy, so
  //   d r / d t = (-fx r_u / r, -fy r_v / r, 1 + (x fx r_u + y fy r_v) / r),
  // r_u, r_v the rendered depth's slopes per pixel between neighbours of the
  // same link (interior pixels; none across a depth jump). Each used pixel
  // is labelled with the link it shows (the links drawn one by one). Over
  // the same pixels as the information, normalised by sigma:
  //   shift_cross_information()  G_dof^T G_shift   (dofs x 3 links)
  //   shift_information()        G_shift^T G_shift (3 links square, 3x3 blocks)
  //   shift_gradient()           G_shift^T u       (u the normalised residuals)
  // Column 3 k + a is axis a of shift_links()[k] (the model's links with geometry).
  // A shift moves its link's pixels and those of every link below it. Two
  // shifts that move the same pixels are one: a link that shows no pixel
  // of its own above a child that shows them all (the sculpted dual arm's
  // right shoulder, three links deep, none of them in view) moves what the
  // child's moves. Its columns are zero in that image and only the deepest
  // keeps them, so that the shift is fitted and considered once
  // (docs/accuracy.md, stop 88: counted three times, the whole arm's
  // translation went into the reported covariance at three times its
  // variance).
  const std::vector<int>& shift_links() const { return shift_links_; }
  const Eigen::MatrixXd& shift_cross_information() const { return shift_cross_; }
  // shift_cross_information() with the motion field's DOF columns (with
  // params.motion_field; else the same).
  const Eigen::MatrixXd& motion_field_shift_cross_information() const {
    return params_.motion_field ? field_shift_cross_ : shift_cross_;
  }
  const Eigen::MatrixXd& shift_information() const { return shift_information_; }
  // The camera's depth scale (with params.depth_scale): every return (1 + c)
  // times the true depth, the same error in every image. Scaling the scene
  // about the camera's centre keeps each pixel where it is, so the rendered
  // depth becomes (1 + c) r and d r / d c = r at every pixel (for a link's
  // shift t = c X, j . X = r). Over the same pixels as the information,
  // normalised by sigma: G_dof^T (r / sigma), in dofs() order, with the
  // motion field's DOF columns when params.motion_field.
  const Eigen::VectorXd& depth_scale_cross_information() const { return depth_scale_cross_; }
  const Eigen::VectorXd& shift_gradient() const { return shift_gradient_; }
  // A moment estimate of the links' shift variance, m^2, from the last
  // compute(): the shifts' least-squares fit p to the residuals with the
  // DOFs projected out (the tracker's estimate is their fit), over the links
  // at least `min_pixels` pixels show, has noise covariance c A^-1 (A the
  // shift information with the DOFs projected out, c the residuals' variance
  // left after fitting both, at least 1). When each shift is N(0, sigma_t^2),
  // E[p_i^2] = sigma_t^2 + c (A^-1)_ii, so the estimate is the mean over
  // the shifts one image pins to within 3 mm of p_i^2 - c (A^-1)_ii, every
  // link weighing the same (a weighting by pixels let the big, well-fitted
  // links hide the small ones' error: half the standard deviation on
  // scenarios/realistic/both.yaml). Unbiased, so negative when the noise
  // fitted less than its expectation (about minus the noise's share when
  // the links fit): one image's estimate is noisy, and a caller averages
  // the estimates over images and clips the average at 0. Clipping each
  // image's (stop 83 and before) kept the noise's positive half: with the
  // robot exactly its URDF under the realistic camera, 1.2 mm of model
  // error on arm7 and 0.45 mm on the dual arm (docs/accuracy.md, stop 84).
  // 0 when no shift is counted. Each link's bulge (below) is projected out
  // with the DOFs. Its matrices (k up to 3 x links, plus the DOFs and
  // bulges) are kept between calls. `pinned`, when given, is
  // set per shift column (3 per link, as shift_cross_information()) to
  // whether this image pinned it (and so counted it); `column_square_m2`
  // to that shift's p_i^2 - c (A^-1)_ii where pinned, 0 elsewhere;
  // `equations` to the fit's normal equations (ProjectedShiftEquations);
  // `scales` to each link's scale fitted with the DOFs and shifts alone
  // (LinkScaleFit, below); `bulge_square_m2` per shift link to its bulge's
  // fit squared less its noise variance, as the shifts' (NaN where not
  // fitted or where one image does not pin it to within 3 mm). Allocates
  // nothing when this image shows the same links as the last (its
  // workspaces keep their sizes).
  struct ProjectedShiftEquations;
  struct LinkScaleFit;
  double link_shift_variance_m2(std::vector<char>* pinned = nullptr,
                                std::vector<double>* column_square_m2 = nullptr,
                                ProjectedShiftEquations* equations = nullptr,
                                std::vector<LinkScaleFit>* scales = nullptr,
                                std::vector<double>* bulge_square_m2 = nullptr,
                                int min_pixels = 20) const;
  // Link bulges (with params.link_shifts): a link's surface moved out along
  // its own normals by a distance d (a thicker cover, a casting rounder or
  // flatter than its model, a simplified mesh's faces inside the surface
  // they approximate), the links below it not moved. j lies along the
  // surface's normal, so the rendered depth at the link's own pixels falls
  // by d |j|. A round link's bulge is no shift of it (a shift moves its
  // near side and one flank; a bulge, the whole visible surface towards
  // the camera), and fitted as shifts it reads as one: on the realistic
  // dual arm, four links scaled by 3-5%, the pooled shift estimate read
  // 1.7-1.8 mm, 0.8-0.9 mm with the bulges fitted apart (docs/accuracy.md,
  // stop 87). Only pixels on round shapes and curved mesh triangles count:
  // a flat face's bulge is a shift of it.
  // Over the link's own used pixels, normalised by sigma, the motion
  // field's G_dof^T g (dofs x links; the finite differences' without
  // params.motion_field), g = -|j| / sigma: a bulge's columns as consider
  // parameters (ReportedCovariance).
  const Eigen::MatrixXd& motion_field_bulge_cross_information() const {
    return params_.motion_field ? field_bulge_cross_ : bulge_cross_;
  }
  // The shifts' normal equations with the DOFs projected out, as
  // link_shift_variance_m2() fits them: over the shift columns `columns`
  // (indices as shift_cross_information()'s), A (k x k) and b (k), in
  // normalised residuals per metre; the fit is A^-1 b with noise
  // covariance noise_var A^-1. noise_var 0 (and k 0): the image fitted no
  // shift (none shown, or A indefinite).
  struct ProjectedShiftEquations {
    std::vector<int> columns;
    Eigen::MatrixXd A;
    Eigen::VectorXd b;
    double noise_var = 0;
  };
  // Link scales (with params.link_shifts): a link's geometry larger or
  // smaller than the model's by a fraction s about the link frame's origin
  // o (a mesh exported at the wrong scale, a thicker cover; not its
  // children, which a shift moves). A pixel's surface point X then moves by
  // s (X - o) and its rendered depth by s j . (X - o), j the link-shift
  // vector above. A shift of the link is a scale about another point plus
  // a scale about o, so each link's scale is fitted beside the shifts: with
  // the DOFs and the pinned shifts projected out, over the links at least
  // `min_pixels` pixels show, its noise variance noise_var times the
  // shifts' residual variance c. Per shift link (shift_links() order); NaN
  // where not fitted, or where the fit's noise standard deviation is over
  // kMaxScaleNoise (the image hardly tells its size). One image's fit is
  // noisy and its noise unbiased: a caller averages over images
  // (ReportedCovariance, the health's LinkModelError::scale).
  struct LinkScaleFit {
    double scale = std::numeric_limits<double>::quiet_NaN();      // s, a fraction
    double noise_var = std::numeric_limits<double>::quiet_NaN();  // of s
  };
  static constexpr double kMaxScaleNoise = 0.05;
  // The camera's pose in each link with geometry's frame (index as
  // shift_links()) at the last compute()'s configuration: a shift of link k
  // along its own axis a is T_link_camera()[k].linear().row(a) in camera
  // axes.
  const std::vector<Eigen::Isometry3d>& T_link_camera() const { return T_link_camera_; }

  // Rigid fits (the end-effector fit, end_effector_fit.h): for each link
  // given to set_rigid_fit_links() (links with geometry), the normal
  // equations of a small rigid motion of that link and every link below it
  // (a hand with its fingers): a translation t and a rotation w about the
  // link's origin o, in camera axes. A pixel's surface point X then moves
  // by t + w x (X - o) and its rendered depth by j . (t + w x (X - o)) (j
  // the link-shift vector above, from the slopes), so its row is
  // g = (j, (X - o) x j) / sigma; over the used pixels of those links,
  // information G^T G and gradient G^T u (u the normalised residuals): the
  // fit is information^-1 gradient, in m and rad, its noise covariance
  // information^-1 when the pixels' noise is the likelihood's. Computed by
  // compute() whether or not params.link_shifts is on.
  // A link of the subtree whose shape is s larger than its model's about
  // its own origin o_l (LinkScaleFit, below) moves its pixels' depth by
  // s h, h = j . (X - o_l): the fit then moves by s information^-1 G^T h,
  // an error a rigid motion cannot take up (a hand 4% bigger, fitted, sits
  // 2 mm off). Per subtree link, G^T h is a column of scale_cross, the
  // link's index as shift_links()'s in scale_links (sized at the first
  // compute(), then kept).
  struct RigidFit {
    Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> gradient = Eigen::Matrix<double, 6, 1>::Zero();
    Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();  // o, camera axes, at q
    int pixels = 0;
    std::vector<int> scale_links;
    Eigen::Matrix<double, 6, Eigen::Dynamic> scale_cross;
  };
  // `links`: model link indices, each with geometry (InputError otherwise);
  // repeats allowed. Before the first compute().
  void set_rigid_fit_links(const RobotModel& model, std::vector<int> links);
  // The last compute()'s, in set_rigid_fit_links() order.
  const std::vector<RigidFit>& rigid_fits() const { return rigid_fits_; }

 private:
  struct Worker;  // one worker's renderer and scratch images
  std::vector<int> dofs_;
  ImageInformationParams params_;
  KinematicsState kinematics_;
  Eigen::VectorXd q_;
  DepthImage base_;
  // Per worker, and which DOF columns each renders (balanced by the
  // triangles they draw); made for one model and camera.
  std::vector<std::unique_ptr<Worker>> workers_;
  std::vector<std::vector<int>> worker_columns_;
  const RobotModel* workers_model_ = nullptr;
  CameraIntrinsics workers_camera_;
  std::vector<LinkSet> column_links_;   // per column: the links its DOF moves in the image
  std::vector<bool> column_moves_all_;  // per column: every link (the DOF moves the camera)
  // Each link with geometry drawn alone at q (index as shift_links_), and
  // the rectangle it covers.
  std::vector<DepthImage> link_depth_;
  std::vector<PixelRect> link_rect_;
  Eigen::MatrixXf gradients_;  // pixel x DOF: d r / d q_dof / sigma (0 where unused)
  std::vector<char> used_;     // per pixel
  Eigen::VectorXf residuals_;  // per pixel: (z - r) / sigma (0 where unused)
  Eigen::MatrixXd information_, field_information_;
  Eigen::MatrixXf product_f_;         // a float product before its cast to double
  Eigen::VectorXf product_vector_f_;  // the same for a vector
  Eigen::MatrixXf field_gradients_;   // pixel x DOF, motion field (params.motion_field)
  Eigen::VectorXd field_pixel_gradient_;
  Eigen::VectorXd gradient_;
  // motion_field_gradient()'s workspace: its float product and the result.
  mutable Eigen::VectorXf field_product_f_;
  mutable Eigen::VectorXd field_gradient_;
  int pixels_used_ = 0;
  std::vector<int> pixels_per_dof_;
  double effective_pixel_fraction_ = 1;
  double fitted_residual_factor_ = 1;
  // fitted_residual_factor()'s fit: (G^T G, ridged) factored, the fit and
  // the residuals left (per pixel, 0 where unused).
  Eigen::LDLT<Eigen::MatrixXd> residual_fit_factor_;
  Eigen::MatrixXd residual_fit_information_;
  Eigen::VectorXd residual_fit_gradient_, residual_fit_;
  Eigen::VectorXf residual_fit_f_, fitted_residuals_;
  // Link shifts.
  std::vector<int> shift_links_;
  std::vector<std::vector<bool>> shift_link_sets_;  // per shift link: it alone
  std::vector<std::vector<int>> shift_above_;       // per shift link: it and those above it
  std::vector<char> shift_merged_;  // per shift link: merged into a child (workspace)
  std::vector<int> label_;          // per pixel: shift link index, -1 none
  std::vector<int> shift_pixels_;   // per shift link: used pixels
  Eigen::MatrixXd shift_cross_, shift_information_, field_shift_cross_;
  // Link scales, per shift link (its own pixels): G_dof^T g (dofs x links),
  // g^T G_shift (links x 3 links), g^T g and g^T u, g = j . (X - o) / sigma.
  Eigen::MatrixXd scale_cross_, scale_shift_cross_;
  Eigen::VectorXd scale_information_, scale_gradient_;
  // Link bulges, per shift link (its own pixels), as the scales' with
  // g = -|j| / sigma; the motion field's DOF columns too.
  Eigen::MatrixXd bulge_cross_, field_bulge_cross_, bulge_shift_cross_;
  Eigen::VectorXd bulge_information_, bulge_gradient_;
  std::vector<int> bulge_pixels_;
  Eigen::VectorXd shift_gradient_, pixel_gradient_;
  Eigen::VectorXf depth_scale_pixels_;  // per pixel: r / sigma (0 where unused)
  Eigen::VectorXd depth_scale_cross_;
  double residual_sum_sq_ = 0;  // of the used pixels' residuals u
  // Rigid fits: per fit its link's shift_links_ index; per shift link
  // (label), the fits whose subtree it belongs to, and its column in each
  // one's scale_cross.
  std::vector<int> rigid_fit_shift_;
  std::vector<std::vector<int>> rigid_fits_of_label_, rigid_scale_column_of_label_;
  std::vector<RigidFit> rigid_fits_;
  void compute_rigid_fits(const CameraIntrinsics& camera, const DepthLikelihood& likelihood);

  void prepare_workers(DepthRenderer& renderer, int num_workers);
  void render_labelled(WorkerPool* pool);
  void difference_column(int k, const DepthLikelihood& likelihood, Worker& w);
  void motion_field_gradients(const RobotModel& model, const CameraIntrinsics& camera,
                              const DepthLikelihood& likelihood, WorkerPool* pool);
  // The rendered surface point at pixel p (the base render's depth along
  // the pixel centre's ray), camera axes.
  Eigen::Vector3d rendered_point(int p, const CameraIntrinsics& camera) const;
  // `curved`, when given, is set when the surface normal came from a round
  // shape or a curved mesh triangle.
  Eigen::Vector3d depth_slope_vector(int p, const CameraIntrinsics& camera, double sigma,
                                     bool surface_normals, bool* curved = nullptr) const;
  // Per pixel: on a round shape or a curved mesh triangle (with
  // params.motion_field, from motion_field_gradients(); else looked up).
  std::vector<char> curved_;
  bool on_curved_surface(int p, int shift, const CameraIntrinsics& camera) const;
  // Every link's round shapes (RoundShape) seen from the camera at q
  // (place_surfaces(), per compute()): the link's are
  // [first_round_shape_[l], first_round_shape_[l + 1]) (prepare_workers(),
  // with shift_links_, from the model).
  std::vector<int> first_round_shape_;
  std::vector<Eigen::Isometry3d> T_shape_camera_;
  // Every link with geometry's mesh as the smooth surface it approximates
  // (index as shift_links_; prepare_workers(), from the model), and the
  // camera's pose in each such link's frame at q (place_surfaces()).
  std::vector<SurfaceNormals> surface_normals_;
  std::vector<Eigen::Isometry3d> T_link_camera_;
  std::vector<Eigen::Vector3d> link_origin_camera_;  // o per shift link, camera axes, at q
  void place_surfaces(const RobotModel& model);
  // The unit normal, in camera axes, of the round shape of `link` that
  // camera-frame point X lies on, at q; false when on none.
  // (surface_normal(): the same for the link's mesh, `shift` its index in
  // shift_links_.)
  bool surface_normal(int shift, const Eigen::Vector3d& X_camera, Eigen::Vector3d& n_camera) const;
  bool round_surface_normal(int link, const Eigen::Vector3d& X_camera,
                            Eigen::Vector3d& n_camera) const;
  // Either: the normal of a round shape or of a curved mesh triangle of
  // shift link `shift` at X.
  bool curved_surface_normal(int shift, const Eigen::Vector3d& X_camera,
                             Eigen::Vector3d& n_camera) const;
  // Calls f(pixel, labelled link index, j / sigma) for every used pixel of
  // the labelled render (j: depth_slope_vector), in [begin, end) (row-major
  // pixel indices; end -1: the whole image); `curved`, when given, per
  // pixel: whether j came from a curved surface's normal.
  template <class F>
  void for_each_labelled_pixel(const CameraIntrinsics& camera, const DepthLikelihood& likelihood,
                               bool surface_normals, F&& f, int begin = 0, int end = -1,
                               char* curved = nullptr) const {
    if (end < 0) end = camera.width * camera.height;
    for (int p = begin; p < end; ++p) {
      if (!used_[std::size_t(p)] || label_[std::size_t(p)] < 0) continue;
      const double sigma = likelihood.noise_std_at_m(likelihood.observed_depth_m(p));
      bool on_curve = false;
      const Eigen::Vector3d j = depth_slope_vector(p, camera, sigma, surface_normals, &on_curve);
      if (curved) curved[p] = on_curve;
      f(p, label_[std::size_t(p)], Eigen::Vector3d(j / sigma));
    }
  }
  struct MotionTerm {
    int joint = 0;           // link index of the joint
    bool prismatic = false;  // else revolute
    double factor = 0;       // +-1 (moves the link / the camera) times the mimic multiplier
  };
  std::vector<std::vector<MotionTerm>> motion_terms_;       // per column x labelled link
  std::vector<Eigen::Vector3d> joint_axis_, joint_origin_;  // per link, camera axes
  void compute_link_shifts(const CameraIntrinsics& camera, const DepthLikelihood& likelihood);
  // After compute_link_shifts(): zeroes the columns of the shifts that move
  // the same pixels as a child's (shift_links() above).
  void merge_identical_shifts();
  // The shifts' normal equations with a nuisance projected out: the DOFs
  // and the bulges of `bulges` (shift_links_ indices; the caller picks the
  // links with min_pixels curved pixels), over the shift columns of the
  // links at least min_pixels pixels show (columns). The
  // nuisance's information (ridged) and gradient, its cross information
  // with the shifts C, A and b (before A's ridge), A's factor (ridged),
  // the shifts' fit and the residuals' variance left, c (noise_var).
  // False when no shift is shown or A is indefinite.
  struct ShiftProjection {
    std::vector<int> columns, bulges;
    Eigen::MatrixXd nuisance_information;
    Eigen::VectorXd nuisance_gradient;
    Eigen::LDLT<Eigen::MatrixXd> nuisance;
    Eigen::MatrixXd C, A;
    Eigen::VectorXd b;
    Eigen::LDLT<Eigen::MatrixXd> shifts;
    Eigen::VectorXd estimate;
    double noise_var = 1;
    // Scratch: the solves and products subtracted from A and b, A ridged.
    Eigen::MatrixXd solved_C, product, ridged;
    Eigen::VectorXd solved_gradient, product_vector;
  };
  bool project_shifts(int min_pixels, std::span<const int> bulges, ShiftProjection& out) const;
  // The model-error fits' matrices (link_shift_variance_m2() and the
  // functions it calls), kept between images: an image that shows the
  // same links as the last resizes nothing, so its fits allocate nothing
  // (they run per image on the image thread).
  struct FitWorkspace {
    ShiftProjection shifts_alone, with_bulges;  // the DOFs projected out; and the bulges
    std::vector<int> bulges, scale_links, scales_kept;
    Eigen::MatrixXd shift_noise;  // A^-1 of the shifts' fit
    // fit_link_bulges(): the whole normal equations, their factor and fit.
    Eigen::MatrixXd whole;
    Eigen::VectorXd whole_gradient, whole_fit, unit, unit_solved;
    Eigen::LDLT<Eigen::MatrixXd> whole_factor;
    // fit_link_scales(): the scales' cross terms, normal equations, their
    // solves and products, and fit.
    Eigen::MatrixXd scale_dofs, scale_shifts, scales, scale_noise, scales_kept_ridged;
    Eigen::MatrixXd dofs_solved, shifts_solved, scale_shift_product, scale_product;
    Eigen::VectorXd scale_gradient, scale_gradient_kept, scale_fit;
    Eigen::VectorXd dofs_solved_gradient, shifts_solved_gradient, scale_product_vector;
    Eigen::LDLT<Eigen::MatrixXd> scale_factor;
  };
  mutable FitWorkspace fit_workspace_;
  // link_shift_variance_m2()'s bulges: each fitted with the DOFs and the
  // shifts beside it, from `fit` (project_shifts with bulges).
  void fit_link_bulges(const ShiftProjection& fit, std::vector<double>& bulge_square_m2) const;
  // link_shift_variance_m2()'s scales: `dofs` the DOFs' information,
  // `columns` the fit's shift columns, `shift_cross` their cross
  // information with the DOFs, `shifts` and `shift_b` their normal
  // equations with the DOFs projected out, `noise_var` c.
  void fit_link_scales(const Eigen::LDLT<Eigen::MatrixXd>& dofs, const std::vector<int>& columns,
                       const Eigen::MatrixXd& shift_cross,
                       const Eigen::LDLT<Eigen::MatrixXd>& shifts, const Eigen::VectorXd& shift_b,
                       double noise_var, int min_pixels, std::vector<LinkScaleFit>& scales) const;
  void estimate_effective_pixel_fraction(int width);
  void estimate_fitted_residual_factor(int width);
  // The correlation of the used pixels' values in `r` `step` apart (1: the
  // next column, width: the next row), about 0 (not the mean: a shared
  // offset is the correlated part), clamped to [0, 0.99].
  double neighbour_correlation(const Eigen::VectorXf& r, int step, int width) const;
  // The fraction of the used pixels of `r` that count as independent
  // samples, from its neighbour correlations along rows and columns:
  // (1 - rho_x) / (1 + rho_x) * (1 - rho_y) / (1 + rho_y) (AR(1) in each
  // direction).
  double independent_sample_fraction(const Eigen::VectorXf& r, int width) const;
};

}  // namespace arttrack
