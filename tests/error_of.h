// Tests' view of an expected InputError: its message, to check that it names
// the file, key or item at fault.
#pragma once

#include <string>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::test_support {

// The message of the InputError that f() throws, or "" if it throws none
// (any other exception propagates and fails the test).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The message of the InputError a tracker configuration given as YAML text
// (file name "t.yaml") raises, or "".
inline std::string tracker_config_error(const std::string& yaml) {
  return error_of([&] { tracker_config_from_yaml(load_yaml_string(yaml, "t.yaml")); });
}

}  // namespace arttrack::test_support
