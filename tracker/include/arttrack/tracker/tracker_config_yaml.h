// Reading a TrackerConfig from YAML (the format of tracker/config/
// default.yaml, which lists and documents every key). Kept out of
// tracker_config.h so that the tracker's public header needs no yaml-cpp.
//
// Unknown keys, wrong types and impossible values are errors naming the file
// and the key (yaml_config.h).
#pragma once

#include <string>

#include "arttrack/tracker/tracker_config.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack {

// Reads a tracker configuration file. Keys not given keep the in-class
// defaults; to start from the shipped defaults, extend them or apply
// overrides to default_tracker_document().
TrackerConfig load_tracker_config(const std::string& path);
TrackerConfig tracker_config_from_yaml(const YamlDocument& doc);

// The built-in tracker/config/default.yaml as a document (a fresh copy: edit
// it with apply_override), named kDefaultTrackerConfigName in messages.
YamlDocument default_tracker_document();

}  // namespace arttrack
