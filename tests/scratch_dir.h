// Scratch folders for the files a test writes. A ScratchDir is a fresh folder
// under the system's temporary directory that is removed, with everything in
// it, when the object goes out of scope, so that a test run leaves nothing
// behind in /tmp (a test that crashes still can).
//
//   const test_support::ScratchDir dir("scene_test");
//   const auto urdf = dir.write("robot.urdf", text);
//
// Helpers that write files outside any one test's scope use
// program_scratch_dir(), which lives until the test program exits.
#pragma once

#include <errno.h>  // program_invocation_short_name (glibc)
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace arttrack::test_support {

class ScratchDir {
 public:
  // <temp>/arttrack_<tag>_<process id>. The process id keeps apart the test
  // processes that CTest runs in parallel; a folder of the same name left by
  // a crashed run is emptied first.
  explicit ScratchDir(const std::string& tag)
      : dir_(std::filesystem::temp_directory_path() /
             ("arttrack_" + tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  ~ScratchDir() {
    std::error_code ignored;  // a destructor must not throw; nothing to do about it
    std::filesystem::remove_all(dir_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return dir_; }
  std::filesystem::path operator/(const std::filesystem::path& relative) const {
    return dir_ / relative;
  }

  // Writes `text` (bytes as they are) to path() / relative, creating the
  // folders on the way; returns the file's path.
  std::filesystem::path write(const std::filesystem::path& relative,
                              const std::string& text) const {
    const std::filesystem::path file = dir_ / relative;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }

  // A fresh subfolder, created (emptied if it exists); returns its path.
  std::filesystem::path subfolder(const std::filesystem::path& relative) const {
    const std::filesystem::path folder = dir_ / relative;
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
  }

 private:
  std::filesystem::path dir_;
};

// The running test program's scratch folder, named after the program (one
// per process, as CTest runs one test per process); removed when it exits.
inline const ScratchDir& program_scratch_dir() {
  static const ScratchDir dir(program_invocation_short_name);
  return dir;
}

// Writes `text` to program_scratch_dir() / relative (ScratchDir::write), for
// the test programs that keep all their files in that one folder; returns the
// file's path.
inline std::filesystem::path write_scratch_file(const std::filesystem::path& relative,
                                                const std::string& text) {
  return program_scratch_dir().write(relative, text);
}

}  // namespace arttrack::test_support
