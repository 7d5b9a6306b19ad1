// The Python module `arttrack` (docs/python.md): the tracker half
// (tracker_bindings.cc: RobotModel, TrackerConfig, Camera, Tracker) and the
// testbed half (testbed_bindings.cc: scenarios, rendering, datasets), joined
// in module.cc. Errors cross as Python exceptions with the C++ message:
// arttrack::InputError as arttrack.InputError (a ValueError), the command
// line's UsageError as arttrack.UsageError (a ValueError too, but not an
// InputError).
#pragma once

#include <pybind11/pybind11.h>

#include <cstddef>
#include <string>
#include <vector>

namespace arttrack::python {
namespace py = pybind11;

void bind_tracker(py::module_& m);
void bind_testbed(py::module_& m);

// Overrides as the Python functions take them, as `key=value` assignments
// for apply_override (yaml_config.h, the one override syntax of --set and
// tracker_overrides): None (none), a dict {key path: value} applied in its
// order, or a list of "key=value" strings. A str value is YAML text, as
// after the `=` of --set; a bool, int, float, list, tuple or dict is written
// as YAML (floats with 17 significant digits, NaN and infinities as .nan,
// .inf, -.inf).
std::vector<std::string> override_assignments(const py::handle& overrides);

// A docstring wrapped at 76 columns, so that help() reads like the C++
// headers: "One line of any length."_doc. Lines already shorter stay as
// they are (and so do their line breaks). The text lives for the process.
const char* operator""_doc(const char* text, std::size_t size);

}  // namespace arttrack::python
