#include "arttrack/tracker/kinematics.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>

#include "../count_allocations.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {
namespace {

// base -> j1 (revolute, non-unit axis) -> l1 -> j2 (prismatic, oblique axis)
// -> l2 -> fixed -> l3 -> j3 (continuous) -> camera_optical_frame.
constexpr char kChain[] = R"(<robot name="chain">
  <link name="base_link"/><link name="l1"/><link name="l2"/><link name="l3"/>
  <link name="camera_optical_frame"/>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="l1"/>
    <origin xyz="0.1 -0.2 0.3" rpy="0.3 -0.5 1.2"/><axis xyz="0 0 2"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="prismatic">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0 0.4 0" rpy="-1.0 0.2 0.7"/><axis xyz="1 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="fix" type="fixed">
    <parent link="l2"/><child link="l3"/><origin xyz="0.05 0 -0.1" rpy="2.0 0.1 -0.4"/>
  </joint>
  <joint name="j3" type="continuous">
    <parent link="l3"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 0.2" rpy="0 1.5 0"/><axis xyz="0.3 -0.4 0.5"/>
  </joint>
</robot>
)";

// Elementary rotations written out, independent of urdfdom and Eigen's AngleAxis.
Eigen::Matrix3d Rx(double a) {
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return R;
}
Eigen::Matrix3d Ry(double a) {
  Eigen::Matrix3d R;
  R << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return R;
}
Eigen::Matrix3d Rz(double a) {
  Eigen::Matrix3d R;
  R << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return R;
}
// Rodrigues' formula for a rotation by `angle` about unit `k`.
Eigen::Matrix3d rotation_about(const Eigen::Vector3d& k, double angle) {
  Eigen::Matrix3d K;
  K << 0, -k.z(), k.y(), k.z(), 0, -k.x(), -k.y(), k.x(), 0;
  return Eigen::Matrix3d::Identity() + std::sin(angle) * K + (1 - std::cos(angle)) * K * K;
}
// URDF origin: translation xyz, rotation Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix4d origin(double x, double y, double z, double roll, double pitch, double yaw) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = Rz(yaw) * Ry(pitch) * Rx(roll);
  T.topRightCorner<3, 1>() = Eigen::Vector3d(x, y, z);
  return T;
}
Eigen::Matrix4d rotation4(const Eigen::Matrix3d& R) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = R;
  return T;
}
Eigen::Matrix4d translation4(const Eigen::Vector3d& p) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topRightCorner<3, 1>() = p;
  return T;
}

TEST(Kinematics, MatchesHandComposedTransforms) {
  RobotModelOptions options;
  options.add_virtual_camera_joints = false;
  const RobotModel model = RobotModel::from_urdf_string(kChain, "", options);
  ASSERT_EQ(model.num_joints(), 3);
  KinematicsState state(model);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-2, 2);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d q(U(rng), 0.3 * U(rng), 3 * U(rng));
    forward_kinematics(model, q, state);
    const Eigen::Matrix4d T_base_l1 = origin(0.1, -0.2, 0.3, 0.3, -0.5, 1.2) * rotation4(Rz(q[0]));
    const Eigen::Matrix4d T_base_l2 = T_base_l1 * origin(0, 0.4, 0, -1.0, 0.2, 0.7) *
                                      translation4(q[1] * Eigen::Vector3d(1, 1, 0) / std::sqrt(2));
    const Eigen::Matrix4d T_base_l3 = T_base_l2 * origin(0.05, 0, -0.1, 2.0, 0.1, -0.4);
    const Eigen::Matrix4d T_base_cam =
        T_base_l3 * origin(0, 0, 0.2, 0, 1.5, 0) *
        rotation4(rotation_about(Eigen::Vector3d(0.3, -0.4, 0.5).normalized(), q[2]));
    EXPECT_LT((state.T_root_link[model.link_index("l1")].matrix() - T_base_l1).norm(), 1e-13);
    EXPECT_LT((state.T_root_link[model.link_index("l2")].matrix() - T_base_l2).norm(), 1e-13);
    EXPECT_LT((state.T_root_link[model.link_index("l3")].matrix() - T_base_l3).norm(), 1e-13);
    EXPECT_LT(
        (state.T_root_link[model.link_index("camera_optical_frame")].matrix() - T_base_cam).norm(),
        1e-13);
  }
}

// d/dq of a point fixed on a link below DOF j is w x (p - o) for a revolute
// joint (w its world axis, o its world origin) and w for a prismatic one; the
// rotation's derivative is [w]x R for revolute and zero for prismatic.
TEST(Kinematics, FiniteDifferencesMatchJointScrews) {
  const RobotModel model = RobotModel::from_urdf_string(kChain, "");
  KinematicsState state(model), plus(model), minus(model);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  const Eigen::Vector3d p_link(0.2, -0.1, 0.3);  // a point on each link
  const double h = 1e-6;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q(model.num_joints());
    for (int j = 0; j < q.size(); ++j) q[j] = U(rng);
    forward_kinematics(model, q, state);
    for (int j = 0; j < model.num_joints(); ++j) {
      const int child = model.joint_child_link(j);
      const Eigen::Isometry3d& T_root_child = state.T_root_link[child];
      const Eigen::Vector3d w = T_root_child.linear() * model.link(child).axis;
      const Eigen::Vector3d o = T_root_child.translation();
      const bool prismatic = model.joint_type(j) == JointType::kPrismatic;
      Eigen::VectorXd qp = q, qm = q;
      qp[j] += h;
      qm[j] -= h;
      forward_kinematics(model, qp, plus);
      forward_kinematics(model, qm, minus);
      const LinkSet moved = model.links_moved_by(j);
      for (int l = 0; l < model.num_links(); ++l) {
        const Eigen::Vector3d p = state.T_root_link[l] * p_link;
        const Eigen::Vector3d dp =
            (plus.T_root_link[l] * p_link - minus.T_root_link[l] * p_link) / (2 * h);
        const Eigen::Matrix3d dR =
            (plus.T_root_link[l].linear() - minus.T_root_link[l].linear()) / (2 * h);
        Eigen::Vector3d dp_expected = Eigen::Vector3d::Zero();
        Eigen::Matrix3d dR_expected = Eigen::Matrix3d::Zero();
        if (moved[l]) {
          dp_expected = prismatic ? w : Eigen::Vector3d(w.cross(p - o));
          if (!prismatic) {
            Eigen::Matrix3d W;
            W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
            dR_expected = W * state.T_root_link[l].linear();
          }
        }
        EXPECT_LT((dp - dp_expected).norm(), 1e-7)
            << model.joint_name(j) << " " << model.link_name(l);
        EXPECT_LT((dR - dR_expected).norm(), 1e-7)
            << model.joint_name(j) << " " << model.link_name(l);
      }
    }
  }
}

TEST(Kinematics, VirtualJointsCorrectTheCameraFrameOnly) {
  const RobotModel model = RobotModel::from_urdf_string(kChain, "");
  ASSERT_EQ(model.num_joints(), 9);
  KinematicsState zero(model), state(model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  q.head(3) << 0.4, 0.1, -0.7;
  forward_kinematics(model, q, zero);
  const double x = 0.02, y = -0.03, z = 0.05, roll = 0.1, pitch = -0.2, yaw = 0.3;
  q.tail(6) << x, y, z, roll, pitch, yaw;
  forward_kinematics(model, q, state);
  const int nominal = model.nominal_camera_link();
  const int corrected = model.camera_link();
  // All zero: the corrected frame is the nominal one.
  EXPECT_LT((zero.T_root_link[corrected].matrix() - zero.T_root_link[nominal].matrix()).norm(),
            1e-15);
  // T_nominal_corrected = Trans(x, y, z) Rx(roll) Ry(pitch) Rz(yaw).
  const Eigen::Matrix4d T_nominal_corrected =
      translation4(Eigen::Vector3d(x, y, z)) * rotation4(Rx(roll) * Ry(pitch) * Rz(yaw));
  EXPECT_LT((state.T_root_link[corrected].matrix() -
             state.T_root_link[nominal].matrix() * T_nominal_corrected)
                .norm(),
            1e-14);
  // Every URDF link stays where it was.
  for (int l = 0; l <= nominal; ++l) {
    EXPECT_TRUE(state.T_root_link[l].isApprox(zero.T_root_link[l], 1e-15)) << model.link_name(l);
  }
  // The pose of a link in the corrected camera frame.
  const Eigen::Isometry3d T_cam_l1 = T_camera_link(model, state, model.link_index("l1"));
  EXPECT_TRUE((state.T_root_link[corrected] * T_cam_l1)
                  .isApprox(state.T_root_link[model.link_index("l1")], 1e-12));
}

// A tree: a joint above both the hand and the camera (j0), an arm with a
// prismatic joint and a mimic finger (1.5 times a1, off 0.2), the camera on
// its own branch (c1).
constexpr char kBranchedTree[] = R"(<robot name="tree">
  <link name="base_link"/><link name="trunk"/><link name="arm1"/><link name="arm2"/>
  <link name="hand"/><link name="finger"/><link name="neck"/><link name="camera_optical_frame"/>
  <joint name="j0" type="revolute">
    <parent link="base_link"/><child link="trunk"/>
    <origin xyz="0.1 0 0.3" rpy="0.2 0 0.4"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="a1" type="revolute">
    <parent link="trunk"/><child link="arm1"/>
    <origin xyz="0.3 -0.2 0.1" rpy="-0.4 0.9 0.1"/><axis xyz="1 2 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="a2" type="prismatic">
    <parent link="arm1"/><child link="arm2"/>
    <origin xyz="0 0.4 0.05" rpy="1.1 -0.3 0.2"/><axis xyz="0 1 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="wrist" type="fixed">
    <parent link="arm2"/><child link="hand"/><origin xyz="0.05 0.1 -0.2" rpy="0.3 0.2 -0.5"/>
  </joint>
  <joint name="m1" type="revolute">
    <parent link="hand"/><child link="finger"/>
    <origin xyz="0.02 0 0.1" rpy="0 0.7 0"/><axis xyz="0.2 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
    <mimic joint="a1" multiplier="1.5" offset="0.2"/>
  </joint>
  <joint name="c1" type="continuous">
    <parent link="trunk"/><child link="neck"/>
    <origin xyz="0 0.1 0.5" rpy="0 0 0"/><axis xyz="0 1 0.3"/>
  </joint>
  <joint name="mount" type="fixed">
    <parent link="neck"/><child link="camera_optical_frame"/>
    <origin xyz="0.1 0 0.05" rpy="-1.6 0 -1.5"/>
  </joint>
</robot>
)";

// camera_link_jacobian() against central differences of T_camera_link:
// the position's, and the rotation vector of R(q + h) R(q - h)^T.
void expect_jacobian_matches_differences(const RobotModel& model, const std::vector<int>& links,
                                         unsigned seed) {
  KinematicsState state(model), plus(model), minus(model);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  const double h = 1e-6;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd q(model.num_joints());
    for (int j = 0; j < q.size(); ++j) q[j] = model.is_virtual_joint(j) ? 0.05 * U(rng) : U(rng);
    forward_kinematics(model, q, state);
    for (int link : links) {
      camera_link_jacobian(model, state, link, J);
      ASSERT_EQ(J.cols(), model.num_joints());
      for (int j = 0; j < model.num_joints(); ++j) {
        Eigen::VectorXd qp = q, qm = q;
        qp[j] += h;
        qm[j] -= h;
        forward_kinematics(model, qp, plus);
        forward_kinematics(model, qm, minus);
        const Eigen::Isometry3d Tp = T_camera_link(model, plus, link);
        const Eigen::Isometry3d Tm = T_camera_link(model, minus, link);
        const Eigen::AngleAxisd turn(Tp.linear() * Tm.linear().transpose());
        const Eigen::Vector3d dp = (Tp.translation() - Tm.translation()) / (2 * h);
        const Eigen::Vector3d dw = turn.angle() * turn.axis() / (2 * h);
        EXPECT_LT((J.col(j).head<3>() - dp).norm(), 1e-7)
            << model.link_name(link) << " " << model.joint_name(j);
        EXPECT_LT((J.col(j).tail<3>() - dw).norm(), 1e-7)
            << model.link_name(link) << " " << model.joint_name(j);
      }
    }
  }
}

TEST(Kinematics, CameraFrameJacobianMatchesCentralDifferences) {
  const RobotModel tree = RobotModel::from_urdf_string(kBranchedTree, "");
  std::vector<int> links;
  for (int l = 0; l < tree.num_links(); ++l) links.push_back(l);  // the camera's own too
  expect_jacobian_matches_differences(tree, links, 3);
  // A joint above both the hand and the camera moves neither relative to the other.
  KinematicsState state(tree);
  forward_kinematics(tree, Eigen::VectorXd::Constant(tree.num_joints(), 0.4), state);
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;
  camera_link_jacobian(tree, state, tree.link_index("finger"), J);
  EXPECT_LT(J.col(tree.joint_index("j0")).norm(), 1e-12);
  EXPECT_GT(J.col(tree.joint_index("a1")).norm(), 0.1);  // a1, and the finger's mimic of it
  EXPECT_GT(J.col(tree.joint_index("c1")).norm(), 0.1);  // the camera's own joint
  // The shipped dual arm: its hands, its head camera and its six camera joints.
  const RobotModel dual =
      RobotModel::from_urdf_file(std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm.urdf");
  expect_jacobian_matches_differences(
      dual, {dual.link_index("left_hand"), dual.link_index("right_hand"), dual.link_index("torso")},
      5);
}

TEST(Kinematics, CameraFrameJacobianAllocatesNothingOnceSized) {
  const RobotModel model = RobotModel::from_urdf_string(kBranchedTree, "");
  KinematicsState state(model);
  forward_kinematics(model, Eigen::VectorXd::Constant(model.num_joints(), 0.3), state);
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, model.num_joints());
  const long before = g_allocations.load();
  for (int i = 0; i < 100; ++i) camera_link_jacobian(model, state, model.link_index("finger"), J);
  EXPECT_EQ(g_allocations.load(), before);
}

TEST(Kinematics, AllocatesNothingOnceSized) {
  const RobotModel model = RobotModel::from_urdf_string(kChain, "");
  KinematicsState state(model);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(model.num_joints(), 0.3);
  forward_kinematics(model, q, state);
  const long before = g_allocations.load();
  for (int i = 0; i < 100; ++i) forward_kinematics(model, q, state);
  EXPECT_EQ(g_allocations.load(), before);
}

}  // namespace
}  // namespace arttrack
