#include "arttrack/sim/internal/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <sstream>

#include "arttrack/sim/internal/text_format.h"
#include "arttrack/tracker/internal/non_finite.h"

namespace arttrack::sim::chart {

namespace {

// Average advance of a character of the 11 px tick and legend font, px:
// enough to lay out legends and thin tick labels without measuring text.
constexpr double kCharPx = 6.8;
constexpr double kLegendRowPx = 18;

std::string esc(const std::string& s) { return text::html_escape(s); }

// The dash pattern of a stroke, as an attribute (Stroke order).
const char* dash_attribute(Stroke stroke) {
  static const char* const kDash[] = {
      "", " stroke-dasharray=\"6 4\"", " stroke-dasharray=\"1.5 3\"",
      " stroke-dasharray=\"8 3 1.5 3\"", " stroke-dasharray=\"8 3 1.5 3 1.5 3\""};
  return kDash[int(stroke)];
}

void line(std::ostream& o, double x1, double y1, double x2, double y2, const std::string& attrs) {
  o << "<line x1=\"" << px(x1) << "\" y1=\"" << px(y1) << "\" x2=\"" << px(x2) << "\" y2=\""
    << px(y2) << "\" " << attrs << "/>";
}

void rect(std::ostream& o, double x, double y, double w, double h, const std::string& attrs) {
  o << "<rect x=\"" << px(x) << "\" y=\"" << px(y) << "\" width=\"" << px(w) << "\" height=\""
    << px(h) << "\" " << attrs;
}

// A grey cell or swatch crossed out.
void cross(std::ostream& o, double x, double y, double w, double h) {
  o << "<path d=\"M" << px(x + 3) << ' ' << px(y + 3) << " L" << px(x + w - 3) << ' '
    << px(y + h - 3) << " M" << px(x + w - 3) << ' ' << px(y + 3) << " L" << px(x + 3) << ' '
    << px(y + h - 3) << "\" stroke=\"#666\" stroke-width=\"1.2\"/>";
}

double entry_width(const LegendEntry& e) { return 26 + kCharPx * double(e.name.size()) + 16; }

// The sample of a legend entry, 20 x 12 px with its left at x, centred on y.
void legend_mark(std::ostream& o, const LegendEntry& e, double x, double y) {
  switch (e.mark) {
    case Mark::kLine:
      line(o, x, y, x + 20, y,
           "stroke=\"" + e.colour + "\" stroke-width=\"2.5\"" + dash_attribute(e.stroke));
      break;
    case Mark::kDots:
      o << "<circle cx=\"" << px(x + 10) << "\" cy=\"" << px(y) << "\" r=\"3.5\" fill=\""
        << e.colour << "\"/>";
      break;
    case Mark::kRing:
      o << "<circle cx=\"" << px(x + 10) << "\" cy=\"" << px(y) << "\" r=\"5.5\" fill=\"none\" "
        << "stroke=\"" << e.colour << "\" stroke-width=\"2\"/>";
      break;
    case Mark::kBand:
      rect(o, x, y - 6, 20, 12, "fill=\"" + e.colour + "\" fill-opacity=\"0.25\"/>");
      break;
    case Mark::kSwatch:
      rect(o, x + 2, y - 7, 16, 14, "fill=\"" + e.colour + "\"/>");
      break;
    case Mark::kOutline:
      rect(o, x + 3, y - 6, 14, 12,
           "fill=\"none\" stroke=\"" + e.colour + "\" stroke-width=\"2\"/>");
      break;
    case Mark::kCross:
      rect(o, x + 2, y - 7, 16, 14, "fill=\"#bbb\"/>");
      cross(o, x + 2, y - 7, 16, 14);
      break;
    case Mark::kDashedBox:
      rect(o, x + 2, y - 7, 16, 14, "fill=\"#fff\" stroke=\"#aaa\" stroke-dasharray=\"2 2\"/>");
      break;
  }
}

}  // namespace

// ---------------------------------------------------------------- the page

const char kPageCss[] =
    R"(body{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif;font-size:14px;color:#222;margin:0;background:#fff}
main{max-width:1200px;margin:0 auto;padding:12px 16px}
h1{font-size:22px;margin:8px 0}h2{font-size:18px;margin:22px 0 6px;border-bottom:1px solid #ccc}
h3{font-size:15px;margin:16px 0 4px}
p.read{background:#f4f6f8;padding:6px 10px;border-left:3px solid #789}
p.warn{background:#fff4e5;padding:6px 10px;border-left:3px solid #d80}
dl.meta{display:grid;grid-template-columns:max-content 1fr;gap:2px 14px;margin:6px 0}
dl.meta dt{font-weight:bold}dl.meta dd{margin:0}
.one{max-width:760px}
.two{display:grid;grid-template-columns:1fr 1fr;gap:10px}
.multi{display:grid;grid-template-columns:repeat(4,1fr);gap:6px}
.three{display:grid;grid-template-columns:repeat(3,1fr);gap:6px}
.maps{display:flex;flex-wrap:wrap;gap:14px 28px;align-items:flex-start;margin:4px 0 10px}
.maps h4{font-size:14px;margin:6px 0 2px}
svg.chart,svg.bar{width:100%;height:auto;display:block}
svg.heat,svg.legend{display:block;max-width:100%;height:auto}
svg text{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif}
.ct{font-size:13px;font-weight:bold}.tl{font-size:11px;fill:#333}.al{font-size:12px;fill:#222}
.val{font-size:11px;fill:#111}.note{font-size:10px;fill:#555;paint-order:stroke;stroke:#fff;stroke-width:3px}
.hv{font-size:12px}.hk{font-size:12px;fill:#333}
.grid{stroke:#e3e3e3;stroke-width:1}.axis{stroke:#444;stroke-width:1}
.mark{stroke:#777;stroke-width:1;stroke-dasharray:4 3}
figure{margin:0}figure img{width:100%;height:auto;image-rendering:pixelated;display:block;border:1px solid #999}
figcaption{font-size:13px;margin:3px 0 10px}
table{border-collapse:collapse;font-size:13px;margin:6px 0}
th,td{border:1px solid #ccc;padding:2px 6px;text-align:right}th{background:#f0f0f0}
td.m,th.m{text-align:left}
.key{display:inline-block;width:18px;height:4px;vertical-align:middle;margin:0 4px 0 12px}
.better{color:#070}.worse,.fail{color:#b00}
details>summary{font-weight:bold;cursor:pointer;margin-top:8px}
code{font-size:13px}
pre{font-size:11px;background:#f8f8f8;padding:6px;overflow:auto}
)";

std::string page_start(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
         "<title>" +
         esc(title) + "</title>\n<style>\n" + kPageCss + "</style>\n</head><body><main>\n";
}

std::string page_end() { return "</main></body></html>\n"; }

// ---------------------------------------------------------------- numbers

std::string px(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", v);
  return std::string(buf) == "-0.0" ? "0.0" : buf;
}

std::string fixed(double v, int decimals) {
  if (std::isnan(v)) return "&ndash;";
  if (std::isinf(v)) return v > 0 ? "&infin;" : "-&infin;";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  if (std::string(buf).find_first_not_of("-0.") == std::string::npos && buf[0] == '-')
    return std::string(buf + 1);  // no "-0.00"
  return buf;
}

std::string significant(double v) {
  if (!std::isfinite(v) || v == 0) return fixed(v, 0);
  return fixed(v, std::clamp(2 - int(std::floor(std::log10(std::abs(v)))), 0, 4));
}

// ---------------------------------------------------------------- axes

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

double Axis::map(double v) const {
  double t;
  if (log) {
    v = std::max(v, lo);
    t = (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
  } else {
    t = (v - lo) / (hi - lo);
  }
  return px_lo + std::clamp(t, -0.02, 1.02) * (px_hi - px_lo);
}

std::string Axis::label(double v) const {
  const double unit = log ? v : step;
  return fixed(v, std::max(0, int(-std::floor(std::log10(unit) + 1e-9))));
}

Axis linear_axis(double lo, double hi, int max_ticks, bool widen) {
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

Axis log_axis(double lo, double hi) {
  Axis a;
  a.log = true;
  const int d0 = int(std::floor(std::log10(lo) + 1e-9));
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

// ---------------------------------------------------------------- pieces

void svg_open(std::ostream& o, const Frame& f, const std::string& id, const std::string& title,
              const std::string& css_class) {
  o << "<svg class=\"" << css_class << "\" data-chart=\"" << esc(id) << "\" viewBox=\"0 0 "
    << px(f.width) << ' ' << px(f.height) << "\" width=\"" << px(f.width) << "\" height=\""
    << px(f.height) << "\" role=\"img\"><title>" << esc(title) << "</title>\n";
  if (!title.empty())
    o << "<text class=\"ct\" x=\"" << px(f.left) << "\" y=\"18\">" << esc(title) << "</text>\n";
}

void y_axis(std::ostream& o, const Frame& f, const Axis& a, const std::string& label) {
  for (double t : a.ticks) {
    const double y = a.map(t);
    line(o, f.x0(), y, f.x1(), y, "class=\"grid\"");
    o << "<text class=\"tl\" x=\"" << px(f.x0() - 5) << "\" y=\"" << px(y + 4)
      << "\" text-anchor=\"end\">" << a.label(t) << "</text>\n";
  }
  const double ym = 0.5 * (f.y0() + f.y1());
  o << "<text class=\"al\" transform=\"translate(13," << px(ym)
    << ") rotate(-90)\" text-anchor=\"middle\">" << esc(label) << (a.log ? " (log scale)" : "")
    << "</text>\n";
  line(o, f.x0(), f.y0(), f.x0(), f.y1(), "class=\"axis\"");
  o << "\n";
}

void x_axis(std::ostream& o, const Frame& f, const Axis& a, const std::string& label) {
  for (double t : a.ticks) {
    const double x = a.map(t);
    line(o, x, f.y0(), x, f.y1(), "class=\"grid\"");
    o << "<text class=\"tl\" x=\"" << px(x) << "\" y=\"" << px(f.y0() + 15)
      << "\" text-anchor=\"middle\">" << a.label(t) << "</text>\n";
  }
  line(o, f.x0(), f.y0(), f.x1(), f.y0(), "class=\"axis\"");
  o << "\n";
  if (!label.empty())
    o << "<text class=\"al\" x=\"" << px(0.5 * (f.x0() + f.x1())) << "\" y=\"" << px(f.height - 6)
      << "\" text-anchor=\"middle\">" << esc(label) << (a.log ? " (log scale)" : "") << "</text>\n";
}

int legend_row_count(const std::vector<LegendEntry>& entries, double x, double x_max) {
  int rows = entries.empty() ? 0 : 1;
  double at = x;
  for (const LegendEntry& e : entries) {
    if (at > x && at + entry_width(e) > x_max) {
      ++rows;
      at = x;
    }
    at += entry_width(e);
  }
  return rows;
}

int legend_rows(std::ostream& o, const std::vector<LegendEntry>& entries, double x, double y,
                double x_max) {
  int rows = entries.empty() ? 0 : 1;
  double at = x;
  o << "<g class=\"legend\">";
  for (const LegendEntry& e : entries) {
    if (at > x && at + entry_width(e) > x_max) {
      ++rows;
      at = x;
      y += kLegendRowPx;
    }
    legend_mark(o, e, at, y - 4);
    o << "<text class=\"tl\" x=\"" << px(at + 25) << "\" y=\"" << px(y) << "\">" << esc(e.name)
      << "</text>";
    at += entry_width(e);
  }
  o << "</g>\n";
  return rows;
}

void legend(std::ostream& o, const std::string& id, const std::vector<LegendEntry>& entries,
            double width) {
  const int rows = legend_row_count(entries, 4, width - 4);
  const double height = 8 + kLegendRowPx * rows;
  o << "<svg class=\"legend\" data-chart=\"" << esc(id) << "\" viewBox=\"0 0 " << px(width) << ' '
    << px(height) << "\" width=\"" << px(width) << "\" height=\"" << px(height)
    << "\" role=\"img\"><title>legend</title>";
  legend_rows(o, entries, 4, 16, width - 4);
  o << "</svg>\n";
}

// ---------------------------------------------------------------- line charts

LegendEntry legend_entry(const Series& s) { return {s.name, s.colour, s.mark, s.stroke}; }

namespace {

// Per pixel column, the indices of the smallest and largest y in time order:
// the polyline looks the same as with every point, at a bounded size.
std::vector<std::size_t> decimate(const std::vector<double>& xs, const std::vector<double>& ys,
                                  const Axis& xa, const Axis& ya) {
  std::vector<std::size_t> keep;
  const std::size_t n = std::min(xs.size(), ys.size());
  const double columns = std::abs(xa.px_hi - xa.px_lo);
  if (n <= 2 * columns) {
    for (std::size_t i = 0; i < n; ++i) keep.push_back(i);
    return keep;
  }
  std::size_t i = 0;
  while (i < n) {
    const long col = std::lround(xa.map(xs[i]));
    std::size_t lo = i, hi = i, j = i;
    bool finite = true;
    for (; j < n && std::lround(xa.map(xs[j])) == col; ++j) {
      if (!std::isfinite(ys[j])) finite = false;
      if (ya.map(ys[j]) < ya.map(ys[lo])) lo = j;  // pixel y grows downwards
      if (ya.map(ys[j]) > ya.map(ys[hi])) hi = j;
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

void band(std::ostream& o, const Series& s, const Axis& xa, const Axis& ya) {
  std::ostringstream d;
  bool open = false;
  for (std::size_t i : decimate(s.x, s.band_hi, xa, ya))
    if (std::isfinite(s.band_hi[i])) {
      d << (open ? " L" : "M") << px(xa.map(s.x[i])) << ' ' << px(ya.map(s.band_hi[i]));
      open = true;
    }
  const std::vector<std::size_t> kl = decimate(s.x, s.band_lo, xa, ya);
  for (auto it = kl.rbegin(); it != kl.rend(); ++it)
    if (std::isfinite(s.band_lo[*it]))
      d << (open ? " L" : "M") << px(xa.map(s.x[*it])) << ' ' << px(ya.map(s.band_lo[*it]));
  if (open)
    o << "<path d=\"" << d.str() << " Z\" fill=\"" << s.colour
      << "\" fill-opacity=\"0.2\" stroke=\"none\"/>\n";
}

void series_points(std::ostream& o, const Series& s, const Axis& xa, const Axis& ya) {
  for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
    if (!std::isfinite(s.y[i])) continue;
    o << "<circle cx=\"" << px(xa.map(s.x[i])) << "\" cy=\"" << px(ya.map(s.y[i]));
    if (s.mark == Mark::kRing)
      o << "\" r=\"5.5\" fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\"2\"/>";
    else
      o << "\" r=\"3.5\" fill=\"" << s.colour << "\"/>";
  }
  o << "\n";
}

void series_line(std::ostream& o, const Series& s, const Axis& xa, const Axis& ya, double width) {
  std::ostringstream d;
  bool open = false;
  for (std::size_t i : decimate(s.x, s.y, xa, ya)) {
    if (!std::isfinite(s.y[i])) {
      open = false;  // a gap: lost estimate or no value
      continue;
    }
    d << (open ? " L" : " M") << px(xa.map(s.x[i])) << ' ' << px(ya.map(s.y[i]));
    open = true;
  }
  if (d.str().empty()) return;
  o << "<path d=\"" << d.str() << "\" fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\""
    << px(width) << "\" stroke-linejoin=\"round\"" << dash_attribute(s.stroke) << "/>\n";
}

}  // namespace

void line_chart(std::ostream& o, const LineChart& c) {
  Frame f = c.frame;
  std::vector<LegendEntry> entries;
  if (c.legend)
    for (const Series& s : c.series) entries.push_back(legend_entry(s));
  const int rows = legend_row_count(entries, f.x0(), f.x1());
  f.top += kLegendRowPx * rows;

  std::vector<double> ys = c.y_axis_values;
  if (ys.empty()) {
    for (const Series& s : c.series) {
      ys.insert(ys.end(), s.y.begin(), s.y.end());
      ys.insert(ys.end(), s.band_lo.begin(), s.band_lo.end());
      ys.insert(ys.end(), s.band_hi.begin(), s.band_hi.end());
    }
    for (const auto& m : c.y_marks) ys.push_back(m.first);
  }
  Axis ya = auto_axis(ys, c.y_ticks, c.allow_log, c.min_span, c.include_zero);
  ya.px_lo = f.y0();
  ya.px_hi = f.y1();
  // Room on the left for the longest tick label and the rotated axis label.
  std::size_t longest = 0;
  for (double t : ya.ticks) longest = std::max(longest, ya.label(t).size());
  f.left = std::max(f.left, 30 + kCharPx * double(longest));
  Axis xa = linear_axis(c.x_lo, c.x_hi, c.x_ticks, false);
  if (c.integer_x) {
    std::erase_if(xa.ticks, [](double t) { return std::abs(t - std::round(t)) > 1e-9; });
    xa.step = std::max(xa.step, 1.0);  // labels without decimals
  }
  xa.px_lo = f.x0();
  xa.px_hi = f.x1();

  svg_open(o, f, c.id, c.title);
  if (rows) legend_rows(o, entries, f.x0(), 18 + kLegendRowPx, f.x1());
  y_axis(o, f, ya, c.y_label);
  x_axis(o, f, xa, c.x_label);
  // Reference lines under the data, their labels over it.
  std::ostringstream labels;
  const auto outside = [](const Axis& a, double v) { return !(v >= a.lo && v <= a.hi); };
  for (const auto& [x, text] : c.x_marks) {
    if (outside(xa, x)) continue;
    const double X = xa.map(x);
    line(o, X, f.y0(), X, f.y1(), "class=\"mark\"");
    o << "\n";
    labels << "<text class=\"note\" x=\"" << px(X + 3) << "\" y=\"" << px(f.y1() + 11) << "\">"
           << esc(text) << "</text>\n";
  }
  for (const auto& [y, text] : c.y_marks) {
    if (outside(ya, y)) continue;
    const double Y = ya.map(y);
    line(o, f.x0(), Y, f.x1(), Y, "class=\"mark\"");
    o << "\n";
    labels << "<text class=\"note\" x=\"" << px(f.x1() - 3) << "\" y=\"" << px(Y - 3)
           << "\" text-anchor=\"end\">" << esc(text) << "</text>\n";
  }
  o << "<clipPath id=\"clip-" << esc(c.id) << "\"><rect x=\"" << px(f.x0() - 6) << "\" y=\""
    << px(f.y1() - 6) << "\" width=\"" << px(f.x1() - f.x0() + 12) << "\" height=\""
    << px(f.y0() - f.y1() + 12) << "\"/></clipPath><g clip-path=\"url(#clip-" << esc(c.id)
    << ")\">\n";
  // Bands first, lines over them, points on top.
  for (const Series& s : c.series)
    if (!s.band_lo.empty()) band(o, s, xa, ya);
  for (const Series& s : c.series)
    if (s.mark == Mark::kLine) series_line(o, s, xa, ya, c.line_width);
  for (const Series& s : c.series)
    if (s.mark == Mark::kDots || s.mark == Mark::kRing) series_points(o, s, xa, ya);
  o << "</g>\n" << labels.str() << "</svg>\n";
}

// ---------------------------------------------------------------- box plots

void box_plot(std::ostream& o, const std::string& id, const std::string& title,
              const std::string& y_label, const std::vector<Box>& boxes, Axis axis) {
  Frame f;
  f.height = 320;
  f.bottom = 28;
  svg_open(o, f, id, title);
  axis.px_lo = f.y0();
  axis.px_hi = f.y1();
  y_axis(o, f, axis, y_label);
  line(o, f.x0(), f.y0(), f.x1(), f.y0(), "class=\"axis\"");
  o << "\n";
  const double slot = (f.x1() - f.x0()) / double(std::max<std::size_t>(1, boxes.size()));
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    const double xc = f.x0() + (double(i) + 0.5) * slot;
    const double half = std::min(28.0, 0.22 * slot);
    o << "<text class=\"tl\" x=\"" << px(xc) << "\" y=\"" << px(f.y0() + 16)
      << "\" text-anchor=\"middle\">" << esc(b.name) << "</text>\n";
    if (b.count == 0 || std::isnan(b.p50)) {
      o << "<text class=\"note\" x=\"" << px(xc) << "\" y=\"" << px(0.5 * (f.y0() + f.y1()))
        << "\" text-anchor=\"middle\">no samples</text>\n";
      continue;
    }
    auto y = [&](double v) { return std::isinf(v) ? f.y1() : axis.map(v); };
    const std::string& c = b.colour;
    o << "<g stroke=\"" << c << "\" stroke-width=\"1.5\">";
    line(o, xc, y(b.p01), xc, y(b.p99), "");
    for (double v : {b.p01, b.p99})
      if (std::isfinite(v)) line(o, xc - 0.6 * half, y(v), xc + 0.6 * half, y(v), "");
    const double top = y(b.p75), bottom = y(b.p25);
    rect(o, xc - half, top, 2 * half, std::max(1.0, bottom - top),
         "fill=\"" + c + "\" fill-opacity=\"0.3\"/>");
    line(o, xc - half, y(b.p50), xc + half, y(b.p50), "stroke-width=\"3\"");
    o << "</g>\n";
    if (std::isinf(b.p99))
      o << "<path d=\"M" << px(xc - 5) << ' ' << px(f.y1() + 8) << " L" << px(xc) << ' '
        << px(f.y1()) << " L" << px(xc + 5) << ' ' << px(f.y1() + 8) << "\" fill=\"none\" stroke=\""
        << c << "\" stroke-width=\"1.5\"/><text class=\"note\" x=\"" << px(xc + 8) << "\" y=\""
        << px(f.y1() + 10) << "\">lost</text>\n";
    o << "<text class=\"val\" x=\"" << px(xc + half + 4) << "\" y=\"" << px(y(b.p50) + 4) << "\">"
      << significant(b.p50) << "</text>\n";
  }
  o << "</svg>\n";
}

// ---------------------------------------------------------------- bar charts

void bar_chart(std::ostream& o, const BarChart& c) {
  Frame f;
  f.height = 240;
  f.bottom = 40;
  std::vector<LegendEntry> entries;
  std::vector<double> values{0.0};
  for (const BarSeries& s : c.series) {
    entries.push_back({s.name, s.colour, Mark::kSwatch, Stroke::kSolid});
    values.insert(values.end(), s.values.begin(), s.values.end());
  }
  f.top += kLegendRowPx * legend_row_count(entries, f.x0(), f.x1());
  Axis a = auto_axis(values, 5, false, 0, true);
  a.px_lo = f.y0();
  a.px_hi = f.y1();
  svg_open(o, f, c.id, c.title);
  legend_rows(o, entries, f.x0(), 18 + kLegendRowPx, f.x1());
  y_axis(o, f, a, c.y_label);
  line(o, f.x0(), f.y0(), f.x1(), f.y0(), "class=\"axis\"");
  o << "\n";
  const double group = (f.x1() - f.x0()) / double(std::max<std::size_t>(1, c.categories.size()));
  const double n = double(std::max<std::size_t>(1, c.series.size()));
  const double bar = (group - 16) / n;
  for (std::size_t i = 0; i < c.categories.size(); ++i) {
    const double gx = f.x0() + group * double(i);
    for (std::size_t k = 0; k < c.series.size(); ++k) {
      const BarSeries& s = c.series[k];
      const double v = i < s.values.size() ? s.values[i] : kInf;
      const double bx = gx + 8 + bar * double(k);
      if (!std::isfinite(v)) {
        o << "<text class=\"note\" x=\"" << px(bx + bar / 2) << "\" y=\"" << px(f.y0() - 4)
          << "\" text-anchor=\"middle\">&ndash;</text>";
        continue;
      }
      const double top = a.map(v);
      rect(o, bx, top, bar - 1, std::max(0.0, f.y0() - top), "fill=\"" + s.colour + "\">");
      o << "<title>" << esc(s.name + " " + c.categories[i] + ": ") << significant(v)
        << "</title></rect>";
    }
    const std::string& name = c.categories[i];
    const std::size_t space = name.find(' ');
    const std::string first = name.substr(0, space);
    o << "<text class=\"tl\" x=\"" << px(gx + group / 2) << "\" y=\"" << px(f.y0() + 14)
      << "\" text-anchor=\"middle\">" << esc(first) << "</text>";
    if (space != std::string::npos)
      o << "<text class=\"tl\" x=\"" << px(gx + group / 2) << "\" y=\"" << px(f.y0() + 27)
        << "\" text-anchor=\"middle\">" << esc(name.substr(space + 1)) << "</text>";
    o << "\n";
  }
  o << "</svg>\n";
}

// ---------------------------------------------------------------- colours

double ColourScale::t(double v) const {
  double u = 0.5;
  if (hi > lo) {
    if (log && lo > 0)
      u = (std::log10(std::max(v, lo)) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
    else
      u = (v - lo) / (hi - lo);
  }
  return t_of(std::clamp(u, 0.0, 1.0));
}

double ColourScale::t_of(double u) const { return t_min + (1 - t_min) * (reversed ? 1 - u : u); }

void heat_map(std::ostream& o, const HeatMap& m) {
  const std::size_t nx = std::max<std::size_t>(1, m.x_values.size());
  const std::size_t ny = std::max<std::size_t>(1, m.y_values.size());
  const double cw = std::clamp(560.0 / double(nx), 28.0, 80.0);
  const double ch = std::clamp(320.0 / double(ny), 24.0, 44.0);
  std::size_t longest_y = 1;
  for (const std::string& v : m.y_values) longest_y = std::max(longest_y, v.size());
  const bool has_y = !m.y_values.empty();
  Frame f;
  f.left = has_y ? 30 + 7.5 * double(longest_y) : 10;
  f.top = m.title.empty() ? 8 : 28;
  f.bottom = 44;
  f.right = 10;
  f.width = f.left + cw * double(nx) + f.right;
  f.height = f.top + ch * double(ny) + f.bottom;
  auto X = [&](std::size_t x) { return f.left + cw * double(x); };
  auto Y = [&](std::size_t y) { return f.top + ch * double(ny - 1 - y); };  // row 0 at the bottom
  auto cell = [&](std::size_t x, std::size_t y) -> const HeatCell* {
    const std::size_t i = y * nx + x;
    return i < m.cells.size() ? &m.cells[i] : nullptr;
  };

  svg_open(o, f, m.id, m.title, "heat");
  for (std::size_t y = 0; y < ny; ++y)
    for (std::size_t x = 0; x < nx; ++x) {
      const HeatCell* c = cell(x, y);
      if (!c) continue;
      const double x0 = X(x), y0 = Y(y);
      const std::string tip = "<title>" + esc(c->tooltip) + "</title></rect>";
      if (c->state == HeatCell::State::kMissing) {
        rect(o, x0, y0, cw, ch, "fill=\"#fff\" stroke=\"#ccc\" stroke-dasharray=\"2 2\">" + tip);
        continue;
      }
      if (c->state == HeatCell::State::kFailed) {
        rect(o, x0, y0, cw, ch, "fill=\"#bbb\" stroke=\"#fff\">" + tip);
        cross(o, x0, y0, cw, ch);
        continue;
      }
      Rgb fill{238, 238, 238};
      if (std::isinf(c->value) && c->value > 0)
        fill = {17, 17, 17};
      else if (std::isfinite(c->value))
        fill = m.scale.colour(c->value);
      rect(o, x0, y0, cw, ch,
           "fill=\"" + hex(fill) + "\" stroke=\"#fff\" stroke-width=\"1\">" + tip);
      if (!c->text.empty() && kCharPx * 1.1 * double(c->text.size()) <= cw - 4)
        o << "<text class=\"hv\" x=\"" << px(x0 + cw / 2) << "\" y=\"" << px(y0 + ch / 2 + 4)
          << "\" text-anchor=\"middle\" fill=\""
          << (relative_luminance(fill) > 0.18 ? "#000" : "#fff") << "\">" << esc(c->text)
          << "</text>";
    }
  o << "\n";
  // Outlines, and the boundaries between groups.
  for (std::size_t y = 0; y < ny; ++y)
    for (std::size_t x = 0; x < nx; ++x) {
      const HeatCell* c = cell(x, y);
      if (!c) continue;
      if (c->outlined)
        rect(o, X(x) + 1.5, Y(y) + 1.5, cw - 3, ch - 3,
             "fill=\"none\" stroke=\"#ff00ff\" stroke-width=\"2.5\"/>");
      if (c->group < 0) continue;
      const HeatCell* right = x + 1 < nx ? cell(x + 1, y) : nullptr;
      const HeatCell* up = y + 1 < ny ? cell(x, y + 1) : nullptr;
      if (right && right->group >= 0 && right->group != c->group)
        line(o, X(x + 1), Y(y), X(x + 1), Y(y) + ch, "stroke=\"#000\" stroke-width=\"3\"");
      if (up && up->group >= 0 && up->group != c->group)
        line(o, X(x), Y(y), X(x) + cw, Y(y), "stroke=\"#000\" stroke-width=\"3\"");
    }
  o << "\n";
  // Tick labels, thinned so that they do not overlap.
  std::size_t longest_x = 1;
  for (const std::string& v : m.x_values) longest_x = std::max(longest_x, v.size());
  const std::size_t every =
      std::max<std::size_t>(1, std::size_t(std::ceil((kCharPx * double(longest_x) + 6) / cw)));
  for (std::size_t x = 0; x < m.x_values.size(); x += every)
    o << "<text class=\"hk\" x=\"" << px(X(x) + cw / 2) << "\" y=\"" << px(f.y0() + 15)
      << "\" text-anchor=\"middle\">" << esc(m.x_values[x]) << "</text>";
  const std::size_t every_y = std::max<std::size_t>(1, std::size_t(std::ceil(14.0 / ch)));
  for (std::size_t y = 0; y < m.y_values.size(); y += every_y)
    o << "<text class=\"hk\" x=\"" << px(f.left - 5) << "\" y=\"" << px(Y(y) + ch / 2 + 4)
      << "\" text-anchor=\"end\">" << esc(m.y_values[y]) << "</text>";
  o << "\n<text class=\"al\" x=\"" << px(0.5 * (f.x0() + f.x1())) << "\" y=\"" << px(f.height - 8)
    << "\" text-anchor=\"middle\">" << esc(m.x_label) << "</text>\n";
  if (has_y)
    o << "<text class=\"al\" transform=\"translate(14," << px(0.5 * (f.y0() + f.y1()))
      << ") rotate(-90)\" text-anchor=\"middle\">" << esc(m.y_label) << "</text>\n";
  o << "</svg>\n";
}

void colour_bar(std::ostream& o, const std::string& id, const ColourScale& scale,
                const std::string& label) {
  const Frame f{560, 52, 20, 20, 6, 30};  // width, height, left, right, top, bottom
  o << "<svg class=\"bar\" data-chart=\"" << esc(id) << "\" viewBox=\"0 0 " << px(f.width) << ' '
    << px(f.height) << "\" width=\"" << px(f.width) << "\" height=\"" << px(f.height)
    << "\" role=\"img\"><title>" << esc(label) << "</title><defs><linearGradient id=\"g-" << esc(id)
    << "\">";
  for (int i = 0; i <= 16; ++i)
    o << "<stop offset=\"" << px(i * 6.25) << "%\" stop-color=\""
      << hex(turbo(scale.t_of(i / 16.0))) << "\"/>";
  o << "</linearGradient></defs>";
  rect(o, f.x0(), f.top, f.x1() - f.x0(), 14, "fill=\"url(#g-" + esc(id) + ")\"/>");
  o << "\n";
  Axis a =
      scale.log && scale.lo > 0 ? log_axis(scale.lo, scale.hi) : linear_axis(scale.lo, scale.hi, 8);
  a.px_lo = f.x0();
  a.px_hi = f.x1();
  // The ticks may widen the axis; the bar spans exactly lo..hi.
  Axis bar = a;
  bar.lo = scale.lo;
  bar.hi = scale.hi > scale.lo ? scale.hi : scale.lo + 1;
  const double eps = 1e-9 * std::abs(bar.hi - bar.lo);
  for (double t : a.ticks) {
    if (t < bar.lo - eps || t > bar.hi + eps) continue;
    const double x = bar.map(t);
    line(o, x, f.top + 14, x, f.top + 18, "class=\"axis\"");
    o << "<text class=\"tl\" x=\"" << px(x) << "\" y=\"" << px(f.top + 30)
      << "\" text-anchor=\"middle\">" << a.label(t) << "</text>";
  }
  o << "<text class=\"tl\" x=\"" << px(f.x1()) << "\" y=\"" << px(f.height - 2)
    << "\" text-anchor=\"end\">" << esc(label) << (scale.log ? " (log scale)" : "")
    << "</text></svg>\n";
}

}  // namespace arttrack::sim::chart
