#include "arttrack/sim/internal/text_format.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <vector>

#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace text {

namespace {

constexpr const char* kBlank = " \t\r";

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

}  // namespace

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(kBlank);
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(kBlank);
  return s.substr(b, e - b + 1);
}

bool parse_number_or_non_finite(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(t.c_str(), &end);
  const bool overflow = errno == ERANGE && std::isinf(out);
  return end == t.c_str() + t.size() && !overflow;
}

bool parse_number(const std::string& text, double& out) {
  return parse_number_or_non_finite(text, out) && std::isfinite(out);
}

std::string format_g(double v, int digits) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
  return buf;
}

std::string csv_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return format_g(v, 17);
}

std::string shortest_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, r.ptr);
}

std::string pose_fields(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  std::string out;
  for (double v :
       {T.translation().x(), T.translation().y(), T.translation().z(), q.w(), q.x(), q.y(), q.z()})
    out += ',' + shortest_number(v);
  return out;
}

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  return s;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::optional<std::vector<std::string>> split_csv(const std::string& line, CsvSpace space) {
  const bool trim_space = space == CsvSpace::kTrim;
  std::vector<std::string> fields;
  std::string cur;
  // With kTrim: cur's length up to its last byte that is not blank space
  // outside quotes, and whether the field has begun (blank space before it
  // is dropped).
  std::size_t kept = 0;
  bool begun = false, quoted = false;
  auto end_field = [&] {
    if (trim_space) cur.resize(kept);
    fields.push_back(std::move(cur));
    cur.clear();
    kept = 0;
    begun = false;
  };
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cur += c;
      }
      kept = cur.size();
    } else if (c == '"') {
      quoted = begun = true;
    } else if (c == ',') {
      end_field();
    } else if (trim_space && is_blank(c)) {
      if (begun) cur += c;
    } else {
      cur += c;
      kept = cur.size();
      begun = true;
    }
  }
  if (quoted) return std::nullopt;
  end_field();
  return fields;
}

CsvReader::CsvReader(const std::filesystem::path& path, CsvSpace space)
    : path_(path), in_(path, std::ios::binary), space_(space) {
  if (!in_) throw InputError(path.string() + ": cannot read file");
}

bool CsvReader::next(std::vector<std::string>& fields) {
  std::string text;
  while (std::getline(in_, text)) {
    ++line_;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (trim(text).empty()) continue;
    auto split = split_csv(text, space_);
    if (!split) fail("a quote is not closed");
    fields = std::move(*split);
    return true;
  }
  return false;
}

std::string CsvReader::where() const { return path_.string() + ":" + std::to_string(line_); }

void CsvReader::fail(const std::string& problem) const {
  throw InputError(where() + ": " + problem);
}

void CsvReader::expect_width(const std::vector<std::string>& fields, std::size_t n) const {
  if (fields.size() != n)
    fail("has " + std::to_string(fields.size()) + " fields, the header has " + std::to_string(n));
}

double CsvReader::number(const std::vector<std::string>& fields, std::size_t i,
                         const std::vector<std::string>& header) const {
  double v = 0;
  if (!parse_number_or_non_finite(fields[i], v))
    fail("column '" + header[i] + "': '" + fields[i] + "' is not a number");
  return v;
}

double CsvReader::finite(const std::vector<std::string>& fields, std::size_t i,
                         const std::vector<std::string>& header) const {
  const double v = number(fields, i, header);
  if (!std::isfinite(v)) fail("column '" + header[i] + "' is not finite");
  return v;
}

std::string html_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string base64(std::span<const std::uint8_t> bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v =
        (std::uint32_t(bytes[i]) << 16) | (std::uint32_t(bytes[i + 1]) << 8) | bytes[i + 2];
    for (int s : {18, 12, 6, 0}) out += kAlphabet[(v >> s) & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest) {
    std::uint32_t v = std::uint32_t(bytes[i]) << 16;
    if (rest == 2) v |= std::uint32_t(bytes[i + 1]) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw InputError(path.string() + ": cannot write file");
}

}  // namespace text

double median_convergence_s(const std::vector<std::optional<double>>& time_to_converge_s) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> t;
  for (const auto& c : time_to_converge_s) t.push_back(c ? *c : kInf);
  if (t.empty()) return kInf;
  std::sort(t.begin(), t.end());
  const std::size_t n = t.size();
  if (n % 2) return t[n / 2];
  if (!std::isfinite(t[n / 2])) return kInf;
  return 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

}  // namespace arttrack::sim
