// Checks of a triangle mesh's shape that the mesh loader's and the mesh
// simplifier's tests both make: what it encloses, and whether its surface is
// closed and consistently wound.
#pragma once

#include <Eigen/Dense>

#include <map>
#include <utility>

#include "arttrack/tracker/mesh_loader.h"

namespace arttrack::test_support {

// Volume enclosed by a closed mesh (divergence theorem), m^3; positive when
// the triangles face outwards.
inline double signed_volume_m3(const TriangleMesh& mesh) {
  double volume = 0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices_m[t[0]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices_m[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices_m[t[2]].cast<double>();
    volume += a.dot(b.cross(c)) / 6;
  }
  return volume;
}

// Every directed edge is matched by the opposite edge of exactly one other
// triangle: the surface is closed and consistently wound.
inline bool closed_and_consistent(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const Eigen::Vector3i& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return true;
}

}  // namespace arttrack::test_support
