#include "arttrack/sim/urdf_perturbation.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "arttrack/sim/internal/config_geometry.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/model_limits.h"
#include "arttrack/tracker/robot_model.h"
#include "urdf_xml.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using tinyxml2::XMLDocument;
using tinyxml2::XMLElement;

namespace {

// Full double precision, so a perturbation is exactly what was asked for.
std::string vec3_text(const Eigen::Vector3d& v) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "%.17g %.17g %.17g", v.x(), v.y(), v.z());
  return buf;
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

// Inverse of rpy_matrix (any of the equivalent angle triples).
Eigen::Vector3d matrix_rpy(const Eigen::Matrix3d& R) {
  const Eigen::Vector3d ypr = R.eulerAngles(2, 1, 0);  // R = Rz(a0) Ry(a1) Rx(a2)
  return {ypr[2], ypr[1], ypr[0]};
}

void write_origin(XMLDocument& doc, XMLElement* parent, const Eigen::Isometry3d& T) {
  XMLElement* o = parent->FirstChildElement("origin");
  if (!o) {
    o = doc.NewElement("origin");
    parent->InsertFirstChild(o);
  }
  o->SetAttribute("xyz", vec3_text(T.translation()).c_str());
  o->SetAttribute("rpy", vec3_text(matrix_rpy(T.linear())).c_str());
}

XMLElement* find_named(XMLElement* robot, const char* kind, const std::string& name) {
  for (XMLElement* e = robot->FirstChildElement(kind); e; e = e->NextSiblingElement(kind))
    if (const char* n = e->Attribute("name"); n && name == n) return e;
  return nullptr;
}

XMLElement* parent_joint_of(XMLElement* robot, const std::string& link) {
  for (XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const XMLElement* child = j->FirstChildElement("child");
    if (child && child->Attribute("link") && link == child->Attribute("link")) return j;
  }
  return nullptr;
}

bool is_finite(const Eigen::Isometry3d& T) { return T.matrix().allFinite(); }

// Scales every visual and collision shape of a link about the link frame.
void scale_link(XMLElement* link, double s, const std::string& context) {
  for (const char* kind : {"visual", "collision"}) {
    for (XMLElement* g = link->FirstChildElement(kind); g; g = g->NextSiblingElement(kind)) {
      if (XMLElement* o = g->FirstChildElement("origin"))
        o->SetAttribute(
            "xyz", vec3_text(s * parse_vec3(o->Attribute("xyz"), Eigen::Vector3d::Zero(), context))
                       .c_str());
      XMLElement* geometry = g->FirstChildElement("geometry");
      if (!geometry) continue;
      if (XMLElement* box = geometry->FirstChildElement("box"))
        box->SetAttribute("size", vec3_text(s * parse_vec3(box->Attribute("size"),
                                                           Eigen::Vector3d::Zero(), context))
                                      .c_str());
      if (XMLElement* c = geometry->FirstChildElement("cylinder")) {
        c->SetAttribute("radius", number_text(s * c->DoubleAttribute("radius", 0)).c_str());
        c->SetAttribute("length", number_text(s * c->DoubleAttribute("length", 0)).c_str());
      }
      if (XMLElement* sphere = geometry->FirstChildElement("sphere"))
        sphere->SetAttribute("radius",
                             number_text(s * sphere->DoubleAttribute("radius", 0)).c_str());
      if (XMLElement* mesh = geometry->FirstChildElement("mesh"))
        mesh->SetAttribute("scale", vec3_text(s * parse_vec3(mesh->Attribute("scale"),
                                                             Eigen::Vector3d::Ones(), context))
                                        .c_str());
    }
  }
}

}  // namespace

bool UrdfSummary::has_link(const std::string& name) const {
  return std::find(link_names.begin(), link_names.end(), name) != link_names.end();
}

bool UrdfSummary::has_joint(const std::string& name) const {
  return std::find(joint_names.begin(), joint_names.end(), name) != joint_names.end();
}

int UrdfSummary::movable_index(const std::string& name) const {
  const auto it = std::find(movable_joints.begin(), movable_joints.end(), name);
  return it == movable_joints.end() ? -1 : int(it - movable_joints.begin());
}

bool UrdfSummary::is_prismatic(const std::string& name) const {
  const int i = movable_index(name);
  return i >= 0 && movable_prismatic[std::size_t(i)] != 0;
}

UrdfSummary read_urdf_summary(const fs::path& urdf) {
  const std::string where = urdf.string();
  XMLDocument doc;
  const XMLElement* robot = load_urdf_document(urdf, doc);
  UrdfSummary s;
  s.path = urdf;
  for (const XMLElement* l = robot->FirstChildElement("link"); l;
       l = l->NextSiblingElement("link")) {
    if (!l->Attribute("name")) throw InputError(where + ": a <link> has no name");
    s.link_names.push_back(l->Attribute("name"));
  }
  for (const XMLElement* j = robot->FirstChildElement("joint"); j;
       j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    const char* type = j->Attribute("type");
    if (!name || !type) throw InputError(where + ": a <joint> has no name or type");
    s.joint_names.push_back(name);
    const std::string t = type;
    if (t != "revolute" && t != "continuous" && t != "prismatic") continue;
    if (j->FirstChildElement("mimic")) continue;
    JointLimit limit;
    const XMLElement* l = j->FirstChildElement("limit");
    if (t != "continuous" && l && l->Attribute("lower") && l->Attribute("upper")) {
      limit.lower_rad = l->DoubleAttribute("lower");
      limit.upper_rad = l->DoubleAttribute("upper");
    }
    s.movable_joints.push_back(name);
    s.movable_limits.push_back(limit);
    s.movable_prismatic.push_back(t == "prismatic");
  }
  check_model_count(where, s.link_names.size(), ModelLimits::kMaxLinks, "links");
  check_model_count(where, s.joint_names.size(), ModelLimits::kMaxJoints, "joints");
  std::map<std::string, std::string> parent_of;  // child link -> parent link
  for (const XMLElement* j = robot->FirstChildElement("joint"); j;
       j = j->NextSiblingElement("joint")) {
    const XMLElement* parent = j->FirstChildElement("parent");
    const XMLElement* child = j->FirstChildElement("child");
    if (parent && child && parent->Attribute("link") && child->Attribute("link"))
      parent_of.emplace(child->Attribute("link"), parent->Attribute("link"));
  }
  check_chain_depth(where, parent_of);
  return s;
}

bool UrdfPerturbation::empty() const {
  return T_nominal_true_camera.isApprox(Eigen::Isometry3d::Identity(), 0.0) &&
         joint_changes.empty() && origin_extension_m.empty() && link_scale.empty();
}

void perturb_urdf_document(XMLDocument& doc, const std::string& source, const UrdfPerturbation& p) {
  XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw InputError(source + ": no <robot> element");

  auto joint = [&](const std::string& name, const std::string& what) {
    XMLElement* j = find_named(robot, "joint", name);
    if (!j) throw InputError(source + ": " + what + ": no joint '" + name + "' in the URDF");
    return j;
  };

  // 0. The scene's camera mount: a new link on a fixed joint.
  if (p.camera_mount) {
    const CameraMount& m = *p.camera_mount;
    const std::string what = source + ": camera mount";
    if (!is_finite(m.T_parent_camera)) throw InputError(what + " is not finite");
    if (find_named(robot, "link", p.camera_link))
      throw InputError(what + ": the URDF already has a link '" + p.camera_link +
                       "'; name the mounted camera's link otherwise (camera.link) or drop "
                       "camera.mount to use that link");
    std::string parent = m.parent_link;
    if (parent.empty()) {  // the world: the root link
      for (XMLElement* l = robot->FirstChildElement("link"); l && parent.empty();
           l = l->NextSiblingElement("link"))
        if (l->Attribute("name") && !parent_joint_of(robot, l->Attribute("name")))
          parent = l->Attribute("name");
    } else if (!find_named(robot, "link", parent)) {
      throw InputError(what + ": parent '" + parent +
                       "' is not a link of the URDF (name one of its links, or world)");
    }
    XMLElement* link = robot->InsertNewChildElement("link");
    link->SetAttribute("name", p.camera_link.c_str());
    XMLElement* j = robot->InsertNewChildElement("joint");
    j->SetAttribute("name", (p.camera_link + "_mount").c_str());
    j->SetAttribute("type", "fixed");
    j->InsertNewChildElement("parent")->SetAttribute("link", parent.c_str());
    j->InsertNewChildElement("child")->SetAttribute("link", p.camera_link.c_str());
    write_origin(doc, j, m.T_parent_camera);
  }

  // 1. Link lengths: the joint origin moves along its own translation.
  for (const auto& [name, extension_m] : p.origin_extension_m) {
    const std::string what = "link length change of joint '" + name + "'";
    XMLElement* j = joint(name, "link length change");
    if (!std::isfinite(extension_m)) throw InputError(source + ": " + what + " is not finite");
    Eigen::Isometry3d T = parse_origin(j, source + ": joint '" + name + "'");
    const double length = T.translation().norm();
    if (length < 1e-9)
      throw InputError(source + ": " + what +
                       ": the joint's origin has no translation to lengthen");
    if (length + extension_m <= 0)
      throw InputError(source + ": " + what + " of " + number_text(extension_m) +
                       " m would shorten it below zero (length " + number_text(length) + " m)");
    T.translation() *= (length + extension_m) / length;
    write_origin(doc, j, T);
  }

  // 2. Joint origin and axis changes.
  for (const JointOriginChange& c : p.joint_changes) {
    XMLElement* j = joint(c.joint, "joint change");
    const std::string context = source + ": joint '" + c.joint + "'";
    if (!is_finite(c.T_old_new) || !c.R_axis.allFinite())
      throw InputError(context + ": the change is not finite");
    write_origin(doc, j, parse_origin(j, context) * c.T_old_new);
    XMLElement* axis = j->FirstChildElement("axis");
    if (!axis) {
      axis = doc.NewElement("axis");
      j->InsertEndChild(axis);
    }
    const Eigen::Vector3d a = parse_vec3(axis->Attribute("xyz"), Eigen::Vector3d::UnitX(), context);
    if (a.norm() < 1e-12) throw InputError(context + ": axis is zero");
    axis->SetAttribute("xyz", vec3_text((c.R_axis * a.normalized()).normalized()).c_str());
  }

  // 3. Camera offset, composed after everything else on its parent joint.
  if (!p.T_nominal_true_camera.isApprox(Eigen::Isometry3d::Identity(), 0.0)) {
    if (!is_finite(p.T_nominal_true_camera))
      throw InputError(source + ": camera offset is not finite");
    if (!find_named(robot, "link", p.camera_link))
      throw InputError(source + ": camera offset: no link '" + p.camera_link + "' in the URDF");
    XMLElement* j = parent_joint_of(robot, p.camera_link);
    if (!j)
      throw InputError(source + ": camera offset: camera link '" + p.camera_link +
                       "' has no parent joint to move");
    write_origin(doc, j, parse_origin(j, source + ": camera joint") * p.T_nominal_true_camera);
  }

  // 4. Shapes.
  for (const auto& [name, scale] : p.link_scale) {
    XMLElement* l = find_named(robot, "link", name);
    if (!l) throw InputError(source + ": shape scale: no link '" + name + "' in the URDF");
    if (!(scale > 0) || !std::isfinite(scale))
      throw InputError(source + ": shape scale of link '" + name + "' must be > 0, got " +
                       number_text(scale));
    scale_link(l, scale, source + ": link '" + name + "'");
  }
}

std::string perturb_urdf_text(const std::string& xml, const std::string& source,
                              const fs::path& urdf_dir,
                              const std::map<std::string, fs::path>& package_paths,
                              const UrdfPerturbation& p) {
  XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw InputError(source + ": malformed URDF XML: " + (doc.ErrorStr() ? doc.ErrorStr() : ""));
  XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw InputError(source + ": no <robot> element");
  perturb_urdf_document(doc, source, p);

  // Absolute mesh paths: the copy lives elsewhere.
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    for (const char* kind : {"visual", "collision"}) {
      for (XMLElement* g = l->FirstChildElement(kind); g; g = g->NextSiblingElement(kind)) {
        XMLElement* geometry = g->FirstChildElement("geometry");
        XMLElement* mesh = geometry ? geometry->FirstChildElement("mesh") : nullptr;
        if (!mesh || !mesh->Attribute("filename")) continue;
        const std::string filename = mesh->Attribute("filename");
        const fs::path resolved = resolve_mesh_path(filename, urdf_dir, package_paths);
        if (resolved.empty())
          throw InputError(source + ": link '" + std::string(l->Attribute("name")) + "' mesh '" +
                           filename +
                           "': unknown package (give its folder in the scene's robot.packages)");
        mesh->SetAttribute("filename", fs::absolute(resolved).lexically_normal().c_str());
      }
    }
  }

  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

PerturbedUrdf::PerturbedUrdf(const fs::path& urdf,
                             const std::map<std::string, fs::path>& package_paths,
                             const UrdfPerturbation& perturbation) {
  std::ifstream in(urdf);
  if (!in || !fs::is_regular_file(urdf)) throw InputError(urdf.string() + ": URDF file not found");
  std::stringstream text;
  text << in.rdbuf();
  const std::string perturbed = perturb_urdf_text(
      text.str(), urdf.string(), fs::absolute(urdf).parent_path(), package_paths, perturbation);
  std::string tmpl = (fs::temp_directory_path() / "arttrack_urdf_XXXXXX").string();
  if (!mkdtemp(tmpl.data()))
    throw InputError("cannot create a temporary folder in " + fs::temp_directory_path().string());
  dir_ = tmpl;
  path_ = dir_ / urdf.filename();
  std::ofstream out(path_);
  out << perturbed;
  if (!out) {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    throw InputError(urdf.string() + ": cannot write its perturbed copy in the temporary folder " +
                     dir_.string());
  }
}

std::string perturbed_urdf_text(const SceneDescription& scene, const fs::path& urdf,
                                UrdfPerturbation changes) {
  std::ifstream in(urdf);
  if (!in || !fs::is_regular_file(urdf)) throw InputError(urdf.string() + ": URDF file not found");
  std::stringstream text;
  text << in.rdbuf();
  changes.camera_link = scene.camera_link;
  changes.camera_mount = scene.camera_mount;
  return perturb_urdf_text(text.str(), urdf.string(), fs::absolute(urdf).parent_path(),
                           scene.package_paths, changes);
}

std::string mounted_urdf_text(const SceneDescription& scene, const fs::path& urdf) {
  return perturbed_urdf_text(scene, urdf, {});
}

RobotModel tracker_robot_model(const SceneDescription& scene, const fs::path& urdf,
                               RobotModelOptions options) {
  options.camera_frame = scene.camera_link;
  for (const auto& [name, dir] : scene.package_paths) options.mesh_search_paths.push_back(dir);
  return RobotModel::from_urdf_string(mounted_urdf_text(scene, urdf),
                                      fs::absolute(urdf).parent_path().string(), options,
                                      urdf.string());
}

PerturbedUrdf::~PerturbedUrdf() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

}  // namespace arttrack::sim
