#include "arttrack/sim/search_paths.h"

#include <system_error>
#include <utility>

#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

std::vector<fs::path>& dirs() {
  static std::vector<fs::path> d;
  return d;
}

}  // namespace

void set_search_dirs(std::vector<fs::path> d) { dirs() = std::move(d); }

const std::vector<fs::path>& search_dirs() { return dirs(); }

std::optional<fs::path> find_in_search_dirs(const fs::path& relative) {
  std::error_code ec;  // a name too long for the system is no file, not an exception
  for (const fs::path& dir : dirs())
    if (fs::exists(dir / relative, ec)) return dir / relative;
  return std::nullopt;
}

std::string search_dirs_text() {
  if (dirs().empty()) return "none set";
  std::string text;
  for (const fs::path& dir : dirs()) text += (text.empty() ? "" : ", ") + dir.string();
  return text;
}

fs::path find_default_file(const fs::path& relative, const std::string& what) {
  if (const std::optional<fs::path> found = find_in_search_dirs(relative)) return *found;
  throw InputError("the " + what + " " + relative.string() + " is in none of the search folders (" +
                   search_dirs_text() + ")");
}

}  // namespace arttrack::sim
