// track_arm: the arttrack tracker fed from a program's own loop.
//
// A three-joint arm (URDF below) moves its turntable back and forth; its
// encoders report at 1 kHz, the second joint's with a constant bias of 3
// degrees. A depth camera fixed in the world sends an image at 30 Hz
// (rendered here from the true configuration with the library's own depth
// renderer; a real program passes its camera's images). The tracker starts
// from the shipped default configuration and estimates the angles, the
// biases and the camera offset; the program prints the estimate twice a
// second and the bias it found at the end.
//
//   track_arm              full fusion with depth images
//   track_arm --no-images  the encoders alone (the bias stays unseen)
//
// Exits 1 if the bias estimate with images is off by more than 1 degree, so
// that the build's check notices a broken installation.
#include <arttrack/tracker/depth_renderer.h>
#include <arttrack/tracker/kinematics.h>
#include <arttrack/tracker/tracker.h>
#include <arttrack/tracker/version.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numbers>
#include <vector>

namespace {

constexpr double kDeg = std::numbers::pi / 180;

constexpr char kArmUrdf[] = R"(<robot name="example_arm">
  <link name="world"/>
  <link name="turntable"><visual><origin xyz="0 0 0.025"/>
    <geometry><cylinder radius="0.08" length="0.05"/></geometry></visual></link>
  <link name="link_a"><visual><origin xyz="0 0 0.15"/>
    <geometry><box size="0.05 0.06 0.3"/></geometry></visual></link>
  <link name="link_b"><visual><origin xyz="0 0 0.125"/>
    <geometry><box size="0.04 0.08 0.25"/></geometry></visual></link>
  <link name="tool"/>
  <link name="camera_optical_frame"/>
  <joint name="yaw" type="revolute"><parent link="world"/><child link="turntable"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <joint name="pitch_1" type="revolute"><parent link="turntable"/><child link="link_a"/>
    <origin xyz="0 0 0.05"/><axis xyz="1 0 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="pitch_2" type="revolute"><parent link="link_a"/><child link="link_b"/>
    <origin xyz="0 0 0.3"/><axis xyz="1 0 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="link_b"/><child link="tool"/>
    <origin xyz="0 0 0.25"/></joint>
  <joint name="camera_joint" type="fixed"><parent link="world"/><child link="camera_optical_frame"/>
    <origin xyz="1.0 0 0.3" rpy="-1.5707963267948966 0 1.5707963267948966"/></joint>
</robot>)";

// The true motion: the turntable sways, the arm holds a pose.
std::vector<double> true_angles_rad(double t_s) {
  return {0.2 * std::sin(2 * std::numbers::pi * 0.25 * t_s), 0.3, -0.5};
}

}  // namespace

int main(int argc, char** argv) {
  const bool images = !(argc > 1 && std::strcmp(argv[1], "--no-images") == 0);
  try {
    const auto model = std::make_shared<const arttrack::RobotModel>(
        arttrack::RobotModel::from_urdf_string(kArmUrdf, "."));
    const std::vector<std::string> joints{"yaw", "pitch_1", "pitch_2"};
    const std::vector<double> bias_rad{0.0, 3 * kDeg, 0.0};

    arttrack::TrackerConfig config = arttrack::default_tracker_config();
    config.method =
        images ? arttrack::TrackingMethod::kFullFusion : arttrack::TrackingMethod::kEncodersOnly;
    config.end_effectors = {"tool"};
    config.threads = 1;
    // The likelihood at the camera's full resolution (the default's 80x60
    // suits a robot that fills the image; this arm is small in it).
    config.depth_model.width = 160;
    config.depth_model.height = 120;
    // The camera is bolted to the world here: no camera offset to estimate
    // (a planar arm cannot tell it from a joint angle).
    config.camera_translation = {1e-9, 1e-9};
    config.camera_rotation = {1e-9, 1e-9};
    arttrack::Tracker tracker(model, config, joints);

    // The "camera": the true configuration rendered by the library.
    const auto camera = arttrack::CameraIntrinsics::from_vertical_fov(160, 120, 45 * kDeg);
    arttrack::DepthRenderer renderer(*model, camera);
    arttrack::KinematicsState state(*model);
    arttrack::DepthImage image;

    std::printf("arttrack %s, %s\n", ARTTRACK_VERSION,
                images ? "full fusion (joints 1 kHz, depth 30 Hz)" : "encoders only (1 kHz)");
    const int steps = 4000;  // 4 s at 1 kHz
    for (int k = 0; k <= steps; ++k) {
      const double t_s = 0.001 * k;
      const std::vector<double> q = true_angles_rad(t_s);
      std::vector<double> reading(q.size());
      for (std::size_t j = 0; j < q.size(); ++j) reading[j] = q[j] + bias_rad[j];
      tracker.add_joint_measurement(t_s, reading);
      if (images && k % 33 == 0) {
        Eigen::VectorXd q_model = Eigen::VectorXd::Zero(model->num_joints());
        for (std::size_t j = 0; j < joints.size(); ++j)
          q_model[model->joint_index(joints[j])] = q[j];
        arttrack::forward_kinematics(*model, q_model, state);
        renderer.render(state, image);
        tracker.add_depth_image(t_s, image, camera);
      }
      if (k % 500 == 0) {
        const arttrack::TrackerEstimate e = tracker.estimate();
        const Eigen::Vector3d tool_m = e.T_camera_ee[0].translation();
        std::printf("t %.1f s  angles [deg]", t_s);
        for (std::size_t j = 0; j < e.joint_names.size(); ++j)
          std::printf(" %s %.2f (bias %.2f)", e.joint_names[j].c_str(), e.angle_rad[j] / kDeg,
                      e.bias_rad[j] / kDeg);
        std::printf("  tool in camera [m] %.3f %.3f %.3f\n", tool_m.x(), tool_m.y(), tool_m.z());
      }
    }
    const arttrack::TrackerEstimate e = tracker.estimate();
    const double found_deg = e.bias_rad[model->joint_index("pitch_1")] / kDeg;
    std::printf("bias of pitch_1: %.2f deg (true 3.00), %d images applied\n", found_deg,
                tracker.stats().images_applied);
    return images && std::abs(found_deg - 3.0) > 1.0 ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "track_arm: %s\n", e.what());
    return 1;
  }
}
