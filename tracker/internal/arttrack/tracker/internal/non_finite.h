// The two non-finite doubles by name, for the tracker's and the testbed's
// sources (never included by a header): kInf, no bound or never; kNaN, no
// value. One definition for all of them, so that sources compiled together
// (a unity build, CMAKE_UNITY_BUILD) do not define them twice. Not inline:
// each source keeps its own copy, as with the file-local constants these
// replace, and the same generated code.
#pragma once

#include <limits>

namespace arttrack {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace arttrack
