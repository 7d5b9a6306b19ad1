// The chart layer of the simulator's HTML pages (the run report, the sweep
// page, the tuning page): inline SVG charts styled by one CSS string, so
// that every page draws axes, ticks, legends and colours the same way.
// Internal to the testbed (reporting and experiments); no script, no network, nothing but text.
//
// What it draws:
//   - line charts (lines, dots, bands around a line, dashed reference
//     lines), box plots, grouped bar charts, heat maps, colour bars, and
//     stand-alone legends;
//   - axes with round ticks (1, 2 or 5 times a power of ten), linear or
//     logarithmic (decades), with a label that names the quantity and its
//     unit ("time, s"; a log axis adds "(log scale)").
//
// Every text given to it (titles, labels, names, tooltips) is plain text:
// the layer escapes it for HTML (text::html_escape). Numbers it writes are
// finite: a value that is not (NaN: no value, +inf: lost or never) is left
// out of a line (a gap), drawn at the edge of a box plot, or drawn in a
// heat map as its own state. Pixel sizes are of the SVG's viewBox; the CSS
// (kPageCss) scales charts of class "chart" to their container's width and
// keeps heat maps (class "heat") at their own size.
//
// Each chart is an <svg class="chart" data-chart="ID"> element with a
// <title>; ids must be unique in a page (they also name clip paths).
#pragma once

#include <cstddef>
#include <iosfwd>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "arttrack/sim/internal/colour_map.h"

namespace arttrack::sim::chart {

// ---- the page ----

// The CSS of every page: text, headings, tables, notes, chart classes.
extern const char kPageCss[];

// "<!DOCTYPE html>..." up to and including "<main>": UTF-8, a viewport,
// `title` (escaped) and kPageCss. page_end() closes what it opened.
std::string page_start(const std::string& title);
std::string page_end();

// ---- numbers as text ----

// SVG coordinate: one decimal ("12.5").
std::string px(double v);

// Fixed-point number with `decimals` decimals, for HTML: "&infin;" or
// "-&infin;" for infinities, "&ndash;" for NaN, never "-0.00".
std::string fixed(double v, int decimals);

// Three significant digits, at most four decimals: 42.1, 3.22, 0.0831, 0.0083.
std::string significant(double v);

// ---- axes ----

// Round axis ticks covering [lo, hi]: multiples of 1, 2 or 5 times a power of
// ten, at most max_ticks + 1 of them, first <= lo and last >= hi (the axis
// is widened to them). lo == hi gives a small range around the value.
std::vector<double> round_ticks(double lo, double hi, int max_ticks = 6);

// Maps values to pixels, linear or log10, with its ticks.
struct Axis {
  double lo = 0, hi = 1;  // value range (log: both > 0)
  bool log = false;
  double px_lo = 0, px_hi = 1;  // pixel positions of lo and hi
  std::vector<double> ticks;
  double step = 1;  // linear: the tick step, which sets the labels' decimals

  // Pixel position of v; values outside [lo, hi] stop 2% past the ends (a
  // log axis maps v <= lo to lo).
  double map(double v) const;
  // A tick's label: as many decimals as the step (log: the tick) needs.
  std::string label(double v) const;
};

// A linear axis over round_ticks(lo, hi, max_ticks). widen: the axis ends at
// the outer ticks; else it spans exactly [lo, hi] (time axes) and keeps the
// ticks inside.
Axis linear_axis(double lo, double hi, int max_ticks, bool widen = true);

// A log axis over the decades around [lo, hi] (lo > 0), with ticks at 2 and
// 5 times each power of ten when there are at most two decades.
Axis log_axis(double lo, double hi);

// Values spanning more than this factor (largest over smallest positive)
// get a log axis from auto_axis.
constexpr double kLogRatio = 100.0;

// An axis for the finite values: log if allow_log, none is negative and they
// span more than kLogRatio; else linear with at least min_span and, if
// include_zero, from 0. No finite value: linear 0..1.
Axis auto_axis(const std::vector<double>& values, int max_ticks, bool allow_log = false,
               double min_span = 0, bool include_zero = false);

// ---- pieces of a chart ----

// A plot area inside an SVG of width x height (viewBox pixels).
struct Frame {
  double width = 580, height = 300;
  double left = 62, right = 14, top = 30, bottom = 44;
  double x0() const { return left; }
  double x1() const { return width - right; }
  double y0() const { return height - bottom; }  // bottom of the plot area
  double y1() const { return top; }
};

// Opens <svg class="css_class" data-chart="id"> with its <title> and draws
// the title in the top left corner.
void svg_open(std::ostream& o, const Frame& f, const std::string& id, const std::string& title,
              const std::string& css_class = "chart");

// Gridlines, tick labels and the axis line; the label rotated on the left
// (y) or centred below (x). The axis' pixel range must be set.
void y_axis(std::ostream& o, const Frame& f, const Axis& a, const std::string& label);
void x_axis(std::ostream& o, const Frame& f, const Axis& a, const std::string& label);

// How a series or a legend entry is drawn. Strokes: solid, dashed (6 4),
// dotted (1.5 3), dash-dot and dash-dot-dot (dashes of 8).
enum class Stroke { kSolid, kDashed, kDotted, kDashDot, kDashDotDot };
enum class Mark {
  kLine,       // a line (with Stroke)
  kDots,       // a dot per point
  kRing,       // a larger open circle per point (to single points out)
  kBand,       // a filled band (legend: a pale swatch)
  kSwatch,     // legend: a filled square
  kOutline,    // legend: a square outlined in the colour
  kCross,      // legend: a grey square crossed out
  kDashedBox,  // legend: a white square with a dashed grey border
};

// One entry of a legend.
struct LegendEntry {
  std::string name, colour;
  Mark mark = Mark::kLine;
  Stroke stroke = Stroke::kSolid;
};

// Legend entries laid out left to right from x, wrapping before x_max, rows
// 18 px apart from baseline y. Returns the number of rows.
int legend_rows(std::ostream& o, const std::vector<LegendEntry>& entries, double x, double y,
                double x_max);
// How many rows legend_rows would take between x and x_max.
int legend_row_count(const std::vector<LegendEntry>& entries, double x, double x_max);

// A legend alone, as its own <svg class="legend"> of the given width.
void legend(std::ostream& o, const std::string& id, const std::vector<LegendEntry>& entries,
            double width = 1160);

// ---- line charts ----

// A series of a line chart: a line (gaps at non-finite y), dots or rings,
// optionally with a band (band_lo..band_hi, same length as x) under it.
struct Series {
  std::string name, colour;
  std::vector<double> x, y;
  std::vector<double> band_lo, band_hi;  // empty: no band
  Mark mark = Mark::kLine;
  Stroke stroke = Stroke::kSolid;
};

struct LineChart {
  std::string id, title, x_label, y_label;
  Frame frame;
  std::vector<Series> series;
  // The y axis: auto_axis over the series (and bands and y marks), or over
  // y_axis_values when given (points beyond it stop at the edge).
  bool allow_log = false;
  bool include_zero = false;
  double min_span = 0;  // smallest y range
  std::vector<double> y_axis_values;
  // The x axis spans exactly [x_lo, x_hi]; integer_x: whole-number ticks only.
  double x_lo = 0, x_hi = 1;
  bool integer_x = false;
  // Legend of the series between the title and the plot (the plot area
  // shrinks by its rows).
  bool legend = true;
  std::vector<std::pair<double, std::string>> x_marks, y_marks;  // dashed reference lines
  int y_ticks = 6, x_ticks = 8;
  double line_width = 1.6;  // px
};

void line_chart(std::ostream& o, const LineChart& c);

// The legend entry that draws like the series.
LegendEntry legend_entry(const Series& s);

// ---- box plots ----

// One box of a box plot, in display units; count 0 or a NaN median: "no samples".
struct Box {
  std::string name, colour;
  double p01 = 0, p25 = 0, p50 = 0, p75 = 0, p99 = 0;
  std::size_t count = 0;
};

// The paper's box plot: box p25-p75, whisker p1-p99 with ticks at p1 and p99,
// thick tick at p50 (value written beside it). Values beyond the axis (+inf:
// lost estimates) end in an arrow at the top marked "lost". 580 x 320.
void box_plot(std::ostream& o, const std::string& id, const std::string& title,
              const std::string& y_label, const std::vector<Box>& boxes, Axis axis);

// ---- bar charts ----

// Grouped bars from 0: per category one bar per series, a legend of the
// series; a value that is not finite draws no bar and writes "–" over its
// place. 580 x 240.
struct BarSeries {
  std::string name, colour;
  std::vector<double> values;  // per category
};
struct BarChart {
  std::string id, title, y_label;
  std::vector<std::string> categories;  // a space breaks a name onto two lines
  std::vector<BarSeries> series;
};
void bar_chart(std::ostream& o, const BarChart& c);

// ---- colour scales, heat maps and colour bars ----

// Values to Turbo colours: lo -> t_min, hi -> 1 (reversed: the other way
// round), linear or log10 (lo > 0); values outside are clamped.
struct ColourScale {
  double lo = 0, hi = 1;
  bool log = false;
  bool reversed = false;
  // Where the map starts: above 0 to leave out Turbo's darkest blue where
  // black means something else (no return in a depth image).
  double t_min = 0;
  double t(double v) const;
  // The map's t at fraction u in [0, 1] of the way from lo to hi.
  double t_of(double u) const;
  Rgb colour(double v) const { return turbo(t(v)); }
};

// A cell of a heat map.
struct HeatCell {
  enum class State {
    kValue,    // coloured by the scale; +inf black, NaN light grey
    kMissing,  // not in these results: white, dashed border
    kFailed,   // grey, crossed out
  };
  State state = State::kMissing;
  double value = std::numeric_limits<double>::quiet_NaN();
  std::string text;       // written in the cell when it fits
  std::string tooltip;    // shown on hover
  bool outlined = false;  // a magenta outline (a colour Turbo does not have)
  // A thick black line separates neighbours in different groups (both >= 0).
  int group = -1;
};

// Cells over x_values across and y_values up (first value bottom left), with
// the values as tick labels and the axis labels below and left; cells are
// 28-80 px wide and 24-44 px high, text 12 px.
struct HeatMap {
  std::string id, title;
  std::string x_label, y_label;
  std::vector<std::string> x_values, y_values;  // y_values empty: one row
  ColourScale scale;
  std::vector<HeatCell> cells;  // cells[y * x_values.size() + x]
};
void heat_map(std::ostream& o, const HeatMap& map);

// A horizontal bar of the scale's colours from scale.lo (left) to scale.hi,
// round ticks (log: decades) and `label` below; 560 x 52.
void colour_bar(std::ostream& o, const std::string& id, const ColourScale& scale,
                const std::string& label);

}  // namespace arttrack::sim::chart
