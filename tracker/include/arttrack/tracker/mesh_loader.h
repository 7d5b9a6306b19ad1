// Triangle meshes of link shapes: loading mesh files (STL, OBJ, DAE through
// assimp) and tessellating the URDF primitives (box, cylinder, sphere).
//
// Every mesh is closed and wound counter-clockwise seen from outside (the
// renderer culls back faces). Lengths are metres.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace arttrack {

// An indexed triangle mesh, float vertices (what the renderer transforms).
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices_m;
  std::vector<Eigen::Vector3i> triangles;  // vertex indices, counter-clockwise seen from outside

  bool empty() const { return triangles.empty(); }

  // Appends `other` with its vertices mapped by T_this_other (metres). A
  // mirroring transform (negative determinant) flips the winding so the
  // triangles still face outwards.
  void append(const TriangleMesh& other,
              const Eigen::Affine3d& T_this_other = Eigen::Affine3d::Identity());

  // Merges vertices at exactly the same position and drops triangles that
  // became degenerate, so each shared vertex is transformed once per render.
  void weld_vertices();
};

// Loads every sub-mesh of a mesh file (STL ASCII or binary, OBJ, DAE, or any
// format assimp reads), each placed by its node transform, triangulated, with
// coordinates multiplied by `scale` (the URDF mesh scale). COLLADA units are
// honoured; the COLLADA up axis is ignored (the ROS/RViz convention: mesh
// coordinates are link coordinates). Throws InputError naming the file when
// it is missing, unreadable or holds no triangle.
TriangleMesh load_mesh(const std::string& path,
                       const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

// A box centred at the origin with edge lengths `size_m` along x, y, z
// (8 vertices, 12 triangles).
TriangleMesh make_box(const Eigen::Vector3d& size_m);

// A cylinder centred at the origin along z (the URDF convention), with
// `segments` sides. The polygon's radius is chosen so that its area equals
// the circle's, so its silhouette is the true one on average.
TriangleMesh make_cylinder(double radius_m, double length_m, int segments);

// A UV sphere centred at the origin: `segments` meridians and segments / 2
// latitude bands, enlarged until it holds the sphere's volume, so that its
// surface, and the depth rendered from it, is the sphere's on average.
TriangleMesh make_sphere(double radius_m, int segments);

}  // namespace arttrack
