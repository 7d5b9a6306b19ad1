#include "arttrack/tracker/depth_renderer.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace arttrack {
namespace {

// Screen position and inverse depth of a homogeneous image point
// (fx x + cx z, fy y + cy z, z). One formula for mesh and clipped vertices,
// so a point shared by two triangles projects to bit-identical coordinates.
inline Eigen::Vector3f project(const Eigen::Vector3f& hom) {
  const float inv_z = 1.f / hom.z();
  return Eigen::Vector3f(hom.x() * inv_z, hom.y() * inv_z, inv_z);
}

// Lexicographic order of screen points: each edge is evaluated from its
// smaller end, so two triangles sharing it get exactly opposite values.
inline bool screen_less(const Eigen::Vector3f& p, const Eigen::Vector3f& q) {
  return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
}

// First pixel index whose centre is at or after x (clamped into [lo, hi + 1]),
// computed in float before the integer conversion so huge values cannot overflow.
inline int first_centre_at_or_after(float x, int lo, int hi) {
  const float u = std::ceil(x - 0.5f);
  return u <= float(lo) ? lo : u >= float(hi + 1) ? hi + 1 : int(u);
}
// Last pixel index whose centre is at or before x (clamped into [lo - 1, hi]).
inline int last_centre_at_or_before(float x, int lo, int hi) {
  const float u = std::floor(x - 0.5f);
  return u >= float(hi) ? hi : u <= float(lo - 1) ? lo - 1 : int(u);
}

}  // namespace

PixelRect PixelRect::united(const PixelRect& other) const {
  if (empty()) return other;
  if (other.empty()) return *this;
  return {std::min(u0, other.u0), std::min(v0, other.v0), std::max(u1, other.u1),
          std::max(v1, other.v1)};
}

DepthRenderer::DepthRenderer(const RobotModel& model, const CameraIntrinsics& camera,
                             const RenderOptions& options)
    : model_(&model),
      camera_(camera),
      options_(options),
      all_links_(model.num_links(), true),
      bounds_(model.num_links()) {
  assert(model.camera_link() >= 0 && camera.width > 0 && camera.height > 0);
  size_t max_vertices = 0;
  for (int l : model.links_with_geometry()) {
    const std::vector<Eigen::Vector3f>& v = model.link(l).mesh.vertices_m;
    max_vertices = std::max(max_vertices, v.size());
    Eigen::Vector3f lo = v[0], hi = v[0];
    for (const Eigen::Vector3f& p : v) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    LinkBounds& b = bounds_[l];
    b.centre_m = 0.5f * (lo + hi);
    for (const Eigen::Vector3f& p : v) b.radius_m = std::max(b.radius_m, (p - b.centre_m).norm());
    b.radius_m *= 1.0001f;  // float rounding of the transformed vertices
  }
  hom_.resize(max_vertices);
  screen_.resize(max_vertices);
  // A camera-frame point p is inside the view when 0 <= u <= W and 0 <= v <= H,
  // i.e. fx x + cx z >= 0, -fx x + (W - cx) z >= 0, and the same in y.
  const float fx = float(camera.fx), fy = float(camera.fy);
  const float cx = float(camera.cx), cy = float(camera.cy);
  frustum_planes_ << fx, 0, cx, -fx, 0, float(camera.width) - cx, 0, fy, cy, 0, -fy,
      float(camera.height) - cy;
  frustum_planes_.rowwise().normalize();
}

PixelRect DepthRenderer::render(const KinematicsState& state, DepthImage& out) {
  return render_links(state, all_links_, out);
}

PixelRect DepthRenderer::render_links(const KinematicsState& state, const LinkSet& links,
                                      DepthImage& out) {
  if (out.width != camera_.width || out.height != camera_.height) {
    out = DepthImage(camera_.width, camera_.height);
  } else {
    std::fill(out.depth_m.begin(), out.depth_m.end(), 0.f);
  }
  return draw_links(state, links, out);
}

PixelRect DepthRenderer::draw_links(const KinematicsState& state, const LinkSet& links,
                                    DepthImage& depth) {
  assert(depth.width == camera_.width && depth.height == camera_.height);
  assert(int(state.T_root_link.size()) == model_->num_links());
  const Eigen::Isometry3d T_camera_root =
      state.T_root_link[model_->camera_link()].inverse(Eigen::Isometry);
  PixelRect drawn;
  for (int l : model_->links_with_geometry()) {
    if (links[l]) drawn = drawn.united(draw_link(l, T_camera_root * state.T_root_link[l], depth));
  }
  return drawn;
}

PixelRect DepthRenderer::draw_link(int link, const Eigen::Isometry3d& T_camera_link,
                                   DepthImage& depth) {
  const float near = options_.near_m;
  // Cull the whole link when its bounding sphere is behind the near plane or
  // outside a side of the view.
  const LinkBounds& bounds = bounds_[link];
  const Eigen::Vector3f centre = (T_camera_link * bounds.centre_m.cast<double>()).cast<float>();
  if (centre.z() + bounds.radius_m < near) return {};
  if ((frustum_planes_ * centre).minCoeff() < -bounds.radius_m) return {};
  const bool may_clip = centre.z() - bounds.radius_m < near;

  // Link frame to homogeneous image coordinates in one 3x4 float matrix.
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = camera_.fx;
  K(1, 1) = camera_.fy;
  K(0, 2) = camera_.cx;
  K(1, 2) = camera_.cy;
  const Eigen::Matrix3f A = (K * T_camera_link.linear()).cast<float>();
  const Eigen::Vector3f b = (K * T_camera_link.translation()).cast<float>();

  const TriangleMesh& mesh = model_->link(link).mesh;
  const int nv = int(mesh.vertices_m.size());
  const Eigen::Vector3f* v = mesh.vertices_m.data();
  Eigen::Vector3f* hom = hom_.data();
  Eigen::Vector3f* screen = screen_.data();
  if (!may_clip) {
    for (int i = 0; i < nv; ++i) {
      hom[i] = A * v[i] + b;
      screen[i] = project(hom[i]);
    }
  } else {
    for (int i = 0; i < nv; ++i) {
      hom[i] = A * v[i] + b;
      if (hom[i].z() >= near) screen[i] = project(hom[i]);
    }
  }

  PixelRect drawn{camera_.width, camera_.height, 0, 0};
  for (const Eigen::Vector3i& t : mesh.triangles) {
    if (may_clip) {
      const int in =
          int(hom[t[0]].z() >= near) + int(hom[t[1]].z() >= near) + int(hom[t[2]].z() >= near);
      if (in == 0) continue;
      if (in < 3) {
        const Eigen::Vector3f* corners[3] = {&hom[t[0]], &hom[t[1]], &hom[t[2]]};
        raster_clipped(corners, depth, drawn);
        continue;
      }
    }
    raster_triangle(screen[t[0]], screen[t[1]], screen[t[2]], depth, drawn);
  }
  return drawn.empty() ? PixelRect{} : drawn;
}

// Clips a triangle (homogeneous image points) against z >= near and draws the
// remaining polygon (a triangle or a quadrilateral) as a fan.
void DepthRenderer::raster_clipped(const Eigen::Vector3f* hom[3], DepthImage& depth,
                                   PixelRect& drawn) const {
  const float near = options_.near_m;
  Eigen::Vector3f poly[4];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3f& p = *hom[k];
    const Eigen::Vector3f& q = *hom[(k + 1) % 3];
    const bool p_in = p.z() >= near, q_in = q.z() >= near;
    if (p_in) poly[n++] = p;
    if (p_in != q_in) {
      // Always interpolate from the inside end, so the triangle across this
      // edge computes the very same point.
      const Eigen::Vector3f& in = p_in ? p : q;
      const Eigen::Vector3f& out = p_in ? q : p;
      const float s = (near - in.z()) / (out.z() - in.z());
      Eigen::Vector3f cut = in + s * (out - in);
      cut.z() = near;
      poly[n++] = cut;
    }
  }
  Eigen::Vector3f screen[4];
  for (int k = 0; k < n; ++k) screen[k] = project(poly[k]);
  for (int k = 1; k + 1 < n; ++k)
    raster_triangle(screen[0], screen[k], screen[k + 1], depth, drawn);
}

// Draws one triangle given as screen points (u, v, 1/z): every pixel whose
// centre is inside or on an edge, depth-tested against what `depth` holds.
void DepthRenderer::raster_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b0,
                                    const Eigen::Vector3f& c0, DepthImage& depth,
                                    PixelRect& drawn) const {
  const int W = depth.width, H = depth.height;
  // Pixel centres inside the bounding box; most triangles of a low-resolution
  // image hold none and end here.
  const float x_min = std::min({a.x(), b0.x(), c0.x()}), x_max = std::max({a.x(), b0.x(), c0.x()});
  const int u_lo = first_centre_at_or_after(x_min, 0, W - 1);
  const int u_hi = last_centre_at_or_before(x_max, 0, W - 1);
  if (u_lo > u_hi) return;
  const float y_min = std::min({a.y(), b0.y(), c0.y()}), y_max = std::max({a.y(), b0.y(), c0.y()});
  const int v_lo = first_centre_at_or_after(y_min, 0, H - 1);
  const int v_hi = last_centre_at_or_before(y_max, 0, H - 1);
  if (v_lo > v_hi) return;

  // Twice the signed screen area. With v pointing down, a triangle wound
  // counter-clockwise seen from outside has negative area when it faces the
  // camera: area = fx fy (n . p_a) / (z_a z_b z_c), n its outward normal.
  float area = (b0.x() - a.x()) * (c0.y() - a.y()) - (b0.y() - a.y()) * (c0.x() - a.x());
  if (options_.cull_back_faces ? !(area < 0.f) : area == 0.f) return;
  // Orient so the area is positive and "inside" is where all edge functions are >= 0.
  const bool flip = area < 0.f;
  const Eigen::Vector3f& b = flip ? c0 : b0;
  const Eigen::Vector3f& c = flip ? b0 : c0;
  area = std::abs(area);

  // Edge k from p to q: E(x, y) = ex (y - my) - ey (x - mx) >= 0 inside,
  // evaluated from the edge's lexicographically smaller end m with signs
  // folded into (ex, ey); a neighbour sharing the edge gets exactly -E, so a
  // pixel centre is never missed by both (on the edge, both draw it).
  float mx[3], my[3], ex[3], ey[3];
  const Eigen::Vector3f* corners[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3f& p = *corners[k];
    const Eigen::Vector3f& q = *corners[(k + 1) % 3];
    const bool swap = screen_less(q, p);
    const Eigen::Vector3f& m = swap ? q : p;
    const Eigen::Vector3f& M = swap ? p : q;
    const float sign = swap ? -1.f : 1.f;
    mx[k] = m.x();
    my[k] = m.y();
    ex[k] = sign * (M.x() - m.x());
    ey[k] = sign * (M.y() - m.y());
  }

  // 1/z is affine in screen coordinates on a planar triangle:
  // 1/z = o.z + gx (x - o.x) + gy (y - o.y), taken from the farthest corner o
  // so that a corner just past the near plane (1/z huge) costs no precision
  // at the far pixels.
  const float dxb = b.x() - a.x(), dyb = b.y() - a.y(), dzb = b.z() - a.z();
  const float dxc = c.x() - a.x(), dyc = c.y() - a.y(), dzc = c.z() - a.z();
  const float inv_area = 1.f / area;
  const float gx = (dzb * dyc - dzc * dyb) * inv_area;
  const float gy = (dzc * dxb - dzb * dxc) * inv_area;
  const Eigen::Vector3f& o = a.z() <= b.z() ? (a.z() <= c.z() ? a : c) : (b.z() <= c.z() ? b : c);
  // Rounding must not take a depth outside the triangle's own range.
  const float iz_min = o.z(), iz_max = std::max({a.z(), b.z(), c.z()});

  const bool wide = u_hi - u_lo > 4;
  float* rows = depth.depth_m.data();
  for (int v = v_lo; v <= v_hi; ++v) {
    const float py = float(v) + 0.5f;
    float r[3];
    int span_lo = u_lo, span_hi = u_hi;
    for (int k = 0; k < 3; ++k) r[k] = ex[k] * (py - my[k]);
    if (wide) {
      // Where each edge function crosses zero on this row; one pixel of slack
      // either way, the exact test below decides.
      for (int k = 0; k < 3; ++k) {
        if (ey[k] == 0.f) {
          if (r[k] < 0.f) span_hi = span_lo - 1;
          continue;
        }
        const float x_cross = mx[k] + r[k] / ey[k];
        if (ey[k] > 0.f) {
          span_hi = std::min(span_hi, last_centre_at_or_before(x_cross, u_lo, u_hi) + 1);
        } else {
          span_lo = std::max(span_lo, first_centre_at_or_after(x_cross, u_lo, u_hi) - 1);
        }
      }
    }
    float* row = rows + size_t(v) * W;
    const float iz_row = o.z() + gy * (py - o.y());
    for (int u = span_lo; u <= span_hi; ++u) {
      const float px = float(u) + 0.5f;
      const float e0 = r[0] - ey[0] * (px - mx[0]);
      const float e1 = r[1] - ey[1] * (px - mx[1]);
      const float e2 = r[2] - ey[2] * (px - mx[2]);
      if (e0 < 0.f || e1 < 0.f || e2 < 0.f) continue;
      const float iz = std::clamp(iz_row + gx * (px - o.x()), iz_min, iz_max);
      const float z = 1.f / iz;
      float& d = row[u];
      if (d == 0.f || z < d) {
        d = z;
        drawn.u0 = std::min(drawn.u0, u);
        drawn.u1 = std::max(drawn.u1, u + 1);
        drawn.v0 = std::min(drawn.v0, v);
        drawn.v1 = std::max(drawn.v1, v + 1);
      }
    }
  }
}

void merge_nearer(const DepthImage& src, const PixelRect& rect, DepthImage& depth) {
  assert(src.width == depth.width && src.height == depth.height);
  for (int v = rect.v0; v < rect.v1; ++v) {
    const float* s = src.depth_m.data() + size_t(v) * src.width;
    float* d = depth.depth_m.data() + size_t(v) * depth.width;
    for (int u = rect.u0; u < rect.u1; ++u) {
      if (s[u] != 0.f && (d[u] == 0.f || s[u] < d[u])) d[u] = s[u];
    }
  }
}

LinkSet links_affecting_depth(const RobotModel& model, const std::vector<int>& dofs) {
  LinkSet links(model.num_links(), false);
  for (int dof : dofs) {
    const LinkSet moved = model.links_moved_by(dof);
    // A DOF that moves the camera moves the whole image.
    if (moved[model.camera_link()]) return LinkSet(model.num_links(), true);
    for (int l = 0; l < model.num_links(); ++l) links[l] = links[l] || moved[l];
  }
  return links;
}

CachedRenderer::CachedRenderer(DepthRenderer& renderer, const std::vector<int>& moving_dofs)
    : renderer_(&renderer),
      moving_(links_affecting_depth(renderer.model(), moving_dofs)),
      fixed_(moving_.size()),
      cached_(renderer.camera().width, renderer.camera().height) {
  for (size_t l = 0; l < moving_.size(); ++l) fixed_[l] = !moving_[l];
}

void CachedRenderer::set_reference(const KinematicsState& state) {
  renderer_->render_links(state, fixed_, cached_);
}

PixelRect CachedRenderer::render(const KinematicsState& state, DepthImage& out) {
  if (out.width != cached_.width || out.height != cached_.height) {
    out = cached_;
  } else {
    std::copy(cached_.depth_m.begin(), cached_.depth_m.end(), out.depth_m.begin());
  }
  return renderer_->draw_links(state, moving_, out);
}

}  // namespace arttrack
