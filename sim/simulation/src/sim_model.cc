#include "arttrack/sim/sim_model.h"

#include <tinyxml2.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <set>

#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/error.h"
#include "urdf_prepare.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using tinyxml2::XMLDocument;
using tinyxml2::XMLElement;

namespace {

// Contact bits: robot geoms touch the scene, never each other; scene geoms
// touch the robot and each other. (Contact if contype_a & conaffinity_b or
// contype_b & conaffinity_a.)
constexpr int kRobotContype = 1, kRobotConaffinity = 2;
constexpr int kSceneContype = 2, kSceneConaffinity = 3;

constexpr char kCameraName[] = "arttrack_depth";

// A private folder for the prepared URDF, meshes and MJCF; removed when done.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "arttrack_sim_XXXXXX").string();
    if (!mkdtemp(tmpl.data()))
      throw InputError("cannot create a temporary folder in " + fs::temp_directory_path().string());
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Full double precision; MuJoCo's own writer keeps six digits only.
std::string nums(std::initializer_list<double> values) {
  std::string out;
  char buf[32];
  for (double v : values) {
    std::snprintf(buf, sizeof(buf), "%.17g", v);
    if (!out.empty()) out += ' ';
    out += buf;
  }
  return out;
}

std::string pos_attr(const Eigen::Vector3d& p) { return nums({p.x(), p.y(), p.z()}); }

std::string quat_attr(const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  return nums({q.w(), q.x(), q.y(), q.z()});
}

std::string rgba_attr(const Eigen::Vector4f& c) { return nums({c[0], c[1], c[2], c[3]}); }

XMLElement* child(XMLDocument& doc, XMLElement* parent, const char* name, bool first = false) {
  if (XMLElement* e = parent->FirstChildElement(name)) return e;
  XMLElement* e = doc.NewElement(name);
  if (first)
    parent->InsertFirstChild(e);
  else
    parent->InsertEndChild(e);
  return e;
}

XMLElement* add(XMLDocument& doc, XMLElement* parent, const char* name) {
  XMLElement* e = doc.NewElement(name);
  parent->InsertEndChild(e);
  return e;
}

void collect_bodies(XMLElement* parent, std::map<std::string, XMLElement*>& out) {
  for (XMLElement* b = parent->FirstChildElement("body"); b; b = b->NextSiblingElement("body")) {
    if (const char* name = b->Attribute("name")) out[name] = b;
    collect_bodies(b, out);
  }
}

void set_pose(XMLElement* e, const Eigen::Isometry3d& T) {
  e->SetAttribute("pos", pos_attr(T.translation()).c_str());
  e->SetAttribute("quat", quat_attr(T.linear()).c_str());
}

void set_shape(XMLElement* g, SceneShape::Type type, const Eigen::Vector3d& size_m) {
  switch (type) {
    case SceneShape::Type::kBox:
      g->SetAttribute("type", "box");
      g->SetAttribute("size", pos_attr(0.5 * size_m).c_str());
      break;
    case SceneShape::Type::kCylinder:
      g->SetAttribute("type", "cylinder");
      g->SetAttribute("size", nums({size_m[0], 0.5 * size_m[1]}).c_str());
      break;
    case SceneShape::Type::kSphere:
      g->SetAttribute("type", "sphere");
      g->SetAttribute("size", nums({size_m[0]}).c_str());
      break;
  }
}

// A person of height h: frame on the floor between the feet, facing +x.
// Proportions of a 1.75 m adult, scaled.
void add_person(XMLDocument& doc, XMLElement* body, double h, const Eigen::Vector4f& rgba) {
  const double s = h / 1.75;
  struct Part {
    SceneShape::Type type;
    Eigen::Vector3d size, pos;
  };
  const Part parts[] = {
      {SceneShape::Type::kCylinder, {0.07 * s, 0.86 * s, 0}, {0, 0.1 * s, 0.43 * s}},  // legs
      {SceneShape::Type::kCylinder, {0.07 * s, 0.86 * s, 0}, {0, -0.1 * s, 0.43 * s}},
      {SceneShape::Type::kBox, {0.24 * s, 0.4 * s, 0.6 * s}, {0, 0, 1.16 * s}},         // torso
      {SceneShape::Type::kSphere, {0.11 * s, 0, 0}, {0, 0, 1.62 * s}},                  // head
      {SceneShape::Type::kCylinder, {0.05 * s, 0.62 * s, 0}, {0, 0.26 * s, 1.14 * s}},  // arms
      {SceneShape::Type::kCylinder, {0.05 * s, 0.62 * s, 0}, {0, -0.26 * s, 1.14 * s}},
  };
  for (const Part& p : parts) {
    XMLElement* g = add(doc, body, "geom");
    set_shape(g, p.type, p.size);
    g->SetAttribute("pos", pos_attr(p.pos).c_str());
    g->SetAttribute("rgba", rgba_attr(rgba).c_str());
    g->SetAttribute("group", kGroupOccluder);
    g->SetAttribute("contype", 0);
    g->SetAttribute("conaffinity", 0);
  }
}

// The robot part of the MJCF MuJoCo wrote: restore full precision, set
// contact bits, armature and the camera.
void edit_robot(XMLDocument& doc, const std::map<std::string, XMLElement*>& bodies,
                const UrdfInfo& urdf, const mjModel* m_urdf, const SceneDescription& scene) {
  for (const auto& [link, T] : urdf.T_parent_link) {
    auto it = bodies.find(link);
    if (it != bodies.end()) set_pose(it->second, T);
  }
  const std::set<std::string> servoed(urdf.joint_names.begin(), urdf.joint_names.end());
  for (const auto& [name, body] : bodies) {
    for (XMLElement* j = body->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
      const char* jname = j->Attribute("name");
      if (!jname) continue;
      if (auto a = urdf.joint_axis.find(jname); a != urdf.joint_axis.end())
        j->SetAttribute("axis", pos_attr(a->second).c_str());
      j->SetAttribute("armature", nums({scene.armature_kg_m2}).c_str());
    }
    // Primitive geoms: MuJoCo's compiled values equal the URDF's; take them
    // at full precision. (Mesh geoms are offset by the mesh's centroid in the
    // compiled model, so their six-digit MJCF values stay.)
    const int b = mj_name2id(m_urdf, mjOBJ_BODY, name.c_str());
    int k = 0;
    for (XMLElement* g = body->FirstChildElement("geom"); g;
         g = g->NextSiblingElement("geom"), ++k) {
      const bool collision =
          g->IntAttribute("contype", 1) != 0 || g->IntAttribute("conaffinity", 1) != 0;
      if (collision) {
        g->SetAttribute("contype", kRobotContype);
        g->SetAttribute("conaffinity", kRobotConaffinity);
      }
      if (b < 0 || k >= m_urdf->body_geomnum[b]) continue;
      const int id = m_urdf->body_geomadr[b] + k;
      const int type = m_urdf->geom_type[id];
      if (type == mjGEOM_MESH) continue;
      const mjtNum* p = m_urdf->geom_pos + 3 * id;
      const mjtNum* q = m_urdf->geom_quat + 4 * id;
      const mjtNum* s = m_urdf->geom_size + 3 * id;
      g->SetAttribute("pos", nums({p[0], p[1], p[2]}).c_str());
      g->SetAttribute("quat", nums({q[0], q[1], q[2], q[3]}).c_str());
      const int nsize = type == mjGEOM_SPHERE                               ? 1
                        : type == mjGEOM_CYLINDER || type == mjGEOM_CAPSULE ? 2
                                                                            : 3;
      g->SetAttribute("size", nsize == 1   ? nums({s[0]}).c_str()
                              : nsize == 2 ? nums({s[0], s[1]}).c_str()
                                           : nums({s[0], s[1], s[2]}).c_str());
    }
  }
  // The optical frame has z forward and y down; a MuJoCo camera looks along
  // -z with y up: rotate by pi about x, quat (0, 1, 0, 0).
  XMLElement* camera = add(doc, bodies.at(scene.camera_link), "camera");
  camera->SetAttribute("name", kCameraName);
  camera->SetAttribute("pos", "0 0 0");
  camera->SetAttribute("quat", "0 1 0 0");
  camera->SetAttribute("fovy", nums({scene.fovy_rad * 180.0 / M_PI}).c_str());
}

void add_scene(XMLDocument& doc, XMLElement* world, const SceneDescription& scene) {
  if (scene.floor) {
    XMLElement* g = doc.NewElement("geom");
    world->InsertFirstChild(g);
    g->SetAttribute("name", "floor");
    g->SetAttribute("type", "plane");
    // The third size is MuJoCo's rendering grid spacing, for lighting: at
    // 0.05 m the floor was drawn as 200 x 200 quads (mjMAXPLANEGRID) on
    // every frame, a third of a depth frame's time on the primitive dual
    // arm. A flat plane's depth is the same from 2 x 2.
    g->SetAttribute("size", "20 20 20");
    g->SetAttribute("rgba", "0.75 0.75 0.7 1");
    g->SetAttribute("group", kGroupScene);
    g->SetAttribute("contype", kSceneContype);
    g->SetAttribute("conaffinity", kSceneConaffinity);
  }
  for (const SceneShape& s : scene.shapes) {
    XMLElement* parent = world;
    if (s.free) {
      parent = add(doc, world, "body");
      parent->SetAttribute("name", s.name.c_str());
      set_pose(parent, s.T_world_shape);
      XMLElement* j = add(doc, parent, "joint");
      j->SetAttribute("name", s.name.c_str());
      j->SetAttribute("type", "free");
    }
    XMLElement* g = add(doc, parent, "geom");
    g->SetAttribute("name", s.name.c_str());
    set_shape(g, s.type, s.size_m);
    if (s.free)
      g->SetAttribute("mass", nums({s.mass_kg}).c_str());
    else
      set_pose(g, s.T_world_shape);
    g->SetAttribute("rgba", rgba_attr(s.rgba).c_str());
    g->SetAttribute("group", kGroupScene);
    g->SetAttribute("contype", kSceneContype);
    g->SetAttribute("conaffinity", kSceneConaffinity);
  }
  for (const SceneLight& l : scene.lights) {
    XMLElement* e = add(doc, world, "light");
    e->SetAttribute("pos", pos_attr(l.position_m).c_str());
    e->SetAttribute("dir", pos_attr(l.direction.normalized()).c_str());
    e->SetAttribute("directional", l.directional ? "true" : "false");
    e->SetAttribute("castshadow", "false");
  }
  for (const OccluderSpec& o : scene.occluders) {
    XMLElement* b = add(doc, world, "body");
    b->SetAttribute("name", ("occluder_" + o.name).c_str());
    b->SetAttribute("mocap", "true");
    set_pose(b, o.T_world_occluder);
    if (o.type == OccluderSpec::Type::kPerson) {
      add_person(doc, b, o.size_m[0], o.rgba);
      continue;
    }
    XMLElement* g = add(doc, b, "geom");
    set_shape(
        g,
        o.type == OccluderSpec::Type::kBox ? SceneShape::Type::kBox : SceneShape::Type::kCylinder,
        o.size_m);
    g->SetAttribute("rgba", rgba_attr(o.rgba).c_str());
    g->SetAttribute("group", kGroupOccluder);
    g->SetAttribute("contype", 0);
    g->SetAttribute("conaffinity", 0);
  }
}

// Position servos: torque = kp (ctrl - q) - kv qdot, a <general> actuator
// (2.2's <position> has no kv). Clamped to the URDF effort if asked.
void add_actuators(XMLDocument& doc, XMLElement* root, const UrdfInfo& urdf, const mjModel* m_urdf,
                   const SceneDescription& scene) {
  XMLElement* actuators = child(doc, root, "actuator");
  for (const std::string& name : urdf.joint_names) {
    const auto g = scene.joint_gains.count(name) ? scene.joint_gains.at(name) : scene.default_gains;
    XMLElement* a = add(doc, actuators, "general");
    a->SetAttribute("name", ("servo_" + name).c_str());
    a->SetAttribute("joint", name.c_str());
    a->SetAttribute("gainprm", nums({g.kp_Nm_per_rad}).c_str());
    a->SetAttribute("biastype", "affine");
    a->SetAttribute("biasprm", nums({0, -g.kp_Nm_per_rad, -g.kv_Nms_per_rad}).c_str());
    const int j = mj_name2id(m_urdf, mjOBJ_JOINT, name.c_str());
    if (j >= 0 && m_urdf->jnt_limited[j]) {
      a->SetAttribute("ctrllimited", "true");
      a->SetAttribute("ctrlrange",
                      nums({m_urdf->jnt_range[2 * j], m_urdf->jnt_range[2 * j + 1]}).c_str());
    } else {
      a->SetAttribute("ctrllimited", "false");
    }
    const double effort = urdf.joint_effort.count(name) ? urdf.joint_effort.at(name) : 0.0;
    if (scene.limit_torque_to_urdf_effort && effort > 0) {
      a->SetAttribute("forcelimited", "true");
      a->SetAttribute("forcerange", nums({-effort, effort}).c_str());
    }
  }
  if (urdf.mimics.empty()) return;
  XMLElement* equality = child(doc, root, "equality");
  for (const auto& mimic : urdf.mimics) {
    XMLElement* e = add(doc, equality, "joint");
    e->SetAttribute("joint1", mimic.joint.c_str());
    e->SetAttribute("joint2", mimic.leader.c_str());
    e->SetAttribute("polycoef", nums({mimic.offset, mimic.multiplier, 0, 0, 0}).c_str());
  }
}

void add_options(XMLDocument& doc, XMLElement* root, const SceneDescription& scene,
                 const fs::path& mesh_dir, int nv) {
  // MuJoCo's default stack (about 1.4 M + 20 nv^2 numbers) runs out in the
  // compiler's first step past a few hundred degrees of freedom (the
  // implicit integrator's dense nv x nv terms): 40 nv^2 is enough at
  // ModelLimits::kMaxJoints (1000: 41 M numbers, 330 MB).
  if (nv > 200) child(doc, root, "size")->SetAttribute("nstack", 1000000 + 40 * nv * nv);
  child(doc, root, "compiler", true)->SetAttribute("meshdir", mesh_dir.string().c_str());
  XMLElement* option = child(doc, root, "option");
  option->SetAttribute("timestep", nums({scene.timestep_s}).c_str());
  option->SetAttribute("gravity", pos_attr(scene.gravity_m_s2).c_str());
  // Implicit in the servos' damping: stiff gains on light links stay stable.
  option->SetAttribute("integrator", "implicit");
  // Pinned so that the depth mapping (near = znear extent) never moves.
  child(doc, root, "statistic")->SetAttribute("extent", nums({scene.extent_m}).c_str());
  XMLElement* visual = child(doc, root, "visual");
  XMLElement* global = child(doc, visual, "global");
  global->SetAttribute("offwidth", scene.width);
  global->SetAttribute("offheight", scene.height);
  XMLElement* quality = child(doc, visual, "quality");
  quality->SetAttribute("offsamples", 0);  // multisampling would blur depth edges
  quality->SetAttribute("shadowsize", 0);
  // Finer than the default 28 x 16 so that drawn cylinders and spheres stay
  // close to the true shapes.
  quality->SetAttribute("numslices", scene.shape_segments);
  quality->SetAttribute("numstacks", (scene.shape_segments + 1) / 2);
  XMLElement* map = child(doc, visual, "map");
  map->SetAttribute("znear", nums({scene.near_m / scene.extent_m}).c_str());
  map->SetAttribute("zfar", nums({scene.far_m / scene.extent_m}).c_str());
}

std::string to_string(const XMLDocument& doc) {
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

// Checks that every name the scene uses exists in the robot.
void check_names(const SceneDescription& scene, const UrdfInfo& urdf) {
  const std::string where = scene.source.empty() ? urdf.source.string() : scene.source;
  const std::set<std::string> links(urdf.link_names.begin(), urdf.link_names.end());
  const std::set<std::string> joints(urdf.joint_names.begin(), urdf.joint_names.end());
  const std::string in_urdf = " of " + urdf.source.string();
  if (!links.count(scene.camera_link))
    throw InputError(where + ": camera link '" + scene.camera_link + "' is not a link" + in_urdf);
  for (const auto& l : scene.end_effector_links)
    if (!links.count(l))
      throw InputError(where + ": end effector '" + l + "' is not a link" + in_urdf);
  for (const auto& [j, q] : scene.initial_joints_rad)
    if (!joints.count(j))
      throw InputError(where + ": initial joint '" + j + "' is not a movable joint" + in_urdf);
  for (const auto& [j, g] : scene.joint_gains)
    if (!joints.count(j))
      throw InputError(where + ": actuators.joints '" + j + "' is not a movable joint" + in_urdf);
  std::set<std::string> occluders;
  for (const auto& o : scene.occluders)
    if (!occluders.insert(o.name).second)
      throw InputError(where + ": occluder name '" + o.name + "' is used twice");
  std::set<std::string> shapes(links);
  for (const auto& s : scene.shapes)
    if (!shapes.insert(s.name).second)
      throw InputError(where + ": object name '" + s.name + "' is used twice (or names a link)");
}

int id_of(const mjModel* m, mjtObj type, const std::string& name, const std::string& where) {
  const int id = mj_name2id(m, type, name.c_str());
  if (id < 0) throw InputError(where + ": '" + name + "' is missing from the compiled model");
  return id;
}

}  // namespace

int SimModel::joint_index(const std::string& name) const {
  for (size_t i = 0; i < joint_names.size(); ++i)
    if (joint_names[i] == name) return int(i);
  return -1;
}

int SimModel::link_index(const std::string& name) const {
  for (size_t i = 0; i < link_names.size(); ++i)
    if (link_names[i] == name) return int(i);
  return -1;
}

int SimModel::occluder_index(const std::string& name) const {
  for (size_t i = 0; i < occluder_names.size(); ++i)
    if (occluder_names[i] == name) return int(i);
  return -1;
}

CameraIntrinsics SimModel::intrinsics() const {
  return CameraIntrinsics::from_vertical_fov(scene.width, scene.height, scene.fovy_rad);
}

namespace {

// The first few names of a list, then how many more.
std::string some_names(const std::vector<std::string>& names) {
  constexpr std::size_t kShown = 12;
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < kShown; ++i)
    out += (out.empty() ? "" : ", ") + names[i];
  if (names.size() > kShown) out += " and " + std::to_string(names.size() - kShown) + " more";
  return out;
}

// Lines on stderr, once per URDF and process (sweeps build many models).
void report_notices(const UrdfInfo& urdf) {
  static std::mutex mutex;
  static std::set<std::string> reported;
  std::lock_guard lock(mutex);
  if (!reported.insert(urdf.source.string()).second) return;
  for (const std::string& notice : urdf.notices) std::cerr << "notice: " << notice << "\n";
  if (urdf.links_with_derived_inertia.empty()) return;
  std::vector<std::string> missing;
  for (const auto& l : urdf.links_with_derived_inertia)
    if (!urdf.unusable_inertials.count(l)) missing.push_back(l);
  std::string what;
  if (!missing.empty())
    what = "no <inertial> on " + std::to_string(missing.size()) + " links (" + some_names(missing) +
           ")";
  for (const auto& [link, why] : urdf.unusable_inertials)
    what +=
        (what.empty() ? "" : "; ") + ("link '" + link + "': <inertial> with " + why +
                                      " (MuJoCo needs positive mass and inertia on a moving link)");
  std::cerr << "notice: " << urdf.source.filename().string() << ": " << what
            << "; mass and inertia derived from their geometry (solid, 1000 kg/m^3)\n";
}

}  // namespace

std::shared_ptr<const SimModel> build_sim_model(const SceneDescription& scene,
                                                const UrdfPerturbation& perturbation) {
  const std::string where = scene.source.empty() ? scene.urdf_path.string() : scene.source;
  TempDir work;
  UrdfPerturbation changes = perturbation;  // with the scene's camera link
  changes.camera_link = scene.camera_link;
  changes.camera_mount = scene.camera_mount;
  const UrdfInfo urdf = prepare_urdf(scene.urdf_path, scene.package_paths, work.path(), changes);
  check_names(scene, urdf);
  report_notices(urdf);

  // Stage 1: the robot alone, through MuJoCo's URDF importer.
  char error[1024] = "";
  std::unique_ptr<mjModel, MjModelDeleter> m_urdf(
      mj_loadXML(urdf.prepared_urdf.c_str(), nullptr, error, sizeof(error)));
  if (!m_urdf) throw InputError(urdf.retell(error));
  // Read back below as XML (tinyxml2, at most 100 nested elements: the
  // chain depth limit keeps the bodies within).
  const fs::path robot_xml = work.path() / "robot.xml";
  const std::string in_urdf = scene.urdf_path.string() + ": ";
  if (!mj_saveLastXML(robot_xml.c_str(), m_urdf.get(), error, sizeof(error)))
    throw InputError(in_urdf + "MuJoCo cannot write its model as MJCF: " + error);

  // Stage 2: the scene around it.
  XMLDocument doc;
  if (doc.LoadFile(robot_xml.c_str()) != tinyxml2::XML_SUCCESS)
    throw InputError(in_urdf + "MuJoCo's MJCF of it cannot be read back: " + doc.ErrorName());
  XMLElement* root = doc.FirstChildElement("mujoco");
  XMLElement* world = root ? root->FirstChildElement("worldbody") : nullptr;
  if (!world) throw InputError(in_urdf + "MuJoCo's MJCF of it has no worldbody");
  std::map<std::string, XMLElement*> bodies;
  collect_bodies(world, bodies);
  if (!bodies.count(scene.camera_link))
    throw InputError(where + ": camera link '" + scene.camera_link +
                     "' has no body in MuJoCo's model of " + scene.urdf_path.string());
  edit_robot(doc, bodies, urdf, m_urdf.get(), scene);
  add_scene(doc, world, scene);
  add_actuators(doc, root, urdf, m_urdf.get(), scene);
  add_options(doc, root, scene, work.path(), m_urdf->nv);

  auto model = std::make_shared<SimModel>();
  model->scene = scene;
  model->mjcf = to_string(doc);
  const fs::path scene_xml = work.path() / "scene.xml";
  if (doc.SaveFile(scene_xml.c_str()) != tinyxml2::XML_SUCCESS)
    throw InputError(where + ": cannot write the simulator's model in the temporary folder " +
                     work.path().string());
  model->mj.reset(mj_loadXML(scene_xml.c_str(), nullptr, error, sizeof(error)));
  if (!model->mj) {  // the lines of the generated MJCF mean nothing to the user
    const MujocoError e = parse_mujoco_error(error);
    throw InputError(where + ": MuJoCo cannot compile the scene: " + e.what +
                     (e.object.empty() ? "" : " ('" + e.object + "')"));
  }
  const mjModel* m = model->mj.get();

  const int n = int(urdf.joint_names.size());
  model->joint_names = urdf.joint_names;
  model->joint_lower.setConstant(n, -std::numeric_limits<double>::infinity());
  model->joint_upper.setConstant(n, std::numeric_limits<double>::infinity());
  model->initial_joints.setZero(n);
  for (int i = 0; i < n; ++i) {
    const std::string& name = urdf.joint_names[i];
    const int j = id_of(m, mjOBJ_JOINT, name, where);
    model->joint_id.push_back(j);
    model->joint_qpos_adr.push_back(m->jnt_qposadr[j]);
    model->joint_dof_adr.push_back(m->jnt_dofadr[j]);
    model->joint_actuator.push_back(id_of(m, mjOBJ_ACTUATOR, "servo_" + name, where));
    if (m->jnt_limited[j]) {
      model->joint_lower[i] = m->jnt_range[2 * j];
      model->joint_upper[i] = m->jnt_range[2 * j + 1];
    }
    if (auto it = scene.initial_joints_rad.find(name); it != scene.initial_joints_rad.end())
      model->initial_joints[i] = it->second;
  }
  model->link_names = urdf.link_names;
  for (const auto& l : urdf.link_names) model->link_body.push_back(id_of(m, mjOBJ_BODY, l, where));
  model->root_link = urdf.root_link;
  model->camera_id = id_of(m, mjOBJ_CAMERA, kCameraName, where);
  model->camera_body = id_of(m, mjOBJ_BODY, scene.camera_link, where);
  model->render_both_sides = urdf.open_visual_meshes;
  for (const auto& e : scene.end_effector_links) {
    model->end_effector_names.push_back(e);
    model->end_effector_body.push_back(id_of(m, mjOBJ_BODY, e, where));
  }
  for (const auto& o : scene.occluders) {
    model->occluder_names.push_back(o.name);
    const int b = id_of(m, mjOBJ_BODY, "occluder_" + o.name, where);
    model->occluder_mocap.push_back(m->body_mocapid[b]);
  }
  return model;
}

}  // namespace arttrack::sim
