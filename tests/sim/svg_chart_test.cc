// The chart layer of the HTML pages (arttrack/sim/internal/svg_chart.h of
// sim/reporting) and its colour map (internal/colour_map.h of sim/simulation):
// round ticks, log axes, escaping of every text, legends that draw like their series, heat maps and
// bars, and Turbo against the published table.
#include "arttrack/sim/internal/svg_chart.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <regex>
#include <sstream>

#include "../text_search.h"
#include "arttrack/sim/internal/colour_map.h"

namespace arttrack::sim::chart {
namespace {

using test_support::count_occurrences;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The texts of the <text class="cls"> elements, in order.
std::vector<std::string> texts(const std::string& svg, const std::string& cls) {
  std::vector<std::string> out;
  const std::regex re("<text class=\"" + cls + "\"[^>]*>([^<]*)</text>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator();
       ++it)
    out.push_back((*it)[1]);
  return out;
}

Series series(const std::string& name, const std::string& colour, std::vector<double> x,
              std::vector<double> y) {
  Series s;
  s.name = name;
  s.colour = colour;
  s.x = std::move(x);
  s.y = std::move(y);
  return s;
}

LineChart chart(const std::string& id, const std::string& title, const std::string& x_label,
                const std::string& y_label) {
  LineChart c;
  c.id = id;
  c.title = title;
  c.x_label = x_label;
  c.y_label = y_label;
  return c;
}

TEST(SvgChart, RoundTicks) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> exponent(-4, 4), unit(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, exponent(rng));
    double lo = unit(rng) * scale, hi = unit(rng) * scale;
    if (lo > hi) std::swap(lo, hi);
    const int max_ticks = 3 + trial % 6;
    const std::vector<double> t = round_ticks(lo, hi, max_ticks);
    ASSERT_GE(t.size(), 2u);
    ASSERT_LE(t.size(), std::size_t(max_ticks + 1)) << lo << " " << hi;
    EXPECT_LE(t.front(), lo);
    EXPECT_GE(t.back(), hi);
    const double step = t[1] - t[0];
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 ||
                std::abs(mantissa - 5) < 1e-6)
        << step;
    for (std::size_t i = 0; i < t.size(); ++i) {
      EXPECT_NEAR(t[i] / step, std::round(t[i] / step), 1e-6);  // multiples of the step
      if (i > 0) {
        EXPECT_NEAR(t[i] - t[i - 1], step, 1e-9 * scale);
      }
    }
  }
  EXPECT_EQ(round_ticks(0, 10, 6), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  const std::vector<double> t = round_ticks(0.13, 0.87, 5);  // 0.1 steps would be 9 ticks
  ASSERT_EQ(t.size(), 6u);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(t[i], 0.2 * i, 1e-12);
  EXPECT_EQ(round_ticks(kNaN, 1), (std::vector<double>{0, 1}));
}

TEST(SvgChart, TickLabelsHaveTheDecimalsOfTheStep) {
  const Axis a = linear_axis(0, 1, 5);  // 0, 0.2, ..., 1
  EXPECT_EQ(a.label(0.4), "0.4");
  EXPECT_EQ(a.label(1), "1.0");
  const Axis b = linear_axis(0, 300, 4);  // 0, 100, 200, 300
  EXPECT_EQ(b.label(200), "200");
  EXPECT_EQ(fixed(-0.0001, 2), "0.00");  // never "-0.00"
  EXPECT_EQ(fixed(kInf, 1), "&infin;");
  EXPECT_EQ(fixed(kNaN, 1), "&ndash;");
  EXPECT_EQ(significant(0.08312), "0.0831");
  EXPECT_EQ(significant(0.008312), "0.0083");  // at most four decimals
  EXPECT_EQ(significant(42.14), "42.1");
}

TEST(SvgChart, LogAxisSpansDecadesAndMapsThemEvenly) {
  Axis a = log_axis(0.3, 420);
  EXPECT_TRUE(a.log);
  EXPECT_EQ(a.lo, 0.1);
  EXPECT_EQ(a.hi, 1000);
  EXPECT_EQ(a.ticks, (std::vector<double>{0.1, 1, 10, 100, 1000}));  // four decades: no 2 and 5
  a.px_lo = 0;
  a.px_hi = 400;
  EXPECT_NEAR(a.map(1), 100, 1e-9);
  EXPECT_NEAR(a.map(10), 200, 1e-9);
  EXPECT_NEAR(a.map(std::sqrt(10.0)), 150, 1e-9);
  EXPECT_NEAR(a.map(0), 0, 1e-9);  // at or below lo: the bottom
  EXPECT_EQ(a.label(0.1), "0.1");
  EXPECT_EQ(a.label(1000), "1000");
  // Two decades or fewer: 2 and 5 between.
  EXPECT_EQ(log_axis(2, 30).ticks, (std::vector<double>{1, 2, 5, 10, 20, 50, 100}));

  // auto_axis: log only past kLogRatio, never with negative values.
  EXPECT_TRUE(auto_axis({0.2, 42}, 6, true).log);
  EXPECT_FALSE(auto_axis({2, 42}, 6, true).log);
  EXPECT_FALSE(auto_axis({-0.2, 42}, 6, true).log);
  EXPECT_FALSE(auto_axis({0.2, 42}, 6, false).log);
  EXPECT_TRUE(auto_axis({0.0, 0.2, 42, kInf, kNaN}, 6, true).log);  // zero and non-finite ignored
  const Axis flat = auto_axis({5, 5}, 6, false, 2.0);
  EXPECT_LE(flat.lo, 4.0);
  EXPECT_GE(flat.hi, 6.0);
}

TEST(SvgChart, EveryTextIsEscaped) {
  LineChart c = chart("x\"y", "a<b & \"c\"", "time <s>", "error & more");
  c.series.push_back(series("<script>", "#000", {0, 1}, {1, 2}));
  c.x_marks = {{0.5, "mark <here>"}};
  std::ostringstream o;
  line_chart(o, c);
  const std::string svg = o.str();
  EXPECT_EQ(svg.find("<script>"), std::string::npos);
  EXPECT_EQ(svg.find("<b "), std::string::npos);
  EXPECT_EQ(svg.find("<s>"), std::string::npos);
  EXPECT_NE(svg.find("&lt;script&gt;"), std::string::npos);
  EXPECT_NE(svg.find("a&lt;b &amp; &quot;c&quot;"), std::string::npos);
  EXPECT_NE(svg.find("error &amp; more"), std::string::npos);
  EXPECT_NE(svg.find("mark &lt;here&gt;"), std::string::npos);
  EXPECT_NE(svg.find("data-chart=\"x&quot;y\""), std::string::npos);

  HeatMap m;
  m.x_values = {"<1>"};
  m.x_label = "k&v";
  m.cells = {{HeatCell::State::kValue, 1.0, "<v>", "tip <t>", false, -1}};
  std::ostringstream h;
  heat_map(h, m);
  EXPECT_EQ(h.str().find("<1>"), std::string::npos);
  EXPECT_EQ(h.str().find("<t>"), std::string::npos);
  EXPECT_NE(h.str().find("k&amp;v"), std::string::npos);
  EXPECT_NE(page_start("<T>").find("<title>&lt;T&gt;</title>"), std::string::npos);
}

TEST(SvgChart, LineChartHasAxesLegendAndGapsNoNaN) {
  LineChart c = chart("t", "title", "evaluation", "objective, mm");
  c.x_lo = 0.5;
  c.x_hi = 7.5;
  c.integer_x = true;
  Series line = series("best so far", "#009E73", {1, 2, 3, 4, 5, 6, 7}, {5, 4, kNaN, 3, 3, 2, 2});
  line.stroke = Stroke::kDashed;
  Series dots = series("evaluation", "#0072B2", {1, 2, 3, 4, 5, 6, 7}, {5, 6, 7, 3, 4, 2, kInf});
  dots.mark = Mark::kDots;
  c.series = {line, dots};
  std::ostringstream o;
  line_chart(o, c);
  const std::string svg = o.str();
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  // Whole-number x ticks only, the axis labels with their units.
  const std::vector<std::string> ticks = texts(svg, "tl");
  for (const char* t : {"1", "2", "7"})
    EXPECT_NE(std::find(ticks.begin(), ticks.end(), t), ticks.end()) << t;
  EXPECT_EQ(std::find(ticks.begin(), ticks.end(), "1.5"), ticks.end());
  EXPECT_EQ(texts(svg, "al"), (std::vector<std::string>{"objective, mm", "evaluation"}));
  // A gap at NaN: the line is two pieces; six finite dots.
  const std::regex path("<path d=\"([^\"]*)\" fill=\"none\" stroke=\"#009E73\"");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(svg, m, path));
  EXPECT_EQ(count_occurrences(m[1], "M"), 2u);
  EXPECT_EQ(count_occurrences(svg, "<circle"), 6u + 1u);  // and the legend's dot
  // The legend draws each entry like its series: the dashed line dashed.
  const std::string legend = svg.substr(svg.find("<g class=\"legend\">"));
  EXPECT_NE(legend.find("stroke=\"#009E73\" stroke-width=\"2.5\" stroke-dasharray=\"6 4\"/>"
                        "<text class=\"tl\""),
            std::string::npos);
  EXPECT_NE(svg.find("stroke=\"#009E73\" stroke-width=\"1.6\" stroke-linejoin=\"round\" "
                     "stroke-dasharray=\"6 4\""),
            std::string::npos);
  EXPECT_NE(legend.find(">best so far</text>"), std::string::npos);
  EXPECT_NE(legend.find(">evaluation</text>"), std::string::npos);
}

TEST(SvgChart, LegendWrapsIntoRowsThatTheChartMakesRoomFor) {
  const LegendEntry entry{"camera_offset_only: contradicted", "#000", Mark::kLine, Stroke::kSolid};
  const std::vector<LegendEntry> entries(12, entry);
  EXPECT_EQ(legend_row_count(entries, 62, 1146), 3);  // 4 per row
  EXPECT_EQ(legend_row_count({}, 62, 1146), 0);
  LineChart c;
  c.id = "many";
  for (const LegendEntry& e : entries) c.series.push_back(series(e.name, e.colour, {0, 1}, {0, 1}));
  c.frame.width = 1160;
  std::ostringstream o;
  line_chart(o, c);
  // Rows 18 px apart from 36; the plot area starts below the last one.
  EXPECT_EQ(count_occurrences(o.str(), ">camera_offset_only: contradicted</text>"), 12u);
  EXPECT_EQ(count_occurrences(o.str(), "y=\"72.0\">camera_offset_only"), 4u);  // row 3
  EXPECT_EQ(o.str().find("y=\"90.0\">camera_offset_only"), std::string::npos);
  EXPECT_NE(o.str().find("<line x1=\"62.0\" y1=\"256.0\" x2=\"62.0\" y2=\"84.0\" class=\"axis\"/>"),
            std::string::npos)
      << "the y axis should start at the plot top, 30 + 3 * 18 = 84";
}

TEST(SvgChart, BoxPlotSaysNoSamplesAndMarksLostEstimates) {
  std::vector<Box> boxes = {{"a", "#111", 1, 2, 3, 4, 5, 10},
                            {"b", "#222", 1, 2, 3, 4, kInf, 10},
                            {"c", "#333", kNaN, kNaN, kNaN, kNaN, kNaN, 0}};
  std::ostringstream o;
  box_plot(o, "box", "Box", "error, mm", boxes, linear_axis(0, 6, 6));
  EXPECT_EQ(count_occurrences(o.str(), "<rect"), 2u);
  EXPECT_EQ(count_occurrences(o.str(), ">lost</text>"), 1u);
  EXPECT_EQ(count_occurrences(o.str(), ">no samples</text>"), 1u);
  EXPECT_NE(o.str().find(">error, mm</text>"), std::string::npos);
  EXPECT_EQ(o.str().find("nan"), std::string::npos);
}

TEST(SvgChart, BarsFromZeroWithALegendAndNoBarForNoValue) {
  BarChart c;
  c.id = "bars";
  c.y_label = "translation error, mm";
  c.categories = {"translation p50", "converged translation p50"};
  c.series = {{"default", "#999999", {4, kNaN}}, {"tuned", "#0072B2", {3, 2}}};
  std::ostringstream o;
  bar_chart(o, c);
  const std::string svg = o.str();
  EXPECT_EQ(count_occurrences(svg, "fill=\"#0072B2\">"), 2u);  // tuned's two bars
  EXPECT_EQ(count_occurrences(svg, "fill=\"#999999\">"), 1u);  // default has one value
  EXPECT_EQ(count_occurrences(svg, ">&ndash;</text>"), 1u);
  EXPECT_NE(svg.find(">default</text>"), std::string::npos);
  EXPECT_NE(svg.find(">tuned</text>"), std::string::npos);
  const std::vector<std::string> ticks = texts(svg, "tl");
  ASSERT_GE(ticks.size(), 3u);
  EXPECT_EQ(ticks[2], "0");  // after the legend's two names: the axis starts at 0
  EXPECT_EQ(svg.find("nan"), std::string::npos);
}

TEST(SvgChart, HeatMapCellsStatesOutlinesAndReadableText) {
  HeatMap m;
  m.id = "heat";
  m.x_values = {"0", "5", "10"};
  m.y_values = {"0", "0.05"};
  m.x_label = "encoders[0].offset_deg";
  m.y_label = "camera.latency_s";
  m.scale.lo = 1;
  m.scale.hi = 100;
  m.scale.log = true;
  using S = HeatCell::State;
  m.cells = {{S::kValue, 1, "1", "a", false, 0},       {S::kValue, 100, "100", "b", true, 1},
             {S::kValue, kInf, "never", "c", true, 1}, {S::kFailed, kNaN, "", "d", false, -1},
             {S::kMissing, kNaN, "", "e", false, -1},  {S::kValue, 10, "10", "f", false, 0}};
  std::ostringstream o;
  heat_map(o, m);
  const std::string svg = o.str();
  EXPECT_NE(svg.find("fill=\"" + hex(turbo(0)) + "\""), std::string::npos);    // 1: low end
  EXPECT_NE(svg.find("fill=\"" + hex(turbo(1)) + "\""), std::string::npos);    // 100: high end
  EXPECT_NE(svg.find("fill=\"" + hex(turbo(0.5)) + "\""), std::string::npos);  // 10: log middle
  EXPECT_NE(svg.find("fill=\"#111111\""), std::string::npos);                  // never
  EXPECT_EQ(count_occurrences(svg, "stroke=\"#ff00ff\""), 2u);                 // outlined
  EXPECT_EQ(count_occurrences(svg, "stroke-dasharray=\"2 2\""), 1u);           // missing
  EXPECT_EQ(count_occurrences(svg, "stroke=\"#666\""), 1u);                    // failed: crossed
  // Boundaries between groups 0 and 1: right of cell (0,0), above (1,0)...
  EXPECT_EQ(count_occurrences(svg, "stroke=\"#000\" stroke-width=\"3\""), 2u);
  // Values written in the class the CSS sets at 12 px; dark cells get white text.
  EXPECT_EQ(texts(svg, "hv").size(), 4u);
  EXPECT_NE(svg.find("fill=\"#fff\">never</text>"), std::string::npos);
  EXPECT_NE(std::string(kPageCss).find(".hv{font-size:12px}"), std::string::npos);
  // Axis keys and tick values.
  EXPECT_EQ(texts(svg, "al"),
            (std::vector<std::string>{"encoders[0].offset_deg", "camera.latency_s"}));
  EXPECT_EQ(texts(svg, "hk"), (std::vector<std::string>{"0", "5", "10", "0", "0.05"}));
}

TEST(SvgChart, ColourBarTicksStayInsideItsRange) {
  ColourScale s;
  s.lo = 0.83;
  s.hi = 1.37;
  s.reversed = true;
  std::ostringstream o;
  colour_bar(o, "bar", s, "depth, m");
  const std::vector<std::string> ticks = texts(o.str(), "tl");
  ASSERT_GE(ticks.size(), 3u);
  for (std::size_t i = 0; i + 1 < ticks.size(); ++i) {
    const double v = std::stod(ticks[i]);
    EXPECT_GE(v, 0.83);
    EXPECT_LE(v, 1.37);
  }
  EXPECT_EQ(ticks.back(), "depth, m");
  EXPECT_EQ(count_occurrences(o.str(), "<stop "), 17u);
  // Reversed: the first stop is the high end of the map.
  EXPECT_NE(o.str().find("<stop offset=\"0.0%\" stop-color=\"" + hex(turbo(1)) + "\"/>"),
            std::string::npos);
  EXPECT_NEAR(s.t(0.83), 1.0, 1e-12);
  EXPECT_NEAR(s.t(1.37), 0.0, 1e-12);
  EXPECT_NEAR(s.t(5.0), 0.0, 1e-12);  // clamped
}

// Entries of the published 256-entry Turbo table (sRGB in [0, 1]), among
// them ones the implementation interpolates (64, 128, 192).
TEST(ColourMap, TurboMatchesThePublishedTable) {
  struct Entry {
    int index;
    double r, g, b;
  };
  const Entry published[] = {{0, 0.18995, 0.07176, 0.23217},
                             {64, 0.15844, 0.73551, 0.92305},
                             {128, 0.64362, 0.98999, 0.23356},
                             {192, 0.98590, 0.50479, 0.13367},
                             {255, 0.47960, 0.01583, 0.01055}};
  for (const Entry& e : published) {
    const Rgb c = turbo(e.index / 255.0);
    EXPECT_NEAR(c.r, 255 * e.r, 6.0) << e.index;
    EXPECT_NEAR(c.g, 255 * e.g, 6.0) << e.index;
    EXPECT_NEAR(c.b, 255 * e.b, 6.0) << e.index;
  }
  // The ends exactly (to the byte), and clamping.
  EXPECT_EQ(turbo(0), (Rgb{48, 18, 59}));
  EXPECT_EQ(turbo(1), (Rgb{122, 4, 3}));
  EXPECT_EQ(turbo(-3), turbo(0));
  EXPECT_EQ(turbo(7), turbo(1));
  EXPECT_EQ(turbo(kNaN), turbo(0));
  EXPECT_EQ(hex(turbo(0)), "#30123b");
  EXPECT_EQ(hex(Rgb{255, 0, 16}), "#ff0010");
}

TEST(ColourMap, RelativeLuminance) {
  EXPECT_NEAR(relative_luminance({255, 255, 255}), 1.0, 1e-12);
  EXPECT_NEAR(relative_luminance({0, 0, 0}), 0.0, 1e-12);
  EXPECT_NEAR(relative_luminance({255, 0, 0}), 0.2126, 1e-12);
  EXPECT_NEAR(relative_luminance({128, 128, 128}), 0.2158605, 1e-6);  // WCAG's mid grey
  // Turbo's dark ends take white text, its bright middle black.
  EXPECT_LT(relative_luminance(turbo(0)), 0.18);
  EXPECT_LT(relative_luminance(turbo(1)), 0.18);
  EXPECT_GT(relative_luminance(turbo(0.5)), 0.18);
}

}  // namespace
}  // namespace arttrack::sim::chart
