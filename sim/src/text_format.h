// Text helpers shared by the simulator's output writers (run outputs,
// report, sweep, tuning, datasets): number formatting, CSV fields, HTML escaping, base64,
// whole-file writes. Internal to arttrack_sim; outputs depend on these
// byte for byte, so change a behaviour only together with its callers.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include <Eigen/Geometry>

#include "arttrack/sim/scoring.h"

namespace arttrack::sim {
namespace text {

// ---- parsing ----

// `s` without leading and trailing spaces and tabs (only ' ' and '\t'; a
// '\r' or '\n' stays). All blank: "".
std::string trim(const std::string& s);

// Reads the whole of `text`, trimmed as by trim(), as one finite number
// (std::strtod: decimal or hexadecimal, C locale). True if the trimmed text
// is non-empty, strtod consumed all of it and the value is finite ("inf",
// "nan" and overflowing values are false). `out` is written whenever the
// trimmed text is non-empty, also when the result is false.
bool parse_number(const std::string& text, double& out);

// ---- numbers ----

// printf "%.*g" with `digits` significant digits: 0.1 with 3 gives "0.1",
// 1234567 with 3 gives "1.23e+06"; NaN "nan" or "-nan", infinities "inf" and
// "-inf". At most 39 characters (enough for any digits <= 30).
std::string format_g(double v, int digits);

// A number for a CSV cell, exact on reading back: "%.17g" (format_g(v, 17)),
// except NaN of either sign is "nan" and infinities are "inf" and "-inf".
std::string csv_number(double v);

// The shortest text that reads back as the same double (std::to_chars), so
// that a dataset or estimate.csv written from a run reproduces its numbers
// bit for bit: 0.1 gives "0.1"; NaN "nan", infinities "inf" and "-inf".
std::string shortest_number(double v);

// ---- CSV ----

// Column suffixes of an end effector E's pose in datasets and estimate.csv:
// E_x, E_y, E_z (m), then the unit quaternion E_qw, E_qx, E_qy, E_qz.
inline constexpr const char* kPoseSuffixes[7] = {"_x", "_y", "_z", "_qw", "_qx", "_qy", "_qz"};

// The seven pose columns of T in kPoseSuffixes order, each as ',' and its
// shortest_number.
std::string pose_fields(const Eigen::Isometry3d& T);

// `s` with every '\n', '\r' and '\t' replaced by one space (same length):
// a message fit for one CSV field and one HTML line.
std::string one_line(std::string s);

// `s` as one CSV field (RFC 4180 quoting): unchanged unless it contains a
// ',', '"' or '\n'; then enclosed in double quotes with each '"' doubled.
// Nothing else ('\r', leading or trailing spaces) makes it quoted.
std::string csv_field(const std::string& s);

// ---- HTML ----

// `s` escaped for HTML element content and double-quoted attribute values:
// '&' -> "&amp;", '<' -> "&lt;", '>' -> "&gt;", '"' -> "&quot;"; every other
// byte (also '\'' and non-ASCII UTF-8) unchanged.
std::string html_escape(const std::string& s);

// Standard base64 of `bytes` (RFC 4648 alphabet, '=' padding, no line
// breaks): for data URIs.
std::string base64(std::span<const std::uint8_t> bytes);

// ---- files ----

// Writes `text` to `path` in binary mode (no newline translation), replacing
// the file. Failure to open or write: InputError "<path>: cannot write file".
void write_text(const std::filesystem::path& path, const std::string& text);

}  // namespace text

// ---- statistics shown in several outputs ----

// Median over the runs of the convergence time, a run that never converged
// counting as +inf: the middle value for an odd count, else the mean of the
// two middle ones (+inf if the upper one is). No runs: +inf. As in
// summary.json, the report and sweep cells.
double median_convergence_s(const std::vector<std::optional<double>>& time_to_converge_s);
inline double median_convergence_s(const MethodSummary& s) {
  return median_convergence_s(s.time_to_converge_s);
}

}  // namespace arttrack::sim
