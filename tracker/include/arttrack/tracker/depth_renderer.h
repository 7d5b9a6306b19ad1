// CPU depth rendering of the robot: what a depth camera at the model's camera
// link would see of the robot alone, for one kinematic state.
//
// Output depth is metres along the optical axis (planar depth), 0 where no
// link is seen, in the optical frame of model.camera_link() (z forward, x
// right, y down) with pinhole intrinsics; pixel (u, v) samples the ray through
// its centre (u + 0.5, v + 0.5). Link meshes are closed and wound
// counter-clockwise seen from outside, and back faces are culled (on a link
// with an open mesh part too, unless RenderOptions::open_parts_both_sides);
// triangles crossing the near plane are clipped, depth is exact for planar
// triangles (1/z interpolated in screen space), and triangles sharing an
// edge leave no gap between them (a pixel centre belongs to the triangle
// whose half-open span [left, right) holds it). Vertices are transformed in
// float.
//
// URDF cylinders and spheres (RoundShape) are drawn exactly: each pixel
// whose ray meets the shape gets the depth of the ray's entry point
// (intersected in double), drawn when that point lies at or beyond the near
// plane (as a clipped closed mesh with culled back faces would be). A
// tessellation fixed to its link drew a shape that changes as a joint turns
// it about itself; 16-sided cylinders and 12-meridian spheres made the
// default scenario's camera roll drift 1.2 degrees in 20 s (none with 64
// and 64, at four times the cost; docs/accuracy.md, "Exact cylinders and
// spheres").
//
// A link with levels of detail (Link::coarser_meshes, made by
// RobotModel::with_simplified_meshes) is drawn with the coarsest level whose
// min_range_m its bounding sphere's nearest depth reaches: a pixel there
// covers as much more as the level's error grew, so the error stays the same
// share of a pixel. The level is a function of the link's pose alone, so a
// link drawn twice at one pose is drawn alike (the evaluator's caches rely
// on it).
//
// Each mesh level is split into clusters of up to 16 neighbouring
// triangles (meshoptimizer's meshlets, built when the renderer is made),
// each with a bounding sphere and the cone its normals lie in. With back
// faces culled, a cluster whose every triangle faces away from the camera
// by more than 0.01 rad (the cone and sphere prove it) is skipped whole:
// its vertices are not transformed, its triangles not tested. A closed
// mesh turns about half its surface away from the camera, but a cluster's
// normals spread: on the sculpted dual arm 30% of the triangles are
// skipped. So is a cluster whose bounding sphere's screen extent holds no
// pixel centre column or row (at 80x60 a sculpted cluster often falls
// between centres; a quarter of the rest), or lies off the view: none of
// its triangles could cover a centre. The image is the same as testing each
// triangle (the margins keep the float per-triangle tests and the
// cluster's bounds from disagreeing).
//
// A DepthRenderer is a per-thread workspace: it refers to a shared immutable
// RobotModel and owns buffers sized once, so rendering never allocates after
// the first call with a given output image. Copy one to give another thread
// a renderer of the same model and camera without building the clusters
// again.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {

// Rasterizer settings.
struct RenderOptions {
  // Near clipping plane, metres along the optical axis; nearer geometry is cut away.
  float near_m = 0.01f;
  // Skip triangles seen from behind (valid for closed outward-wound meshes).
  bool cull_back_faces = true;
  // Draw the links with an open mesh part (Link::has_open_parts()) from
  // both sides: what a camera sees of an open surface, at up to 1.6 times
  // the cost of those links (sculpted dual arm, all links: 123 -> 198 us).
  bool open_parts_both_sides = false;
};

// Renders depth images of a robot model from its camera link.
class DepthRenderer {
 public:
  DepthRenderer(const RobotModel& model, const CameraIntrinsics& camera,
                const RenderOptions& options = {});

  const RobotModel& model() const { return *model_; }
  const CameraIntrinsics& camera() const { return camera_; }
  const RenderOptions& options() const { return options_; }

  // Renders every link: `out` is sized to the camera, cleared and drawn.
  // Returns the bounding rectangle of the robot's pixels (exactly that of
  // the nonzero pixels of `out`).
  PixelRect render(const KinematicsState& state, DepthImage& out);

  // Renders only the links in `links` (a flag per link) into a cleared `out`.
  PixelRect render_links(const KinematicsState& state, const LinkSet& links, DepthImage& out);

  // Draws the links in `links` into `depth`, which must have the camera's
  // size, keeping per pixel the nearer of what it holds and the new surface
  // (0 = empty). Drawing onto a copy of a cached image of the other links
  // gives the image of all. Returns the bounding rectangle of the pixels
  // these links cover, nearer or not: every pixel changed lies in it.
  PixelRect draw_links(const KinematicsState& state, const LinkSet& links, DepthImage& depth);

 private:
  struct LinkBounds {
    Eigen::Vector3f centre_m = Eigen::Vector3f::Zero();  // bounding sphere, link frame
    float radius_m = 0;
  };
  PixelRect draw_link(int link, const Eigen::Isometry3d& T_camera_root, DepthImage& depth);
  // Rows [v_top, v_bottom): first_centre_from() of the corners' least and greatest v.
  void raster_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                       int v_top, int v_bottom, DepthImage& depth, PixelRect& drawn) const;
  void raster_clipped(const Eigen::Vector3f* hom[3], bool cull_back_faces, DepthImage& depth,
                      PixelRect& drawn) const;
  void draw_round_shape(const RoundShape& shape, const Eigen::Isometry3d& T_camera_link,
                        DepthImage& depth, PixelRect& drawn) const;

  // A patch of one mesh level's triangles, culled whole when all of them
  // face away from the camera.
  struct Cluster {
    int first_triangle = 0, num_triangles = 0;  // in Clusters::triangles
    // The cluster's own copies of its vertices in Clusters::x, y, z, from
    // first_vertex (a multiple of kLanes) on, padded to a multiple of
    // kLanes with its last vertex: transformed kLanes at a time.
    int first_vertex = 0, num_vertices = 0;
    Eigen::Vector3f centre_m = Eigen::Vector3f::Zero();  // bounding sphere, link frame
    float radius_m = 0;
    // Every triangle's unit normal lies within an angle a of `axis`; cos a
    // <= 0 (a half-space of normals or more): never culled.
    Eigen::Vector3f axis = Eigen::Vector3f::UnitZ();
    float cos_angle = -1, sin_angle = 0;
  };
  static constexpr int kLanes = 4;  // one SSE register of floats
  struct Clusters {                 // one mesh level
    std::vector<Cluster> clusters;
    std::vector<Eigen::Vector3i> triangles;  // indices into x, y, z, cluster by cluster
    std::vector<float> x, y, z;              // each cluster's vertices (link frame), padded
  };
  static Clusters make_clusters(const TriangleMesh& mesh, const std::vector<RoundShape>& shapes);
  // Vertex i of `clusters` into hom_, and where it is in front of the near
  // plane (or the link cannot reach it), into screen_ and first_centre_.
  void transform_vertex(int i, const Eigen::Matrix3f& A, const Eigen::Vector3f& b,
                        const Clusters& clusters, bool may_clip);
  // A cluster's vertices, padding included, into screen_ and first_centre_
  // (not hom_) for a link wholly in front of the near plane: the same
  // numbers as transform_vertex, kLanes vertices at a time.
  void transform_cluster(const Cluster& cluster, const Eigen::Matrix3f& A, const Eigen::Vector3f& b,
                         const Clusters& clusters);

  const RobotModel* model_;
  CameraIntrinsics camera_;
  RenderOptions options_;
  LinkSet all_links_;
  std::vector<LinkBounds> bounds_;
  // Per link, per level (0: Link::mesh without its round shapes; k:
  // coarser_meshes[k - 1]).
  std::vector<std::vector<Clusters>> clusters_;
  Eigen::Matrix<float, 4, 3> frustum_planes_;  // inward unit normals of the 4 side planes
  // Per-vertex workspace, indexed as Clusters::x, sized for the largest level:
  std::vector<Eigen::Vector3f> hom_;     // (fx x + cx z, fy y + cy z, z), camera frame
  std::vector<Eigen::Vector3f> screen_;  // (u, v, 1/z) for vertices in front of the near plane
  // Per vertex of screen_: the first pixel column and row whose centre is at
  // or after it (first_centre_from), for the triangles' integer bounding boxes.
  std::vector<Eigen::Vector2i> first_centre_;
};

// Keeps per pixel the nearer of `depth` and `src` within `rect` (0 = empty).
void merge_nearer(const DepthImage& src, const PixelRect& rect, DepthImage& depth);

// The links whose rendered depth can change when the given DOFs change: the
// subtrees they move, or every link if one of them moves the camera.
LinkSet links_affecting_depth(const RobotModel& model, const std::vector<int>& dofs);

// Renders hypotheses that differ from a reference state only in some DOFs:
// the links those DOFs cannot move are rendered once per reference state and
// cached; each hypothesis draws only the moving links over a copy of the cache.
// Like DepthRenderer, one per thread.
class CachedRenderer {
 public:
  CachedRenderer(DepthRenderer& renderer, const std::vector<int>& moving_dofs);

  // Renders and caches the links that `moving_dofs` cannot move, at `state`.
  void set_reference(const KinematicsState& state);

  // The full image at `state`, which must equal the reference state in all
  // DOFs but the moving ones. Returns the rectangle of the moving links' pixels.
  PixelRect render(const KinematicsState& state, DepthImage& out);

  const DepthImage& cached_depth() const { return cached_; }
  const LinkSet& moving_links() const { return moving_; }

 private:
  DepthRenderer* renderer_;
  LinkSet moving_, fixed_;
  DepthImage cached_;
};

}  // namespace arttrack
