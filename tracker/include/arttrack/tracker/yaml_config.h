// Checked reading of YAML configuration files (tracker configurations,
// scenes, scenarios).
//
// Configuration is data, checked once at the edge: every key a reader does
// not consume is an error naming the file and the key's full path, every
// value of the wrong type or out of range is an error naming both, and inner
// code only ever sees plain structs.
//
// Files may extend others (`extends: base.yaml`, relative to the file): maps
// merge deeply, the extending file wins, lists and scalars are replaced.
// Any key can be overridden after loading with `a.b[1].c=value`: a dotted
// path whose steps may index lists, and a value parsed as YAML (so `5`,
// `true`, `[1, 2]` and `{x: 1}` all work). This is the one override syntax:
// `--set`, `--grid`, `tune --params` and `tracker_overrides` all use it.
#pragma once

#include <cstdint>

#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace arttrack {

// A loaded configuration document and where it came from.
struct YamlDocument {
  YAML::Node root;
  std::string file;  // the file named by the user (for messages)
};

// A YAML file arttrack reads (scenario, scene, tracker configuration,
// dataset metadata) is at most this long: the shipped ones are under 11 kB,
// and yaml-cpp takes about 10 s over 50 MB.
constexpr std::uintmax_t kMaxYamlBytes = 4u << 20;

// Loads `path`, following `extends:` chains (cycles are an error). A file
// over kMaxYamlBytes is an InputError naming it, before it is parsed.
YamlDocument load_yaml_file(const std::string& path);

// Parses YAML text; `source` names it in messages.
YamlDocument load_yaml_string(const std::string& text, const std::string& source);

// One step of a key path: a map key, or (name empty) a list index.
struct KeyStep {
  std::string name;
  std::size_t index = 0;
  bool is_index() const { return name.empty(); }
};

// Splits a key path `a.b[1].c` into its steps (a, b, [1], c). An empty
// component, a malformed or negative index: InputError naming the key.
std::vector<KeyStep> parse_key_path(const std::string& key);

// The value at a key path, or nothing when a step is missing (a key absent
// from its map, an index past the end, a step into a value of another kind).
// A malformed path: InputError as parse_key_path.
std::optional<YAML::Node> find_key(const YAML::Node& root, const std::string& key);

// Applies an override `key.path=value` to the document. A map value merges
// into a map already there key by key (deeply, as `extends` merges: the
// override's keys win, the others stay); `{}`, a list or a scalar replaces
// what is there. Missing (or null) maps on the way are created; a list is
// never created or grown. Errors
// (InputError, starting "override 'key=value'") name the step: a map key on
// something that is not a map, an index into something that is not a list,
// an index past the end (with the list's length).
void apply_override(YamlDocument& doc, const std::string& assignment);

// A map node under checked reading. Each get marks the key as used; finish()
// reports keys nobody asked for. Cheap to copy (shares the used-key record).
class ConfigNode {
 public:
  ConfigNode(YAML::Node node, std::string file, std::string path = "");
  static ConfigNode root(const YamlDocument& doc) { return ConfigNode(doc.root, doc.file); }

  bool has(const std::string& key) const;
  // A required value; missing or of the wrong type is an error.
  template <class T>
  T required(const std::string& key) const;
  // An optional value with a default.
  template <class T>
  T get(const std::string& key, const T& fallback) const;
  // A number (infinities pass, NaN does not): the range is the caller's to
  // check, as TrackerConfig::validate does.
  double number(const std::string& key, double fallback) const;
  // A whole number that fits an int (2.5 and 1e12 are errors).
  int whole_number(const std::string& key, int fallback) const;
  // A number with an inclusive range check.
  double number(const std::string& key, double fallback, double min, double max) const;
  double required_number(const std::string& key, double min, double max) const;
  // A string that must be one of `choices`.
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& choices) const;

  // A sub-map (an empty one if absent); a non-map value is an error.
  ConfigNode child(const std::string& key) const;
  // Elements of a list of maps (empty if absent); a non-list is an error.
  std::vector<ConfigNode> list(const std::string& key) const;
  // Keys of this map, in file order (for maps keyed by user names).
  std::vector<std::string> keys() const;
  // This node as a scalar of type T (for list elements and map values).
  template <class T>
  T as() const;
  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }

  // The value of `key` as one line of YAML (flow style), e.g. for
  // apply_override; a missing key is an error.
  std::string flow_text(const std::string& key) const;

  // Throws InputError for every key of this map (and of the sub-maps read
  // through child()/list()) that was never read.
  void finish() const;

  const std::string& file() const { return file_; }
  // Full dotted path of a key of this node, for messages.
  std::string path_of(const std::string& key) const;
  // Throws ConfigKeyError (error.h) naming the file and the key's full path;
  // InputError naming the document when the path is empty.
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

 private:
  YAML::Node value(const std::string& key) const;

  YAML::Node node_;
  std::string file_;
  std::string path_;
  // Keys read so far, shared by all copies and children.
  std::shared_ptr<std::set<std::string>> used_;
  // Sub-nodes handed out, by key, so that asking twice shares the record.
  std::shared_ptr<std::map<std::string, ConfigNode>> children_;
};

// ---- implementation of the templates ----

template <class T>
T ConfigNode::as() const {
  try {
    return node_.as<T>();
  } catch (const YAML::Exception&) {
    fail("", "has the wrong type");
  }
}

template <class T>
T ConfigNode::required(const std::string& key) const {
  if (!has(key)) fail(key, "is required but missing");
  try {
    return value(key).as<T>();
  } catch (const YAML::Exception&) {
    fail(key, "has the wrong type");
  }
}

template <class T>
T ConfigNode::get(const std::string& key, const T& fallback) const {
  if (!has(key)) return fallback;
  return required<T>(key);
}

}  // namespace arttrack
