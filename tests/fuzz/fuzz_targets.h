// Entry points shared by the libFuzzer harnesses (tests/fuzz/fuzz_*.cc, built
// with -DARTTRACK_FUZZ=ON and clang) and the regression test that replays
// their findings in the normal suite (fuzz_regression_test.cc).
//
// Each target feeds one input to the project's readers the way a user's file
// reaches them (written to a file in a private temporary folder, then read by
// the public loader). It returns the InputError's message for input the
// readers reject, "" for input they accept; any other exception propagates
// (a finding: a crash, a hang or an unclear error is never a clean refusal).
//
// Input formats (what tools/fuzz.sh seeds the corpus with):
//   urdf     URDF text, read by RobotModel::from_urdf_string and, written as
//            a file next to the shipped models, by sim::prepare_urdf (with
//            the package arttrack_models there, as the default scene).
//   mesh     one selector byte ('s' STL, 'o' OBJ, 'd' COLLADA; others by
//            value), then the mesh file: load_mesh and the simulator's STL
//            conversion.
//   yaml     one selector byte ('T' tracker configuration, 'S' scene, 'C'
//            scenario; others by value), then the YAML file, written next
//            to the shipped ones so that relative references resolve.
//   dataset  the text files of a dataset separated by lines "@@@":
//            camera.yaml, joints.csv, ground_truth.csv, depth/index.csv,
//            dataset.yaml, then the bytes of depth/a.png; load_dataset, then
//            read_dataset_frame on its first frames.
//   png      a depth PNG: read_depth_png_mm.
#pragma once

#include <string>
#include <string_view>

namespace arttrack::fuzz {

std::string urdf_one(std::string_view data);
std::string mesh_one(std::string_view data);
std::string yaml_one(std::string_view data);
std::string dataset_one(std::string_view data);
std::string png_one(std::string_view data);

// The separator between the files of a dataset input.
inline constexpr std::string_view kDatasetSeparator = "\n@@@\n";

}  // namespace arttrack::fuzz
