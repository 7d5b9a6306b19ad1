// Mesh conversion for MuJoCo 2.2, which reads only binary STL of at most
// 200 000 triangles (and simple OBJ): everything else, and every file whose
// name may collide, is rewritten as binary STL.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "arttrack/tracker/mesh_loader.h"

namespace arttrack::sim {

// MuJoCo 2.2 reads STL files of at most this many triangles.
constexpr std::uint64_t kMaxStlTriangles = 200000;

// What convert_mesh_to_binary_stl wrote.
struct ConvertedMesh {
  std::vector<std::filesystem::path> files;  // one, or parts of kMaxStlTriangles
  std::uint64_t triangles = 0;
  // Every vertex in one plane (within a millionth of the mesh's size): no
  // volume, which MuJoCo 2.2 cannot take as a collision shape (its convex
  // hull fails).
  bool flat = false;
  // What orient_parts() found (the tracker's loader does the same): parts
  // that enclose a volume are written wound outward, the others as they were.
  MeshOrientation orientation;
};

// Writes the mesh at `source` as binary STL: all sub-meshes merged, node
// transforms baked in (a COLLADA file's unit is applied, its up_axis is not,
// as in ROS), each vertex multiplied by `scale`, winding kept outward for
// mirroring scales and parts that enclose a volume turned outward
// (orient_parts(): MuJoCo culls back faces, so a part exported inside out
// would show its far side). Binary STL input is read directly (assimp
// misreads binary STL whose header starts with "solid"); everything else
// goes through assimp. The file is `target_stem`.stl, or, past kMaxStlTriangles,
// parts `target_stem`.stl, `target_stem`_1.stl, ... of at most that many.
// Unreadable or empty meshes, or more than `max_triangles` (checked before
// reading a binary STL): InputError naming `context` (the URDF and mesh
// element).
ConvertedMesh convert_mesh_to_binary_stl(const std::filesystem::path& source,
                                         const std::filesystem::path& target_stem,
                                         const Eigen::Vector3d& scale, const std::string& context,
                                         std::uint64_t max_triangles);

}  // namespace arttrack::sim
