#include <pybind11/pybind11.h>

#include <deque>
#include <sstream>
#include <string>

#include "arttrack/sim/search_paths.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/version.h"
#include "bindings.h"
#include "commands.h"

namespace arttrack::python {

const char* operator""_doc(const char* text, std::size_t size) {
  static std::deque<std::string> docs;  // pybind11 keeps the pointers
  std::istringstream lines(std::string(text, size));
  std::string out, line;
  for (bool first = true; std::getline(lines, line); first = false) {
    if (!first) out += '\n';
    std::size_t column = 0;
    std::istringstream words(line);
    for (std::string word; words >> word;) {
      if (column > 0 && column + 1 + word.size() > 76) {
        out += '\n';
        column = 0;
      } else if (column > 0) {
        out += ' ', ++column;
      }
      out += word;
      column += word.size();
    }
  }
  return docs.emplace_back(std::move(out)).c_str();
}

}  // namespace arttrack::python

PYBIND11_MODULE(_arttrack, m) {
  using arttrack::python::operator""_doc;
  namespace py = pybind11;
  // As the arttrack program: scenes and scenarios find the files they name
  // relative to the source tree, and the defaults, in the tree it was built from.
  arttrack::sim::set_search_dirs({ARTTRACK_SOURCE_DIR});
  m.doc() =
      "arttrack: probabilistic articulated real-time tracking of a robot manipulator, and its "
      "MuJoCo testbed.\n\n"
      "The tracker: RobotModel (from a URDF), TrackerConfig (defaults, YAML, overrides), Camera "
      "(pinhole intrinsics), Tracker (feed joint readings and depth images, read estimate()).\n"
      "The testbed: run_scenario, render_scene, export_dataset, track_dataset, "
      "read_depth_png.\n\n"
      "Units: seconds, radians, metres (depth images: float32 metres or uint16 millimetres).\n"
      "Errors: InputError (a ValueError) for bad input files, keys, names, values and time "
      "stamps, with the message the arttrack program prints; UsageError (a ValueError, not an "
      "InputError) for a call's own arguments that the program would refuse as a usage error."_doc;
  m.attr("__version__") = ARTTRACK_VERSION;

  static py::exception<arttrack::InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<arttrack::cli::UsageError> usage_error(m, "UsageError", PyExc_ValueError);
  input_error.doc() =
      "Bad input: a file, key, name, value or time stamp that is wrong (arttrack::InputError). "
      "The message names the item and what would be right, as the arttrack program prints it."_doc;
  usage_error.doc() =
      "A call's argument that the arttrack program refuses as a usage error (exit code 2): "
      "runs out of range, a negative seed, an empty method list, an output folder holding a "
      "previous run's outputs without force=True."_doc;
  // UsageError derives from InputError in C++: the more specific one first.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const arttrack::cli::UsageError& e) {
      usage_error(e.what());
    } catch (const arttrack::InputError& e) {
      input_error(e.what());
    }
  });

  arttrack::python::bind_tracker(m);
  arttrack::python::bind_testbed(m);
}
