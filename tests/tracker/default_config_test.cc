// The shipped tracker configuration is robot-agnostic and built into the
// library: it is the file tracker/config/default.yaml, it holds exactly the
// in-class defaults of tracker_config.h, field by field, and a tracker built
// from it runs every method on a robot that is not the project's dual-arm
// one (tests/tracker/data/single_arm.urdf).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "../error_of.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "arttrack/tracker/units.h"

namespace arttrack {
namespace {

using arttrack::test_support::error_of;

const std::string kUrdf = std::string(ARTTRACK_SOURCE_DIR) + "/tests/tracker/data/single_arm.urdf";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(DefaultConfigTest, BuiltInTextIsTheShippedFile) {
  EXPECT_EQ(default_tracker_config_yaml(),
            read_text(std::string(ARTTRACK_SOURCE_DIR) + "/tracker/config/default.yaml"));
  const TrackerConfig c = default_tracker_config();
  EXPECT_EQ(c.source, kDefaultTrackerConfigName);
  EXPECT_TRUE(c.joint_overrides.empty());
  EXPECT_TRUE(c.end_effectors.empty());
}

// ---- default.yaml against the in-class defaults, field by field ----

// Converts to the type of any field: an aggregate T can be brace-initialised
// from as many of these as it has fields, and not from one more.
struct AnyField {
  template <class T>
  operator T() const;  // only named in unevaluated contexts
};

// The number of fields of the aggregate T (C++ has no reflection: this is
// what lets the lists below prove that they name every field).
template <class T, class... Fields>
constexpr std::size_t field_count() {
  if constexpr (requires { T{Fields{}..., AnyField{}}; })
    return field_count<T, Fields..., AnyField>();
  else
    return sizeof...(Fields);
}
static_assert(field_count<TrackerConfig::Geometry>() == 4);  // the counting itself
static_assert(field_count<TrackerConfig::Block>() == 2);

// A key of default.yaml and the field of S it holds; a double's value in
// the YAML times `unit` (kRadPerDeg for a _deg key of a field in radians).
template <class S, class T>
struct Key {
  std::string name;
  T S::*field;
  double unit;
};
template <class S, class T>
Key<S, T> key(std::string name, T S::*field, double unit = 1.0) {
  return {std::move(name), field, unit};
}

// One struct of the configuration in default.yaml: each field of S is listed
// with its key (below `prefix`), and the list is checked three ways. The
// key's value in the YAML, in the field's units, equals the
// default-constructed field (`code`); the field as the reader
// (tracker_config_from_yaml) filled it from the file (`file`) equals it too;
// and the list names as many fields as S has (checked when the list ends),
// so that a field added to the struct and not here fails, naming the struct.
// The keys looked up are added to `listed_keys`.
template <class S>
class FieldList {
 public:
  FieldList(const YAML::Node& yaml, std::string prefix, const S& file, const S& code,
            std::set<std::string>& listed_keys)
      : yaml_(yaml), prefix_(std::move(prefix)), file_(file), code_(code), keys_(listed_keys) {}
  FieldList(const FieldList&) = delete;
  FieldList& operator=(const FieldList&) = delete;
  ~FieldList() {
    EXPECT_EQ(listed_, field_count<S>())
        << "the list of '" << prefix_ << "' names " << listed_ << " fields, its struct has "
        << field_count<S>() << ": a field is in one and not the other";
  }

  // Fields of plain types.
  template <class... T>
  void operator()(const Key<S, T>&... keys) {
    (check(keys), ...);
  }
  // An enumeration, written in the YAML as name(value).
  template <class T, class Name>
  void choice(const std::string& key, T S::*field, Name name) {
    if (const std::optional<YAML::Node> value = yaml_value(key)) {
      EXPECT_EQ(value->template as<std::string>(), name(code_.*field)) << prefix_ + key;
    }
    EXPECT_TRUE(file_.*field == code_.*field) << prefix_ + key << " as the reader read it";
  }
  // A struct of its own, its keys below `key_prefix` (e.g. "health.").
  template <class T, class List>
  void nested(const std::string& key_prefix, T S::*field, List list) {
    ++listed_;
    FieldList<T> fields(yaml_, prefix_ + key_prefix, file_.*field, code_.*field, keys_);
    list(fields);
  }
  // A list, or a map by name, of structs at `key`: as long (the same names)
  // in the YAML, the reader's and the code's, and each element field by
  // field (its keys below key[i]. or key.name.).
  template <class T, class List>
  void elements(const std::string& key, std::vector<T> S::*field, List list) {
    same_size(key, (file_.*field).size(), (code_.*field).size());
    for (std::size_t i = 0; i < (code_.*field).size() && i < (file_.*field).size(); ++i) {
      FieldList<T> fields(yaml_, prefix_ + key + "[" + std::to_string(i) + "].", (file_.*field)[i],
                          (code_.*field)[i], keys_);
      list(fields);
    }
  }
  template <class T, class List>
  void elements(const std::string& key, std::map<std::string, T> S::*field, List list) {
    same_size(key, (file_.*field).size(), (code_.*field).size());
    for (const auto& [name, element] : code_.*field) {
      const auto read = (file_.*field).find(name);
      if (read == (file_.*field).end()) continue;  // same_size or another name has failed
      FieldList<T> fields(yaml_, prefix_ + key + "." + name + ".", read->second, element, keys_);
      list(fields);
    }
  }
  // A field that is not a key of the file, and why.
  template <class T>
  void not_in_yaml(T S::*, const char* /*why*/) {
    ++listed_;
  }

 private:
  template <class T>
  void check(const Key<S, T>& key) {
    if (const std::optional<YAML::Node> value = yaml_value(key.name)) {
      if constexpr (std::is_same_v<T, double>)
        EXPECT_EQ(value->template as<double>() * key.unit, code_.*key.field) << prefix_ + key.name;
      else
        EXPECT_EQ(value->template as<T>(), code_.*key.field) << prefix_ + key.name;
    }
    EXPECT_EQ(file_.*key.field, code_.*key.field) << prefix_ + key.name << " as the reader read it";
  }
  // The YAML's value of `key`, counted as listed; a failure naming the key
  // when the YAML lacks it.
  std::optional<YAML::Node> yaml_value(const std::string& key) {
    ++listed_;
    keys_.insert(prefix_ + key);
    std::optional<YAML::Node> value = find_key(yaml_, prefix_ + key);
    EXPECT_TRUE(value) << prefix_ + key << " is a field but not a key of default.yaml";
    return value;
  }
  void same_size(const std::string& key, std::size_t file, std::size_t code) {
    if (const std::optional<YAML::Node> value = yaml_value(key)) {
      EXPECT_EQ(value->size(), code) << prefix_ + key;
    }
    EXPECT_EQ(file, code) << prefix_ + key << " as the reader read it";
  }

  const YAML::Node& yaml_;
  std::string prefix_;
  const S& file_;
  const S& code_;
  std::set<std::string>& keys_;
  std::size_t listed_ = 0;
};

// Every key of the YAML whose value is not a non-empty map, as a dotted path.
void leaf_keys(const YAML::Node& node, const std::string& prefix, std::set<std::string>& out) {
  for (const auto& item : node) {
    const std::string key = prefix + item.first.as<std::string>();
    if (item.second.IsMap() && item.second.size() > 0)
      leaf_keys(item.second, key + ".", out);
    else
      out.insert(key);
  }
}

void list_joint_filter(FieldList<JointFilterParams>& f) {
  using J = JointFilterParams;
  f(key("encoder_noise_deg", &J::encoder_noise_rad, kRadPerDeg),
    key("angle_diffusion_deg_per_sqrt_s", &J::angle_diffusion_rad_per_sqrt_s, kRadPerDeg),
    key("bias_diffusion_deg_per_sqrt_s", &J::bias_diffusion_rad_per_sqrt_s, kRadPerDeg),
    key("bias_decay_per_s", &J::bias_decay_per_s), key("estimate_bias", &J::estimate_bias));
}

void list_depth_model(FieldList<DepthModelParams>& f) {
  using D = DepthModelParams;
  f.choice("occluder_model", &D::occluder_model, [](OccluderModel m) {
    return m == OccluderModel::kTruncated ? "truncated" : "independent";
  });
  f(key("outlier_weight", &D::outlier_weight), key("noise_std_m", &D::noise_std_m),
    key("noise_quadratic_per_m", &D::noise_quadratic_per_m), key("max_range_m", &D::max_range_m),
    key("occluder_decay_per_m", &D::occluder_decay_per_m),
    key("occlusion_prior", &D::occlusion_prior), key("width", &D::width),
    key("height", &D::height));
}

void list_particle_filter(FieldList<CoordinateParticleFilterParams>& f) {
  using P = CoordinateParticleFilterParams;
  f(key("particles", &P::num_particles), key("max_kl_divergence", &P::max_kl_divergence),
    key("proposal_scale", &P::proposal_scale), key("no_evidence_nats", &P::no_evidence_nats),
    key("bandwidth_factor", &P::bandwidth_factor),
    key("block_moments_below_nats", &P::block_moments_below_nats));
}

void list_tracker_config(FieldList<TrackerConfig>& f) {
  using C = TrackerConfig;
  using V = VirtualJointParams;
  f.not_in_yaml(&C::source, "where a configuration came from, for messages");
  f.choice("method", &C::method, method_name);
  f(key("camera_frame", &C::camera_frame), key("end_effectors", &C::end_effectors));
  f.nested("joints.defaults.", &C::joint_defaults, list_joint_filter);
  f.nested("joints.prismatic_defaults.", &C::prismatic_joint_defaults,
           [](FieldList<JointFilterParams>& p) {
             using J = JointFilterParams;
             p(key("encoder_noise_m", &J::encoder_noise_rad),
               key("position_diffusion_m_per_sqrt_s", &J::angle_diffusion_rad_per_sqrt_s),
               key("bias_diffusion_m_per_sqrt_s", &J::bias_diffusion_rad_per_sqrt_s),
               key("bias_decay_per_s", &J::bias_decay_per_s),
               key("estimate_bias", &J::estimate_bias));
           });
  // None in the shipped file; an entry's keys are any of the two above.
  f.elements("joints.per_joint", &C::joint_overrides, [](FieldList<JointFilterOverride>&) {});
  f.nested("encoder_smoothing.", &C::encoder_smoothing, [](FieldList<C::EncoderSmoothing>& e) {
    using E = C::EncoderSmoothing;
    e(key("enabled", &E::enabled), key("rate_diffusion_deg_per_s_per_sqrt_s",
                                       &E::rate_diffusion_rad_per_s_per_sqrt_s, kRadPerDeg));
  });
  f.nested("encoder_noise.", &C::encoder_noise, [](FieldList<C::EncoderNoise>& e) {
    e(key("from_readings", &C::EncoderNoise::from_readings));
  });
  f.nested("camera_offset.translation_", &C::camera_translation, [](FieldList<V>& v) {
    v(key("diffusion_m_per_sqrt_s", &V::diffusion_per_sqrt_s),
      key("initial_std_m", &V::initial_std),
      key("diffusion_m_per_sqrt_rad", &V::motion_diffusion_per_sqrt_rad));
  });
  f.nested("camera_offset.rotation_", &C::camera_rotation, [](FieldList<V>& v) {
    v(key("diffusion_deg_per_sqrt_s", &V::diffusion_per_sqrt_s, kRadPerDeg),
      key("initial_std_deg", &V::initial_std, kRadPerDeg),
      key("diffusion_deg_per_sqrt_rad", &V::motion_diffusion_per_sqrt_rad, kRadPerDeg));
  });
  f(key("vision_only.angle_diffusion_deg_per_sqrt_s",
        &C::vision_only_angle_diffusion_rad_per_sqrt_s, kRadPerDeg),
    key("vision_only.initial_std_deg", &C::vision_only_initial_std_rad, kRadPerDeg));
  f.nested("depth_model.", &C::depth_model, list_depth_model);
  f.nested("geometry.", &C::geometry, [](FieldList<C::Geometry>& g) {
    using G = C::Geometry;
    g(key("max_error_px", &G::max_error_px), key("nearest_range_m", &G::nearest_range_m),
      key("coarser_levels", &G::coarser_levels),
      key("open_parts_both_sides", &G::open_parts_both_sides));
  });
  f.nested("particle_filter.", &C::particle_filter, list_particle_filter);
  f.elements("particle_filter.blocks", &C::blocks, [](FieldList<C::Block>& b) {
    b(key("name", &C::Block::name), key("joints", &C::Block::joints));
  });
  f(key("particle_filter.min_evaluations", &C::min_evaluations),
    key("particle_filter.camera_blocks_per_image", &C::camera_blocks_per_image),
    key("particle_filter.likelihood_exponent", &C::likelihood_exponent),
    key("particle_filter.keep_unseen_prior", &C::keep_unseen_prior),
    key("particle_filter.unseen_below_pixels", &C::unseen_below_pixels),
    key("particle_filter.seed", &C::seed), key("particle_filter.threads", &C::threads));
  f(key("uncertainty.image_information_scale", &C::image_information_scale),
    key("uncertainty.discount_correlated_residuals", &C::discount_correlated_residuals),
    key("uncertainty.pixel_noise_after_fit", &C::pixel_noise_after_fit),
    key("uncertainty.model_error", &C::model_error),
    key("uncertainty.model_error_time_constant_s", &C::model_error_time_constant_s),
    key("uncertainty.model_error_min_std_m", &C::model_error_min_std_m),
    key("uncertainty.model_error_unpinned_scale", &C::model_error_unpinned_scale),
    key("uncertainty.model_error_learned_shifts", &C::model_error_learned_shifts),
    key("uncertainty.model_error_learned_time_constant_s", &C::model_error_learned_time_constant_s),
    key("uncertainty.model_error_learned_max_std_m", &C::model_error_learned_max_std_m),
    key("uncertainty.model_error_unpinned_scale_on_learned",
        &C::model_error_unpinned_scale_on_learned),
    key("uncertainty.link_length_std_m", &C::link_length_std_m),
    key("uncertainty.depth_scale_std", &C::depth_scale_std),
    key("uncertainty.mean_lag_scale", &C::mean_lag_scale),
    key("uncertainty.mean_lag_time_constant_s", &C::mean_lag_time_constant_s));
  f(key("refinement.enabled", &C::refine_mean),
    key("refinement.min_pixels", &C::refinement_min_pixels),
    key("refinement.widen_beyond_sigma", &C::refinement_widen_beyond_sigma),
    key("refinement.unseen_information_ratio", &C::refinement_unseen_information_ratio));
  f.nested("end_effector_fit.", &C::end_effector_fit, [](FieldList<C::EndEffectorFitConfig>& e) {
    using E = C::EndEffectorFitConfig;
    e(key("enabled", &E::enabled), key("time_constant_s", &E::time_constant_s),
      key("max_std_m", &E::max_std_m), key("resolution_factor", &E::resolution_factor),
      key("axis_search_range_m", &E::axis_search_range_m), key("link_scales", &E::link_scales));
  });
  f.nested("acquisition.", &C::acquisition, [](FieldList<C::Acquisition>& a) {
    using A = C::Acquisition;
    a(key("passes", &A::passes), key("coarse_noise_std_m", &A::coarse_noise_std_m),
      key("proposal_shrink", &A::proposal_shrink), key("period_s", &A::period_s),
      key("bias_std_deg", &A::bias_std_rad, kRadPerDeg),
      key("accept_margin_nats", &A::accept_margin_nats), key("searches", &A::searches),
      key("search_camera", &A::search_camera));
  });
  f.nested("health.", &C::health, [](FieldList<C::Health>& h) {
    using H = C::Health;
    h(key("explained_m", &H::explained_m), key("contradicted_m", &H::contradicted_m),
      key("lost_contradicted_fraction", &H::lost_contradicted_fraction),
      key("lost_abandoned_fraction", &H::lost_abandoned_fraction),
      key("unconfirmed_explained_fraction", &H::unconfirmed_explained_fraction),
      key("occluder_gap_m", &H::occluder_gap_m), key("lost_after_images", &H::lost_after_images),
      key("min_pixels", &H::min_pixels));
  });
  f(key("timing.camera_delay_s", &C::camera_delay_s),
    key("timing.buffer_capacity", &C::buffer_capacity),
    key("timing.max_pending_images", &C::max_pending_images),
    key("timing.asynchronous", &C::asynchronous));
  f(key("input_checks.joint_limit_margin_deg", &C::joint_limit_margin_rad, kRadPerDeg),
    key("input_checks.max_image_clock_offset_s", &C::max_image_clock_offset_s));
}

// Every field of the configuration, nested structs and their lists
// included, against its key in default.yaml: adding a field to the structs
// and not to the file (or the reader), or changing a default in one of them,
// fails here naming the key (the struct, for a field not in the lists).
// Exact equality: the defaults in radians are written as the file's degrees
// times kRadPerDeg, as the reader converts them.
TEST(DefaultConfigTest, TheShippedFileHoldsEveryInClassDefault) {
  const std::string path = std::string(ARTTRACK_SOURCE_DIR) + "/tracker/config/default.yaml";
  const YAML::Node yaml = YAML::LoadFile(path);
  std::set<std::string> listed;
  {
    const TrackerConfig file = load_tracker_config(path), code;
    FieldList<TrackerConfig> fields(yaml, "", file, code, listed);
    list_tracker_config(fields);
  }
  // And the other way: every key of the file is one of the fields listed.
  std::set<std::string> keys;
  leaf_keys(yaml, "", keys);
  for (const std::string& key : keys)
    EXPECT_EQ(listed.count(key), 1u) << key << " is a key of default.yaml but of no field listed";
}

TEST(DefaultConfigTest, EveryMethodRunsOnAnotherRobot) {
  const auto model = std::make_shared<const RobotModel>(RobotModel::from_urdf_file(kUrdf));
  const std::vector<std::string> joints{"yaw", "pitch_1", "pitch_2"};
  // The true configuration's depth image, at a small camera.
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 60 * kRadPerDeg);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->num_joints());
  q[model->joint_index("pitch_1")] = 0.3;
  q[model->joint_index("pitch_2")] = -0.5;
  KinematicsState state(*model);
  forward_kinematics(*model, q, state);
  DepthRenderer renderer(*model, camera);
  DepthImage image;
  renderer.render(state, image);

  for (const std::string& method : all_method_names()) {
    SCOPED_TRACE(method);
    TrackerConfig c = default_tracker_config();
    c.method = parse_method(method, "test");
    c.end_effectors = {"tool"};
    c.threads = 1;
    Tracker tracker(model, c,
                    c.method == TrackingMethod::kVisionOnly ? std::vector<std::string>{} : joints);
    const std::vector<double> reading{0.0, 0.3 + 2 * kRadPerDeg, -0.5};
    for (int k = 0; k <= 100; ++k) {
      if (c.method != TrackingMethod::kVisionOnly)
        tracker.add_joint_measurement(0.001 * k, reading);
      if (k == 50) tracker.add_depth_image(0.05, image, camera);
    }
    const TrackerEstimate e = tracker.estimate();
    EXPECT_EQ(e.joint_names, joints);
    ASSERT_EQ(e.T_camera_ee.size(), 1u);
    EXPECT_TRUE(e.T_camera_ee[0].matrix().allFinite());
    if (c.method == TrackingMethod::kFullFusion || c.method == TrackingMethod::kCameraOffsetOnly) {
      EXPECT_EQ(tracker.stats().images_applied, 1);
    }
  }
  // No end effector is fine: none is reported.
  Tracker plain(model, default_tracker_config(), joints);
  plain.add_joint_measurement(0, std::vector<double>{0, 0, 0});
  EXPECT_TRUE(plain.estimate().T_camera_ee.empty());
}

// What the dual-arm robot's overrides (now in its scene) do to any other
// robot: an error naming the joint, not a default that silently fits one.
TEST(DefaultConfigTest, OverrideOfAnotherRobotsJointIsAnError) {
  const auto model = std::make_shared<const RobotModel>(RobotModel::from_urdf_file(kUrdf));
  YamlDocument doc = default_tracker_document();
  apply_override(doc, "joints.per_joint.head_pan_joint.estimate_bias=false");
  const TrackerConfig c = tracker_config_from_yaml(doc);
  const std::string e = error_of([&] { Tracker(model, c, {"yaw", "pitch_1", "pitch_2"}); });
  EXPECT_NE(e.find("unknown joint 'head_pan_joint'"), std::string::npos) << e;
}

}  // namespace
}  // namespace arttrack
