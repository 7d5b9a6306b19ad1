// The testbed's search folders (search_paths.h): set by the program, not
// compiled in; a file found in neither place is named with the folders tried.
#include "arttrack/sim/search_paths.h"

#include <gtest/gtest.h>

#include "../error_of.h"
#include "../scratch_dir.h"
#include "arttrack/sim/scene.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;

// Restores the search folders the test program set (search_dirs.cc).
struct SearchDirsGuard {
  std::vector<fs::path> saved = search_dirs();
  ~SearchDirsGuard() { set_search_dirs(saved); }
};

TEST(SearchPaths, DefaultsAreFoundInTheSearchFoldersOnly) {
  SearchDirsGuard guard;
  EXPECT_EQ(default_scene_path(), fs::path(ARTTRACK_SOURCE_DIR) / "models/scene_default.yaml");
  set_search_dirs({});
  EXPECT_EQ(search_dirs_text(), "none set");
  const std::string e = test_support::error_of([] { default_scene_path(); });
  EXPECT_NE(e.find("models/scene_default.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("none set"), std::string::npos) << e;
}

TEST(SearchPaths, AMissingFileIsNamedWithTheFoldersTried) {
  SearchDirsGuard guard;
  const test_support::ScratchDir dir("search_paths_test");
  const fs::path missing = dir.write("missing.yaml", "robot:\n  urdf: models/no_such.urdf\n");
  set_search_dirs({dir / "first", ARTTRACK_SOURCE_DIR});
  const std::string e = test_support::error_of([&] { load_scene(missing); });
  EXPECT_NE(e.find("models/no_such.urdf"), std::string::npos) << e;
  EXPECT_NE(e.find("next to the scene (in " + dir.path().string()), std::string::npos) << e;
  EXPECT_NE(e.find((dir / "first").string() + ", " + ARTTRACK_SOURCE_DIR), std::string::npos) << e;
  // A file the second folder holds is found there.
  const fs::path found = dir.write("found.yaml", "robot:\n  urdf: models/dual_arm.urdf\n");
  EXPECT_EQ(load_scene(found).urdf_path,
            fs::weakly_canonical(fs::path(ARTTRACK_SOURCE_DIR) / "models/dual_arm.urdf"));
}

}  // namespace
}  // namespace arttrack::sim
