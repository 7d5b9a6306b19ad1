// The " (got VALUE)" that ends the simulation layer's validation messages
// (motion, encoder corruption), VALUE as a stream prints a double.
#pragma once

#include <sstream>
#include <string>

namespace arttrack::sim {

inline std::string got(double value) {
  std::ostringstream s;
  s << " (got " << value << ")";
  return s.str();
}

}  // namespace arttrack::sim
