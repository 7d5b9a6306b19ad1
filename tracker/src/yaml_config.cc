#include "arttrack/tracker/yaml_config.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"

namespace arttrack {
namespace fs = std::filesystem;

namespace {

// Deep merge: maps merge key by key, anything else in `over` replaces `base`.
YAML::Node merge(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  for (const auto& kv : over) {
    const std::string key = kv.first.as<std::string>();
    out[key] = out[key] ? merge(out[key], kv.second) : YAML::Clone(kv.second);
  }
  return out;
}

// Values a configuration document may hold once its aliases are expanded:
// a few hundred in practice. Aliases of aliases multiply (ten lists of ten
// aliases of the one before: 1e9 values in 500 bytes), and every walk over
// the document would take that long.
constexpr std::size_t kMaxYamlValues = 100000;

// A key given twice in one map: yaml-cpp keeps both and a lookup silently
// takes one of them. `path` is the dotted path of `node` ("" at the top);
// `values` counts the values walked (at most kMaxYamlValues).
void check_unique_keys(const YAML::Node& node, const std::string& source, std::size_t& values,
                       const std::string& path = "") {
  if (++values > kMaxYamlValues)
    throw InputError(source + ": more than " + std::to_string(kMaxYamlValues) +
                     " values once its aliases are expanded (at " + quote_value(path) +
                     "): aliases of aliases? A configuration is far smaller");
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      check_unique_keys(node[i], source, values, path + "[" + std::to_string(i) + "]");
    return;
  }
  if (!node.IsMap()) return;
  std::map<std::string, int> first_line;
  for (const auto& kv : node) {
    const int line = kv.first.Mark().line + 1;
    // A key must be a name: a list or a map as a key ("? [a, b]: 1") is
    // valid YAML that no configuration key can be.
    if (!kv.first.IsScalar())
      throw InputError(source + ":" + std::to_string(line) + ": a key " +
                       (path.empty() ? std::string("at the top") : "under " + quote_value(path)) +
                       " is a " + (kv.first.IsSequence() ? "list" : "map") + ", not a name");
    const std::string key = kv.first.Scalar();
    const std::string key_path = path.empty() ? key : path + "." + key;
    if (const auto [it, added] = first_line.emplace(key, line); !added)
      throw InputError(source + ":" + std::to_string(line) + ": key " + quote_value(key_path) +
                       " appears twice (first at line " + std::to_string(it->second) + ")");
    check_unique_keys(kv.second, source, values, key_path);
  }
}

YAML::Node parse_file(const std::string& path) {
  if (!fs::exists(path)) throw InputError(path + ": file not found");
  if (fs::is_directory(path)) throw InputError(path + ": is a folder, not a YAML file");
  std::error_code ec;
  if (const std::uintmax_t bytes = fs::file_size(path, ec); !ec && bytes > kMaxYamlBytes)
    throw InputError(path + ": " + std::to_string(bytes) + " bytes, more than the " +
                     std::to_string(kMaxYamlBytes) +
                     " a YAML file may have in arttrack (a configuration is a few kB)");
  try {
    YAML::Node node = YAML::LoadFile(path);
    std::size_t values = 0;
    check_unique_keys(node, path, values);
    return node;
  } catch (const YAML::ParserException& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  } catch (const YAML::BadFile&) {
    throw InputError(path + ": cannot read file");
  }
}

YAML::Node load_with_extends(const std::string& path, std::vector<std::string>& chain) {
  const std::string canonical = fs::weakly_canonical(path).string();
  for (const auto& seen : chain)
    if (seen == canonical) throw InputError(path + ": 'extends' forms a cycle");
  chain.push_back(canonical);
  YAML::Node node = parse_file(path);
  if (node.IsNull()) node = YAML::Node(YAML::NodeType::Map);
  if (!node.IsMap()) throw InputError(path + ": the top level must be a map of keys");
  if (!node["extends"]) {
    chain.pop_back();
    return node;
  }
  // One base, or a list merged in order (each later one over the earlier).
  const YAML::Node ext = node["extends"];
  std::vector<std::string> names;
  if (ext.IsScalar()) {
    names.push_back(ext.as<std::string>());
  } else if (ext.IsSequence() && ext.size() > 0) {
    for (const YAML::Node& item : ext) {
      if (!item.IsScalar()) throw InputError(path + ": key 'extends' must list file names");
      names.push_back(item.as<std::string>());
    }
  } else {
    throw InputError(path + ": key 'extends' must be a file name or a list of them");
  }
  YAML::Node base;
  for (const std::string& name : names) {
    fs::path base_path = name;
    if (base_path.is_relative()) base_path = fs::path(path).parent_path() / base_path;
    YAML::Node next = load_with_extends(base_path.string(), chain);
    base = base ? merge(base, next) : next;
  }
  node.remove("extends");
  chain.pop_back();  // the files above this one: a base two lists share is no cycle
  return merge(base, node);
}

std::string describe(const YAML::Node& n) {
  if (!n) return "nothing";
  if (n.IsScalar()) return quote_value(n.Scalar());
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a map";
  return "null";
}

}  // namespace

YamlDocument load_yaml_file(const std::string& path) {
  std::vector<std::string> chain;
  return {load_with_extends(path, chain), path};
}

YamlDocument load_yaml_string(const std::string& text, const std::string& source) {
  try {
    YAML::Node node = YAML::Load(text);
    std::size_t values = 0;
    check_unique_keys(node, source, values);
    if (node.IsNull()) node = YAML::Node(YAML::NodeType::Map);
    if (!node.IsMap()) throw InputError(source + ": the top level must be a map of keys");
    return {node, source};
  } catch (const YAML::ParserException& e) {
    throw InputError(source + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
}

std::vector<KeyStep> parse_key_path(const std::string& key) {
  auto bad = [&](const std::string& why) {
    return InputError("key " + quote_value(key) + " " + why);
  };
  if (key.empty()) throw bad("is empty");
  std::vector<KeyStep> steps;
  std::size_t pos = 0;
  while (true) {
    const std::size_t end = key.find_first_of(".[", pos);
    const std::string name = key.substr(pos, end == std::string::npos ? end : end - pos);
    if (name.empty()) throw bad("has an empty component (write a.b[0].c)");
    if (name.find(']') != std::string::npos) throw bad("has a malformed index (write name[0])");
    steps.push_back({name});
    pos = end;
    while (pos != std::string::npos && key[pos] == '[') {
      const std::size_t close = key.find(']', pos);
      if (close == std::string::npos) throw bad("has a malformed index (write name[0])");
      const std::string digits = key.substr(pos + 1, close - pos - 1);
      if (!digits.empty() && digits[0] == '-')
        throw bad("has a negative index '[" + digits + "]': lists count from [0] at the front");
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos ||
          digits.size() > 9)
        throw bad("has a bad index '[" + digits + "]' (a whole number >= 0)");
      steps.push_back({"", std::stoul(digits)});
      pos = close + 1 < key.size() ? close + 1 : std::string::npos;
    }
    if (pos == std::string::npos) return steps;
    if (key[pos] != '.') throw bad("has a malformed index (write name[0].next)");
    ++pos;  // a trailing '.' leaves an empty name: an error above
  }
}

std::optional<YAML::Node> find_key(const YAML::Node& root, const std::string& key) {
  // Constructed, never assigned: assigning a yaml-cpp node writes into the tree.
  std::vector<YAML::Node> chain{root};
  for (const KeyStep& step : parse_key_path(key)) {
    const YAML::Node& node = chain.back();
    if (step.is_index()) {
      if (!node.IsSequence() || step.index >= node.size()) return std::nullopt;
      chain.push_back(node[step.index]);
    } else {
      if (!node.IsMap() || !node[step.name]) return std::nullopt;
      chain.push_back(node[step.name]);
    }
  }
  return chain.back();
}

void apply_override(YamlDocument& doc, const std::string& assignment) {
  const std::string context = "override " + quote_value(assignment);
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(context + ": expected key=value (e.g. encoders[0].offset_deg=5)");
  std::vector<KeyStep> steps;
  try {
    steps = parse_key_path(assignment.substr(0, eq));
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::ParserException& e) {
    throw InputError(context + ": value is not valid YAML: " + e.msg);
  }
  // Walk with explicit copies: yaml-cpp nodes are references, and assigning to
  // a loop variable would rebind the tree.
  std::vector<YAML::Node> chain{doc.root};
  std::string walked;  // the path of chain.back(), as written
  for (std::size_t i = 0; i < steps.size(); ++i) {
    YAML::Node node = chain.back();
    const KeyStep& step = steps[i];
    if (step.is_index()) {
      // Appended, not "[" + ...: GCC 12 warns falsely (-Wrestrict) on that.
      std::string index = "[";
      index += std::to_string(step.index);
      index += ']';
      if (!node.IsSequence())
        throw InputError(context + ": " + quote_value(walked) + " is " +
                         (node && !node.IsNull() ? describe(node) : "missing") +
                         ", not a list to index with " + index);
      if (step.index >= node.size())
        throw InputError(context + ": " + quote_value(walked) + " has " +
                         std::to_string(node.size()) + " element(s): no " + index);
      walked += index;
    } else {
      if (!node.IsMap()) {
        const std::string hint = node.IsSequence() ? " (a list of " + std::to_string(node.size()) +
                                                         ": index it, e.g. " + walked + "[0])"
                                                   : "";
        throw InputError(context + ": " + quote_value(walked) + " is not a map" + hint);
      }
      walked += (walked.empty() ? "" : ".") + step.name;
    }
    if (i + 1 == steps.size()) {
      // A map merges into a map key by key, as `extends` merges, so that
      // `tracker_overrides.uncertainty.a=1` and a file's own
      // `uncertainty.b` both hold; anything else, and `{}`, replaces.
      const YAML::Node old = step.is_index() ? node[step.index] : node[step.name];
      const YAML::Node put =
          old && old.IsMap() && value.IsMap() && value.size() > 0 ? merge(old, value) : value;
      if (step.is_index())
        node[step.index] = put;
      else
        node[step.name] = put;
      return;
    }
    // A missing or null map on the way is created; a list never is.
    const YAML::Node child = step.is_index() ? node[step.index] : node[step.name];
    if ((!child || child.IsNull()) && !steps[i + 1].is_index()) {
      if (step.is_index())
        node[step.index] = YAML::Node(YAML::NodeType::Map);
      else
        node[step.name] = YAML::Node(YAML::NodeType::Map);
    }
    chain.push_back(step.is_index() ? node[step.index] : node[step.name]);
  }
}

ConfigNode::ConfigNode(YAML::Node node, std::string file, std::string path)
    : node_(node),
      file_(std::move(file)),
      path_(std::move(path)),
      used_(std::make_shared<std::set<std::string>>()),
      children_(std::make_shared<std::map<std::string, ConfigNode>>()) {}

std::string ConfigNode::path_of(const std::string& key) const {
  if (key.empty()) return path_;
  return path_.empty() ? key : path_ + "." + key;
}

std::string ConfigNode::flow_text(const std::string& key) const {
  YAML::Emitter out;
  out << YAML::Flow << required<YAML::Node>(key);
  return out.c_str();
}

void ConfigNode::fail(const std::string& key, const std::string& problem) const {
  if (path_of(key).empty()) throw InputError(file_ + ": the document " + problem);
  throw ConfigKeyError(file_, path_of(key), problem);
}

bool ConfigNode::has(const std::string& key) const {
  return node_.IsMap() && node_[key] && !node_[key].IsNull();
}

YAML::Node ConfigNode::value(const std::string& key) const {
  used_->insert(key);
  return node_[key];
}

double ConfigNode::number(const std::string& key, double fallback) const {
  return number(key, fallback, -kInf, kInf);
}

int ConfigNode::whole_number(const std::string& key, int fallback) const {
  if (!has(key)) return fallback;
  const double v = required_number(key, -kInf, kInf);
  if (v != std::floor(v) || v < std::numeric_limits<int>::min() ||
      v > std::numeric_limits<int>::max()) {
    std::ostringstream os;
    os << "= " << v << " is not a whole number (from " << std::numeric_limits<int>::min() << " to "
       << std::numeric_limits<int>::max() << ")";
    fail(key, os.str());
  }
  return int(v);
}

double ConfigNode::number(const std::string& key, double fallback, double min, double max) const {
  if (!has(key)) return fallback;
  return required_number(key, min, max);
}

double ConfigNode::required_number(const std::string& key, double min, double max) const {
  if (!has(key)) fail(key, "is required but missing");
  const YAML::Node n = value(key);
  double v;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(key, "must be a number, got " + describe(n));
  }
  if (std::isnan(v)) fail(key, "must be a number, got " + describe(n));
  if (!(v >= min && v <= max)) {
    std::ostringstream os;
    os << "= " << v << " is out of range [" << min << ", " << max << "]";
    fail(key, os.str());
  }
  return v;
}

std::string ConfigNode::choice(const std::string& key, const std::string& fallback,
                               const std::vector<std::string>& choices) const {
  const std::string v = get<std::string>(key, fallback);
  for (const auto& c : choices)
    if (c == v) return v;
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  fail(key, "= " + quote_value(v) + " is not one of: " + list);
}

ConfigNode ConfigNode::child(const std::string& key) const {
  if (auto it = children_->find(key); it != children_->end()) return it->second;
  YAML::Node n = has(key) ? value(key) : YAML::Node(YAML::NodeType::Map);
  if (!n.IsMap()) fail(key, "must be a map, got " + describe(n));
  ConfigNode c(n, file_, path_of(key));
  children_->emplace(key, c);
  return c;
}

std::vector<ConfigNode> ConfigNode::list(const std::string& key) const {
  std::vector<ConfigNode> out;
  if (!has(key)) return out;
  YAML::Node n = value(key);
  if (!n.IsSequence()) fail(key, "must be a list, got " + describe(n));
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string item = key + "[" + std::to_string(i) + "]";
    if (auto it = children_->find(item); it != children_->end()) {
      out.push_back(it->second);
      continue;
    }
    ConfigNode c(n[i], file_, path_of(item));
    children_->emplace(item, c);
    out.push_back(c);
  }
  return out;
}

std::vector<std::string> ConfigNode::keys() const {
  std::vector<std::string> out;
  if (!node_.IsMap()) return out;
  for (const auto& kv : node_) out.push_back(kv.first.as<std::string>());
  return out;
}

void ConfigNode::finish() const {
  if (node_.IsMap()) {
    for (const auto& kv : node_) {
      const std::string key = kv.first.as<std::string>();
      if (!used_->count(key)) fail(key, "is not a known key here");
    }
  }
  for (const auto& [key, c] : *children_) c.finish();
}

}  // namespace arttrack
