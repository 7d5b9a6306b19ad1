// A URDF as a tinyxml2 document, shared by the preparation for MuJoCo
// (urdf_prepare.cc) and the perturbation (urdf_perturbation.cc): reading the
// file, the numbers and poses of its attributes, its mesh paths, and the
// perturbation applied to a parsed document. Internal to
// arttrack_sim_simulation.
#pragma once

#include <Eigen/Geometry>

#include <filesystem>
#include <map>
#include <string>

#include "arttrack/sim/urdf_perturbation.h"

namespace tinyxml2 {
class XMLDocument;
class XMLElement;
}  // namespace tinyxml2

namespace arttrack::sim {

// Reads the URDF file `urdf` into `doc` and returns its <robot> element. A
// xacro file, a missing file, one past ModelLimits::kMaxUrdfBytes, XML
// entity declarations, malformed XML or no <robot>: InputError naming the
// file.
tinyxml2::XMLElement* load_urdf_document(const std::filesystem::path& urdf,
                                         tinyxml2::XMLDocument& doc);

// Resolves a URDF mesh file name (package://, file://, relative, absolute).
// Returns an empty path if a package is unknown.
std::filesystem::path resolve_mesh_path(
    const std::string& filename, const std::filesystem::path& urdf_dir,
    const std::map<std::string, std::filesystem::path>& package_paths);

// Three numbers from a URDF attribute ("0 0.1 0.2"), or `fallback` when the
// attribute is absent (null). Throws InputError naming `context` otherwise.
Eigen::Vector3d parse_vec3(const char* text, const Eigen::Vector3d& fallback,
                           const std::string& context);

// The pose a URDF element's `<origin xyz rpy>` child gives (identity when
// it has none). Throws InputError naming `context` for a bad attribute.
Eigen::Isometry3d parse_origin(const tinyxml2::XMLElement* parent, const std::string& context);

// Applies `perturbation` to a parsed URDF in place (urdf_perturbation.h's
// rules; elements keep their line numbers). Errors name `source`. Defined
// in urdf_perturbation.cc; prepare_urdf applies it before converting.
void perturb_urdf_document(tinyxml2::XMLDocument& doc, const std::string& source,
                           const UrdfPerturbation& perturbation);

}  // namespace arttrack::sim
