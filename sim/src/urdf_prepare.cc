#include "urdf_prepare.h"

#include <tinyxml2.h>

#include <fstream>
#include <map>
#include <sstream>

#include "arttrack/tracker/error.h"
#include "mesh_convert.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using tinyxml2::XMLElement;

namespace {

Eigen::Vector3d parse_vec3(const char* text, const Eigen::Vector3d& fallback,
                           const std::string& context) {
  if (!text) return fallback;
  std::istringstream in(text);
  Eigen::Vector3d v;
  if (!(in >> v.x() >> v.y() >> v.z()))
    throw InputError(context + ": expected three numbers, got '" + text + "'");
  return v;
}

// URDF <origin xyz rpy>: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Isometry3d parse_origin(const XMLElement* parent, const std::string& context) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const XMLElement* o = parent->FirstChildElement("origin");
  if (!o) return T;
  T.translation() = parse_vec3(o->Attribute("xyz"), Eigen::Vector3d::Zero(), context + " origin");
  const Eigen::Vector3d rpy =
      parse_vec3(o->Attribute("rpy"), Eigen::Vector3d::Zero(), context + " origin");
  T.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

bool package_xml_names(const fs::path& dir, const std::string& name) {
  std::ifstream in(dir / "package.xml");
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str().find("<name>" + name + "</name>") != std::string::npos;
}

// ROS-like lookup without ROS: a folder of that name (or with a package.xml
// naming it) among the URDF's ancestors, or a sibling of one of them.
fs::path find_package(const std::string& name, const fs::path& urdf_dir) {
  for (fs::path d = urdf_dir; !d.empty(); d = d.parent_path()) {
    if (d.filename() == name || package_xml_names(d, name)) return d;
    if (fs::is_directory(d / name)) return d / name;
    if (d == d.parent_path()) break;
  }
  return {};
}

}  // namespace

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
      root = find_package(name, urdf_dir);
    if (root.empty()) return {};
    return root / inside;
  }
  fs::path p =
      filename.rfind(kFile, 0) == 0 ? fs::path(filename.substr(kFile.size())) : fs::path(filename);
  return p.is_absolute() ? p : urdf_dir / p;
}

UrdfInfo prepare_urdf(const fs::path& urdf, const std::map<std::string, fs::path>& package_paths,
                      const fs::path& work_dir) {
  const std::string where = urdf.string();
  if (!fs::is_regular_file(urdf)) throw InputError(where + ": URDF file not found");
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(urdf.string().c_str()) != tinyxml2::XML_SUCCESS)
    throw InputError(where + ": malformed URDF XML: " + (doc.ErrorStr() ? doc.ErrorStr() : ""));
  XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw InputError(where + ": no <robot> element");

  UrdfInfo info;
  info.source = urdf;
  const fs::path urdf_dir = fs::absolute(urdf).parent_path();

  std::map<std::string, std::string> children;  // link -> the joint it is the child of
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    const char* name = l->Attribute("name");
    if (!name) throw InputError(where + ": a <link> has no name");
    info.link_names.push_back(name);
  }
  for (XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    const char* type = j->Attribute("type");
    if (!name || !type) throw InputError(where + ": a <joint> has no name or type");
    const std::string context = where + ": joint '" + std::string(name) + "'";
    const XMLElement* child = j->FirstChildElement("child");
    if (!child || !child->Attribute("link")) throw InputError(context + " has no child link");
    const std::string child_link = child->Attribute("link");
    if (const auto [it, added] = children.emplace(child_link, name); !added)
      throw InputError(where + ": link '" + child_link + "' is the child of joints '" + it->second +
                       "' and '" + name + "'; a URDF is a tree (no kinematic loops)");
    info.T_parent_link[child_link] = parse_origin(j, context);
    const std::string t = type;
    const bool movable = t == "revolute" || t == "continuous" || t == "prismatic";
    if (!movable) continue;
    if (const XMLElement* mimic = j->FirstChildElement("mimic")) {
      if (!mimic->Attribute("joint")) throw InputError(context + ": <mimic> names no joint");
      info.mimics.push_back({name, mimic->Attribute("joint"),
                             mimic->DoubleAttribute("multiplier", 1.0),
                             mimic->DoubleAttribute("offset", 0.0)});
      continue;
    }
    const XMLElement* axis = j->FirstChildElement("axis");
    const Eigen::Vector3d a =
        parse_vec3(axis ? axis->Attribute("xyz") : nullptr, Eigen::Vector3d::UnitX(), context);
    if (a.norm() < 1e-12) throw InputError(context + ": axis is zero");
    info.joint_axis[name] = a.normalized();
    const XMLElement* limit = j->FirstChildElement("limit");
    info.joint_effort[name] = limit ? limit->DoubleAttribute("effort", 0.0) : 0.0;
    info.joint_names.push_back(name);
  }
  for (const auto& l : info.link_names)
    if (!children.count(l)) {
      if (!info.root_link.empty())
        throw InputError(where + ": links '" + info.root_link + "' and '" + l +
                         "' both have no parent; a URDF has one root");
      info.root_link = l;
    }
  if (info.root_link.empty()) throw InputError(where + ": no root link (a cycle of joints?)");

  // Every mesh becomes <work_dir>/m<k>_<stem>.stl: unique even when two files
  // share a base name, and converted once per (file, scale).
  std::map<std::pair<std::string, std::string>, std::string> converted;
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    for (const char* kind : {"visual", "collision"}) {
      for (XMLElement* g = l->FirstChildElement(kind); g; g = g->NextSiblingElement(kind)) {
        XMLElement* geometry = g->FirstChildElement("geometry");
        XMLElement* mesh = geometry ? geometry->FirstChildElement("mesh") : nullptr;
        if (!mesh) continue;
        const std::string context =
            where + ": link '" + l->Attribute("name") + "' " + kind + " mesh";
        const char* filename = mesh->Attribute("filename");
        if (!filename) throw InputError(context + " has no filename");
        const fs::path path = resolve_mesh_path(filename, urdf_dir, package_paths);
        if (path.empty())
          throw InputError(context + " '" + filename +
                           "': unknown package (give its folder in the scene's robot.packages)");
        const char* scale_text = mesh->Attribute("scale");
        const Eigen::Vector3d scale = parse_vec3(scale_text, Eigen::Vector3d::Ones(), context);
        const auto key = std::make_pair(fs::weakly_canonical(path).string(),
                                        std::string(scale_text ? scale_text : "1 1 1"));
        auto it = converted.find(key);
        if (it == converted.end()) {
          std::string out = "m";
          out += std::to_string(converted.size());
          out += '_';
          out += path.stem().string();
          out += ".stl";
          convert_mesh_to_binary_stl(path, work_dir / out, scale, context + " '" + filename + "'");
          it = converted.emplace(key, out).first;
        }
        mesh->SetAttribute("filename", it->second.c_str());
        mesh->DeleteAttribute("scale");
      }
    }
  }

  // Replace any MuJoCo block of the user's with ours.
  while (XMLElement* m = robot->FirstChildElement("mujoco")) robot->DeleteChild(m);
  XMLElement* mujoco = doc.NewElement("mujoco");
  XMLElement* compiler = doc.NewElement("compiler");
  compiler->SetAttribute("discardvisual", "false");
  compiler->SetAttribute("fusestatic", "false");
  compiler->SetAttribute("strippath", "false");
  compiler->SetAttribute("meshdir", work_dir.string().c_str());
  // Real URDFs often break the triangle inequality of inertias slightly.
  compiler->SetAttribute("balanceinertia", "true");
  mujoco->InsertEndChild(compiler);
  robot->InsertFirstChild(mujoco);

  info.prepared_urdf = work_dir / "robot.urdf";
  if (doc.SaveFile(info.prepared_urdf.string().c_str()) != tinyxml2::XML_SUCCESS)
    throw InputError(where + ": cannot write prepared copy '" + info.prepared_urdf.string() + "'");
  return info;
}

}  // namespace arttrack::sim
