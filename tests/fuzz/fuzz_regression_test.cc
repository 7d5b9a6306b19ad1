// Replays what fuzzing found (tests/fuzz/regressions/<target>/<input>) through
// the fuzz targets: each must now be refused with a clear InputError (any
// other exception, a crash or a hang fails). And the shipped files, fed the
// way tools/fuzz.sh seeds the corpus, must be accepted, so that the targets
// really reach the readers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include "../scratch_dir.h"
#include "arttrack/sim/dataset.h"
#include "fuzz_targets.h"

namespace arttrack::fuzz {
namespace {
namespace fs = std::filesystem;

const fs::path kSource(ARTTRACK_SOURCE_DIR);

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::map<std::string, std::function<std::string(std::string_view)>> kTargets = {
    {"urdf", urdf_one},
    {"mesh", mesh_one},
    {"yaml", yaml_one},
    {"dataset", dataset_one},
    {"png", png_one}};

// Replays regressions/<target>/* for the targets named; returns how many.
int replay_findings(std::initializer_list<std::string> targets) {
  int replayed = 0;
  for (const std::string& name : targets) {
    const fs::path dir = kSource / "tests/fuzz/regressions" / name;
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      SCOPED_TRACE(entry.path().string());
      std::string error;
      EXPECT_NO_THROW(error = kTargets.at(name)(read_file(entry.path())));
      EXPECT_FALSE(error.empty()) << "accepted";
      ++replayed;
    }
  }
  return replayed;
}

TEST(FuzzRegression, FindingsAreRefusedCleanly) {
  EXPECT_GT(replay_findings({"urdf", "yaml", "dataset", "png"}), 0);
}

// Apart, because assimp leaks its half-built scene on a malformed COLLADA
// file (its own bug): the sanitizer stage runs this test alone with
// tests/fuzz/lsan.supp (tests/fuzz/CMakeLists.txt).
TEST(FuzzRegressionAssimp, MeshFindingsAreRefusedCleanly) {
  EXPECT_GT(replay_findings({"mesh"}), 0);
}

TEST(FuzzRegression, ShippedFilesAreAccepted) {
  for (const char* urdf : {"models/dual_arm.urdf", "models/dual_arm_meshes.urdf"})
    EXPECT_EQ(urdf_one(read_file(kSource / urdf)), "") << urdf;
  for (const char* mesh : {"smeshes/forearm.stl", "omeshes/upper_arm.obj", "dmeshes/left/hand.dae"})
    EXPECT_EQ(mesh_one(mesh[0] + read_file(kSource / "models" / (mesh + 1))), "") << mesh;
  EXPECT_EQ(yaml_one("T" + read_file(kSource / "tracker/config/default.yaml")), "");
  EXPECT_EQ(yaml_one("S" + read_file(kSource / "models/scene_default.yaml")), "");
  EXPECT_EQ(yaml_one("C" + read_file(kSource / "scenarios/occlusion.yaml")), "");
}

TEST(FuzzRegression, ExportedDatasetIsAccepted) {
  const test_support::ScratchDir scratch("fuzz_regression_test");
  const fs::path dir = scratch / "dataset";
  // The small dataset tools/fuzz.sh seeds its corpus with.
  sim::export_scenario(
      kSource / "scenarios/default.yaml",
      {"duration_s=0.1", "camera.width=32", "camera.height=24", "joint_rate_hz=100"}, -1, dir);
  // As the corpus: the index lists the one image the input carries.
  const std::string png = read_file(dir / "depth/000000.000000.png");
  const std::string index = "stamp_s,arrival_s,file\n0,0,a.png\n";
  auto input = [&](const std::string& camera) {
    return camera + std::string(kDatasetSeparator) + read_file(dir / "joints.csv") +
           std::string(kDatasetSeparator) + read_file(dir / "ground_truth.csv") +
           std::string(kDatasetSeparator) + index + std::string(kDatasetSeparator) +
           read_file(dir / "dataset.yaml") + std::string(kDatasetSeparator) + png;
  };
  const std::string camera = read_file(dir / "camera.yaml");
  EXPECT_EQ(png_one(png), "");
  EXPECT_EQ(dataset_one(input(camera)), "");
  // The image is read: one of another size than camera.yaml's is refused.
  std::string wider = camera;
  wider.replace(wider.find("width: 32"), 9, "width: 33");
  EXPECT_NE(dataset_one(input(wider)).find("camera.yaml says 33x24"), std::string::npos);
}

}  // namespace
}  // namespace arttrack::fuzz
