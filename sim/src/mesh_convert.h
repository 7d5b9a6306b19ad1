// Mesh conversion for MuJoCo 2.2, which reads only binary STL (and simple
// OBJ): everything else, and every file whose name may collide, is rewritten
// as a binary STL.
#pragma once

#include <Eigen/Geometry>

#include <filesystem>
#include <string>

namespace arttrack::sim {

// Writes the mesh at `source` as a binary STL at `target`: all sub-meshes
// merged, node transforms baked in (a COLLADA file's unit is applied, its
// up_axis is not, as in ROS), each vertex multiplied by `scale`, winding kept
// outward for mirroring scales. Binary STL input is read directly (assimp
// misreads binary STL whose header starts with "solid"); everything else goes
// through assimp. Returns the number of triangles written. Unreadable,
// empty or too large (over MuJoCo's 200000 faces) meshes: InputError
// naming `context` (the URDF and mesh element).
int convert_mesh_to_binary_stl(const std::filesystem::path& source,
                               const std::filesystem::path& target, const Eigen::Vector3d& scale,
                               const std::string& context);

}  // namespace arttrack::sim
