// Where the testbed looks for a file that a scene or scenario names by a
// relative path and does not hold next to itself (`urdf:`, `packages:`,
// `scene:`, `tracker:`, ...), and for the default scene and scenario. The
// program sets the folders (the arttrack program and the Python module: the
// source tree they were built from, from their own compile definition); the
// library has none compiled in, and without them finds files next to the
// naming file only. Set them before loading anything, from one thread.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace arttrack::sim {

// The folders, searched in order (none by default).
void set_search_dirs(std::vector<std::filesystem::path> dirs);
const std::vector<std::filesystem::path>& search_dirs();

// dir / relative for the first search folder where that exists; nullopt if
// none does.
std::optional<std::filesystem::path> find_in_search_dirs(const std::filesystem::path& relative);

// The search folders for messages: "a, b", or "none set".
std::string search_dirs_text();

// find_in_search_dirs(relative), or InputError naming `what`, the file and
// the folders tried: for the default scene and scenario.
std::filesystem::path find_default_file(const std::filesystem::path& relative,
                                        const std::string& what);

}  // namespace arttrack::sim
