#include "config_range.h"

#include <sstream>

#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

// Enough digits that a value just past a bound does not print as the bound.
std::string number_text(double v) {
  std::ostringstream os;
  os.precision(12);
  os << v;
  return os.str();
}

}  // namespace

ConfigRange ConfigRange::ends(double lo, double hi, bool lo_open, bool hi_open) {
  ConfigRange r;
  r.lo = lo;
  r.hi = hi;
  r.lo_open = lo_open;
  r.hi_open = hi_open;
  return r;
}

bool ConfigRange::contains(double v) const {
  return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

std::string ConfigRange::text() const {
  std::string lo_text = number_text(lo);
  if (!lo_key.empty()) lo_text += " (" + lo_key + ")";
  return std::string(lo_open ? "(" : "[") + lo_text + ", " + number_text(hi) +
         (hi_open ? ")" : "]");
}

void check_range(std::string_view source, const std::string& key, double value,
                 const ConfigRange& range, double unit) {
  ConfigRange scaled = range;
  scaled.lo *= unit;
  scaled.hi *= unit;
  if (scaled.contains(value)) return;
  fail_key(source, key, "= " + number_text(value / unit) + " is out of range " + range.text());
}

void fail_key(std::string_view source, const std::string& key, const std::string& problem) {
  throw ConfigKeyError(std::string(source), key, problem);
}

}  // namespace arttrack
