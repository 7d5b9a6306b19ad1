// Triangle meshes of link shapes: loading mesh files (STL, OBJ, DAE through
// assimp) and tessellating the URDF primitives (box, cylinder, sphere).
//
// The primitives are closed and wound counter-clockwise seen from outside
// (the renderer culls back faces). A mesh file need not be: orient_parts()
// turns its parts outward and finds those that are open. Lengths are
// metres.
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

  // Merges vertices at exactly the same position (-0 as 0), every triangle
  // kept in its place.
  void join_equal_vertices();
  // join_equal_vertices(), then drops the triangles that became degenerate,
  // so each shared vertex is transformed once per render.
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

// What orient_parts() found in a mesh: its parts (triangles joined by
// edges that exactly two triangles share), those it turned outward, and
// those it left open.
struct MeshOrientation {
  int parts = 0;
  // Parts some of whose triangles were wound the other way (a part inside
  // out, or faces flipped in it): their triangles now wind counter-clockwise
  // seen from outside (the part encloses a positive volume). An open part
  // is turned too when it still encloses a volume (small holes: a crack, a
  // T-junction), at least 1% of its area^1.5.
  int turned_parts = 0;
  // Parts with a border edge (one triangle), an edge of three or more
  // triangles, or no consistent winding: culling their back faces is only
  // right where they are nearly closed (RenderOptions::open_parts_both_sides).
  int open_parts = 0;
  int open_triangles = 0;

  MeshOrientation& operator+=(const MeshOrientation& other);
};

// Winds every closed part of `mesh` (and every open one that still encloses
// a volume) counter-clockwise seen from outside, as the renderer's
// back-face culling needs, and reports the parts that are not closed.
// Published meshes come with faces flipped, parts inside out (a mirrored
// export) and open shells; the camera sees their surfaces whichever way
// they are wound. A part of zero volume (two faces back to back, a sheet)
// is left as it is; a triangle with a repeated corner belongs to no part.
MeshOrientation orient_parts(TriangleMesh& mesh);

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
