#include "urdf_xml.h"

#include <tinyxml2.h>

#include <fstream>
#include <sstream>

#include "arttrack/sim/internal/config_geometry.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/model_limits.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using tinyxml2::XMLElement;

XMLElement* load_urdf_document(const fs::path& urdf, tinyxml2::XMLDocument& doc) {
  const std::string where = urdf.string();
  check_not_xacro(where);
  if (!fs::is_regular_file(urdf)) throw InputError(where + ": URDF file not found");
  check_urdf_file_size(urdf);
  std::ifstream in(urdf, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw InputError(where + ": cannot read the URDF file");
  check_urdf_text(text.str(), where);
  if (doc.Parse(text.str().c_str(), text.str().size()) != tinyxml2::XML_SUCCESS)
    throw InputError(where + ": malformed URDF XML: " + (doc.ErrorStr() ? doc.ErrorStr() : ""));
  XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw InputError(where + ": no <robot> element");
  return robot;
}

fs::path resolve_mesh_path(const std::string& filename, const fs::path& urdf_dir,
                           const std::map<std::string, fs::path>& package_paths) {
  const std::string kPackage = "package://", kFile = "file://";
  if (filename.rfind(kPackage, 0) == 0) {
    const std::string rest = filename.substr(kPackage.size());
    const auto slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    fs::path root;
    if (auto it = package_paths.find(name); it != package_paths.end())
      root = it->second;
    else
      root = find_package_folder(name, urdf_dir);
    if (root.empty()) return {};
    return root / inside;
  }
  fs::path p =
      filename.rfind(kFile, 0) == 0 ? fs::path(filename.substr(kFile.size())) : fs::path(filename);
  return p.is_absolute() ? p : urdf_dir / p;
}

Eigen::Vector3d parse_vec3(const char* text, const Eigen::Vector3d& fallback,
                           const std::string& context) {
  if (!text) return fallback;
  std::istringstream in(text);
  Eigen::Vector3d v;
  if (!(in >> v.x() >> v.y() >> v.z()))
    throw InputError(context + ": expected three numbers, got '" + text + "'");
  return v;
}

Eigen::Isometry3d parse_origin(const XMLElement* parent, const std::string& context) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const XMLElement* o = parent->FirstChildElement("origin");
  if (!o) return T;
  T.translation() = parse_vec3(o->Attribute("xyz"), Eigen::Vector3d::Zero(), context + " origin");
  T.linear() =
      rpy_matrix(parse_vec3(o->Attribute("rpy"), Eigen::Vector3d::Zero(), context + " origin"));
  return T;
}

}  // namespace arttrack::sim
