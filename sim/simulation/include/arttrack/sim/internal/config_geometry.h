// Geometry as the simulator's inputs write it: fixed-size number lists of
// scenario and scene YAML (`position_m: [0.5, 0, 0.8]`) and URDF's
// roll-pitch-yaw rotations (URDF `<origin xyz rpy>` elements: urdf_xml.h).
// Internal to the testbed (simulation and evaluation).
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <vector>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {

// URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll), angles in radians.
inline Eigen::Matrix3d rpy_matrix(const Eigen::Vector3d& rpy_rad) {
  return (Eigen::AngleAxisd(rpy_rad.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy_rad.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy_rad.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// The list of N finite numbers at `key` of `n`, or `fallback` when the key
// is absent. Fails (ConfigNode::fail: file, key, problem) for anything else.
template <int N>
Eigen::Matrix<double, N, 1> vec(const ConfigNode& n, const std::string& key,
                                const Eigen::Matrix<double, N, 1>& fallback) {
  if (!n.has(key)) return fallback;
  std::vector<double> v;
  try {
    v = n.required<std::vector<double>>(key);
  } catch (const InputError&) {
    n.fail(key, "must be a list of " + std::to_string(N) + " numbers");
  }
  if (int(v.size()) != N) n.fail(key, "must be a list of " + std::to_string(N) + " numbers");
  Eigen::Matrix<double, N, 1> out;
  for (int i = 0; i < N; ++i) {
    if (!std::isfinite(v[i])) n.fail(key, "must hold finite numbers");
    out[i] = v[i];
  }
  return out;
}

}  // namespace arttrack::sim
