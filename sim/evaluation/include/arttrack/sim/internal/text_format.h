// Text helpers shared by the simulator's readers and output writers (run
// outputs, report, sweep, tuning, datasets): trimming and number parsing,
// number formatting, CSV fields and rows, HTML escaping, base64, whole-file
// writes. Internal to the testbed (evaluation and the layers above); outputs depend on these byte
// for byte, so change a behaviour only together with its callers.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "arttrack/sim/scoring.h"

namespace arttrack::sim {
namespace text {

// ---- parsing ----

// `s` without leading and trailing spaces, tabs and carriage returns (' ',
// '\t', '\r': the '\r' of a CRLF line ending goes too; a '\n' stays). All
// blank: "".
std::string trim(const std::string& s);

// Reads the whole of `text`, trimmed as by trim(), as one finite number
// (std::strtod: decimal or hexadecimal, C locale). True if the trimmed text
// is non-empty, strtod consumed all of it and the value is finite ("inf",
// "nan" and overflowing values are false). `out` is written whenever the
// trimmed text is non-empty, also when the result is false.
bool parse_number(const std::string& text, double& out);

// As parse_number, but a non-finite value is true too: "nan", "inf",
// "infinity" in any case and with an optional sign (strtod's spellings; those
// csv_number and shortest_number write among them). A finite literal too
// large for a double ("1e999") is still false. For files that record
// missing or unbounded values; check finiteness where a value must be one.
bool parse_number_or_non_finite(const std::string& text, double& out);

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

// How split_csv and CsvReader treat the space around a field.
enum class CsvSpace {
  kTrim,      // drop ' ', '\t' and '\r' before and after a field's text
              // (outside its quotes): for files people write
  kVerbatim,  // keep every byte (RFC 4180): for files written by csv_field
};

// One CSV line split into its fields, the inverse of joining csv_field's
// with ',': a field in double quotes may hold ',' and '""' for one '"'; no
// field holds a line break. n commas outside quotes make n + 1 fields ("" is
// one empty field). nullopt if a quote is left open.
std::optional<std::vector<std::string>> split_csv(const std::string& line, CsvSpace space);

// A CSV file read row by row with its line numbers, for errors that name
// the file, the line and the field. Lines may end in "\n" or "\r\n"; lines
// that are blank (only spaces, tabs, '\r') are skipped.
class CsvReader {
 public:
  // Opens `path`; failure: InputError "<path>: cannot read file".
  CsvReader(const std::filesystem::path& path, CsvSpace space);
  // The next non-blank line's fields (split_csv); false at the end of the
  // file. A quote left open is an error naming the line.
  bool next(std::vector<std::string>& fields);
  // "<file>:<line>" of the row last read (":0" before the first).
  std::string where() const;
  // Throws InputError "<file>:<line>: <problem>".
  [[noreturn]] void fail(const std::string& problem) const;
  // Unless the row has `n` fields: fail "has <k> fields, the header has <n>".
  void expect_width(const std::vector<std::string>& fields, std::size_t n) const;
  // Field i as a number, non-finite ones included (parse_number_or_non_finite);
  // else fail "column '<header[i]>': '<field>' is not a number".
  double number(const std::vector<std::string>& fields, std::size_t i,
                const std::vector<std::string>& header) const;
  // As number(), and a non-finite value fails "column '<header[i]>' is not finite".
  double finite(const std::vector<std::string>& fields, std::size_t i,
                const std::vector<std::string>& header) const;

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  CsvSpace space_;
  int line_ = 0;
};

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
