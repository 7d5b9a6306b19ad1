#include "arttrack/tracker/internal/image_information.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/surface_normals.h"
#include "arttrack/tracker/internal/worker_pool.h"

namespace arttrack {
namespace {

// A shift counts in the model-error estimate when one image pins it to
// within 3 mm (standard deviation).
constexpr double kMaxShiftNoiseVar_m2 = 0.003 * 0.003;
// A mesh's smooth surface (surface_normals.h): corners whose triangles turn
// by more than this stay apart (a box's edges); the drawn surface (a
// coarser level, up to 4 times the simplifier's bound of a few tenths of a
// pixel, within a few millimetres of the model's mesh) is looked up this far.
constexpr double kSurfaceCreaseAngleRad = 40 * std::numbers::pi / 180;
constexpr double kSurfaceNormalReachM = 0.006;

}  // namespace

ImageInformation::ImageInformation(std::vector<int> dofs, const ImageInformationParams& params)
    : dofs_(std::move(dofs)), params_(params) {
  if (!(params_.revolute_step_rad > 0) || !(params_.prismatic_step_m > 0) ||
      !(params_.inlier_sigmas > 0))
    throw InputError("image information: steps and inlier_sigmas must be > 0");
}

// One worker's renderer (null for worker 0: the caller's) and scratch.
struct ImageInformation::Worker {
  std::unique_ptr<DepthRenderer> own_renderer;
  DepthRenderer* renderer = nullptr;
  KinematicsState kinematics;
  Eigen::VectorXd q;
  DepthImage statics, plus, minus;
  std::vector<char> failed;  // per pixel: a DOF of this worker's saw an edge there
};

ImageInformation::~ImageInformation() = default;

const Eigen::MatrixXd& ImageInformation::compute(DepthRenderer& renderer, std::span<const double> q,
                                                 const DepthLikelihood& likelihood,
                                                 WorkerPool* pool) {
  const RobotModel& model = renderer.model();
  if (int(q.size()) != model.num_joints())
    throw InputError("image information: configuration has " + std::to_string(q.size()) +
                     " values, the model " + std::to_string(model.num_joints()) + " DOFs");
  if (renderer.camera().width != likelihood.width() ||
      renderer.camera().height != likelihood.height())
    throw InputError("image information: the renderer's camera and the likelihood differ in size");
  const int num_pixels = likelihood.width() * likelihood.height();
  const int m = int(dofs_.size());
  if (kinematics_.T_root_link.empty()) kinematics_ = KinematicsState(model);
  q_ = Eigen::Map<const Eigen::VectorXd>(q.data(), Eigen::Index(q.size()));
  gradients_.setZero(num_pixels, m);
  used_.assign(std::size_t(num_pixels), 0);
  curved_.assign(std::size_t(num_pixels), 0);
  residuals_.setZero(num_pixels);
  prepare_workers(renderer, pool ? pool->num_workers() : 1);
  for (auto& w : workers_) {
    w->q = q_;
    std::fill(w->failed.begin(), w->failed.end(), 0);
  }

  forward_kinematics(model, q_, kinematics_);
  place_surfaces(model);
  render_labelled(pool);
  // Pixels the robot at q covers and the image explains.
  for (int p = 0; p < num_pixels; ++p) {
    const double r = base_.depth_m[std::size_t(p)];
    const double z = likelihood.observed_depth_m(p);
    if (r > 0 && z > 0 && std::abs(z - r) < params_.inlier_sigmas * likelihood.noise_std_at_m(z))
      used_[std::size_t(p)] = 1;
  }
  // Each column on its worker; a pixel where any DOF sees an edge is left out.
  auto columns = [&](int begin, int end, int worker) {
    for (int w = begin; w < end; ++w)
      for (int k : worker_columns_[std::size_t(w)])
        difference_column(k, likelihood, *workers_[std::size_t(worker)]);
  };
  if (pool) {
    pool->parallel_for(int(workers_.size()), columns);
  } else {
    columns(0, 1, 0);
  }
  for (const auto& w : workers_)
    for (int p = 0; p < num_pixels; ++p)
      if (w->failed[std::size_t(p)]) used_[std::size_t(p)] = 0;
  pixels_used_ = 0;
  residual_sum_sq_ = 0;
  if (params_.depth_scale) depth_scale_pixels_.setZero(num_pixels);
  for (int p = 0; p < num_pixels; ++p) {
    if (used_[std::size_t(p)]) {
      ++pixels_used_;
      const double z = likelihood.observed_depth_m(p), r = base_.depth_m[std::size_t(p)];
      const double sigma = likelihood.noise_std_at_m(z);
      residuals_[p] = float((z - r) / sigma);
      residual_sum_sq_ += double(residuals_[p]) * residuals_[p];
      if (params_.depth_scale) depth_scale_pixels_[p] = float(r / sigma);  // d r / d c = r
    } else {
      gradients_.row(p).setZero();
    }
  }
  pixels_per_dof_.assign(std::size_t(m), 0);
  for (int k = 0; k < m; ++k)
    for (int p = 0; p < num_pixels; ++p) pixels_per_dof_[std::size_t(k)] += gradients_(p, k) != 0;
  // The float products into kept matrices, then to double (a cast of the
  // product would evaluate it into a temporary: the same numbers, allocated).
  product_f_.noalias() = gradients_.transpose() * gradients_;
  information_ = product_f_.cast<double>();
  product_vector_f_.noalias() = gradients_.transpose() * residuals_;
  gradient_ = product_vector_f_.cast<double>();
  if (params_.motion_field) {
    field_gradients_.setZero(num_pixels, m);
    motion_field_gradients(model, renderer.camera(), likelihood, pool);
    product_f_.noalias() = field_gradients_.transpose() * field_gradients_;
    field_information_ = product_f_.cast<double>();
  }
  if (params_.depth_scale) {
    const Eigen::MatrixXf& G = params_.motion_field ? field_gradients_ : gradients_;
    product_vector_f_.noalias() = G.transpose() * depth_scale_pixels_;
    depth_scale_cross_ = product_vector_f_.cast<double>();
  }
  estimate_effective_pixel_fraction(likelihood.width());
  if (params_.fitted_residuals) estimate_fitted_residual_factor(likelihood.width());
  if (params_.link_shifts) compute_link_shifts(renderer.camera(), likelihood);
  if (!rigid_fits_.empty()) compute_rigid_fits(renderer.camera(), likelihood);
  return information_;
}

const Eigen::VectorXd& ImageInformation::motion_field_gradient() const {
  if (!params_.motion_field) return gradient_;
  field_product_f_.noalias() = field_gradients_.transpose() * residuals_;
  field_gradient_ = field_product_f_.cast<double>();
  return field_gradient_;
}

// field_gradients_: d r / d q from the motion field (motion_field_information()
// in the header), over the pixels the central differences kept.
void ImageInformation::motion_field_gradients(const RobotModel& model,
                                              const CameraIntrinsics& camera,
                                              const DepthLikelihood& likelihood, WorkerPool* pool) {
  const int W = likelihood.width();
  const int L = int(shift_links_.size()), m = int(dofs_.size());
  if (motion_terms_.empty()) {
    // Per column and labelled link: the joints (link indices) whose motion
    // moves the link's points relative to the camera, with the sign and the
    // mimic multiplier.
    auto above = [&](int link) {
      std::vector<char> mark(std::size_t(model.num_links()), 0);
      for (int a = link; a >= 0; a = model.link(a).parent) mark[std::size_t(a)] = 1;
      return mark;
    };
    const std::vector<char> above_camera = above(model.camera_link());
    motion_terms_.assign(std::size_t(m) * L, {});
    for (int li = 0; li < L; ++li) {
      const std::vector<char> above_link = above(shift_links_[std::size_t(li)]);
      for (int k = 0; k < m; ++k) {
        const int dof = dofs_[std::size_t(k)];
        for (int j = 1; j < model.num_links(); ++j) {
          const Link& joint = model.link(j);
          const double multiplier = joint.dof == dof         ? 1.0
                                    : joint.mimic_dof == dof ? joint.mimic_multiplier
                                                             : 0.0;
          const int sign = int(above_link[std::size_t(j)]) - int(above_camera[std::size_t(j)]);
          if (multiplier != 0 && sign != 0)
            motion_terms_[std::size_t(k) * L + li].push_back(
                {j, joint.joint_type == JointType::kPrismatic, sign * multiplier});
        }
      }
    }
  }
  // Joint axes and origins in camera axes.
  const Eigen::Isometry3d& T_root_camera =
      kinematics_.T_root_link[std::size_t(model.camera_link())];
  const Eigen::Matrix3d R_camera_root = T_root_camera.linear().transpose();
  joint_axis_.resize(std::size_t(model.num_links()));
  joint_origin_.resize(std::size_t(model.num_links()));
  for (int j = 1; j < model.num_links(); ++j) {
    const Eigen::Isometry3d& T = kinematics_.T_root_link[std::size_t(j)];
    joint_axis_[std::size_t(j)] = R_camera_root * (T.linear() * model.link(j).axis);
    joint_origin_[std::size_t(j)] = R_camera_root * (T.translation() - T_root_camera.translation());
  }
  // Each pixel on its own (its row of field_gradients_ only), rows of the
  // image spread over the pool's workers: the same numbers on any count.
  auto pixel = [&](int p, int li, const Eigen::Vector3d& j) {
    const Eigen::Vector3d X = rendered_point(p, camera);
    for (int k = 0; k < m; ++k) {
      double g = 0;
      for (const MotionTerm& t : motion_terms_[std::size_t(k) * L + li]) {
        const Eigen::Vector3d& a = joint_axis_[std::size_t(t.joint)];
        const Eigen::Vector3d dX =
            t.prismatic ? a : Eigen::Vector3d(a.cross(X - joint_origin_[std::size_t(t.joint)]));
        g += t.factor * j.dot(dX);
      }
      field_gradients_(p, k) = float(g);
    }
  };
  auto rows = [&](int v0, int v1, int) {
    for_each_labelled_pixel(camera, likelihood, true, pixel, v0 * W, v1 * W, curved_.data());
  };
  if (pool)
    pool->parallel_for(camera.height, rows, 4);
  else
    rows(0, camera.height, 0);
}

Eigen::Vector3d ImageInformation::rendered_point(int p, const CameraIntrinsics& camera) const {
  const double r = base_.depth_m[std::size_t(p)];
  const int u = p % camera.width, v = p / camera.width;
  return {r * (u + 0.5 - camera.cx) / camera.fx, r * (v + 0.5 - camera.cy) / camera.fy, r};
}

// j = d r / d t at pixel p of the labelled render (link shifts, in the
// header): (-fx r_u / r, -fy r_v / r, 1 + (x fx r_u + y fy r_v) / r), the
// slopes between neighbours that show the same surface of the same link.
Eigen::Vector3d ImageInformation::depth_slope_vector(int p, const CameraIntrinsics& camera,
                                                     double sigma, bool surface_normals,
                                                     bool* curved) const {
  const int W = camera.width, H = camera.height;
  const int l = label_[std::size_t(p)];
  const int u = p % W, v = p / W;
  const double r = base_.depth_m[std::size_t(p)];
  // A neighbour's depth when it shows the same surface: the same link, and
  // no jump (a surface up to 76 degrees from facing the camera changes by
  // at most 4 pixel footprints r / f between neighbours).
  const double max_step_m = 4 * r / std::min(camera.fx, camera.fy) + params_.inlier_sigmas * sigma;
  auto neighbour = [&](int uu, int vv, double& d) {
    if (uu < 0 || uu >= W || vv < 0 || vv >= H) return false;
    const std::size_t i = std::size_t(vv) * W + uu;
    if (label_[i] != l) return false;
    d = base_.depth_m[i];
    return std::abs(d - r) < max_step_m;
  };
  auto slope = [&](int du, int dv) {
    double next = 0, prev = 0;
    const bool has_next = neighbour(u + du, v + dv, next);
    const bool has_prev = neighbour(u - du, v - dv, prev);
    if (has_next && has_prev) return 0.5 * (next - prev);
    if (has_next) return next - r;
    if (has_prev) return r - prev;
    return 0.0;
  };
  const double x = (u + 0.5 - camera.cx) / camera.fx, y = (v + 0.5 - camera.cy) / camera.fy;
  // With surface_normals, the surface's own normal n: a plane through the
  // point moved by dX moves the depth along the ray (x, y, 1) by n . dX /
  // n . (x, y, 1). On a cylinder or sphere (drawn exactly) n is exact; on a
  // mesh it is the smooth surface's the mesh stands for (surface_normals.h).
  // Slopes between neighbours are chords of the curve, and a shape turned
  // about its own axis then seemed to move (arm7's round base, and the
  // sculpted arm7's mesh base: the camera turned about it with joint 1
  // turned back). Beyond 76 degrees from facing the camera (the slopes'
  // bound) the pixel says nothing: there the first order holds for a sliver
  // of a pixel, and only the pixels whose depth stayed within the inlier
  // band were kept.
  const Eigen::Vector3d ray(x, y, 1);
  Eigen::Vector3d n;
  if (surface_normals && curved_surface_normal(l, r * ray, n)) {
    if (curved) *curved = true;
    const double facing = n.dot(ray);
    return std::abs(facing) > 0.25 * ray.norm() ? Eigen::Vector3d(n / facing)
                                                : Eigen::Vector3d::Zero();
  }
  const double r_u = slope(1, 0), r_v = slope(0, 1);
  return Eigen::Vector3d(-camera.fx * r_u / r, -camera.fy * r_v / r,
                         1 + (x * camera.fx * r_u + y * camera.fy * r_v) / r);
}

void ImageInformation::place_surfaces(const RobotModel& model) {
  const Eigen::Isometry3d T_camera_root =
      kinematics_.T_root_link[std::size_t(model.camera_link())].inverse();
  for (std::size_t k = 0; k < shift_links_.size(); ++k) {
    T_link_camera_[k] =
        (T_camera_root * kinematics_.T_root_link[std::size_t(shift_links_[k])]).inverse();
    link_origin_camera_[k] = T_link_camera_[k].inverse().translation();
  }
  for (int l = 0; l < model.num_links(); ++l) {
    int i = first_round_shape_[std::size_t(l)];
    for (const RoundShape& s : model.link(l).round_shapes)
      T_shape_camera_[std::size_t(i++)] =
          (T_camera_root * kinematics_.T_root_link[std::size_t(l)] * s.T_link_shape).inverse();
  }
}

bool ImageInformation::curved_surface_normal(int shift, const Eigen::Vector3d& X_camera,
                                             Eigen::Vector3d& n_camera) const {
  return round_surface_normal(shift_links_[std::size_t(shift)], X_camera, n_camera) ||
         surface_normal(shift, X_camera, n_camera);
}

bool ImageInformation::on_curved_surface(int p, int shift, const CameraIntrinsics& camera) const {
  if (params_.motion_field) return curved_[std::size_t(p)];  // motion_field_gradients() found it
  Eigen::Vector3d n;
  return curved_surface_normal(shift, rendered_point(p, camera), n);
}

bool ImageInformation::surface_normal(int shift, const Eigen::Vector3d& X_camera,
                                      Eigen::Vector3d& n_camera) const {
  const SurfaceNormals& surface = surface_normals_[std::size_t(shift)];
  const Eigen::Isometry3d& T_link_camera = T_link_camera_[std::size_t(shift)];
  Eigen::Vector3d n_link;
  if (!surface.normal_at(T_link_camera * X_camera, n_link)) return false;
  n_camera = T_link_camera.linear().transpose() * n_link;
  return true;
}

bool ImageInformation::round_surface_normal(int link, const Eigen::Vector3d& X_camera,
                                            Eigen::Vector3d& n_camera) const {
  const std::vector<RoundShape>& shapes = workers_model_->link(link).round_shapes;
  // The rendered depth is a float: the point lies on the surface to a few
  // micrometres.
  const double tolerance_m = 2e-5 + 2e-6 * X_camera.z();
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const RoundShape& s = shapes[k];
    const Eigen::Isometry3d& T_shape_camera =
        T_shape_camera_[std::size_t(first_round_shape_[std::size_t(link)]) + k];
    const Eigen::Vector3d P = T_shape_camera * X_camera;
    // Squared distances against the band [radius - tolerance, radius +
    // tolerance]: no square root for the many pixels on no shape.
    const double inner = std::max(0.0, s.radius_m - tolerance_m), outer = s.radius_m + tolerance_m;
    Eigen::Vector3d n_shape;
    if (s.kind == RoundShape::Kind::kSphere) {
      const double d2 = P.squaredNorm();
      if (d2 < inner * inner || d2 > outer * outer) continue;
      n_shape = P;
    } else {
      const double radial2 = P.x() * P.x() + P.y() * P.y(), half = 0.5 * s.length_m;
      if (radial2 >= inner * inner && radial2 <= outer * outer &&
          std::abs(P.z()) <= half + tolerance_m)
        n_shape = Eigen::Vector3d(P.x(), P.y(), 0);
      else if (std::abs(std::abs(P.z()) - half) <= tolerance_m && radial2 <= outer * outer)
        n_shape = Eigen::Vector3d(0, 0, P.z());
      else
        continue;
    }
    if (n_shape.squaredNorm() == 0) continue;
    n_camera = T_shape_camera.linear().transpose() * n_shape.normalized();
    return true;
  }
  return false;
}

// Worker renderers and the DOFs' columns split between them, for the
// renderer's model and camera.
void ImageInformation::prepare_workers(DepthRenderer& renderer, int num_workers) {
  const RobotModel& model = renderer.model();
  const CameraIntrinsics& camera = renderer.camera();
  const int W = camera.width, H = camera.height;
  if (shift_links_.empty()) {
    shift_links_ = model.links_with_geometry();
    std::vector<int> index(std::size_t(model.num_links()), -1);
    for (int k = 0; k < int(shift_links_.size()); ++k) index[std::size_t(shift_links_[k])] = k;
    for (int l : shift_links_) {
      shift_link_sets_.emplace_back(std::size_t(model.num_links()), false);
      shift_link_sets_.back()[std::size_t(l)] = true;
      shift_above_.emplace_back();
      for (int a = l; a >= 0; a = model.link(a).parent)
        if (index[std::size_t(a)] >= 0) shift_above_.back().push_back(index[std::size_t(a)]);
    }
    shift_merged_.assign(shift_links_.size(), 0);
    first_round_shape_.assign(std::size_t(model.num_links()) + 1, 0);
    for (int l = 0; l < model.num_links(); ++l)
      first_round_shape_[std::size_t(l) + 1] =
          first_round_shape_[std::size_t(l)] + int(model.link(l).round_shapes.size());
    T_shape_camera_.resize(std::size_t(first_round_shape_.back()));
    T_link_camera_.resize(shift_links_.size());
    link_origin_camera_.resize(shift_links_.size());
    surface_normals_.clear();
    for (int l : shift_links_)
      surface_normals_.emplace_back(model.link(l).mesh, model.link(l).round_shapes,
                                    kSurfaceCreaseAngleRad, kSurfaceNormalReachM);
  }
  if (workers_model_ == &model && workers_camera_ == camera &&
      int(workers_.size()) == num_workers) {
    workers_[0]->renderer = &renderer;
    return;
  }
  workers_model_ = &model;
  workers_camera_ = camera;
  base_ = DepthImage(W, H);
  link_depth_.assign(shift_links_.size(), DepthImage(W, H));
  link_rect_.assign(shift_links_.size(), PixelRect{});
  label_.assign(std::size_t(W) * H, -1);
  workers_.clear();
  for (int w = 0; w < num_workers; ++w) {
    auto worker = std::make_unique<Worker>();
    if (w > 0)  // a copy of the caller's: its clusters are not built again
      worker->own_renderer = std::make_unique<DepthRenderer>(renderer);
    worker->renderer = w > 0 ? worker->own_renderer.get() : &renderer;
    worker->kinematics = KinematicsState(model);
    worker->statics = worker->plus = worker->minus = DepthImage(W, H);
    worker->failed.assign(std::size_t(W) * H, 0);
    workers_.push_back(std::move(worker));
  }
  // What each column renders, and its cost in triangles: the largest first
  // to the least loaded worker.
  const int m = int(dofs_.size());
  column_links_.assign(std::size_t(m), {});
  column_moves_all_.assign(std::size_t(m), false);
  std::vector<std::pair<long long, int>> cost(static_cast<std::size_t>(m));
  for (int k = 0; k < m; ++k) {
    const int dof = dofs_[std::size_t(k)];
    column_links_[std::size_t(k)] = links_affecting_depth(model, {dof});
    column_moves_all_[std::size_t(k)] = model.links_moved_by(dof)[std::size_t(model.camera_link())];
    long long triangles = 0;
    for (int l : shift_links_)
      if (column_links_[std::size_t(k)][std::size_t(l)])
        triangles += 1 + (long long)model.link(l).mesh.triangles.size();
    cost[std::size_t(k)] = {triangles, k};
  }
  std::sort(cost.begin(), cost.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  worker_columns_.assign(std::size_t(num_workers), {});
  std::vector<long long> load(std::size_t(num_workers), 0);
  for (const auto& [triangles, k] : cost) {
    const auto least = std::min_element(load.begin(), load.end()) - load.begin();
    worker_columns_[std::size_t(least)].push_back(k);
    load[std::size_t(least)] += triangles;
  }
}

// Each link alone at q (link_depth_, link_rect_), on the workers in turn;
// base_ as the nearest of them (the same depths as drawing them together),
// and which link each pixel shows.
void ImageInformation::render_labelled(WorkerPool* pool) {
  const int L = int(shift_links_.size());
  const int W = base_.width;
  auto draw = [&](int begin, int end, int worker) {
    Worker& w = *workers_[std::size_t(worker)];
    for (int k = begin; k < end; ++k) {
      DepthImage& image = link_depth_[std::size_t(k)];
      const PixelRect old = link_rect_[std::size_t(k)];
      for (int v = old.v0; v < old.v1; ++v)
        std::fill_n(image.depth_m.data() + std::size_t(v) * W + old.u0, old.width(), 0.f);
      link_rect_[std::size_t(k)] =
          w.renderer->draw_links(kinematics_, shift_link_sets_[std::size_t(k)], image);
    }
  };
  if (pool) {
    pool->parallel_for(L, draw);
  } else {
    draw(0, L, 0);
  }
  std::fill(base_.depth_m.begin(), base_.depth_m.end(), 0.f);
  std::fill(label_.begin(), label_.end(), -1);
  for (int k = 0; k < L; ++k) {
    const PixelRect& rect = link_rect_[std::size_t(k)];
    const DepthImage& single = link_depth_[std::size_t(k)];
    for (int v = rect.v0; v < rect.v1; ++v) {
      for (int u = rect.u0; u < rect.u1; ++u) {
        const std::size_t i = std::size_t(v) * W + u;
        const float d = single.depth_m[i];
        if (d > 0.f && (base_.depth_m[i] == 0.f || d < base_.depth_m[i])) {
          base_.depth_m[i] = d;
          label_[i] = k;
        }
      }
    }
  }
}

// Column k of gradients_ by central differences: the DOF's links drawn at
// q +- h over the other links' images at q (or everything, when it moves
// the camera). Pixels where a step leaves the silhouette or jumps between
// surfaces are marked in w.failed.
void ImageInformation::difference_column(int k, const DepthLikelihood& likelihood, Worker& w) {
  const RobotModel& model = w.renderer->model();
  const int dof = dofs_[std::size_t(k)];
  const int W = base_.width;
  const int num_pixels = W * base_.height;
  const LinkSet& moving = column_links_[std::size_t(k)];
  if (!column_moves_all_[std::size_t(k)]) {
    std::fill(w.statics.depth_m.begin(), w.statics.depth_m.end(), 0.f);
    for (int l = 0; l < int(shift_links_.size()); ++l)
      if (!moving[std::size_t(shift_links_[std::size_t(l)])])
        merge_nearer(link_depth_[std::size_t(l)], link_rect_[std::size_t(l)], w.statics);
  }
  auto render_at = [&](double value, DepthImage& out) {
    w.q[dof] = value;
    forward_kinematics(model, w.q, w.kinematics);
    if (column_moves_all_[std::size_t(k)]) {
      w.renderer->render(w.kinematics, out);
    } else {
      std::copy(w.statics.depth_m.begin(), w.statics.depth_m.end(), out.depth_m.begin());
      w.renderer->draw_links(w.kinematics, moving, out);
    }
  };
  const double h = model.joint_type(dof) == JointType::kPrismatic ? params_.prismatic_step_m
                                                                  : params_.revolute_step_rad;
  const double q0 = q_[dof];
  render_at(q0 + h, w.plus);
  render_at(q0 - h, w.minus);
  w.q[dof] = q0;
  for (int p = 0; p < num_pixels; ++p) {
    if (!used_[std::size_t(p)]) continue;
    const float rp = w.plus.depth_m[std::size_t(p)], rm = w.minus.depth_m[std::size_t(p)];
    if (!(rp > 0 && rm > 0)) {  // on the silhouette: not differentiable here
      w.failed[std::size_t(p)] = 1;
      continue;
    }
    // A jump between surfaces (one link in front of another) is an edge too.
    const double r0 = base_.depth_m[std::size_t(p)];
    const double sigma = likelihood.noise_std_at_m(likelihood.observed_depth_m(p));
    if (std::abs(rp - r0) > params_.inlier_sigmas * sigma ||
        std::abs(rm - r0) > params_.inlier_sigmas * sigma) {
      w.failed[std::size_t(p)] = 1;
      continue;
    }
    gradients_(p, k) = float((rp - rm) / (2 * h) / sigma);
  }
}

void ImageInformation::compute_link_shifts(const CameraIntrinsics& camera,
                                           const DepthLikelihood& likelihood) {
  const int n = int(dofs_.size()), L = int(shift_links_.size());
  shift_cross_.setZero(n, 3 * L);
  field_shift_cross_.setZero(n, 3 * L);
  shift_information_.setZero(3 * L, 3 * L);
  shift_gradient_.setZero(3 * L);
  shift_pixels_.assign(std::size_t(L), 0);
  scale_cross_.setZero(n, L);
  scale_shift_cross_.setZero(L, 3 * L);
  scale_information_.setZero(L);
  scale_gradient_.setZero(L);
  bulge_cross_.setZero(n, L);
  field_bulge_cross_.setZero(n, L);
  bulge_shift_cross_.setZero(L, 3 * L);
  bulge_information_.setZero(L);
  bulge_gradient_.setZero(L);
  bulge_pixels_.assign(std::size_t(L), 0);
  // The slopes, not the surfaces' normals: with the round shapes' normals the link
  // shifts' variance (link_shift_variance_m2) fell to nothing on the
  // realistic dual arm (1.8 mm -> 0.2 mm in 8 s, realistic/both.yaml, stop
  // 44; why is not understood), and the covariance with it.
  for_each_labelled_pixel(camera, likelihood, false, [&](int p, int l, const Eigen::Vector3d& j) {
    // The pixel moves with the shift of its link and of every link above it.
    const Eigen::Matrix3d jj = j * j.transpose();
    pixel_gradient_ = gradients_.row(p).transpose().cast<double>();  // sized once: no allocation
    if (params_.motion_field)
      field_pixel_gradient_ = field_gradients_.row(p).transpose().cast<double>();
    for (int a : shift_above_[std::size_t(l)]) {
      shift_cross_.middleCols<3>(3 * a).noalias() += pixel_gradient_ * j.transpose();
      if (params_.motion_field)
        field_shift_cross_.middleCols<3>(3 * a).noalias() += field_pixel_gradient_ * j.transpose();
      shift_gradient_.segment<3>(3 * a) += double(residuals_[p]) * j;
      ++shift_pixels_[std::size_t(a)];
      for (int b : shift_above_[std::size_t(l)]) shift_information_.block<3, 3>(3 * a, 3 * b) += jj;
    }
    // The link's own scale: its surface point moves by s (X - o).
    const double g = j.dot(rendered_point(p, camera) - link_origin_camera_[std::size_t(l)]);
    scale_cross_.col(l).noalias() += pixel_gradient_ * g;
    scale_information_[l] += g * g;
    scale_gradient_[l] += double(residuals_[p]) * g;
    for (int a : shift_above_[std::size_t(l)])
      scale_shift_cross_.block<1, 3>(l, 3 * a) += g * j.transpose();
    // The link's own bulge, on its curved surfaces (a flat face's bulge is
    // a shift of it): j lies along the surface's normal, and a surface
    // moved out by d meets the ray d |j| nearer.
    if (!on_curved_surface(p, l, camera)) return;
    const double bulge = -j.norm();
    if (bulge == 0) return;
    bulge_cross_.col(l).noalias() += pixel_gradient_ * bulge;
    if (params_.motion_field) field_bulge_cross_.col(l).noalias() += field_pixel_gradient_ * bulge;
    bulge_information_[l] += bulge * bulge;
    bulge_gradient_[l] += double(residuals_[p]) * bulge;
    ++bulge_pixels_[std::size_t(l)];
    for (int a : shift_above_[std::size_t(l)])
      bulge_shift_cross_.block<1, 3>(l, 3 * a) += bulge * j.transpose();
  });
  merge_identical_shifts();
}

void ImageInformation::merge_identical_shifts() {
  // A link's pixels are its own and its subtree's, so a parent that shows
  // as many as one of its children shows none of its own: the two shifts
  // move the same pixels. The parent's columns go (the child, the deepest
  // of a chain, keeps them). Marked first: a chain of three shows one count.
  const int L = int(shift_links_.size());
  std::fill(shift_merged_.begin(), shift_merged_.end(), 0);
  for (int c = 0; c < L; ++c) {
    const std::vector<int>& above = shift_above_[std::size_t(c)];  // c first, then its parent
    const int a = above.size() > 1 ? above[1] : -1;
    if (a >= 0 && shift_pixels_[std::size_t(c)] > 0 &&
        shift_pixels_[std::size_t(a)] == shift_pixels_[std::size_t(c)])
      shift_merged_[std::size_t(a)] = 1;
  }
  for (int a = 0; a < L; ++a) {
    if (!shift_merged_[std::size_t(a)]) continue;
    shift_cross_.middleCols<3>(3 * a).setZero();
    field_shift_cross_.middleCols<3>(3 * a).setZero();
    shift_information_.middleRows<3>(3 * a).setZero();
    shift_information_.middleCols<3>(3 * a).setZero();
    shift_gradient_.segment<3>(3 * a).setZero();
    scale_shift_cross_.middleCols<3>(3 * a).setZero();
    bulge_shift_cross_.middleCols<3>(3 * a).setZero();
    shift_pixels_[std::size_t(a)] = 0;
  }
}

void ImageInformation::set_rigid_fit_links(const RobotModel& model, std::vector<int> links) {
  const std::vector<int>& with_geometry = model.links_with_geometry();
  rigid_fit_shift_.clear();
  for (int link : links) {
    const auto it = std::find(with_geometry.begin(), with_geometry.end(), link);
    if (it == with_geometry.end())
      throw InputError("rigid fit: link " + std::to_string(link) + " has no geometry");
    rigid_fit_shift_.push_back(int(it - with_geometry.begin()));  // shift_links_'s order
  }
  rigid_fits_.assign(links.size(), RigidFit{});
  rigid_fits_of_label_.clear();
  rigid_scale_column_of_label_.clear();
}

void ImageInformation::compute_rigid_fits(const CameraIntrinsics& camera,
                                          const DepthLikelihood& likelihood) {
  if (rigid_fits_of_label_.empty()) {  // shift_above_ is the model's (prepare_workers)
    rigid_fits_of_label_.resize(shift_links_.size());
    rigid_scale_column_of_label_.resize(shift_links_.size());
    for (std::size_t l = 0; l < shift_above_.size(); ++l)
      for (std::size_t f = 0; f < rigid_fit_shift_.size(); ++f)
        if (std::find(shift_above_[l].begin(), shift_above_[l].end(), rigid_fit_shift_[f]) !=
            shift_above_[l].end()) {
          rigid_fits_of_label_[l].push_back(int(f));
          rigid_scale_column_of_label_[l].push_back(int(rigid_fits_[f].scale_links.size()));
          rigid_fits_[f].scale_links.push_back(int(l));
        }
    for (RigidFit& fit : rigid_fits_) fit.scale_cross.resize(6, std::ssize(fit.scale_links));
  }
  for (std::size_t f = 0; f < rigid_fits_.size(); ++f) {
    RigidFit& fit = rigid_fits_[f];  // reset in place: scale_cross keeps its size
    fit.information.setZero();
    fit.gradient.setZero();
    fit.scale_cross.setZero();
    fit.pixels = 0;
    fit.origin_m = link_origin_camera_[std::size_t(rigid_fit_shift_[f])];
  }
  for_each_labelled_pixel(camera, likelihood, false, [&](int p, int l, const Eigen::Vector3d& j) {
    const std::vector<int>& fits = rigid_fits_of_label_[std::size_t(l)];
    if (fits.empty()) return;
    const Eigen::Vector3d X = rendered_point(p, camera);
    // The pixel's own link's scale, about that link's origin.
    const double h = j.dot(X - link_origin_camera_[std::size_t(l)]);
    for (std::size_t i = 0; i < fits.size(); ++i) {
      RigidFit& fit = rigid_fits_[std::size_t(fits[i])];
      Eigen::Matrix<double, 6, 1> g;
      g << j, (X - fit.origin_m).cross(j);
      fit.information.noalias() += g * g.transpose();
      fit.gradient += double(residuals_[p]) * g;
      fit.scale_cross.col(rigid_scale_column_of_label_[std::size_t(l)][i]) += h * g;
      ++fit.pixels;
    }
  });
}

bool ImageInformation::project_shifts(int min_pixels, std::span<const int> bulges,
                                      ShiftProjection& out) const {
  const int n = int(dofs_.size());
  out.columns.clear();
  out.bulges.assign(bulges.begin(), bulges.end());
  for (int l = 0; l < int(shift_links_.size()); ++l)
    if (shift_pixels_[std::size_t(l)] >= min_pixels)
      for (int a = 0; a < 3; ++a) out.columns.push_back(3 * l + a);
  const int k = int(out.columns.size()), m = int(out.bulges.size()), nm = n + m;
  if (k == 0) return false;
  // The nuisance: the DOFs, then the bulges (a pixel shows one link: no
  // cross terms between bulges).
  Eigen::MatrixXd& I_xx = out.nuisance_information;
  I_xx.setZero(nm, nm);
  I_xx.topLeftCorner(n, n) = information_;
  out.nuisance_gradient.resize(nm);
  out.nuisance_gradient.head(n) = gradient_;
  for (int i = 0; i < m; ++i) {
    const int l = out.bulges[std::size_t(i)];
    I_xx.block(0, n + i, n, 1) = bulge_cross_.col(l);
    I_xx.block(n + i, 0, 1, n) = bulge_cross_.col(l).transpose();
    I_xx(n + i, n + i) = bulge_information_[l];
    out.nuisance_gradient[n + i] = bulge_gradient_[l];
  }
  // A small ridge keeps DOFs the image does not see solvable.
  I_xx.diagonal().array() += 1e-9 * std::max(1.0, I_xx.diagonal().maxCoeff());
  out.nuisance.compute(I_xx);
  out.C.resize(nm, k);
  out.A.resize(k, k);
  out.b.resize(k);
  for (int c = 0; c < k; ++c) {
    const int column = out.columns[std::size_t(c)];
    out.C.col(c).head(n) = shift_cross_.col(column);
    for (int i = 0; i < m; ++i)
      out.C(n + i, c) = bulge_shift_cross_(out.bulges[std::size_t(i)], column);
    out.b[c] = shift_gradient_[column];
    for (int d = 0; d < k; ++d)
      out.A(c, d) = shift_information_(column, out.columns[std::size_t(d)]);
  }
  // Each product into the workspace, then subtracted: what `out.A -= C^T
  // solve(C)` evaluates through temporaries, without allocating them.
  out.solved_C = out.nuisance.solve(out.C);
  out.product.noalias() = out.C.transpose() * out.solved_C;
  out.A -= out.product;
  out.solved_gradient = out.nuisance.solve(out.nuisance_gradient);
  out.product_vector.noalias() = out.C.transpose() * out.solved_gradient;
  out.b -= out.product_vector;
  out.ridged = out.A;  // the ridge on a copy: out.A is the caller's, without
  out.ridged.diagonal().array() += 1e-9 * std::max(1.0, out.ridged.diagonal().maxCoeff());
  out.shifts.compute(out.ridged);
  // A is positive semi-definite in exact arithmetic. Where the image barely
  // sees a DOF (the camera's broad prior at the first image, arm7's
  // world-fixed camera) projecting it out cancels to rounding and leaves A
  // indefinite: the "fit" then ran to metres with negative noise variances
  // (2.7 m of model error from one image). Such an image says nothing about
  // the shifts.
  if (out.shifts.info() != Eigen::Success || !(out.shifts.vectorD().array() > 0).all())
    return false;
  out.estimate = out.shifts.solve(out.b);
  const double chi2 = out.b.dot(out.estimate);
  const double fitted = out.nuisance_gradient.dot(out.solved_gradient);
  const int left = pixels_used_ - nm - k;
  out.noise_var = left > 0 ? std::max(1.0, (residual_sum_sq_ - fitted - chi2) / left) : 1.0;
  return true;
}

double ImageInformation::link_shift_variance_m2(std::vector<char>* pinned,
                                                std::vector<double>* column_square_m2,
                                                ProjectedShiftEquations* equations,
                                                std::vector<LinkScaleFit>* scales,
                                                std::vector<double>* bulge_square_m2,
                                                int min_pixels) const {
  const std::size_t L = shift_links_.size();
  if (scales) scales->assign(L, LinkScaleFit{});
  if (pinned) pinned->assign(3 * L, 0);
  if (column_square_m2) column_square_m2->assign(3 * L, 0.0);
  if (bulge_square_m2) bulge_square_m2->assign(L, std::numeric_limits<double>::quiet_NaN());
  if (equations) {
    equations->columns.clear();
    equations->noise_var = 0;
  }
  if (!params_.link_shifts || pixels_used_ == 0) return 0;
  // Two projections, each with its own workspace: the sizes of each stay
  // the same from image to image.
  FitWorkspace& ws = fit_workspace_;
  const ShiftProjection& alone = ws.shifts_alone;
  if (!project_shifts(min_pixels, {}, ws.shifts_alone)) return 0;
  // The scales beside the DOFs and shifts alone: a round link's scale is
  // mostly its bulge.
  if (scales)
    fit_link_scales(alone.nuisance, alone.columns, alone.C, alone.shifts, alone.b, alone.noise_var,
                    min_pixels, *scales);
  // The bulges beside the DOFs, of the links with curved pixels enough.
  std::vector<int>& bulges = ws.bulges;
  bulges.clear();
  for (int l = 0; l < int(shift_links_.size()); ++l)
    if (bulge_pixels_[std::size_t(l)] >= min_pixels) bulges.push_back(l);
  if (!bulges.empty() && !project_shifts(min_pixels, bulges, ws.with_bulges)) return 0;
  const ShiftProjection& fit = bulges.empty() ? alone : ws.with_bulges;
  const int k = int(fit.columns.size());
  const double c = fit.noise_var;
  if (equations) {
    equations->columns = fit.columns;
    equations->A = fit.A;
    equations->b = fit.b;
    equations->noise_var = c;
  }
  if (bulge_square_m2) fit_link_bulges(fit, *bulge_square_m2);
  // Each shift's square less its noise variance c (A^-1)_ii, averaged over
  // the shifts: every link counts the same, however many pixels it has.
  Eigen::MatrixXd& noise = ws.shift_noise;
  noise = fit.shifts.solve(Eigen::MatrixXd::Identity(k, k));
  double sum = 0;
  int counted = 0;
  for (int i = 0; i < k; ++i) {
    if (!(c * noise(i, i) < kMaxShiftNoiseVar_m2)) continue;  // the image hardly sees it
    const double square_m2 = fit.estimate[i] * fit.estimate[i] - c * noise(i, i);
    sum += square_m2;
    ++counted;
    if (pinned) (*pinned)[std::size_t(fit.columns[std::size_t(i)])] = 1;
    if (column_square_m2) (*column_square_m2)[std::size_t(fit.columns[std::size_t(i)])] = square_m2;
  }
  return counted > 0 ? sum / counted : 0.0;  // unbiased: the caller clips its average
}

void ImageInformation::fit_link_bulges(const ShiftProjection& fit,
                                       std::vector<double>& bulge_square_m2) const {
  const int n = int(dofs_.size()), m = int(fit.bulges.size()), k = int(fit.columns.size());
  if (m == 0) return;
  // The whole normal equations over (DOFs, bulges, shifts): each bulge's fit
  // and noise variance with the DOFs and every shift beside it.
  const int nm = n + m, N = nm + k;
  FitWorkspace& ws = fit_workspace_;
  Eigen::MatrixXd& M = ws.whole;
  Eigen::VectorXd& g = ws.whole_gradient;
  M.resize(N, N);
  g.resize(N);
  M.topLeftCorner(nm, nm) = fit.nuisance_information;  // ridged
  M.topRightCorner(nm, k) = fit.C;
  M.bottomLeftCorner(k, nm) = fit.C.transpose();
  g.head(nm) = fit.nuisance_gradient;
  for (int c = 0; c < k; ++c) {
    g[nm + c] = shift_gradient_[fit.columns[std::size_t(c)]];
    for (int d = 0; d < k; ++d)
      M(nm + c, nm + d) =
          shift_information_(fit.columns[std::size_t(c)], fit.columns[std::size_t(d)]);
  }
  M.diagonal().array() += 1e-9 * std::max(1.0, M.diagonal().maxCoeff());
  Eigen::LDLT<Eigen::MatrixXd>& all = ws.whole_factor;
  all.compute(M);
  if (all.info() != Eigen::Success) return;
  Eigen::VectorXd& x = ws.whole_fit;
  x = all.solve(g);
  Eigen::VectorXd& unit = ws.unit;
  unit.setZero(N);
  for (int i = 0; i < m; ++i) {
    unit.setZero();
    unit[n + i] = 1;
    ws.unit_solved = all.solve(unit);
    const double var = fit.noise_var * ws.unit_solved[n + i];
    if (!(var > 0 && var < kMaxShiftNoiseVar_m2)) continue;  // the image hardly sees it
    bulge_square_m2[std::size_t(fit.bulges[std::size_t(i)])] = x[n + i] * x[n + i] - var;
  }
}

void ImageInformation::fit_link_scales(const Eigen::LDLT<Eigen::MatrixXd>& dofs,
                                       const std::vector<int>& columns,
                                       const Eigen::MatrixXd& shift_cross,
                                       const Eigen::LDLT<Eigen::MatrixXd>& shifts,
                                       const Eigen::VectorXd& shift_b, double noise_var,
                                       int min_pixels, std::vector<LinkScaleFit>& scales) const {
  FitWorkspace& ws = fit_workspace_;
  std::vector<int>& links = ws.scale_links;
  links.clear();
  for (int l = 0; l < int(shift_links_.size()); ++l)
    if (shift_pixels_[std::size_t(l)] >= min_pixels && scale_information_[l] > 0)
      links.push_back(l);
  const int m = int(links.size()), n = int(dofs_.size()), k = int(shift_b.size());
  if (m == 0) return;
  // The normal equations over (DOFs, the fit's shift columns, the scales),
  // the DOFs then the shifts projected out (Schur complements).
  Eigen::MatrixXd &S = ws.scale_dofs, &X = ws.scale_shifts, &A = ws.scales;
  Eigen::VectorXd& b = ws.scale_gradient;
  S.resize(n, m);
  X.resize(k, m);
  A.setZero(m, m);
  b.resize(m);
  for (int i = 0; i < m; ++i) {
    const int l = links[std::size_t(i)];
    S.col(i) = scale_cross_.col(l);
    for (int c = 0; c < k; ++c) X(c, i) = scale_shift_cross_(l, columns[std::size_t(c)]);
    A(i, i) = scale_information_[l];  // a pixel shows one link: no cross terms
    b[i] = scale_gradient_[l];
  }
  // Each product into the workspace, then subtracted (as project_shifts()).
  ws.dofs_solved = dofs.solve(S);  // dofs_S
  ws.scale_shift_product.noalias() = shift_cross.transpose() * ws.dofs_solved;
  X -= ws.scale_shift_product;
  ws.scale_product.noalias() = S.transpose() * ws.dofs_solved;
  A -= ws.scale_product;
  ws.dofs_solved_gradient = dofs.solve(gradient_);
  ws.scale_product_vector.noalias() = S.transpose() * ws.dofs_solved_gradient;
  b -= ws.scale_product_vector;
  ws.shifts_solved = shifts.solve(X);
  ws.scale_product.noalias() = X.transpose() * ws.shifts_solved;
  A -= ws.scale_product;
  ws.shifts_solved_gradient = shifts.solve(shift_b);
  ws.scale_product_vector.noalias() = X.transpose() * ws.shifts_solved_gradient;
  b -= ws.scale_product_vector;
  // A scale the DOFs and shifts reproduce leaves nothing (a flat face's
  // scale is a tilt and a shift of it): it is left out, as 0, where
  // rounding would leave the others' fit indefinite.
  std::vector<int>& kept = ws.scales_kept;
  kept.clear();
  for (int i = 0; i < m; ++i)
    if (A(i, i) > 1e-6 * scale_information_[links[std::size_t(i)]]) kept.push_back(i);
  const int f = int(kept.size());
  if (f == 0) return;
  Eigen::MatrixXd& A_kept = ws.scales_kept_ridged;
  A_kept.resize(f, f);  // A(kept, kept) and b(kept) would copy `kept` (an allocation)
  ws.scale_gradient_kept.resize(f);
  for (int i = 0; i < f; ++i) {
    ws.scale_gradient_kept[i] = b[kept[std::size_t(i)]];
    for (int j = 0; j < f; ++j) A_kept(i, j) = A(kept[std::size_t(i)], kept[std::size_t(j)]);
  }
  A_kept.diagonal().array() += 1e-9 * std::max(1.0, A_kept.diagonal().maxCoeff());
  Eigen::LDLT<Eigen::MatrixXd>& fit = ws.scale_factor;
  fit.compute(A_kept);
  if (fit.info() != Eigen::Success || !(fit.vectorD().array() > 0).all()) return;
  Eigen::VectorXd& estimate = ws.scale_fit;
  estimate = fit.solve(ws.scale_gradient_kept);
  Eigen::MatrixXd& noise = ws.scale_noise;
  noise = fit.solve(Eigen::MatrixXd::Identity(f, f));
  for (int i = 0; i < f; ++i) {
    const double var = noise_var * noise(i, i);
    if (!(var > 0 && var < kMaxScaleNoise * kMaxScaleNoise)) continue;  // hardly seen
    scales[std::size_t(links[std::size_t(kept[std::size_t(i)])])] = {estimate[i], var};
  }
}

double ImageInformation::neighbour_correlation(const Eigen::VectorXf& r, int step,
                                               int width) const {
  const int num_pixels = int(used_.size());
  const bool same_row = step < width;
  double cross = 0, a2 = 0, b2 = 0;
  for (int p = 0; p + step < num_pixels; ++p) {
    if (same_row && (p % width) + step >= width) continue;
    if (!used_[std::size_t(p)] || !used_[std::size_t(p + step)]) continue;
    const double a = r[p], b = r[p + step];
    cross += a * b;
    a2 += a * a;
    b2 += b * b;
  }
  if (!(a2 > 0 && b2 > 0)) return 0.0;
  return std::clamp(cross / std::sqrt(a2 * b2), 0.0, 0.99);
}

double ImageInformation::independent_sample_fraction(const Eigen::VectorXf& r, int width) const {
  const double rho_x = neighbour_correlation(r, 1, width);
  const double rho_y = neighbour_correlation(r, width, width);
  return (1 - rho_x) / (1 + rho_x) * (1 - rho_y) / (1 + rho_y);
}

void ImageInformation::estimate_effective_pixel_fraction(int width) {
  effective_pixel_fraction_ = 1;
  if (pixels_used_ == 0) return;
  // Correlation without removing the mean: a shared offset is exactly the
  // correlated part that must not count N times.
  const double mean_square = residual_sum_sq_ / pixels_used_;
  effective_pixel_fraction_ =
      std::min(1.0, independent_sample_fraction(residuals_, width) / mean_square);
}

void ImageInformation::estimate_fitted_residual_factor(int width) {
  fitted_residual_factor_ = 1;
  const int m = int(dofs_.size());
  if (pixels_used_ <= m || m == 0) return;
  const Eigen::MatrixXf& G = params_.motion_field ? field_gradients_ : gradients_;
  residual_fit_information_ = params_.motion_field ? field_information_ : information_;
  // A small ridge keeps DOFs the image does not see solvable (their fit 0).
  residual_fit_information_.diagonal().array() +=
      1e-9 * std::max(1.0, residual_fit_information_.diagonal().maxCoeff());
  residual_fit_factor_.compute(residual_fit_information_);
  product_vector_f_.noalias() = G.transpose() * residuals_;
  residual_fit_gradient_ = product_vector_f_.cast<double>();
  residual_fit_ = residual_fit_factor_.solve(residual_fit_gradient_);
  fitted_residuals_ = residuals_;  // 0 where unused, and G's rows are 0 there
  residual_fit_f_ = residual_fit_.cast<float>();
  fitted_residuals_.noalias() -= G * residual_fit_f_;
  const double ess = independent_sample_fraction(fitted_residuals_, width);
  const double mean_square = double(fitted_residuals_.squaredNorm()) / (pixels_used_ - m);
  const double factor = mean_square / ess;
  if (std::isfinite(factor)) fitted_residual_factor_ = factor;  // else 1: the model's
}

}  // namespace arttrack
