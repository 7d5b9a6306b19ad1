// Files the tracker's loader tests write: a fresh folder per test and the toy
// meshes that more than one test program reads (an OBJ cube), so that a
// change to a fixture is made once.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scratch_dir.h"

namespace arttrack::test_support {

// A fresh folder for the files the running test writes, named after the test,
// in the program's scratch folder (scratch_dir.h).
inline std::filesystem::path fresh_test_dir() {
  return program_scratch_dir().subfolder(
      ::testing::UnitTest::GetInstance()->current_test_info()->name());
}

// Writes `text` to `path` byte for byte; its folder must exist.
inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A unit cube of six quads wound counter-clockwise seen from outside.
inline constexpr char kUnitCubeObj[] = R"(# unit cube
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)";

}  // namespace arttrack::test_support
