#include "urdf_prepare.h"

#include <tinyxml2.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "arttrack/tracker/error.h"
#include "config_geometry.h"
#include "mesh_convert.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using tinyxml2::XMLElement;

namespace {

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

// Mass and inertia of a link that has no <inertial>, from its geometry (its
// <collision> elements, else its <visual> ones): solid primitives of density
// kDerivedDensity_kg_m3 about their common centre of mass. A link without
// primitives (a frame, or meshes only) that moves on its own gets
// kFallbackMass_kg with a small isotropic inertia at its origin: MuJoCo needs
// mass on every moving body.
constexpr double kDerivedDensity_kg_m3 = 1000.0;
constexpr double kFallbackMass_kg = 0.01;
constexpr double kFallbackInertia_kg_m2 = 1e-5;

// Returns false (and adds nothing) for a link without primitives that does
// not move on its own: a frame welded to its parent needs no mass.
bool add_derived_inertial(tinyxml2::XMLDocument& doc, XMLElement* link, bool moving,
                          const std::string& context) {
  const char* kind = link->FirstChildElement("collision") ? "collision" : "visual";
  double mass_kg = 0;
  Eigen::Vector3d moment_kg_m = Eigen::Vector3d::Zero();  // sum of m c
  struct Part {
    double m;
    Eigen::Vector3d c;
    Eigen::Matrix3d I;  // about its own centre, link axes
  };
  std::vector<Part> parts;
  for (XMLElement* g = link->FirstChildElement(kind); g; g = g->NextSiblingElement(kind)) {
    const XMLElement* geometry = g->FirstChildElement("geometry");
    if (!geometry) continue;
    const Eigen::Isometry3d T = parse_origin(g, context);
    double volume_m3 = 0;
    Eigen::Vector3d unit;  // principal inertia per unit mass
    if (const XMLElement* box = geometry->FirstChildElement("box")) {
      const Eigen::Vector3d s =
          parse_vec3(box->Attribute("size"), Eigen::Vector3d::Zero(), context + " box");
      volume_m3 = s.prod();
      const Eigen::Vector3d s2 = s.cwiseAbs2();
      unit = Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y()) / 12.0;
    } else if (const XMLElement* cyl = geometry->FirstChildElement("cylinder")) {
      const double r = cyl->DoubleAttribute("radius"), l = cyl->DoubleAttribute("length");
      volume_m3 = M_PI * r * r * l;
      const double across = (3 * r * r + l * l) / 12.0;
      unit = Eigen::Vector3d(across, across, r * r / 2.0);
    } else if (const XMLElement* sphere = geometry->FirstChildElement("sphere")) {
      const double r = sphere->DoubleAttribute("radius");
      volume_m3 = 4.0 / 3.0 * M_PI * r * r * r;
      unit.setConstant(0.4 * r * r);
    }
    if (!(volume_m3 > 0)) continue;  // meshes and degenerate shapes
    const double m = kDerivedDensity_kg_m3 * volume_m3;
    parts.push_back(
        {m, T.translation(), T.linear() * (m * unit).asDiagonal() * T.linear().transpose()});
    mass_kg += m;
    moment_kg_m += m * T.translation();
  }
  Eigen::Vector3d com_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I = Eigen::Matrix3d::Identity() * kFallbackInertia_kg_m2;
  if (parts.empty()) {
    if (!moving) return false;
    mass_kg = kFallbackMass_kg;
  } else {
    com_m = moment_kg_m / mass_kg;
    I.setZero();
    for (const Part& p : parts) {  // parallel axis theorem
      const Eigen::Vector3d d = p.c - com_m;
      I += p.I + p.m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
    }
  }
  const auto text = [](std::initializer_list<double> values) {  // full precision
    std::ostringstream out;
    out.precision(17);
    for (const double v : values) out << (out.tellp() > 0 ? " " : "") << v;
    return out.str();
  };
  XMLElement* inertial = doc.NewElement("inertial");
  inertial->InsertNewChildElement("origin")->SetAttribute(
      "xyz", text({com_m.x(), com_m.y(), com_m.z()}).c_str());
  inertial->InsertNewChildElement("mass")->SetAttribute("value", text({mass_kg}).c_str());
  XMLElement* inertia = inertial->InsertNewChildElement("inertia");
  const char* names[6] = {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"};
  const int rows[6] = {0, 0, 0, 1, 1, 2}, cols[6] = {0, 1, 2, 1, 2, 2};
  for (int k = 0; k < 6; ++k) inertia->SetAttribute(names[k], text({I(rows[k], cols[k])}).c_str());
  link->InsertFirstChild(inertial);
  return true;
}

// Every mimic follows a movable joint, directly or through other mimics,
// without a cycle.
void check_mimics(const UrdfInfo& info, const std::string& where) {
  std::map<std::string, std::string> leader;
  for (const auto& m : info.mimics) leader[m.joint] = m.leader;
  for (const auto& m : info.mimics) {
    std::string j = m.joint;
    for (size_t steps = 0; leader.count(j); ++steps) {
      if (steps > leader.size())
        throw InputError(where + ": mimic joint '" + m.joint +
                         "' is part of a cycle of mimics; one of them must be a free joint");
      j = leader.at(j);
    }
    if (std::find(info.joint_names.begin(), info.joint_names.end(), j) == info.joint_names.end())
      throw InputError(where + ": mimic joint '" + m.joint + "' follows '" + j +
                       "', which is not a revolute, continuous or prismatic joint of the URDF");
  }
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
  std::set<std::string> moving_links;           // children of movable joints
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
    moving_links.insert(child_link);
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
  check_mimics(info, where);
  for (const auto& l : info.link_names)
    if (!children.count(l)) {
      if (!info.root_link.empty())
        throw InputError(where + ": links '" + info.root_link + "' and '" + l +
                         "' both have no parent; a URDF has one root");
      info.root_link = l;
    }
  if (info.root_link.empty()) throw InputError(where + ": no root link (a cycle of joints?)");
  // Links whose joints form a loop apart from the tree have a parent each,
  // so the root above is unique, but they hang from nothing.
  std::multimap<std::string, std::string> links_under;  // parent link -> child link
  for (XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const XMLElement* parent = j->FirstChildElement("parent");
    if (!parent || !parent->Attribute("link"))
      throw InputError(where + ": joint '" + j->Attribute("name") + "' has no parent link");
    links_under.emplace(parent->Attribute("link"),
                        j->FirstChildElement("child")->Attribute("link"));
  }
  std::set<std::string> reached{info.root_link};
  for (std::vector<std::string> todo{info.root_link}; !todo.empty();) {
    const std::string link = todo.back();
    todo.pop_back();
    for (auto [it, end] = links_under.equal_range(link); it != end; ++it)
      if (reached.insert(it->second).second) todo.push_back(it->second);
  }
  for (const auto& l : info.link_names)
    if (!reached.count(l))
      throw InputError(where + ": link '" + l + "' is not connected to the root link '" +
                       info.root_link +
                       "' (its joints form a loop); a URDF is a tree (no kinematic loops)");

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

  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    if (l->FirstChildElement("inertial")) continue;
    const std::string name = l->Attribute("name");
    if (add_derived_inertial(doc, l, moving_links.count(name) > 0, where + ": link '" + name + "'"))
      info.links_with_derived_inertia.push_back(name);
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
