#include "urdf_prepare.h"

#include <tinyxml2.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "arttrack/sim/internal/config_geometry.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/model_limits.h"
#include "arttrack/tracker/robot_model.h"
#include "mesh_convert.h"
#include "urdf_xml.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using tinyxml2::XMLElement;

namespace {

// "<where>:<line>" of an element of the user's file; `where` alone for one
// arttrack added (line 0).
std::string at(const std::string& where, const XMLElement* e) {
  const int line = e ? e->GetLineNum() : 0;
  return line > 0 ? where + ":" + std::to_string(line) : where;
}

// Elements urdfdom reads several of, by parent; everything else it reads
// with FirstChildElement, so a repeat is ignored there.
bool may_repeat(const std::string& parent, const std::string& child) {
  if (parent == "robot") return child == "link" || child == "joint" || child == "material";
  if (parent == "link") return child == "visual" || child == "collision";
  return false;
}

void drop_repeats(XMLElement* e) {
  const std::string name = e->Name();
  std::set<std::string> seen;
  for (XMLElement* c = e->FirstChildElement(); c;) {
    XMLElement* next = c->NextSiblingElement();
    // A <geometry> is its first shape, whatever follows.
    if ((name == "geometry" && c != e->FirstChildElement()) ||
        (!seen.insert(c->Name()).second && !may_repeat(name, c->Name()))) {
      e->DeleteChild(c);
    } else {
      drop_repeats(c);
    }
    c = next;
  }
}

// urdfdom's colour: four numbers in [0, 1].
bool valid_rgba(const char* text) {
  if (!text) return false;
  std::istringstream in(text);
  int count = 0;
  for (double v; in >> v; ++count)
    if (!(v >= 0 && v <= 1)) return false;
  return count == 4 && in.eof();
}

void drop_bad_colors(XMLElement* e) {
  for (XMLElement* c = e->FirstChildElement(); c;) {
    XMLElement* next = c->NextSiblingElement();
    if (std::string(c->Name()) == "color" && !valid_rgba(c->Attribute("rgba")))
      e->DeleteChild(c);
    else
      drop_bad_colors(c);
    c = next;
  }
}

// Why a primitive shape has no volume ("" if it has one): MuJoCo needs
// positive sizes.
std::string shape_problem(const XMLElement* shape, const std::string& context) {
  const std::string kind = shape->Name();
  std::vector<std::pair<std::string, double>> sizes;
  if (kind == "box") {
    const Eigen::Vector3d s =
        parse_vec3(shape->Attribute("size"), Eigen::Vector3d::Zero(), context + " box");
    sizes = {{"size x", s.x()}, {"size y", s.y()}, {"size z", s.z()}};
  } else if (kind == "cylinder") {
    sizes = {{"radius", shape->DoubleAttribute("radius")},
             {"length", shape->DoubleAttribute("length")}};
  } else if (kind == "sphere") {
    sizes = {{"radius", shape->DoubleAttribute("radius")}};
  }
  for (const auto& [name, v] : sizes)
    if (!(v > 0) || !std::isfinite(v)) {
      std::ostringstream os;
      os << kind << " " << name << " " << v;
      return os.str();
    }
  return "";
}

// Why MuJoCo would refuse an <inertial> on a moving body ("" if it would
// not): mass and the inertia's eigenvalues must be positive (mjMINVAL).
std::string inertial_problem(const XMLElement* inertial) {
  constexpr double kMin = 1e-15;
  const XMLElement* mass = inertial->FirstChildElement("mass");
  const double m = mass ? mass->DoubleAttribute("value", 0.0) : 0.0;
  if (!(m >= kMin) || !std::isfinite(m)) {
    std::ostringstream os;
    os << "mass " << m;
    return os.str();
  }
  const XMLElement* i = inertial->FirstChildElement("inertia");
  if (!i) return "no <inertia>";
  Eigen::Matrix3d I;
  I << i->DoubleAttribute("ixx"), i->DoubleAttribute("ixy"), i->DoubleAttribute("ixz"),
      i->DoubleAttribute("ixy"), i->DoubleAttribute("iyy"), i->DoubleAttribute("iyz"),
      i->DoubleAttribute("ixz"), i->DoubleAttribute("iyz"), i->DoubleAttribute("izz");
  if (!I.allFinite()) return "an inertia that is not finite";
  const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues()[0];
  if (!(smallest >= kMin)) return "an inertia that is not positive definite";
  return "";
}

// Mass and inertia of a link that has no <inertial>, from its geometry (its
// <collision> elements, else its <visual> ones): solid primitives of density
// kDerivedDensity_kg_m3 about their common centre of mass. A link without
// primitives (a frame, or meshes only) that moves on its own gets
// kFallbackMass_kg with a small isotropic inertia at its origin: MuJoCo needs
// mass on every moving body. So does a welded link of two or more visual
// meshes and no collision shape (MuJoCo: "body mass is too small, cannot
// compute center of mass" for several massless geoms).
constexpr double kDerivedDensity_kg_m3 = 1000.0;
constexpr double kFallbackMass_kg = 0.01;
constexpr double kFallbackInertia_kg_m2 = 1e-5;

// Returns false (and adds nothing) for a link without primitives that does
// not move on its own and has at most one visual mesh: a frame welded to its
// parent needs no mass.
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
    int visuals = 0;
    for (XMLElement* v = link->FirstChildElement("visual"); v; v = v->NextSiblingElement("visual"))
      ++visuals;
    if (!moving && (visuals < 2 || link->FirstChildElement("collision"))) return false;
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

void normalise_urdf(XMLElement* robot) {
  for (XMLElement* e = robot->FirstChildElement(); e;) {
    XMLElement* next = e->NextSiblingElement();
    const std::string name = e->Name();
    if (name != "link" && name != "joint" && name != "material") robot->DeleteChild(e);
    e = next;
  }
  drop_repeats(robot);
  drop_bad_colors(robot);
  for (XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* type = j->Attribute("type");
    if (XMLElement* limit = j->FirstChildElement("limit");
        limit && type && std::string(type) == "continuous") {
      limit->DeleteAttribute("lower");
      limit->DeleteAttribute("upper");
    }
  }
}

std::string UrdfInfo::retell(const std::string& mujoco_error) const {
  const MujocoError e = parse_mujoco_error(mujoco_error);
  std::string out = source.string();
  if (const auto it = source_line.find(e.line); e.line > 0 && it != source_line.end()) {
    out += ':';
    out += std::to_string(it->second);
  }
  out += ": MuJoCo 2.2 cannot load it: " + e.what;
  if (!e.element.empty()) out += " (element <" + e.element + ">)";
  if (!e.object.empty()) out += " ('" + e.object + "')";
  return out;
}

MujocoError parse_mujoco_error(const std::string& text) {
  MujocoError e;
  std::istringstream in(text);
  std::string line;
  std::getline(in, e.what);
  for (const char* prefix : {"XML Error: ", "Error: "})
    if (e.what.rfind(prefix, 0) == 0) e.what = e.what.substr(std::string(prefix).size());
  while (std::getline(in, line)) {
    const std::string kElement = "Element '", kObject = "Object name = ";
    if (line.rfind(kElement, 0) == 0) {
      const auto quote = line.find('\'', kElement.size());
      e.element = line.substr(kElement.size(), quote - kElement.size());
      if (const auto l = line.find("line "); l != std::string::npos)
        e.line = std::atoi(line.c_str() + l + 5);
    } else if (line.rfind(kObject, 0) == 0) {
      e.object = line.substr(kObject.size(), line.find(',') - kObject.size());
    }
  }
  return e;
}

namespace {

void preorder(const XMLElement* e, std::vector<const XMLElement*>& out) {
  out.push_back(e);
  for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
    preorder(c, out);
}

// Prepared line -> the user's line, element by element: the saved copy read
// back has the same elements in the same order as `doc`, whose elements
// still carry the lines of the user's file (0 for those arttrack added).
std::map<int, int> line_map(const tinyxml2::XMLDocument& doc, const fs::path& saved) {
  std::map<int, int> lines;
  tinyxml2::XMLDocument reread;
  if (reread.LoadFile(saved.string().c_str()) != tinyxml2::XML_SUCCESS) return lines;
  std::vector<const XMLElement*> original, prepared;
  if (doc.RootElement()) preorder(doc.RootElement(), original);
  if (reread.RootElement()) preorder(reread.RootElement(), prepared);
  for (std::size_t k = 0; k < original.size() && k < prepared.size(); ++k)
    if (original[k]->GetLineNum() > 0)
      lines.emplace(prepared[k]->GetLineNum(), original[k]->GetLineNum());
  return lines;
}

}  // namespace

UrdfInfo prepare_urdf(const fs::path& urdf, const std::map<std::string, fs::path>& package_paths,
                      const fs::path& work_dir, const UrdfPerturbation& perturbation) {
  const std::string where = urdf.string();
  tinyxml2::XMLDocument doc;
  XMLElement* robot = load_urdf_document(urdf, doc);
  normalise_urdf(robot);
  perturb_urdf_document(doc, where, perturbation);

  UrdfInfo info;
  info.source = urdf;
  const fs::path urdf_dir = fs::absolute(urdf).parent_path();

  // Bounds before cost: counts first, the depth once the tree is known.
  std::size_t num_links = 0, num_joints = 0;
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
    ++num_links;
  for (XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    ++num_joints;
  check_model_count(where, num_links, ModelLimits::kMaxLinks, "links");
  check_model_count(where, num_joints, ModelLimits::kMaxJoints, "joints");

  std::map<std::string, std::string> children;  // link -> the joint it is the child of
  std::set<std::string> moving_links;           // children of movable joints
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    const char* name = l->Attribute("name");
    if (!name) throw InputError(at(where, l) + ": a <link> has no name");
    info.link_names.push_back(name);
  }
  for (XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    const char* type = j->Attribute("type");
    if (!name || !type) throw InputError(at(where, j) + ": a <joint> has no name or type");
    const std::string context = at(where, j) + ": joint '" + std::string(name) + "'";
    const std::string t = type;
    if (t == "floating" || t == "planar")
      throw InputError(context + " is " + t +
                       ": arttrack's robots have a fixed base and joints of one degree of "
                       "freedom (revolute, continuous, prismatic or fixed), in the simulator as "
                       "in the tracker");
    const XMLElement* child = j->FirstChildElement("child");
    if (!child || !child->Attribute("link")) throw InputError(context + " has no child link");
    const std::string child_link = child->Attribute("link");
    if (const auto [it, added] = children.emplace(child_link, name); !added)
      throw InputError(where + ": link '" + child_link + "' is the child of joints '" + it->second +
                       "' and '" + name + "'; a URDF is a tree (no kinematic loops)");
    info.T_parent_link[child_link] = parse_origin(j, context);
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
  std::map<std::string, std::string> parent_of;         // child link -> parent link
  for (XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const XMLElement* parent = j->FirstChildElement("parent");
    if (!parent || !parent->Attribute("link"))
      throw InputError(at(where, j) + ": joint '" + j->Attribute("name") + "' has no parent link");
    const std::string child = j->FirstChildElement("child")->Attribute("link");
    for (const std::string& link : {std::string(parent->Attribute("link")), child})
      if (std::find(info.link_names.begin(), info.link_names.end(), link) == info.link_names.end())
        throw InputError(at(where, j) + ": joint '" + j->Attribute("name") + "' names link '" +
                         link + "', which the URDF does not have");
    links_under.emplace(parent->Attribute("link"), child);
    parent_of.emplace(child, parent->Attribute("link"));
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
  check_chain_depth(where, parent_of);

  // Shapes without volume: a visual's is an error (the tracker's too), a
  // collision's is left out (it collides with nothing in ROS either).
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    for (const char* kind : {"visual", "collision"}) {
      for (XMLElement* g = l->FirstChildElement(kind); g;) {
        XMLElement* next = g->NextSiblingElement(kind);
        const XMLElement* geometry = g->FirstChildElement("geometry");
        const XMLElement* shape = geometry ? geometry->FirstChildElement() : nullptr;
        const std::string context = at(where, g) + ": link '" + l->Attribute("name") + "' " + kind;
        const std::string problem = shape ? shape_problem(shape, context) : "";
        if (!problem.empty() && std::string(kind) == "visual")
          throw InputError(context + ": " + problem + " (expected positive finite sizes)");
        if (!problem.empty()) {
          info.notices.push_back(context + ": " + problem +
                                 " has no volume: left out of the simulator's collision shapes");
          l->DeleteChild(g);
        }
        g = next;
      }
    }
  }

  // Every mesh becomes <work_dir>/m<k>_<stem>.stl (and _1, _2, ... parts past
  // MuJoCo's triangles per file: one more <visual> or <collision> each):
  // unique even when two files share a base name, converted once per (file,
  // scale). Triangles count per use, visual and collision apart.
  std::map<std::pair<std::string, std::string>, ConvertedMesh> converted;
  std::map<std::string, std::uint64_t> triangles;  // by kind
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    for (const char* kind : {"visual", "collision"}) {
      for (XMLElement* g = l->FirstChildElement(kind); g;) {
        XMLElement* next = g->NextSiblingElement(kind);
        XMLElement* geometry = g->FirstChildElement("geometry");
        XMLElement* mesh = geometry ? geometry->FirstChildElement("mesh") : nullptr;
        if (!mesh) {
          g = next;
          continue;
        }
        const std::string context =
            at(where, mesh) + ": link '" + l->Attribute("name") + "' " + kind + " mesh";
        const char* filename = mesh->Attribute("filename");
        if (!filename) throw InputError(context + " has no filename");
        const fs::path path = resolve_mesh_path(filename, urdf_dir, package_paths);
        if (path.empty())
          throw InputError(context + " '" + filename +
                           "': unknown package (give its folder in the scene's robot.packages)");
        const char* scale_text = mesh->Attribute("scale");
        const Eigen::Vector3d scale = parse_vec3(scale_text, Eigen::Vector3d::Ones(), context);
        if (!scale.allFinite() || (scale.array() == 0).any())
          throw InputError(context + " '" + filename + "' has scale '" + scale_text +
                           "' (expected finite, non-zero factors)");
        const auto key = std::make_pair(fs::weakly_canonical(path).string(),
                                        std::string(scale_text ? scale_text : "1 1 1"));
        std::uint64_t& used = triangles[kind];
        auto it = converted.find(key);
        const bool first_use = it == converted.end();
        if (first_use) {
          std::string stem = "m";
          stem += std::to_string(converted.size());
          stem += '_';
          stem += path.stem().string();
          it = converted
                   .emplace(key, convert_mesh_to_binary_stl(path, work_dir / stem, scale,
                                                            context + " '" + filename + "'",
                                                            ModelLimits::kMaxMeshTriangles - used))
                   .first;
        }
        used += it->second.triangles;
        // Once per file: what orient_parts() turned or left open.
        const MeshOrientation& parts = it->second.orientation;
        if (first_use && (parts.turned_parts > 0 || parts.open_parts > 0)) {
          std::string what = context + " '" + filename + "': of its " +
                             std::to_string(parts.parts) + " parts, " +
                             std::to_string(parts.turned_parts) +
                             " wound inside out or with faces flipped (turned outward), " +
                             std::to_string(parts.open_parts) + " open";
          if (parts.open_parts > 0)
            what +=
                " (not closed: the depth camera draws both sides of every surface; the "
                "tracker culls them as if closed unless geometry.open_parts_both_sides)";
          info.notices.push_back(what);
        }
        if (std::string(kind) == "visual")
          info.open_visual_meshes = info.open_visual_meshes || parts.open_parts > 0;
        check_model_count(where, used, ModelLimits::kMaxMeshTriangles,
                          std::string(kind) + " mesh triangles (with '" + filename + "' of link '" +
                              l->Attribute("name") + "')");
        if (it->second.flat && std::string(kind) == "collision") {
          info.notices.push_back(context + " '" + filename +
                                 "' is flat (no volume): left out of the simulator's collision "
                                 "shapes (MuJoCo 2.2 cannot take its convex hull)");
          l->DeleteChild(g);
          g = next;
          continue;
        }
        const std::vector<fs::path>& files = it->second.files;
        mesh->SetAttribute("filename", files[0].filename().c_str());
        mesh->DeleteAttribute("scale");
        for (std::size_t k = 1; k < files.size(); ++k) {  // the other parts, after this one
          XMLElement* part = g->DeepClone(&doc)->ToElement();
          part->FirstChildElement("geometry")
              ->FirstChildElement("mesh")
              ->SetAttribute("filename", files[k].filename().c_str());
          l->InsertAfterChild(g, part);
          g = part;
        }
        g = next;
      }
    }
  }

  // Links without a usable <inertial>: a moving link's that MuJoCo would
  // refuse goes, unless a link welded to it (fixed joints below) has mass.
  std::map<std::string, XMLElement*> link_element;
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
    link_element[l->Attribute("name")] = l;
  std::map<std::string, std::vector<std::string>> welded_below;  // link -> fixed children
  for (XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    if (std::string(j->Attribute("type")) == "fixed")
      welded_below[j->FirstChildElement("parent")->Attribute("link")].push_back(
          j->FirstChildElement("child")->Attribute("link"));
  const auto welded_mass = [&](const std::string& link) {
    for (std::vector<std::string> todo = welded_below[link]; !todo.empty();) {
      const std::string l = todo.back();
      todo.pop_back();
      const XMLElement* inertial = link_element[l]->FirstChildElement("inertial");
      if (inertial && inertial_problem(inertial).empty()) return true;
      for (const auto& c : welded_below[l]) todo.push_back(c);
    }
    return false;
  };
  for (const std::string& name : moving_links) {
    XMLElement* l = link_element[name];
    XMLElement* inertial = l->FirstChildElement("inertial");
    if (!inertial) continue;
    const std::string problem = inertial_problem(inertial);
    if (problem.empty() || welded_mass(name)) continue;
    info.unusable_inertials[name] = problem;
    l->DeleteChild(inertial);
  }
  for (XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    if (l->FirstChildElement("inertial")) continue;
    const std::string name = l->Attribute("name");
    if (add_derived_inertial(doc, l, moving_links.count(name) > 0, where + ": link '" + name + "'"))
      info.links_with_derived_inertia.push_back(name);
  }

  // Our MuJoCo block (normalise_urdf dropped any of the user's).
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
    throw InputError(where + ": cannot write its prepared copy in the temporary folder " +
                     work_dir.string());
  info.source_line = line_map(doc, info.prepared_urdf);
  return info;
}

}  // namespace arttrack::sim
