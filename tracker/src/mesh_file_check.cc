// check_mesh_file (model_limits.h): a mesh file's size, and a COLLADA
// file's geometry checked against its own declared counts, before assimp
// reads it.
#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <fstream>
#include <map>
#include <string_view>
#include <system_error>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/model_limits.h"

namespace arttrack {
namespace {

using tinyxml2::XMLElement;

// Whitespace-separated tokens of an element's text.
template <typename Visit>
void for_each_token(const XMLElement& element, Visit visit) {
  const char* text = element.GetText();
  if (text == nullptr) return;
  const char* at = text;
  for (;;) {
    while (*at != '\0' && std::isspace(static_cast<unsigned char>(*at))) ++at;
    if (*at == '\0') return;
    const char* end = at;
    while (*end != '\0' && !std::isspace(static_cast<unsigned char>(*end))) ++end;
    visit(std::string_view(at, std::size_t(end - at)));
    at = end;
  }
}

// A token for a message: at most 32 characters, others than printable ASCII
// as \xNN.
std::string printable(std::string_view token) {
  static const char* kHex = "0123456789abcdef";
  std::string out;
  for (const char c : token.substr(0, 32)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
    }
  }
  return token.size() > 32 ? out + "..." : out;
}

class ColladaCheck {
 public:
  ColladaCheck(const std::string& path, const tinyxml2::XMLDocument& document)
      : path_(path), document_(document) {}

  void run() {
    const XMLElement* root = document_.RootElement();
    if (root == nullptr || std::strcmp(root->Name(), "COLLADA") != 0)
      fail(root, "the root element is not <COLLADA>");
    for (const XMLElement* library = root->FirstChildElement("library_geometries"); library;
         library = library->NextSiblingElement("library_geometries"))
      for (const XMLElement* geometry = library->FirstChildElement("geometry"); geometry;
           geometry = geometry->NextSiblingElement("geometry"))
        if (const XMLElement* mesh = geometry->FirstChildElement("mesh")) check_mesh(*mesh);
  }

 private:
  const std::string& path_;
  const tinyxml2::XMLDocument& document_;
  std::uint64_t declared_faces_ = 0;
  // Per <mesh>: elements by id with the number of items they index.
  std::map<std::string, std::uint64_t> items_;

  [[noreturn]] void fail(const XMLElement* at, const std::string& problem) const {
    throw InputError("mesh file '" + path_ + "'" +
                     (at ? ": line " + std::to_string(at->GetLineNum()) + " <" + at->Name() + ">"
                         : std::string()) +
                     ": " + problem + " (a COLLADA file arttrack does not hand to assimp)");
  }

  std::uint64_t number(const XMLElement& element, std::string_view token,
                       std::uint64_t limit) const {
    std::uint64_t value = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size())
      fail(&element, "'" + printable(token) + "' is not a non-negative integer");
    if (value > limit)
      fail(&element, std::to_string(value) + " is more than the " + std::to_string(limit) +
                         " arttrack takes here");
    return value;
  }

  std::uint64_t attribute(const XMLElement& element, const char* name, std::uint64_t limit,
                          bool required = true) const {
    const char* text = element.Attribute(name);
    if (text == nullptr) {
      if (required) fail(&element, std::string("no '") + name + "' attribute");
      return 0;
    }
    return number(element, text, limit);
  }

  std::uint64_t count_tokens(const XMLElement& element) const {
    std::uint64_t n = 0;
    for_each_token(element, [&](std::string_view) { ++n; });
    return n;
  }

  // A <source>: its array holds what its accessor reads.
  void check_source(const XMLElement& source) {
    const char* id = source.Attribute("id");
    const XMLElement* array = source.FirstChildElement("float_array");
    if (array == nullptr) array = source.FirstChildElement("int_array");
    std::uint64_t values = 0;
    if (array != nullptr) {
      values = count_tokens(*array);
      if (array->Attribute("count") &&
          attribute(*array, "count", ModelLimits::kMaxMeshFileBytes) != values)
        fail(array, "count=\"" + std::string(array->Attribute("count")) + "\" but " +
                        std::to_string(values) + " values");
    }
    std::uint64_t items = 0;
    if (const XMLElement* common = source.FirstChildElement("technique_common"))
      if (const XMLElement* accessor = common->FirstChildElement("accessor")) {
        items = attribute(*accessor, "count", ModelLimits::kMaxMeshFileBytes);
        const std::uint64_t stride =
            std::max<std::uint64_t>(1, attribute(*accessor, "stride", 1024, false));
        const std::uint64_t offset =
            attribute(*accessor, "offset", ModelLimits::kMaxMeshFileBytes, false);
        if (array != nullptr && offset + items * stride > values)
          fail(accessor, "reads " + std::to_string(items) + " items of " + std::to_string(stride) +
                             " values from " + std::to_string(values));
      }
    if (id != nullptr) items_[id] = items;
  }

  // What an <input>'s source="#id" indexes: a source's items, or the items
  // of a <vertices> element's inputs.
  std::uint64_t input_items(const XMLElement& input) const {
    const char* source = input.Attribute("source");
    if (source == nullptr || source[0] != '#') fail(&input, "no source=\"#id\" attribute");
    const auto found = items_.find(source + 1);
    if (found == items_.end()) fail(&input, std::string("source '") + source + "' is not defined");
    return found->second;
  }

  void check_mesh(const XMLElement& mesh) {
    items_.clear();
    for (const XMLElement* source = mesh.FirstChildElement("source"); source;
         source = source->NextSiblingElement("source"))
      check_source(*source);
    for (const XMLElement* vertices = mesh.FirstChildElement("vertices"); vertices;
         vertices = vertices->NextSiblingElement("vertices")) {
      bool position = false;
      std::uint64_t items = 0;
      for (const XMLElement* input = vertices->FirstChildElement("input"); input;
           input = input->NextSiblingElement("input")) {
        const char* semantic = input->Attribute("semantic");
        if (semantic && std::strcmp(semantic, "POSITION") == 0) {
          position = true;
          items = input_items(*input);
        }
      }
      if (!position) fail(vertices, "no <input semantic=\"POSITION\">");
      if (const char* id = vertices->Attribute("id")) items_[id] = items;
    }
    for (const XMLElement* primitive = mesh.FirstChildElement(); primitive;
         primitive = primitive->NextSiblingElement())
      check_primitive(*primitive);
  }

  void check_primitive(const XMLElement& primitive) {
    const std::string_view name = primitive.Name();
    // Indices per primitive: fixed, from <vcount>, or a whole <p> each.
    int fixed = 0;
    if (name == "triangles")
      fixed = 3;
    else if (name == "lines")
      fixed = 2;
    else if (name != "polylist" && name != "polygons" && name != "trifans" && name != "tristrips" &&
             name != "linestrips")
      return;  // <source>, <vertices>, <extra>
    const std::uint64_t count = attribute(primitive, "count", ModelLimits::kMaxMeshTriangles);
    declared_faces_ += count;
    if (declared_faces_ > ModelLimits::kMaxMeshTriangles)
      fail(&primitive, "the file declares more than the " +
                           std::to_string(ModelLimits::kMaxMeshTriangles) +
                           " faces arttrack takes");
    // Each vertex of a primitive is one index per input offset.
    std::uint64_t stride = 0;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> bound;  // offset, items it indexes
    for (const XMLElement* input = primitive.FirstChildElement("input"); input;
         input = input->NextSiblingElement("input")) {
      const std::uint64_t offset = attribute(*input, "offset", 63);
      stride = std::max(stride, offset + 1);
      bound.emplace_back(offset, input_items(*input));
    }
    if (stride == 0) {  // nothing to index (and no stride to split a <p> by)
      if (count > 0 || primitive.FirstChildElement("p")) fail(&primitive, "no <input>");
      return;
    }
    std::vector<std::uint64_t> limit(stride, ~std::uint64_t(0));
    for (const auto& [offset, items] : bound) limit[offset] = std::min(limit[offset], items);

    const auto check_indices = [&](const XMLElement& p, std::uint64_t expected) {
      std::uint64_t n = 0;
      for_each_token(p, [&](std::string_view token) {
        const std::uint64_t index = number(p, token, ModelLimits::kMaxMeshFileBytes);
        const std::uint64_t offset = n++ % stride;
        if (index >= limit[offset])
          fail(&p, "index " + std::to_string(index) + " (item " + std::to_string(n) +
                       ") is past the " + std::to_string(limit[offset]) + " items of its input");
      });
      if (expected != ~std::uint64_t(0) ? n != expected : n % stride != 0)
        fail(&p, std::to_string(n) + " indices where " + std::string(name) + " count=\"" +
                     std::to_string(count) + "\" with " + std::to_string(stride) +
                     " per vertex needs " +
                     (expected != ~std::uint64_t(0) ? std::to_string(expected)
                                                    : "a multiple of " + std::to_string(stride)));
    };

    if (fixed > 0 || name == "polylist") {
      std::uint64_t vertices = count * std::uint64_t(fixed);
      if (name == "polylist") {
        const XMLElement* vcount = primitive.FirstChildElement("vcount");
        if (vcount == nullptr && count > 0) fail(&primitive, "no <vcount>");
        std::uint64_t polygons = 0;
        vertices = 0;
        if (vcount != nullptr)
          for_each_token(*vcount, [&](std::string_view token) {
            const std::uint64_t n = number(*vcount, token, 1024);
            if (n < 3) fail(vcount, "a polygon of " + std::to_string(n) + " vertices");
            vertices += n;
            ++polygons;
          });
        if (polygons != count)
          fail(vcount, std::to_string(polygons) + " polygons where polylist count=\"" +
                           std::to_string(count) + "\"");
      }
      const XMLElement* p = primitive.FirstChildElement("p");
      if (p == nullptr) {
        if (count > 0) fail(&primitive, "no <p>");
        return;
      }
      if (p->NextSiblingElement("p")) fail(p->NextSiblingElement("p"), "a second <p>");
      check_indices(*p, vertices * stride);
      return;
    }
    // polygons, trifans, tristrips, linestrips: one <p> per primitive.
    std::uint64_t lists = 0;
    for (const XMLElement* p = primitive.FirstChildElement(); p; p = p->NextSiblingElement()) {
      const std::string_view tag = p->Name();
      if (tag == "ph") fail(p, "polygons with holes (<ph>) are not supported");
      if (tag != "p") continue;
      ++lists;
      check_indices(*p, ~std::uint64_t(0));
    }
    if (lists != count)
      fail(&primitive,
           std::to_string(lists) + " <p> lists where count=\"" + std::to_string(count) + "\"");
  }
};

bool is_collada(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".dae") return true;
  // By content too: assimp picks the importer by what the file holds.
  std::ifstream in(path, std::ios::binary);
  char head[512] = {};
  in.read(head, sizeof head);
  return std::string_view(head, std::size_t(in.gcount())).find("<COLLADA") !=
         std::string_view::npos;
}

}  // namespace

void check_mesh_file(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) return;  // the reader reports a missing or unreadable file
  if (bytes > ModelLimits::kMaxMeshFileBytes)
    throw InputError("mesh file '" + path.string() + "': " + std::to_string(bytes) +
                     " bytes, more than the " + std::to_string(ModelLimits::kMaxMeshFileBytes) +
                     " arttrack reads (docs/robots.md, 'Limits'); simplify the mesh");
  if (!is_collada(path)) return;
  tinyxml2::XMLDocument document;
  if (document.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS)
    throw InputError("mesh file '" + path.string() + "': not readable XML: " +
                     (document.ErrorStr() ? document.ErrorStr() : "unknown error"));
  ColladaCheck(path.string(), document).run();
}

}  // namespace arttrack
