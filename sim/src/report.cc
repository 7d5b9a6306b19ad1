#include "arttrack/sim/report.h"

#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <fstream>
#include <limits>
#include <new>
#include <sstream>

#include "arttrack/sim/run_outputs.h"
#include "arttrack/tracker/error.h"
#include "text_format.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMm = 1e3;
constexpr double kDeg = 180.0 / M_PI;
// Log axis when the largest value exceeds the smallest positive one by this.
constexpr double kLogRatio = 100.0;

// ---------------------------------------------------------------- PNG in memory

// libpng reports errors by longjmp; write_png_rows holds no C++ object with a
// destructor in its frame, so the jump skips nothing.
struct PngSink {
  std::vector<std::uint8_t>* out = nullptr;
  char message[256] = "";
};

void on_png_error(png_structp png, png_const_charp msg) {
  auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
  std::snprintf(sink->message, sizeof(sink->message), "%s", msg);
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

void on_png_write(png_structp png, png_bytep data, png_size_t n) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  bool ok = true;
  try {
    sink->out->insert(sink->out->end(), data, data + n);
  } catch (const std::bad_alloc&) {
    ok = false;
  }
  if (!ok)
    png_error(png, "out of memory");  // outside the handler: longjmp leaves no exception behind
}

void on_png_flush(png_structp) {}

bool write_png_rows(int width, int height, png_bytep* rows, PngSink* sink) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, on_png_error, on_png_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    std::snprintf(sink->message, sizeof(sink->message), "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, sink, on_png_write, on_png_flush);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

// ---------------------------------------------------------------- text

// Fixed-point number; "∞" for +infinity (a lost estimate counts as one), "–" for NaN.
std::string fixed(double v, int decimals) {
  if (std::isnan(v)) return "&ndash;";
  if (std::isinf(v)) return v > 0 ? "&infin;" : "-&infin;";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  if (std::string(buf).find_first_not_of("-0.") == std::string::npos && buf[0] == '-')
    return std::string(buf + 1);  // no "-0.00"
  return buf;
}

// Three significant digits (at most four decimals): 42.1, 3.22, 0.00831.
std::string significant(double v) {
  if (!std::isfinite(v) || v == 0) return fixed(v, 0);
  return fixed(v, std::clamp(2 - int(std::floor(std::log10(std::abs(v)))), 0, 4));
}

// SVG coordinate, 0.1 px.
std::string px(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", v);
  return buf;
}

// A tick label: as many decimals as the step between ticks needs.
std::string tick_label(double v, double step) {
  const int decimals = std::max(0, int(-std::floor(std::log10(step) + 1e-9)));
  return fixed(v, decimals);
}

// Okabe-Ito colours (distinguishable with colour-blindness), one per method.
std::string method_colour(const std::string& method, std::size_t index) {
  if (method == "encoders_only") return "#E69F00";
  if (method == "camera_offset_only") return "#0072B2";
  if (method == "full_fusion") return "#009E73";
  if (method == "vision_only") return "#CC79A7";
  static const std::array<const char*, 4> other = {"#D55E00", "#56B4E9", "#F0E442", "#000000"};
  return other[index % other.size()];
}

// ---------------------------------------------------------------- axes

// Maps values to pixels, linear or log10, with its ticks.
struct Axis {
  double lo = 0, hi = 1;
  bool log = false;
  double px_lo = 0, px_hi = 1;  // pixel positions of lo and hi
  std::vector<double> ticks;
  double step = 1;  // linear: tick step, for labels

  double map(double v) const {
    double t;
    if (log) {
      v = std::max(v, lo);
      t = (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
    } else {
      t = (v - lo) / (hi - lo);
    }
    return px_lo + std::clamp(t, -0.02, 1.02) * (px_hi - px_lo);
  }
  std::string label(double v) const {
    if (log) return fixed(v, std::max(0, int(-std::floor(std::log10(v) + 1e-9))));
    return tick_label(v, step);
  }
};

// widen: the axis ends at round ticks; else it spans exactly [lo, hi] (time
// axes) and keeps the ticks inside.
Axis linear_axis(double lo, double hi, int max_ticks, bool widen = true) {
  Axis a;
  a.ticks = round_ticks(lo, hi, max_ticks);
  a.step = a.ticks.size() > 1 ? a.ticks[1] - a.ticks[0] : 1.0;
  if (widen || !(hi > lo)) {
    a.lo = a.ticks.front();
    a.hi = a.ticks.back();
  } else {
    a.lo = lo;
    a.hi = hi;
    const double eps = 1e-9 * (hi - lo);
    std::erase_if(a.ticks, [&](double t) { return t < lo - eps || t > hi + eps; });
  }
  return a;
}

// Decades around [lo, hi] (lo > 0); with 2 and 5 between when they are few.
Axis log_axis(double lo, double hi) {
  Axis a;
  a.log = true;
  int d0 = int(std::floor(std::log10(lo) + 1e-9));
  int d1 = int(std::ceil(std::log10(hi) - 1e-9));
  if (d1 <= d0) d1 = d0 + 1;
  a.lo = std::pow(10.0, d0);
  a.hi = std::pow(10.0, d1);
  for (int d = d0; d <= d1; ++d) {
    const double p = std::pow(10.0, d);
    a.ticks.push_back(p);
    if (d1 - d0 <= 2 && d < d1)
      for (double m : {2.0, 5.0}) a.ticks.push_back(m * p);
  }
  std::sort(a.ticks.begin(), a.ticks.end());
  return a;
}

// A log axis if the positive finite values span more than kLogRatio, else linear.
Axis auto_axis(const std::vector<double>& values, int max_ticks, bool allow_log, double min_span,
               bool include_zero) {
  double lo = kInf, hi = -kInf, lo_pos = kInf;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    if (v > 0) lo_pos = std::min(lo_pos, v);
  }
  if (!(lo <= hi)) return linear_axis(0, 1, max_ticks);
  if (allow_log && lo >= 0 && std::isfinite(lo_pos) && hi / lo_pos > kLogRatio)
    return log_axis(lo_pos, hi);
  if (include_zero) lo = std::min(lo, 0.0);
  if (hi - lo < min_span) {
    const double mid = 0.5 * (lo + hi);
    lo = include_zero && lo >= 0 ? std::max(0.0, mid - 0.5 * min_span) : mid - 0.5 * min_span;
    hi = lo + min_span;
  }
  return linear_axis(lo, hi, max_ticks);
}

// ---------------------------------------------------------------- SVG charts

// A plot area inside an SVG of width x height.
struct Frame {
  double width = 580, height = 300;
  double left = 62, right = 14, top = 30, bottom = 44;
  double x0() const { return left; }
  double x1() const { return width - right; }
  double y0() const { return height - bottom; }  // bottom of the plot area
  double y1() const { return top; }
};

void svg_open(std::ostringstream& o, const Frame& f, const std::string& id,
              const std::string& title) {
  o << "<svg class=\"chart\" data-chart=\"" << text::html_escape(id) << "\" viewBox=\"0 0 "
    << px(f.width) << ' ' << px(f.height) << "\" width=\"" << px(f.width) << "\" height=\""
    << px(f.height) << "\" role=\"img\"><title>" << text::html_escape(title) << "</title>\n";
  o << "<text class=\"ct\" x=\"" << px(f.left) << "\" y=\"18\">" << text::html_escape(title)
    << "</text>\n";
}

void y_axis(std::ostringstream& o, const Frame& f, const Axis& a, const std::string& label) {
  for (double t : a.ticks) {
    const double y = a.map(t);
    o << "<line class=\"grid\" x1=\"" << px(f.x0()) << "\" x2=\"" << px(f.x1()) << "\" y1=\""
      << px(y) << "\" y2=\"" << px(y) << "\"/><text class=\"tl\" x=\"" << px(f.x0() - 5)
      << "\" y=\"" << px(y + 4) << "\" text-anchor=\"end\">" << a.label(t) << "</text>\n";
  }
  const double ym = 0.5 * (f.y0() + f.y1());
  o << "<text class=\"al\" transform=\"translate(13," << px(ym)
    << ") rotate(-90)\" text-anchor=\"middle\">" << text::html_escape(label)
    << (a.log ? " (log scale)" : "") << "</text>\n";
  o << "<line class=\"axis\" x1=\"" << px(f.x0()) << "\" x2=\"" << px(f.x0()) << "\" y1=\""
    << px(f.y0()) << "\" y2=\"" << px(f.y1()) << "\"/>\n";
}

void x_axis(std::ostringstream& o, const Frame& f, const Axis& a, const std::string& label) {
  for (double t : a.ticks) {
    const double x = a.map(t);
    o << "<line class=\"grid\" x1=\"" << px(x) << "\" x2=\"" << px(x) << "\" y1=\"" << px(f.y0())
      << "\" y2=\"" << px(f.y1()) << "\"/><text class=\"tl\" x=\"" << px(x) << "\" y=\""
      << px(f.y0() + 15) << "\" text-anchor=\"middle\">" << a.label(t) << "</text>\n";
  }
  o << "<line class=\"axis\" x1=\"" << px(f.x0()) << "\" x2=\"" << px(f.x1()) << "\" y1=\""
    << px(f.y0()) << "\" y2=\"" << px(f.y0()) << "\"/>\n";
  if (!label.empty())
    o << "<text class=\"al\" x=\"" << px(0.5 * (f.x0() + f.x1())) << "\" y=\"" << px(f.height - 6)
      << "\" text-anchor=\"middle\">" << text::html_escape(label) << "</text>\n";
}

// One box of a box plot, in display units.
struct Box {
  std::string name, colour;
  Percentiles p;
};

Percentiles scaled(const Percentiles& p, double s) {
  Percentiles q = p;
  for (double* v : {&q.p01, &q.p25, &q.p50, &q.p75, &q.p99, &q.mean, &q.max}) *v *= s;
  return q;
}

// The paper's box plot: box p25-p75, whisker p1-p99 with ticks at p1 and p99,
// thick tick at p50 (value written beside it). Values beyond the axis (+inf:
// lost estimates) end in an arrow at the top.
void box_plot(std::ostringstream& o, const std::string& id, const std::string& title,
              const std::string& y_label, const std::vector<Box>& boxes, Axis axis) {
  Frame f;
  f.height = 320;
  f.bottom = 28;
  svg_open(o, f, id, title);
  axis.px_lo = f.y0();
  axis.px_hi = f.y1();
  y_axis(o, f, axis, y_label);
  o << "<line class=\"axis\" x1=\"" << px(f.x0()) << "\" x2=\"" << px(f.x1()) << "\" y1=\""
    << px(f.y0()) << "\" y2=\"" << px(f.y0()) << "\"/>\n";
  const double slot = (f.x1() - f.x0()) / std::max<std::size_t>(1, boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    const double xc = f.x0() + (i + 0.5) * slot;
    const double half = std::min(28.0, 0.22 * slot);
    o << "<text class=\"tl\" x=\"" << px(xc) << "\" y=\"" << px(f.y0() + 16)
      << "\" text-anchor=\"middle\">" << text::html_escape(b.name) << "</text>\n";
    if (b.p.count == 0 || std::isnan(b.p.p50)) {
      o << "<text class=\"note\" x=\"" << px(xc) << "\" y=\"" << px(0.5 * (f.y0() + f.y1()))
        << "\" text-anchor=\"middle\">no samples</text>\n";
      continue;
    }
    auto y = [&](double v) { return std::isinf(v) ? f.y1() : axis.map(v); };
    const std::string& c = b.colour;
    o << "<g stroke=\"" << c << "\" stroke-width=\"1.5\">";
    o << "<line x1=\"" << px(xc) << "\" x2=\"" << px(xc) << "\" y1=\"" << px(y(b.p.p01))
      << "\" y2=\"" << px(y(b.p.p99)) << "\"/>";
    for (double v : {b.p.p01, b.p.p99})
      if (std::isfinite(v))
        o << "<line x1=\"" << px(xc - 0.6 * half) << "\" x2=\"" << px(xc + 0.6 * half) << "\" y1=\""
          << px(y(v)) << "\" y2=\"" << px(y(v)) << "\"/>";
    const double top = y(b.p.p75), bottom = y(b.p.p25);
    o << "<rect x=\"" << px(xc - half) << "\" y=\"" << px(top) << "\" width=\"" << px(2 * half)
      << "\" height=\"" << px(std::max(1.0, bottom - top)) << "\" fill=\"" << c
      << "\" fill-opacity=\"0.3\"/>";
    o << "<line stroke-width=\"3\" x1=\"" << px(xc - half) << "\" x2=\"" << px(xc + half)
      << "\" y1=\"" << px(y(b.p.p50)) << "\" y2=\"" << px(y(b.p.p50)) << "\"/></g>\n";
    if (std::isinf(b.p.p99))
      o << "<path d=\"M" << px(xc - 5) << ' ' << px(f.y1() + 8) << " L" << px(xc) << ' '
        << px(f.y1()) << " L" << px(xc + 5) << ' ' << px(f.y1() + 8) << "\" fill=\"none\" stroke=\""
        << c << "\" stroke-width=\"1.5\"/><text class=\"note\" x=\"" << px(xc + 8) << "\" y=\""
        << px(f.y1() + 10) << "\">lost</text>\n";
    o << "<text class=\"val\" x=\"" << px(xc + half + 4) << "\" y=\"" << px(y(b.p.p50) + 4) << "\">"
      << significant(b.p.p50) << "</text>\n";
  }
  o << "</svg>\n";
}

// A line of a line chart, optionally with a band (lo..hi) around it.
struct Series {
  std::string name, colour;
  std::vector<double> x, y;
  std::vector<double> band_lo, band_hi;  // empty: no band
  enum class Stroke { kSolid, kDashed, kDotted } stroke = Stroke::kSolid;
};

const char* dash_attribute(Series::Stroke stroke) {
  switch (stroke) {
    case Series::Stroke::kDashed:
      return " stroke-dasharray=\"5 3\"";
    case Series::Stroke::kDotted:
      return " stroke-dasharray=\"1.5 3\"";
    case Series::Stroke::kSolid:
      break;
  }
  return "";
}

struct LineChart {
  std::string id, title, x_label, y_label;
  Frame frame;
  std::vector<Series> series;
  bool allow_log = false;
  bool include_zero = false;
  double min_span = 0;  // smallest y range, display units
  double x_lo = 0, x_hi = 1;
  bool legend = true;
  std::vector<std::pair<double, std::string>> x_marks, y_marks;  // dashed reference lines
  int y_ticks = 6, x_ticks = 8;
  double line_width = 1.6;  // px
};

// Per pixel column, the indices of the smallest and largest y in time order:
// the polyline looks the same as with every point, at a bounded size.
std::vector<std::size_t> decimate(const Series& s, const Axis& xa, const Axis& ya) {
  std::vector<std::size_t> keep;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  const double columns = std::abs(xa.px_hi - xa.px_lo);
  if (n <= 2 * columns) {
    for (std::size_t i = 0; i < n; ++i) keep.push_back(i);
    return keep;
  }
  std::size_t i = 0;
  while (i < n) {
    const long col = std::lround(xa.map(s.x[i]));
    std::size_t lo = i, hi = i, j = i;
    bool finite = true;
    for (; j < n && std::lround(xa.map(s.x[j])) == col; ++j) {
      if (!std::isfinite(s.y[j])) finite = false;
      if (ya.map(s.y[j]) < ya.map(s.y[lo])) lo = j;  // pixel y grows downwards
      if (ya.map(s.y[j]) > ya.map(s.y[hi])) hi = j;
    }
    if (!finite) {  // keep the gap visible
      for (std::size_t k = i; k < j; ++k) keep.push_back(k);
    } else {
      keep.push_back(std::min(lo, hi));
      if (lo != hi) keep.push_back(std::max(lo, hi));
    }
    i = j;
  }
  return keep;
}

void line_chart(std::ostringstream& o, const LineChart& c) {
  const Frame& f = c.frame;
  std::vector<double> ys;
  for (const Series& s : c.series) {
    ys.insert(ys.end(), s.y.begin(), s.y.end());
    ys.insert(ys.end(), s.band_lo.begin(), s.band_lo.end());
    ys.insert(ys.end(), s.band_hi.begin(), s.band_hi.end());
  }
  for (const auto& m : c.y_marks) ys.push_back(m.first);
  Axis ya = auto_axis(ys, c.y_ticks, c.allow_log, c.min_span, c.include_zero);
  ya.px_lo = f.y0();
  ya.px_hi = f.y1();
  Axis xa = linear_axis(c.x_lo, c.x_hi, c.x_ticks, false);
  xa.px_lo = f.x0();
  xa.px_hi = f.x1();

  svg_open(o, f, c.id, c.title);
  y_axis(o, f, ya, c.y_label);
  x_axis(o, f, xa, c.x_label);
  // Reference lines under the data, their labels over it.
  std::ostringstream labels;
  for (const auto& [x, text] : c.x_marks) {
    const double X = xa.map(x);
    o << "<line class=\"mark\" x1=\"" << px(X) << "\" x2=\"" << px(X) << "\" y1=\"" << px(f.y0())
      << "\" y2=\"" << px(f.y1()) << "\"/>\n";
    labels << "<text class=\"note\" x=\"" << px(X + 3) << "\" y=\"" << px(f.y1() + 11) << "\">"
           << text::html_escape(text) << "</text>\n";
  }
  for (const auto& [y, text] : c.y_marks) {
    const double Y = ya.map(y);
    o << "<line class=\"mark\" x1=\"" << px(f.x0()) << "\" x2=\"" << px(f.x1()) << "\" y1=\""
      << px(Y) << "\" y2=\"" << px(Y) << "\"/>\n";
    labels << "<text class=\"note\" x=\"" << px(f.x1() - 3) << "\" y=\"" << px(Y - 3)
           << "\" text-anchor=\"end\">" << text::html_escape(text) << "</text>\n";
  }
  o << "<clipPath id=\"clip-" << text::html_escape(c.id) << "\"><rect x=\"" << px(f.x0())
    << "\" y=\"" << px(f.y1()) << "\" width=\"" << px(f.x1() - f.x0()) << "\" height=\""
    << px(f.y0() - f.y1()) << "\"/></clipPath><g clip-path=\"url(#clip-" << text::html_escape(c.id)
    << ")\">\n";
  // Bands first, lines over them.
  for (const Series& s : c.series) {
    if (s.band_lo.empty()) continue;
    Series lo = s, hi = s;
    lo.y = s.band_lo;
    hi.y = s.band_hi;
    const std::vector<std::size_t> ki = decimate(hi, xa, ya), kl = decimate(lo, xa, ya);
    std::ostringstream d;
    bool open = false;
    for (std::size_t i : ki)
      if (std::isfinite(s.band_hi[i])) {
        d << (open ? " L" : "M") << px(xa.map(s.x[i])) << ' ' << px(ya.map(s.band_hi[i]));
        open = true;
      }
    for (auto it = kl.rbegin(); it != kl.rend(); ++it)
      if (std::isfinite(s.band_lo[*it]))
        d << (open ? " L" : "M") << px(xa.map(s.x[*it])) << ' ' << px(ya.map(s.band_lo[*it]));
    if (open)
      o << "<path d=\"" << d.str() << " Z\" fill=\"" << s.colour
        << "\" fill-opacity=\"0.2\" stroke=\"none\"/>\n";
  }
  for (const Series& s : c.series) {
    std::ostringstream d;
    bool open = false;
    for (std::size_t i : decimate(s, xa, ya)) {
      if (!std::isfinite(s.y[i])) {
        open = false;  // a gap: lost estimate or no value
        continue;
      }
      d << (open ? " L" : " M") << px(xa.map(s.x[i])) << ' ' << px(ya.map(s.y[i]));
      open = true;
    }
    if (d.str().empty()) continue;
    o << "<path d=\"" << d.str() << "\" fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\""
      << px(c.line_width) << "\" stroke-linejoin=\"round\"" << dash_attribute(s.stroke) << "/>\n";
  }
  o << "</g>\n" << labels.str();
  if (c.legend) {
    // Right-aligned above the plot, clear of the title (about 7 px per character).
    double width = 0;
    for (const Series& s : c.series) width += 32 + 7.0 * s.name.size();
    double x = f.x1() - width;
    for (const Series& s : c.series) {
      o << "<line x1=\"" << px(x) << "\" x2=\"" << px(x + 18) << "\" y1=\"14\" y2=\"14\" stroke=\""
        << s.colour << "\" stroke-width=\"3\"" << dash_attribute(s.stroke)
        << "/><text class=\"tl\" x=\"" << px(x + 22) << "\" y=\"18\">" << text::html_escape(s.name)
        << "</text>\n";
      x += 32 + 7.0 * s.name.size();
    }
  }
  o << "</svg>\n";
}

// ---------------------------------------------------------------- data

// The worst over the scored end effectors of the translation error, m (NaN
// if any is: a lost estimate).
double worst_translation_m(const EstimateSample& s) {
  if (s.ee_error.empty()) return kNaN;
  double worst = 0;
  for (const PoseError& e : s.ee_error) {
    if (std::isnan(e.translation_m)) return kNaN;
    worst = std::max(worst, e.translation_m);
  }
  return worst;
}

// "left_ee, right_ee".
std::string end_effector_list(const ScenarioResult& r) {
  std::string out;
  for (std::size_t i = 0; i < r.end_effectors.size(); ++i)
    out += (i ? ", " : "") + r.end_effectors[i];
  return out;
}

double median_of(std::vector<double> v) {
  if (v.empty()) return kNaN;
  for (double& x : v)
    if (std::isnan(x)) x = kInf;  // lost counts as the worst
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

const MethodRun* method_run(const RunResult& run, const std::string& method) {
  for (const MethodRun& m : run.methods)
    if (m.method == method) return &m;
  return nullptr;
}

std::size_t method_index(const ScenarioResult& r, const std::string& method) {
  return std::size_t(std::find(r.methods.begin(), r.methods.end(), method) - r.methods.begin());
}

// ---------------------------------------------------------------- depth frames

void jet(double t, std::uint8_t* rgb) {
  const auto channel = [t](double centre) {
    return std::clamp(1.5 - 4.0 * std::abs(t - centre), 0.0, 1.0);
  };
  rgb[0] = std::uint8_t(std::lround(255 * channel(0.75)));
  rgb[1] = std::uint8_t(std::lround(255 * channel(0.5)));
  rgb[2] = std::uint8_t(std::lround(255 * channel(0.25)));
}

// The q-quantile of the valid depths (NaN if none).
double depth_quantile(std::vector<float>& z, double q) {
  if (z.empty()) return kNaN;
  std::sort(z.begin(), z.end());
  return z[std::size_t(q * double(z.size() - 1))];
}

// The depth range the colours span, m. With an estimate, the depths of its
// render set the far end (98th percentile plus a quarter of the span): the
// robot, not the far wall, gets the colours. Without, the 2nd to 98th
// percentile of the whole image.
std::pair<double, double> depth_range(const DepthImage& observed, const DepthImage& estimate) {
  std::vector<float> all, robot;
  for (float z : observed.depth_m)
    if (std::isfinite(z) && z > 0) all.push_back(z);
  for (float z : estimate.depth_m)
    if (std::isfinite(z) && z > 0) robot.push_back(z);
  if (all.empty()) return {0.0, 1.0};
  const double near_all = depth_quantile(all, 0.02), far_all = depth_quantile(all, 0.98);
  double near_m = near_all, far_m = far_all;
  if (robot.size() >= 20) {
    const double near_robot = depth_quantile(robot, 0.02), far_robot = depth_quantile(robot, 0.98);
    near_m = std::min(near_all, near_robot);
    far_m = std::min(far_all, far_robot + 0.25 * (far_robot - near_m));
  }
  return {near_m, far_m > near_m + 0.01 ? far_m : near_m + 0.01};
}

// Observed depth in jet colours (near red, far blue, black: no return), the
// estimate's silhouette edges in white (about 1/320 of the width thick).
std::vector<std::uint8_t> overlay_rgb(const DepthImage& observed, const DepthImage& estimate,
                                      double near_m, double far_m) {
  const int w = observed.width, h = observed.height;
  std::vector<std::uint8_t> rgb(std::size_t(w) * h * 3, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const float z = observed.at(u, v);
      if (std::isfinite(z) && z > 0)
        jet(1.0 - std::clamp((z - near_m) / (far_m - near_m), 0.0, 1.0),
            &rgb[(std::size_t(v) * w + u) * 3]);
    }
  if (estimate.width != w || estimate.height != h) return rgb;
  const int r = std::max(1, w / 320);
  auto covered = [&](int u, int v) {
    return u >= 0 && v >= 0 && u < w && v < h && estimate.at(u, v) > 0;
  };
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      if (!covered(u, v)) continue;
      bool edge = false;
      for (int dv = -r; dv <= r && !edge; ++dv)
        for (int du = -r; du <= r && !edge; ++du) edge = !covered(u + du, v + dv);
      if (edge) std::fill_n(&rgb[(std::size_t(v) * w + u) * 3], 3, std::uint8_t(255));
    }
  return rgb;
}

// A horizontal jet colour bar from near_m to far_m with round ticks.
void colour_bar(std::ostringstream& o, const std::string& id, double near_m, double far_m) {
  Frame f;
  f.width = 560;
  f.height = 52;
  f.left = 20;
  f.right = 20;
  f.top = 6;
  f.bottom = 30;
  o << "<svg class=\"bar\" data-chart=\"" << text::html_escape(id) << "\" viewBox=\"0 0 "
    << px(f.width) << ' ' << px(f.height) << "\" width=\"" << px(f.width) << "\" height=\""
    << px(f.height) << "\" role=\"img\"><title>depth colours, m</title>"
    << "<defs><linearGradient id=\"g-" << text::html_escape(id) << "\">";
  for (int i = 0; i <= 8; ++i) {
    std::uint8_t c[3];
    jet(1.0 - i / 8.0, c);
    char hex[8];
    std::snprintf(hex, sizeof(hex), "#%02x%02x%02x", c[0], c[1], c[2]);
    o << "<stop offset=\"" << px(i * 12.5) << "%\" stop-color=\"" << hex << "\"/>";
  }
  o << "</linearGradient></defs><rect x=\"" << px(f.x0()) << "\" y=\"" << px(f.top) << "\" width=\""
    << px(f.x1() - f.x0()) << "\" height=\"14\" fill=\"url(#g-" << text::html_escape(id)
    << ")\"/>\n";
  Axis a = linear_axis(near_m, far_m, 8);
  a.px_lo = f.x0();
  a.px_hi = f.x1();
  // The ticks widen the axis; the bar spans exactly near..far.
  const double scale = (f.x1() - f.x0()) / (far_m - near_m);
  for (double t : a.ticks) {
    if (t < near_m - 1e-9 || t > far_m + 1e-9) continue;
    const double x = f.x0() + (t - near_m) * scale;
    o << "<line class=\"axis\" x1=\"" << px(x) << "\" x2=\"" << px(x) << "\" y1=\""
      << px(f.top + 14) << "\" y2=\"" << px(f.top + 18) << "\"/><text class=\"tl\" x=\"" << px(x)
      << "\" y=\"" << px(f.top + 30) << "\" text-anchor=\"middle\">" << a.label(t) << "</text>";
  }
  o << "<text class=\"tl\" x=\"" << px(f.x1()) << "\" y=\"" << px(f.height - 2)
    << "\" text-anchor=\"end\">depth, m (black: no return)</text></svg>\n";
}

// ---------------------------------------------------------------- page sections

const char* kStyle = R"(<style>
body{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif;font-size:14px;color:#222;margin:0;background:#fff}
main{max-width:1200px;margin:0 auto;padding:12px 16px}
h1{font-size:22px;margin:8px 0}h2{font-size:18px;margin:22px 0 6px;border-bottom:1px solid #ccc}
p.read{background:#f4f6f8;padding:6px 10px;border-left:3px solid #789}
p.warn{background:#fff4e5;padding:6px 10px;border-left:3px solid #d80}
dl.meta{display:grid;grid-template-columns:max-content 1fr;gap:2px 14px;margin:6px 0}
dl.meta dt{font-weight:bold}dl.meta dd{margin:0}
.two{display:grid;grid-template-columns:1fr 1fr;gap:10px}
.multi{display:grid;grid-template-columns:repeat(4,1fr);gap:6px}
.three{display:grid;grid-template-columns:repeat(3,1fr);gap:6px}
svg.chart,svg.bar{width:100%;height:auto;display:block}
svg text{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif}
.ct{font-size:13px;font-weight:bold}.tl{font-size:11px;fill:#333}.al{font-size:12px;fill:#222}
.val{font-size:11px;fill:#111}.note{font-size:10px;fill:#555;paint-order:stroke;stroke:#fff;stroke-width:3px}
.grid{stroke:#e3e3e3;stroke-width:1}.axis{stroke:#444;stroke-width:1}
.mark{stroke:#777;stroke-width:1;stroke-dasharray:4 3}
figure{margin:0}figure img{width:100%;height:auto;image-rendering:pixelated;display:block;border:1px solid #999}
figcaption{font-size:13px;margin:3px 0 10px}
table{border-collapse:collapse;font-size:13px;margin:6px 0}
th,td{border:1px solid #ccc;padding:2px 6px;text-align:right}th{background:#f0f0f0}
td.m,th.m{text-align:left}
.key{display:inline-block;width:18px;height:4px;vertical-align:middle;margin:0 4px 0 12px}
pre{font-size:11px;background:#f8f8f8;padding:6px;overflow:auto}
</style>
)";

void header(std::ostringstream& o, const ScenarioResult& r) {
  o << "<h1>arttrack run: " << text::html_escape(r.scenario) << "</h1>\n<dl class=\"meta\">";
  o << "<dt>scenario file</dt><dd>" << text::html_escape(r.source) << "</dd>";
  o << "<dt>duration</dt><dd>" << fixed(r.duration_s, 1) << " s simulated per run</dd>";
  o << "<dt>runs</dt><dd>" << r.runs.size() << "</dd><dt>seeds</dt><dd>";
  for (std::size_t i = 0; i < r.seeds.size(); ++i) o << (i ? ", " : "") << r.seeds[i];
  o << "</dd><dt>methods</dt><dd>";
  for (std::size_t i = 0; i < r.methods.size(); ++i)
    o << "<span class=\"key\" style=\"background:" << method_colour(r.methods[i], i) << "\"></span>"
      << text::html_escape(r.methods[i]);
  o << "</dd><dt>scored end effectors</dt><dd>";
  for (std::size_t i = 0; i < r.end_effectors.size(); ++i)
    o << (i ? ", " : "") << text::html_escape(r.end_effectors[i]);
  int captured = 0, delivered = 0;
  for (const RunResult& run : r.runs)
    captured += run.frames_captured, delivered += run.frames_delivered;
  o << "</dd><dt>depth frames</dt><dd>" << captured << " captured, " << delivered
    << " delivered to the trackers (all runs)</dd></dl>\n";
  if (r.duration_s <= r.scoring.converged_after_s)
    o << "<p class=\"warn\"><strong>Short run:</strong> it ends at " << fixed(r.duration_s, 1)
      << "&nbsp;s, before the converged window starts (scoring.converged_after_s = "
      << fixed(r.scoring.converged_after_s, 1)
      << "&nbsp;s), so the converged statistics, times to converge and lost runs below are "
         "empty. Run longer, or set scoring.converged_after_s lower.</p>\n";
  o << "<p class=\"read\">How to read: errors are of the end-effector pose in each method's "
       "<em>estimated</em> camera frame against the true pose in the true camera frame (paper "
       "Sec.&nbsp;V); lower is better. Boxes span the middle half of the samples (p25&ndash;p75), "
       "ticks mark p1, the median p50 (thick, value beside it) and p99; &ldquo;converged&rdquo; "
       "keeps the samples from "
    << fixed(r.scoring.converged_after_s, 1)
    << "&nbsp;s on. Axes marked &ldquo;log scale&rdquo; are logarithmic because the values "
       "span more than two decades. With several end effectors, charts show the worst of them "
       "at each sample (the tables have each one). &infin; or &ldquo;lost&rdquo; on a chart: a "
       "lost estimate (counted as "
       "the worst error).</p>\n";
}

// The page's answer first: per method, whether it converged, how fast, how
// often it was lost, and how often it was worse than encoders only; then the
// best method among those never lost.
void verdict_section(std::ostringstream& o, const ScenarioResult& r) {
  if (r.method_results.empty()) return;
  o << "<h2>Verdict</h2>\n<table><tr><th class=\"m\">method</th><th>verdict</th>"
       "<th>converged p50 / p99, mm</th><th>median time to converge</th><th>lost runs</th>"
       "<th>worse than encoders only</th></tr>\n";
  const MethodResult* best = nullptr;
  for (const MethodResult& m : r.method_results) {
    const MethodSummary& s = m.summary;
    const Percentiles& c = s.converged.translation_m;
    const double convergence_s = median_convergence_s(s);  // as in the tables below
    const auto never = std::size_t(
        std::count(s.time_to_converge_s.begin(), s.time_to_converge_s.end(), std::nullopt));
    const std::size_t lost = s.lost_runs();
    std::string verdict;
    if (c.count == 0)
      verdict = "no converged window";
    else if (lost > 0)
      verdict = "<strong>lost</strong> in " + std::to_string(lost) + " of " +
                std::to_string(s.num_runs) + " runs";
    else if (never == s.time_to_converge_s.size())
      verdict = "never converged";
    else
      verdict = "tracks";
    if (c.count > 0 && lost == 0 && (!best || c.p50 < best->summary.converged.translation_m.p50))
      best = &m;
    o << "<tr><td class=\"m\">" << text::html_escape(m.method) << "</td><td>" << verdict
      << "</td><td>"
      << (c.count ? fixed(c.p50 * kMm, 1) + " / " + fixed(c.p99 * kMm, 1) : std::string("-"))
      << "</td><td>"
      << (std::isfinite(convergence_s) ? fixed(convergence_s, 1) + "&nbsp;s" +
                                             (never ? " (" + std::to_string(never) + " never)" : "")
                                       : std::string("never"))
      << "</td><td>" << lost << " of " << s.num_runs << "</td><td>"
      << (s.converged.reference.compared
              ? fixed(100.0 * s.converged.reference.share_worse(), 0) + "% of samples"
              : std::string("-"))
      << "</td></tr>\n";
  }
  o << "</table>\n<p>";
  if (best)
    o << "Best: <strong>" << text::html_escape(best->method)
      << "</strong> (the lowest converged median among the methods never lost).";
  else
    o << "No method was both converged and never lost.";
  o << " Converged: samples from " << fixed(r.scoring.converged_after_s, 1)
    << "&nbsp;s on, the worst end effector per sample.</p>\n";
}

void box_section(std::ostringstream& o, const ScenarioResult& r) {
  o << "<h2>End-effector errors per method</h2>\n";
  struct Quantity {
    const char* id;
    const char* name;
    const char* unit;
    double scale;
    Percentiles ErrorStats::*field;
  };
  const Quantity quantities[] = {
      {"translation", "Translation error", "translation error, mm", kMm,
       &ErrorStats::translation_m},
      {"rotation", "Angular error", "angular error, degrees", kDeg, &ErrorStats::rotation_rad}};
  std::ostringstream after;
  after << "from " << fixed(r.scoring.converged_after_s, 1) << " s on";
  for (const Quantity& q : quantities) {
    std::vector<Box> all, conv;
    std::vector<double> values;
    for (std::size_t i = 0; i < r.method_results.size(); ++i) {
      const MethodResult& m = r.method_results[i];
      const std::string c = method_colour(m.method, i);
      all.push_back({m.method, c, scaled(m.summary.all.*q.field, q.scale)});
      conv.push_back({m.method, c, scaled(m.summary.converged.*q.field, q.scale)});
      for (const Box* b : {&all.back(), &conv.back()})
        for (double v : {b->p.p01, b->p.p25, b->p.p50, b->p.p75, b->p.p99}) values.push_back(v);
    }
    // Both panels share the axis, so that they compare at a glance.
    const Axis axis = auto_axis(values, 7, true, 0, true);
    const std::size_t n_all = all.empty() ? 0 : all.front().p.count;
    const std::size_t n_conv = conv.empty() ? 0 : conv.front().p.count;
    const std::string name =
        std::string(q.name) +
        (r.end_effectors.size() > 1 ? " (worst of " + end_effector_list(r) + ")" : "");
    o << "<div class=\"two\">\n";
    box_plot(o, std::string("box-") + q.id + "-all",
             name + ", all samples (n = " + std::to_string(n_all) + " per method)", q.unit, all,
             axis);
    box_plot(o, std::string("box-") + q.id + "-converged",
             name + ", " + after.str() + " (n = " + std::to_string(n_conv) + ")", q.unit, conv,
             axis);
    o << "</div>\n";
  }
}

// A chart over the run's time axis, the frame every over-time chart shares.
LineChart time_chart(const ScenarioResult& r, const std::string& id, int height,
                     const std::string& y_label) {
  LineChart c;
  c.id = id;
  c.frame.width = 1160;
  c.frame.height = height;
  c.x_label = "time, s";
  c.y_label = y_label;
  c.include_zero = true;
  c.x_hi = r.duration_s > 0 ? r.duration_s : 1.0;
  return c;
}

void error_time_section(std::ostringstream& o, const ScenarioResult& r) {
  if (r.runs.empty()) return;
  LineChart c = time_chart(r, "error-time", 340, "translation error, mm");
  c.allow_log = true;
  const std::string ees = end_effector_list(r);
  const bool median = r.runs.size() > 1;
  for (std::size_t mi = 0; mi < r.methods.size(); ++mi) {
    Series s;
    s.name = r.methods[mi];
    s.colour = method_colour(s.name, mi);
    if (!median) {
      if (const MethodRun* m = method_run(r.runs[0], s.name))
        for (std::size_t i = 0; i < r.runs[0].truth.size() && i < m->samples.size(); ++i) {
          s.x.push_back(r.runs[0].truth[i].time_s);
          s.y.push_back(worst_translation_m(m->samples[i]) * kMm);
        }
    } else {
      // Runs are sampled at their own camera times: hold each run's last
      // sample on a common grid, then take the median across runs.
      const int n = 600;
      std::vector<std::size_t> cursor(r.runs.size(), 0);
      for (int g = 0; g <= n; ++g) {
        const double t = c.x_hi * g / n;
        std::vector<double> v;
        for (std::size_t k = 0; k < r.runs.size(); ++k) {
          const RunResult& run = r.runs[k];
          const MethodRun* m = method_run(run, s.name);
          if (!m) continue;
          std::size_t& i = cursor[k];
          while (i + 1 < run.truth.size() && i + 1 < m->samples.size() &&
                 run.truth[i + 1].time_s <= t)
            ++i;
          if (i < m->samples.size() && i < run.truth.size() && run.truth[i].time_s <= t)
            v.push_back(worst_translation_m(m->samples[i]) * kMm);
        }
        if (v.empty()) continue;
        s.x.push_back(t);
        s.y.push_back(median_of(v));
      }
    }
    c.series.push_back(std::move(s));
  }
  c.title = std::string("Translation error over time, ") +
            (median ? "median over " + std::to_string(r.runs.size()) + " runs" : "run 0") +
            (r.end_effectors.size() > 1 ? " (worst of " + ees + ")" : " (" + ees + ")");
  c.x_marks.push_back({r.scoring.converged_after_s, "converged window from here"});
  c.y_marks.push_back({r.scoring.convergence_threshold_m * kMm, "convergence threshold"});
  o << "<h2>Error over time</h2>\n";
  line_chart(o, c);
}

// The tracker's own verdict over time (TrackerEstimate::health, run 0): the
// share of the estimate's rendered robot that the image contradicts (sees
// through) and explains, and when it called itself lost.
void health_section(std::ostringstream& o, const ScenarioResult& r) {
  if (r.runs.empty()) return;
  const RunResult& run = r.runs[0];
  LineChart c = time_chart(r, "health-time", 300, "share of the estimate's robot pixels, %");
  c.min_span = 100;
  std::vector<std::string> lost;
  for (std::size_t mi = 0; mi < r.methods.size(); ++mi) {
    const MethodRun* m = method_run(run, r.methods[mi]);
    if (!m) continue;
    Series contradicted, explained, abandoned;
    contradicted.name = r.methods[mi] + ": contradicted";
    explained.name = r.methods[mi] + ": explained";
    abandoned.name = r.methods[mi] + ": abandoned";
    contradicted.colour = explained.colour = abandoned.colour = method_colour(r.methods[mi], mi);
    explained.stroke = Series::Stroke::kDashed;
    abandoned.stroke = Series::Stroke::kDotted;
    double lost_s = 0, previous_t = 0;
    bool any = false;
    for (std::size_t i = 0; i < run.truth.size() && i < m->samples.size(); ++i) {
      const TrackingHealth& h = m->samples[i].health;
      const double t = run.truth[i].time_s;
      if (h.state == TrackingHealth::State::kLost) lost_s += t - previous_t;
      previous_t = t;
      if (h.state == TrackingHealth::State::kNoImage) continue;
      any = true;
      contradicted.x.push_back(t);
      contradicted.y.push_back(100 * h.whole.contradicted_fraction);
      explained.x.push_back(t);
      explained.y.push_back(100 * h.whole.explained_fraction);
      abandoned.x.push_back(t);
      abandoned.y.push_back(100 * h.whole.abandoned_fraction);
    }
    if (!any) continue;
    std::ostringstream l;
    l << text::html_escape(r.methods[mi]) << ": lost for " << fixed(lost_s, 1) << " s";
    lost.push_back(l.str());
    c.series.push_back(std::move(contradicted));
    c.series.push_back(std::move(explained));
    c.series.push_back(std::move(abandoned));
  }
  if (c.series.empty()) return;
  c.title = "Health over time, run 0: the estimate's render against the image";
  o << "<h2>Tracker health</h2>\n<p>Solid: share of the estimate's rendered robot pixels that "
       "the camera sees through (contradicted); dashed: share within the explained depth; "
       "dotted: share of the pixels the estimate explained at its last good image that still "
       "show the same depth but are no longer explained (abandoned: an estimate that left a "
       "robot that did not move). "
    << "Lost (the tracker's own state): ";
  for (std::size_t i = 0; i < lost.size(); ++i) o << (i ? "; " : "") << lost[i];
  o << ".</p>\n";
  line_chart(o, c);
}

void bias_section(std::ostringstream& o, const ScenarioResult& r) {
  o << "<h2>Encoder bias: full_fusion's estimate against the truth (run 0)</h2>\n";
  const MethodRun* m = r.runs.empty() ? nullptr : method_run(r.runs[0], "full_fusion");
  if (!m) {
    o << "<p>full_fusion was not run: no bias estimate to show.</p>\n";
    return;
  }
  const std::string colour = method_colour("full_fusion", method_index(r, "full_fusion"));
  o << "<p><span class=\"key\" style=\"background:#000\"></span>true bias"
    << "<span class=\"key\" style=\"background:" << colour << "\"></span>estimate"
    << "<span class=\"key\" style=\"background:" << colour
    << ";opacity:0.3;height:10px\"></span>estimate &plusmn; one standard deviation; degrees.</p>\n";
  const RunResult& run = r.runs[0];
  o << "<div class=\"multi\">\n";
  for (std::size_t j = 0; j < r.joint_names.size(); ++j) {
    LineChart c;
    c.id = "bias-" + r.joint_names[j];
    c.title = r.joint_names[j];
    c.frame.width = 290;
    c.frame.height = 180;
    c.frame.left = 50;
    c.frame.right = 8;
    c.frame.top = 26;
    c.frame.bottom = 36;
    c.x_label = "time, s";
    c.y_label = "bias, deg";
    c.x_hi = r.duration_s > 0 ? r.duration_s : 1.0;
    c.min_span = 1.0;
    c.line_width = 1.2;  // the band (often narrow) stays visible
    c.legend = false;
    c.y_ticks = 5;
    c.x_ticks = 5;
    Series truth, est;
    truth.name = "true bias";
    truth.colour = "#000";
    truth.stroke = Series::Stroke::kDashed;
    est.name = "estimate";
    est.colour = colour;
    for (std::size_t i = 0; i < run.truth.size() && i < m->samples.size(); ++i) {
      const TruthSample& t = run.truth[i];
      const EstimateSample& s = m->samples[i];
      if (Eigen::Index(j) >= t.bias_rad.size() || Eigen::Index(j) >= s.bias_rad.size()) continue;
      truth.x.push_back(t.time_s);
      truth.y.push_back(t.bias_rad[j] * kDeg);
      est.x.push_back(t.time_s);
      est.y.push_back(s.bias_rad[j] * kDeg);
      const double sd = Eigen::Index(j) < s.bias_std_rad.size() ? s.bias_std_rad[j] : 0.0;
      est.band_lo.push_back((s.bias_rad[j] - sd) * kDeg);
      est.band_hi.push_back((s.bias_rad[j] + sd) * kDeg);
    }
    c.series = {std::move(est), std::move(truth)};
    line_chart(o, c);
  }
  o << "</div>\n";
}

void camera_section(std::ostringstream& o, const ScenarioResult& r) {
  o << "<h2>Camera offset estimates (run 0)</h2>\n";
  std::vector<std::pair<std::size_t, const MethodRun*>> methods;
  if (!r.runs.empty())
    for (std::size_t i = 0; i < r.methods.size(); ++i)
      if (r.methods[i] != "encoders_only")  // every other method estimates the virtual joints
        if (const MethodRun* m = method_run(r.runs[0], r.methods[i])) methods.push_back({i, m});
  if (methods.empty()) {
    o << "<p>No method that estimates the camera offset was run.</p>\n";
    return;
  }
  o << "<p>The virtual camera joints (translation, then roll, pitch, yaw about the nominal "
       "camera frame's axes) as each method estimates them:";
  for (const auto& [i, m] : methods)
    o << "<span class=\"key\" style=\"background:" << method_colour(m->method, i) << "\"></span>"
      << text::html_escape(m->method);
  o << ". The true offset is the scenario's miscalibration (not part of the run's results).</p>\n";
  const char* names[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
  o << "<div class=\"three\">\n";
  for (int k = 0; k < 6; ++k) {
    const bool translation = k < 3;
    LineChart c;
    c.id = std::string("camera-") + names[k];
    c.title = std::string("camera ") + names[k];
    c.frame.width = 385;
    c.frame.height = 200;
    c.frame.left = 56;
    c.frame.right = 8;
    c.frame.top = 26;
    c.frame.bottom = 36;
    c.x_label = "time, s";
    c.y_label = translation ? "offset, mm" : "offset, deg";
    c.x_hi = r.duration_s > 0 ? r.duration_s : 1.0;
    c.min_span = translation ? 2.0 : 0.2;
    c.legend = false;
    c.y_ticks = 5;
    c.x_ticks = 5;
    for (const auto& [i, m] : methods) {
      Series s;
      s.name = m->method;
      s.colour = method_colour(m->method, i);
      for (std::size_t n = 0; n < r.runs[0].truth.size() && n < m->samples.size(); ++n) {
        s.x.push_back(r.runs[0].truth[n].time_s);
        s.y.push_back(m->samples[n].camera_offset[k] * (translation ? kMm : kDeg));
      }
      c.series.push_back(std::move(s));
    }
    line_chart(o, c);
  }
  o << "</div>\n";
}

void frames_section(std::ostringstream& o, const ScenarioResult& r) {
  o << "<h2>Kept depth frames</h2>\n";
  if (r.frames.empty()) {
    o << "<p>No depth frame was kept.</p>\n";
    return;
  }
  o << "<p>The depth image the trackers received (false colour: near red, far blue; black: no "
       "return), with the silhouette of the estimate rendered right after the tracker applied "
       "it drawn in white.</p>\n<div class=\"two\">\n";
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const KeptFrame& k = r.frames[i];
    o << "<figure>";
    if (k.observed.width > 0 && k.observed.height > 0 && !k.observed.empty()) {
      const auto [near_m, far_m] = depth_range(k.observed, k.estimate);
      const std::vector<std::uint8_t> rgb = overlay_rgb(k.observed, k.estimate, near_m, far_m);
      const std::vector<std::uint8_t> png =
          encode_png_rgb(k.observed.width, k.observed.height, rgb);
      o << "<img alt=\"depth frame " << i << "\" width=\"" << k.observed.width << "\" height=\""
        << k.observed.height << "\" src=\"data:image/png;base64," << base64_encode(png) << "\">\n";
      colour_bar(o, "colours-" + std::to_string(i), near_m, far_m);
    }
    o << "<figcaption>Frame " << i << ": captured at t = " << fixed(k.stamp_s, 2)
      << " s, reached the trackers at " << fixed(k.arrival_s, 2) << " s (run " << k.run << "); "
      << (k.estimate.empty() ? std::string("no estimate rendered")
                             : "white: the " + text::html_escape(k.estimate_method) + " estimate")
      << ".</figcaption></figure>\n";
  }
  o << "</div>\n";
}

// Runs in which an end effector is lost.
std::size_t lost_count(const EndEffectorSummary& e) {
  return std::size_t(
      std::count_if(e.lost.begin(), e.lost.end(), [](const auto& l) { return l.has_value(); }));
}

// "12.3%", or "not estimated".
std::string coverage_cell(const Coverage& c) {
  return c.estimated ? fixed(100.0 * c.fraction(), 1) + "%" : std::string("not estimated");
}

void lost_and_consistency_section(std::ostringstream& o, const ScenarioResult& r) {
  o << "<h2>Lost runs, consistency and the camera</h2>\n<p>A run is <em>lost</em> for a method "
       "when an end effector's translation error stays above "
    << fixed(r.scoring.lost_threshold_m * kMm, 1) << "&nbsp;mm for more than "
    << significant(r.scoring.lost_after_s) << "&nbsp;s from "
    << fixed(r.scoring.converged_after_s, 1)
    << "&nbsp;s on. <em>Within 2&sigma;</em>: the share of samples (all of them, every joint or "
       "virtual camera joint) whose true value lies within two of the standard deviations the "
       "method reports; about 95% for an honest filter, far less for an overconfident one. The "
       "true camera offset is the one that puts the nominal model's camera, at the true joint "
       "angles, on the simulator's camera. <em>Camera frame</em>: the estimated camera frame "
       "(the nominal model at the estimated angles and camera offset) against the true one, "
       "relative to the robot base.</p>\n";
  o << "<table><tr><th class=\"m\" rowspan=\"2\">method</th><th rowspan=\"2\">lost runs</th>"
       "<th colspan=\"3\">within 2&sigma;</th><th colspan=\"2\">camera frame, mm</th>"
       "<th colspan=\"2\">camera frame, deg</th></tr><tr><th>angles</th><th>biases</th>"
       "<th>camera offset</th><th>p50</th><th>p99</th><th>p50</th><th>p99</th></tr>\n";
  for (const MethodResult& m : r.method_results) {
    const ErrorStats& s = m.summary.all;
    o << "<tr><td class=\"m\">" << text::html_escape(m.method) << "</td><td>"
      << m.summary.lost_runs() << " of " << m.summary.num_runs << "</td><td>"
      << coverage_cell(s.angle_coverage) << "</td><td>" << coverage_cell(s.bias_coverage)
      << "</td><td>" << coverage_cell(s.camera_offset_coverage) << "</td><td>"
      << fixed(s.camera_translation_m.p50 * kMm, 2) << "</td><td>"
      << fixed(s.camera_translation_m.p99 * kMm, 2) << "</td><td>"
      << fixed(s.camera_rotation_rad.p50 * kDeg, 3) << "</td><td>"
      << fixed(s.camera_rotation_rad.p99 * kDeg, 3) << "</td></tr>\n";
  }
  o << "</table>\n";
  std::ostringstream list;
  for (const MethodResult& m : r.method_results)
    for (std::size_t run = 0; run < m.summary.num_runs; ++run)
      for (const EndEffectorSummary& e : m.summary.end_effectors)
        if (run < e.lost.size() && e.lost[run])
          list << "<li>" << text::html_escape(m.method) << ": run " << run
               << (run < r.seeds.size() ? " (seed " + std::to_string(r.seeds[run]) + ")" : "")
               << ", " << text::html_escape(e.name) << ", from " << fixed(e.lost[run]->from_s, 2)
               << "&nbsp;s for " << fixed(e.lost[run]->duration_s, 2) << "&nbsp;s</li>\n";
  if (!list.str().empty()) o << "<p>Lost:</p><ul class=\"lost\">\n" << list.str() << "</ul>\n";
}

void table_section(std::ostringstream& o, const ScenarioResult& r) {
  const bool several = r.end_effectors.size() > 1;
  o << "<h2>Summary</h2>\n<p>The numbers of summary.json, in millimetres and degrees "
       "(percentiles pooled over runs)"
    << (several ? "; per end effector, and the worst of them (per sample, the larger error)" : "")
    << ".</p>\n";
  std::ostringstream after;
  after << "from " << fixed(r.scoring.converged_after_s, 1) << " s on";
  const char* pct[5] = {"p1", "p25", "p50", "p75", "p99"};
  for (int part = 0; part < 2; ++part) {
    o << "<table><tr><th class=\"m\" rowspan=\"2\">method</th>";
    if (several) o << "<th class=\"m\" rowspan=\"2\">end effector</th>";
    o << "<th colspan=\"5\">translation, mm, " << (part ? after.str() : "all samples")
      << "</th><th colspan=\"5\">rotation, deg, " << (part ? after.str() : "all samples")
      << "</th><th rowspan=\"2\">samples</th>";
    if (part)
      o << "<th rowspan=\"2\">converged after, s<br>(median of runs; below "
        << fixed(r.scoring.convergence_threshold_m * kMm, 1)
        << " mm)</th><th rowspan=\"2\">worse than<br>encoders_only</th><th "
           "rowspan=\"2\">lost runs</th>";
    o << "</tr><tr>";
    for (int k = 0; k < 2; ++k)
      for (const char* p : pct) o << "<th>" << p << "</th>";
    o << "</tr>\n";
    auto row = [&](const std::string& method, const std::string* ee, const ErrorStats& s,
                   double conv, std::size_t lost, std::size_t runs) {
      o << "<tr><td class=\"m\">" << text::html_escape(method) << "</td>";
      if (ee) o << "<td class=\"m\">" << text::html_escape(*ee) << "</td>";
      const Percentiles& t = s.translation_m;
      for (double v : {t.p01, t.p25, t.p50, t.p75, t.p99})
        o << "<td>" << fixed(v * kMm, 2) << "</td>";
      const Percentiles& a = s.rotation_rad;
      for (double v : {a.p01, a.p25, a.p50, a.p75, a.p99})
        o << "<td>" << fixed(v * kDeg, 3) << "</td>";
      o << "<td>" << t.count << "</td>";
      if (part)
        o << "<td>" << (std::isfinite(conv) ? fixed(conv, 1) : std::string("never")) << "</td><td>"
          << (s.reference.compared ? fixed(100.0 * s.reference.share_worse(), 0) + "%"
                                   : std::string("&ndash;"))
          << "</td><td>" << lost << " of " << runs << "</td>";
      o << "</tr>\n";
    };
    static const std::string kWorst = "worst";
    for (const MethodResult& m : r.method_results) {
      const MethodSummary& sm = m.summary;
      if (several)
        for (const EndEffectorSummary& e : sm.end_effectors)
          row(m.method, &e.name, part ? e.converged : e.all,
              median_convergence_s(e.time_to_converge_s), lost_count(e), sm.num_runs);
      row(m.method, several ? &kWorst : nullptr, part ? sm.converged : sm.all,
          median_convergence_s(sm), sm.lost_runs(), sm.num_runs);
    }
    o << "</table>\n";
  }
  lost_and_consistency_section(o, r);
  o << "<h2>Timing</h2>\n<p>Wall time of each tracker call on this machine (summary.json reports "
       "full_fusion's, else the first method's). Speed figures belong to the benchmarks; these "
       "only show where the time went in this run.</p>\n"
       "<table><tr><th class=\"m\" rowspan=\"2\">method</th><th colspan=\"2\">joint update, "
       "&micro;s</th><th colspan=\"2\">image update, ms</th><th rowspan=\"2\">evaluations<br>per "
       "image</th><th rowspan=\"2\">images<br>received</th><th rowspan=\"2\">applied</th><th "
       "rowspan=\"2\">dropped</th></tr><tr><th>p50</th><th>p99</th><th>p50</th><th>p99</th></tr>\n";
  for (const MethodResult& m : r.method_results) {
    long received = 0, applied = 0, dropped = 0;
    for (const RunResult& run : r.runs)
      if (const MethodRun* mr = method_run(run, m.method)) {
        received += mr->stats.images_received;
        applied += mr->stats.images_applied;
        dropped += mr->stats.images_dropped_too_old + mr->stats.images_dropped_backlog +
                   mr->stats.images_dropped_busy;
      }
    const MethodTiming& t = m.timing;
    o << "<tr><td class=\"m\">" << text::html_escape(m.method) << "</td><td>"
      << fixed(t.joint_update_us.p50, 2) << "</td><td>" << fixed(t.joint_update_us.p99, 2)
      << "</td><td>" << fixed(t.image_update_ms.p50, 2) << "</td><td>"
      << fixed(t.image_update_ms.p99, 2) << "</td><td>" << fixed(t.evaluations_per_image, 0)
      << "</td><td>" << received << "</td><td>" << applied << "</td><td>" << dropped
      << "</td></tr>\n";
  }
  o << "</table>\n";
  // The JSON itself, folded (no script needed): its text has no & < >.
  std::string json = summary_json(r);
  std::string escaped;
  for (char c : json)
    escaped += c == '&' ? "&amp;" : c == '<' ? "&lt;" : c == '>' ? "&gt;" : std::string(1, c);
  o << "<details><summary>summary.json</summary><pre>" << escaped << "</pre></details>\n";
}

}  // namespace

std::vector<double> round_ticks(double lo, double hi, int max_ticks) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return {0.0, 1.0};
  if (hi < lo) std::swap(lo, hi);
  if (hi == lo) {
    const double d = lo == 0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= d;
    hi += d;
  }
  max_ticks = std::max(max_ticks, 2);
  // The smallest 1-2-5 step giving at most max_ticks + 1 ticks once widened.
  const double mag = std::pow(10.0, std::floor(std::log10((hi - lo) / (max_ticks - 1))));
  std::vector<double> ticks;
  for (double m : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0}) {
    const double step = m * mag;
    // Integer multiples of the step (no accumulated rounding), covering [lo, hi].
    const double k0 = std::floor(lo / step + 1e-9), k1 = std::ceil(hi / step - 1e-9);
    if (k1 - k0 + 1 > max_ticks + 1 && m < 100.0) continue;
    for (double k = k0; k <= k1 + 0.5; k += 1) ticks.push_back(k == 0 ? 0.0 : k * step);
    break;
  }
  return ticks;
}

std::string base64_encode(std::span<const std::uint8_t> bytes) {
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

std::vector<std::uint8_t> encode_png_rgb(int width, int height, std::span<const std::uint8_t> rgb) {
  if (width <= 0 || height <= 0) throw InputError("PNG encoding: empty image");
  if (rgb.size() != std::size_t(width) * std::size_t(height) * 3)
    throw InputError("PNG encoding: " + std::to_string(rgb.size()) + " bytes for a " +
                     std::to_string(width) + "x" + std::to_string(height) + " RGB image");
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (int v = 0; v < height; ++v)
    rows[std::size_t(v)] = const_cast<png_bytep>(rgb.data() + std::size_t(v) * width * 3);
  std::vector<std::uint8_t> out;
  PngSink sink;
  sink.out = &out;
  if (!write_png_rows(width, height, rows.data(), &sink))
    throw InputError(std::string("PNG encoding failed: ") + sink.message);
  return out;
}

std::string report_html(const ScenarioResult& r) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
    << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
    << "<title>arttrack: " << text::html_escape(r.scenario) << "</title>\n"
    << kStyle << "</head><body><main>\n";
  header(o, r);
  verdict_section(o, r);
  box_section(o, r);
  error_time_section(o, r);
  health_section(o, r);
  bias_section(o, r);
  camera_section(o, r);
  frames_section(o, r);
  table_section(o, r);
  o << "</main></body></html>\n";
  return o.str();
}

void write_report_html(const fs::path& file, const ScenarioResult& result) {
  const std::string html = report_html(result);
  std::ofstream out(file, std::ios::binary);
  out << html;
  out.close();
  if (!out) throw InputError(file.string() + ": cannot write the report");
}

}  // namespace arttrack::sim
