#include "arttrack/tracker/model_limits.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <set>
#include <vector>

#include "arttrack/tracker/error.h"

namespace arttrack {

void check_model_count(const std::string& source, std::uint64_t count, std::uint64_t limit,
                       const std::string& what) {
  if (count <= limit) return;
  throw InputError(source + ": " + std::to_string(count) + " " + what + ", more than the " +
                   std::to_string(limit) +
                   " arttrack takes (docs/robots.md, 'Limits'); simplify the description");
}

int chain_depth(const std::map<std::string, std::string>& parent_of, std::string* deepest) {
  std::map<std::string, int> depth;  // joints from the root, once known
  int best = 0;
  for (const auto& entry : parent_of) {
    // Up to a link of known depth, the root or around a loop; then the
    // depths on the way back down.
    std::vector<std::string> path;
    std::set<std::string> visited;
    std::string link = entry.first;
    int d = 0;
    for (;;) {
      if (const auto known = depth.find(link); known != depth.end()) {
        d = known->second;
        break;
      }
      const auto up = parent_of.find(link);
      if (up == parent_of.end()) {  // the root
        depth[link] = 0;
        break;
      }
      if (!visited.insert(link).second) break;  // a loop: counted from here
      path.push_back(link);
      link = up->second;
    }
    for (auto it = path.rbegin(); it != path.rend(); ++it) {
      depth[*it] = ++d;
      if (d > best) {
        best = d;
        if (deepest) *deepest = *it;
      }
    }
  }
  return best;
}

void check_chain_depth(const std::string& source,
                       const std::map<std::string, std::string>& parent_of) {
  std::string deepest;
  const int depth = chain_depth(parent_of, &deepest);
  if (depth <= ModelLimits::kMaxChainDepth) return;
  throw InputError(source + ": link '" + deepest + "' is " + std::to_string(depth) +
                   " joints from the root, more than the " +
                   std::to_string(ModelLimits::kMaxChainDepth) +
                   " arttrack takes (docs/robots.md, 'Limits'); simplify the description");
}

void check_urdf_file_size(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes <= ModelLimits::kMaxUrdfBytes) return;
  throw InputError(path.string() + ": " + std::to_string(bytes) + " bytes, more than the " +
                   std::to_string(ModelLimits::kMaxUrdfBytes) +
                   " a URDF may have in arttrack (docs/robots.md, 'Limits')");
}

void check_urdf_text(const std::string& xml, const std::string& source) {
  const auto line_at = [&](std::size_t at) {
    return std::to_string(1 + std::count(xml.begin(), xml.begin() + std::ptrdiff_t(at), '\n'));
  };
  if (const std::size_t at = xml.find("<!ENTITY"); at != std::string::npos)
    throw InputError(source + ": line " + line_at(at) +
                     ": an XML entity declaration (<!ENTITY ...>): URDF uses none, and arttrack "
                     "expands none (nested entities can expand a small file to gigabytes); write "
                     "the values out");
  // Element depth: start tags open, end tags close, "/>" opens nothing.
  int depth = 0;
  for (std::size_t at = xml.find('<'); at != std::string::npos; at = xml.find('<', at)) {
    const auto skip_to = [&](const char* end) {
      const std::size_t found = xml.find(end, at);
      return found == std::string::npos ? xml.size() : found + std::strlen(end);
    };
    if (xml.compare(at, 4, "<!--") == 0) {
      at = skip_to("-->");
    } else if (xml.compare(at, 9, "<![CDATA[") == 0) {
      at = skip_to("]]>");
    } else if (xml.compare(at, 2, "<?") == 0) {
      at = skip_to("?>");
    } else if (xml.compare(at, 2, "<!") == 0 || xml.compare(at, 2, "</") == 0) {
      depth -= xml[at + 1] == '/';
      at = skip_to(">");
    } else {  // a start tag, to its '>' outside quoted values
      const std::size_t start = at;
      char quote = 0;
      for (++at; at < xml.size() && (quote || xml[at] != '>'); ++at) {
        if (quote && xml[at] == quote)
          quote = 0;
        else if (!quote && (xml[at] == '"' || xml[at] == '\''))
          quote = xml[at];
      }
      if (at < xml.size() && xml[at - 1] != '/' && ++depth > ModelLimits::kMaxXmlDepth)
        throw InputError(source + ": line " + line_at(start) + ": elements nested more than " +
                         std::to_string(ModelLimits::kMaxXmlDepth) +
                         " deep (a URDF nests 5); arttrack reads at most " +
                         std::to_string(ModelLimits::kMaxXmlDepth));
    }
  }
}

std::optional<std::uint64_t> binary_stl_triangle_count(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  in.seekg(0, std::ios::end);
  const auto size = std::uint64_t(in.tellg());
  if (size < 84) return std::nullopt;
  in.seekg(80);
  char count[4];
  if (!in.read(count, 4)) return std::nullopt;
  std::uint32_t n = 0;
  std::memcpy(&n, count, 4);
  if (size != 84 + 50 * std::uint64_t(n)) return std::nullopt;
  return n;
}

}  // namespace arttrack
