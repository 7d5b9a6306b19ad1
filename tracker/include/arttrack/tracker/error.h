// Errors a user can cause: a file, key, name, value or time stamp that is
// wrong. The message names the item and what would be right; callers at the
// edge (the command line) print it on one line and exit non-zero.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace arttrack {

// Quoted characters of a value a message shows (quote_value()).
constexpr std::size_t kMaxQuoted = 80;

// A value from the user's input as a message quotes it: 'value', or, when
// longer than kMaxQuoted characters, its first kMaxQuoted, an ellipsis and
// its length: 'xxxx...' (52428800 characters). A 50 MB YAML string stays
// off the terminal.
inline std::string quote_value(std::string_view value) {
  std::string out = "'";
  out.append(value.substr(0, kMaxQuoted));
  if (value.size() <= kMaxQuoted) return out += "'";
  out += "...' (";
  out += std::to_string(value.size());
  out += " characters)";
  return out;
}

// Bad input: malformed files, unknown names, impossible values, time stamps
// out of order. Never a programming error (those are std::invalid_argument,
// below, or assertions).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An InputError about one key of a configuration: "<source>: key '<key>'
// <problem>", e.g. "t.yaml: key 'depth_model.max_range_m' = 200 is out of
// range [0.1, 100]". The parts are kept for a caller that knows better where
// the key was set (a scenario's tracker_overrides over a tracker file).
class ConfigKeyError : public InputError {
 public:
  ConfigKeyError(std::string source, std::string key, std::string problem)
      : InputError(source + ": key " + quote_value(key) + " " + problem),
        source_(std::move(source)),
        key_(std::move(key)),
        problem_(std::move(problem)) {}
  const std::string& source() const { return source_; }
  // The dotted path as the user writes it, e.g. joints.per_joint.elbow.bias_decay_per_s.
  const std::string& key() const { return key_; }
  // What is wrong, starting with the value where there is one ("= 200 is ...").
  const std::string& problem() const { return problem_; }

 private:
  std::string source_, key_, problem_;
};

}  // namespace arttrack

// A precondition of a public function on its arguments (vector sizes, joint
// counts, image sizes) that holds in every build, like Pinocchio's argument
// size checks: an assert vanishes from Release, and a wrong size would then
// read or write out of bounds. A violation is the caller's programming
// error, thrown as std::invalid_argument naming the function and the rule.
// Costs a comparison: fine on the hot paths that take whole vectors or images.
#define ARTTRACK_CHECK_ARGUMENT(condition)                                                         \
  do {                                                                                             \
    if (!(condition))                                                                              \
      throw std::invalid_argument(std::string(__func__) + ": argument check failed: " #condition); \
  } while (0)

namespace arttrack {}  // namespace arttrack
