// The HTML report of a run, on a small ScenarioResult built here (no
// simulation): every chart is there, the page is self-contained and
// well-formed, the summary's numbers appear, and the embedded depth frame
// decodes (base64 and PNG checked with independent decoders).
#include "arttrack/sim/report.h"

#include <gtest/gtest.h>

#include <png.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "../scratch_dir.h"
#include "../text_search.h"
#include "arttrack/sim/method_trackers.h"
#include "arttrack/sim/run_outputs.h"
#include "arttrack/tracker/error.h"
#include "png_rgb.h"

namespace arttrack::sim {
namespace {

using test_support::count_occurrences;

namespace fs = std::filesystem;

const std::vector<std::string> kReportJoints = {"shoulder", "elbow", "wrist"};
constexpr double kDt = 0.1, kDuration = 12.0;

// Translation error of each method at time t, m (NaN: lost).
double error_m(const std::string& method, double t) {
  if (method == "encoders_only") return 0.0421;  // constant: every percentile is 42.10 mm
  if (method == "full_fusion") return 0.0002 + 0.04 * std::exp(-t);
  return t > 11.4 ? std::nan("") : 0.003 + 0.001 * std::sin(t);  // vision_only, lost at the end
}

// Three methods, one run, a 40x30 kept frame: enough for every section.
ScenarioResult synthetic_result() {
  ScenarioResult r;
  r.scenario = "synthetic";
  r.source = "scenarios/synthetic.yaml";
  r.duration_s = kDuration;
  r.seeds = {4242};
  r.methods = {"encoders_only", "full_fusion", "vision_only"};
  r.joint_names = kReportJoints;
  r.end_effectors = {"left_ee"};
  r.scoring.converged_after_s = 5.0;
  r.scoring.convergence_threshold_m = 0.01;

  RunResult run;
  run.seed = 4242;
  run.frames_captured = 360;
  run.frames_delivered = 350;
  const int n = int(std::lround(kDuration / kDt));
  for (const std::string& m : r.methods) {
    MethodRun mr;
    mr.method = m;
    mr.stats.images_received = 350;
    mr.stats.images_applied = 340;
    mr.stats.images_dropped_backlog = 10;
    run.methods.push_back(mr);
  }
  for (int i = 0; i <= n; ++i) {
    const double t = i * kDt;
    TruthSample truth;
    truth.time_s = t;
    truth.camera_frame = true;
    truth.angle_rad = Eigen::Vector3d(0.1, 0.2, 0.3);
    truth.bias_rad = Eigen::Vector3d(0.15, -0.05, 0.0);
    truth.T_camera_ee = {Eigen::Isometry3d::Identity()};
    truth.T_base_camera = Eigen::Isometry3d::Identity();
    truth.camera_offset << 0.01, -0.01, 0.015, 0.0, 0.0, 0.01;
    run.truth.push_back(truth);
    for (MethodRun& mr : run.methods) {
      EstimateSample s;
      s.angle_rad = truth.angle_rad;
      s.angle_std_rad = Eigen::Vector3d::Constant(0.01);
      const double approach = 1.0 - std::exp(-0.5 * t);
      s.bias_rad = truth.bias_rad * approach;
      s.bias_std_rad = Eigen::Vector3d::Constant(0.02 + 0.1 * (1.0 - approach));
      s.camera_offset << 0.01 * approach, -0.01 * approach, 0.015 * approach, 0.01, -0.02, 0.01;
      s.T_camera_ee = {Eigen::Isometry3d::Identity()};
      s.ee_error = {PoseError{error_m(mr.method, t), 0.5 * error_m(mr.method, t)}};
      mr.samples.push_back(s);
    }
  }
  r.runs.push_back(run);

  for (const MethodRun& mr : r.runs[0].methods) {
    MethodResult m{
        mr.method, MethodScores(mr.method, kReportJoints, r.end_effectors), {}, {}, {}, {}, {}};
    m.scores.begin_run();
    for (std::size_t i = 0; i < mr.samples.size(); ++i)
      m.scores.add(r.runs[0].truth[i].time_s, mr.samples[i].ee_error[0]);
    r.method_results.push_back(std::move(m));
  }
  for (MethodResult& m : r.method_results)
    m.summary = m.scores.summary(r.scoring, &r.method_results[0].scores);
  for (MethodResult& m : r.method_results) {
    const std::vector<double> joint_us = {1.5, 2.5, 3.5}, image_ms = {4.0, 6.5, 7.0};
    m.timing.joint_update_us = percentiles(joint_us);
    m.timing.image_update_ms = percentiles(image_ms);
    m.timing.evaluations_per_image = 1234;
  }

  KeptFrame f;
  f.stamp_s = 6.0;
  f.arrival_s = 6.05;
  f.estimate_method = "full_fusion";
  f.observed = DepthImage(40, 30);
  for (int v = 0; v < 30; ++v)
    for (int u = 0; u < 40; ++u) f.observed.at(u, v) = u < 2 ? 0.f : 1.0f + 0.02f * u;
  f.estimate = DepthImage(40, 30);
  for (int v = 10; v < 20; ++v)
    for (int u = 15; u < 30; ++u) f.estimate.at(u, v) = 1.2f;
  r.frames.push_back(f);
  return r;
}

// The <svg ...>...</svg> element whose data-chart is `id` ("" if none).
std::string chart(const std::string& html, const std::string& id) {
  const std::size_t at = html.find("data-chart=\"" + id + "\"");
  if (at == std::string::npos) return "";
  const std::size_t begin = html.rfind("<svg", at);
  const std::size_t end = html.find("</svg>", at);
  return html.substr(begin, end + 6 - begin);
}

// Every opened element is closed in order (void elements and "/>" aside).
// Returns the first problem, or "" if none.
std::string tag_problem(const std::string& html) {
  std::vector<std::string> open;
  for (std::size_t at = html.find('<'); at != std::string::npos; at = html.find('<', at + 1)) {
    const std::size_t end = html.find('>', at);
    if (end == std::string::npos) return "unterminated tag at " + std::to_string(at);
    const std::string tag = html.substr(at + 1, end - at - 1);
    if (tag.starts_with("!")) continue;  // <!DOCTYPE html>
    const bool closing = tag.starts_with("/");
    const std::size_t name_end = tag.find_first_of(" \t\n/", closing ? 1 : 0);
    const std::string name =
        tag.substr(closing ? 1 : 0, name_end == std::string::npos ? std::string::npos
                                                                  : name_end - (closing ? 1 : 0));
    if (closing) {
      if (open.empty() || open.back() != name)
        return "</" + name + "> closes <" + (open.empty() ? "nothing" : open.back()) + ">";
      open.pop_back();
    } else if (!tag.ends_with("/") && name != "meta" && name != "img" && name != "br") {
      open.push_back(name);
    }
  }
  return open.empty() ? "" : "<" + open.back() + "> never closed";
}

// RFC 4648 decoding, written independently of the encoder under test.
std::vector<std::uint8_t> base64_decode(const std::string& text) {
  std::vector<std::uint8_t> out;
  std::uint32_t bits = 0;
  int have = 0;
  for (char c : text) {
    int v;
    if (c >= 'A' && c <= 'Z')
      v = c - 'A';
    else if (c >= 'a' && c <= 'z')
      v = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      v = c - '0' + 52;
    else if (c == '+')
      v = 62;
    else if (c == '/')
      v = 63;
    else
      break;  // '=' padding
    bits = (bits << 6) | std::uint32_t(v);
    have += 6;
    if (have >= 8) {
      have -= 8;
      out.push_back(std::uint8_t((bits >> have) & 0xff));
    }
  }
  return out;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

TEST(Report, EveryChartIsThere) {
  const ScenarioResult r = synthetic_result();
  const std::string html = report_html(r);
  std::vector<std::string> ids = {"box-translation-all", "box-translation-converged",
                                  "box-rotation-all",    "box-rotation-converged",
                                  "error-time",          "consistency-time",
                                  "consistency-legend",  "colours-0",
                                  "bias-legend",         "camera-legend"};
  for (const std::string& j : kReportJoints) ids.push_back("bias-" + j);
  for (const char* k : {"x", "y", "z", "roll", "pitch", "yaw"})
    ids.push_back(std::string("camera-") + k);
  for (const std::string& id : ids) EXPECT_NE(chart(html, id), "") << id;
  EXPECT_EQ(count_occurrences(html, "<svg"), ids.size());
  EXPECT_EQ(count_occurrences(html, "</svg>"), ids.size());
  // One box per method in each box plot, one line per method over time.
  for (const char* id : {"box-translation-all", "box-rotation-converged"})
    EXPECT_EQ(count_occurrences(chart(html, id), "<rect"), 3u) << id;
  EXPECT_EQ(count_occurrences(chart(html, "error-time"), "stroke-width=\"1.6\""), 3u);
  // Bias: estimate and truth lines and the band; camera: the two estimating
  // methods and the truth.
  EXPECT_EQ(count_occurrences(chart(html, "bias-elbow"), "<path"), 3u);
  EXPECT_EQ(count_occurrences(chart(html, "camera-yaw"), "<path"), 3u);
  // 42 mm against 0.2 mm: the translation axis is logarithmic and says so.
  EXPECT_NE(chart(html, "box-translation-all").find("(log scale)"), std::string::npos);
  EXPECT_NE(chart(html, "error-time").find("(log scale)"), std::string::npos);
  EXPECT_EQ(chart(html, "bias-shoulder").find("(log scale)"), std::string::npos);
  // vision_only's lost estimates show as such.
  EXPECT_NE(chart(html, "box-translation-all").find(">lost<"), std::string::npos);
}

// The stroke-dasharray of the first element drawn in black (the truth's
// colour) in `svg`: "" if solid, "none" if there is none.
std::string truth_dash(const std::string& svg) {
  const std::size_t at = svg.find("stroke=\"#000\"");
  if (at == std::string::npos) return "none";
  const std::string attrs = svg.substr(at, svg.find("/>", at) - at);
  const std::string key = "stroke-dasharray=\"";
  const std::size_t d = attrs.find(key);
  if (d == std::string::npos) return "";
  return attrs.substr(d + key.size(), attrs.find('"', d + key.size()) - d - key.size());
}

// The simulator's truths (encoder bias, camera offset) are drawn on their
// charts, and the legends draw them as the charts do: dashed.
TEST(Report, TruthsAreDrawnAsTheirLegendsSay) {
  const std::string html = report_html(synthetic_result());
  EXPECT_NE(chart(html, "bias-legend").find(">true bias</text>"), std::string::npos);
  EXPECT_NE(chart(html, "camera-legend").find(">true offset</text>"), std::string::npos);
  EXPECT_NE(truth_dash(chart(html, "bias-elbow")), "");
  EXPECT_NE(truth_dash(chart(html, "bias-elbow")), "none");
  EXPECT_EQ(truth_dash(chart(html, "bias-legend")), truth_dash(chart(html, "bias-elbow")));
  EXPECT_NE(truth_dash(chart(html, "camera-yaw")), "none");
  EXPECT_EQ(truth_dash(chart(html, "camera-legend")), truth_dash(chart(html, "camera-yaw")));
  // Without camera truth (a dataset), no true offset is drawn and the page says so.
  ScenarioResult r = synthetic_result();
  for (TruthSample& t : r.runs[0].truth) t.T_base_camera.reset();
  const std::string without = report_html(r);
  EXPECT_EQ(truth_dash(chart(without, "camera-yaw")), "none");
  EXPECT_EQ(chart(without, "camera-legend").find("true offset"), std::string::npos);
  EXPECT_NE(without.find("the true camera is not known here"), std::string::npos);
}

TEST(Report, SelfContainedAndWellFormed) {
  const std::string html = report_html(synthetic_result());
  EXPECT_EQ(html.find("http"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(count_occurrences(html, "src=\"data:image/png;base64,"),
            count_occurrences(html, "src=\""));  // only data URIs
  EXPECT_EQ(count_occurrences(html, "src=\""), 1u);
  EXPECT_EQ(html.find("url(http"), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");
  EXPECT_TRUE(html.starts_with("<!DOCTYPE html>"));
}

TEST(Report, TagCheckerFindsProblems) {
  EXPECT_NE(tag_problem("<svg><g></svg>"), "");
  EXPECT_NE(tag_problem("<div><svg></svg>"), "");
  EXPECT_EQ(tag_problem("<div><img src=\"x\"><line/></div>"), "");
}

TEST(Report, ShowsTheSummaryNumbers) {
  const ScenarioResult r = synthetic_result();
  const std::string html = report_html(r);
  EXPECT_NE(html.find("<td>42.10</td>"), std::string::npos);  // encoders_only's constant error, mm
  EXPECT_NE(html.find("<td>1.206</td>"), std::string::npos);  // its rotation: 21.05 mrad in degrees
  // Every finite percentile of the summary, in mm (2 decimals) and degrees (3).
  for (const MethodResult& m : r.method_results) {
    for (const ErrorStats* s : {&m.summary.all, &m.summary.converged}) {
      const Percentiles& t = s->translation_m;
      const Percentiles& a = s->rotation_rad;
      for (const auto& [v, text] : {std::pair{t.p01, fixed(t.p01 * 1e3, 2)},
                                    {t.p25, fixed(t.p25 * 1e3, 2)},
                                    {t.p50, fixed(t.p50 * 1e3, 2)},
                                    {t.p75, fixed(t.p75 * 1e3, 2)},
                                    {t.p99, fixed(t.p99 * 1e3, 2)},
                                    {a.p01, fixed(a.p01 * 180 / M_PI, 3)},
                                    {a.p25, fixed(a.p25 * 180 / M_PI, 3)},
                                    {a.p50, fixed(a.p50 * 180 / M_PI, 3)},
                                    {a.p75, fixed(a.p75 * 180 / M_PI, 3)},
                                    {a.p99, fixed(a.p99 * 180 / M_PI, 3)}}) {
        if (std::isfinite(v)) {
          EXPECT_NE(html.find("<td>" + text + "</td>"), std::string::npos) << m.method << " " << v;
        }
      }
    }
  }
  EXPECT_NE(html.find("<td>&infin;</td>"), std::string::npos);  // vision_only's p99: lost
  EXPECT_NE(html.find("<td>2.50</td>"), std::string::npos);     // joint update p50, us
  EXPECT_NE(html.find("<td>6.50</td>"), std::string::npos);     // image update p50, ms
  EXPECT_NE(html.find("<td>1234</td>"), std::string::npos);     // evaluations per image
  // full_fusion converges when its error drops below 10 mm: 0.2 + 40 exp(-t) < 10 for t > 1.41 s,
  // the first sample after is at 1.5 s; the others never converge.
  EXPECT_NE(html.find("<td>1.5</td>"), std::string::npos);
  // In the summary table (the verdict at the top says "never" for them too).
  EXPECT_EQ(count_occurrences(html.substr(html.find("<h2>End-effector errors")), "<td>never</td>"),
            2u);
  EXPECT_EQ(count_occurrences(html, "<td>never</td>"), 4u);
  // The JSON itself, folded in.
  EXPECT_NE(html.find(summary_json(r)), std::string::npos);
  // Header facts.
  for (const char* s :
       {"synthetic", "scenarios/synthetic.yaml", "4242", "12.0 s", "vision_only", "from 5.0 s on"})
    EXPECT_NE(html.find(s), std::string::npos) << s;
}

TEST(Report, EmptyConvergedWindowSaysNoSamples) {
  ScenarioResult r = synthetic_result();
  r.scoring.converged_after_s = 100.0;  // beyond the run
  for (MethodResult& m : r.method_results) m.summary = m.scores.summary(r.scoring);
  const std::string html = report_html(r);
  EXPECT_NE(chart(html, "box-translation-converged").find("no samples"), std::string::npos);
  EXPECT_EQ(chart(html, "box-translation-all").find("no samples"), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");
  // It says why, at the top, and a run long enough does not.
  EXPECT_NE(html.find("Short run:"), std::string::npos);
  EXPECT_EQ(report_html(synthetic_result()).find("Short run:"), std::string::npos);
}

// The page opens with its answer: a verdict row per method and the best
// method among those never lost.
TEST(Report, OpensWithAVerdictPerMethod) {
  const ScenarioResult r = synthetic_result();
  const std::string html = report_html(r);
  const std::size_t verdict = html.find("<h2>Verdict</h2>");
  ASSERT_NE(verdict, std::string::npos);
  EXPECT_LT(verdict, html.find("<h2>End-effector errors per method</h2>"));
  const std::string table = html.substr(verdict, html.find("</table>", verdict) - verdict);
  for (const MethodResult& m : r.method_results)
    EXPECT_NE(table.find(">" + m.method + "<"), std::string::npos) << m.method;
  EXPECT_NE(html.find("Best: <strong>", verdict), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");
}

TEST(Report, EmptyResultGivesAPageSayingSo) {
  const std::string html = report_html(ScenarioResult{});
  EXPECT_EQ(tag_problem(html), "");
  EXPECT_NE(html.find("full_fusion was not run"), std::string::npos);
  EXPECT_NE(html.find("No depth frame was kept"), std::string::npos);
}

TEST(Report, SeveralRunsPlotTheMedian) {
  ScenarioResult r = synthetic_result();
  r.runs.push_back(r.runs[0]);
  r.runs.push_back(r.runs[0]);
  r.seeds = {1, 2, 3};
  const std::string html = report_html(r);
  EXPECT_NE(chart(html, "error-time").find("median over 3 runs"), std::string::npos);
}

// The frame of the two-hand results below: 20 s, two runs (`seeds`),
// encoders_only and full_fusion, one joint, left_ee and right_ee; no
// samples.
ScenarioResult two_hands_frame(const std::string& scenario, std::vector<std::uint64_t> seeds) {
  ScenarioResult r;
  r.scenario = scenario;
  r.duration_s = 20;
  r.seeds = std::move(seeds);
  r.methods = {"encoders_only", "full_fusion"};
  r.joint_names = {"j"};
  r.end_effectors = {"left_ee", "right_ee"};
  return r;
}

// Two hands, two runs of 20 s: full_fusion's right hand is 300 mm off from
// 12 s on in run 1 (lost), the left hand always 2 mm; encoders_only 40 mm on
// both. full_fusion reports angle standard deviations of 1 mrad for errors
// of 3 mrad (never within 2 sigma) and biases within them; encoders_only
// reports no bias standard deviation (not estimated). From 10 s on,
// full_fusion's angle standard deviation is angle_std_from_10s_rad.
ScenarioResult two_hands_result(double angle_std_from_10s_rad = 0.001) {
  ScenarioResult r = two_hands_frame("two_hands", {11, 22});
  for (const std::string& m : r.methods)
    r.method_results.push_back(
        {m, MethodScores(m, r.joint_names, r.end_effectors), {}, {}, {}, {}, {}});
  for (int k = 0; k < 2; ++k) {
    RunResult run;
    run.run = k;
    run.seed = r.seeds[k];
    for (const std::string& m : r.methods) run.methods.push_back({m, {}, {}, {}, {}});
    for (MethodResult& m : r.method_results) m.scores.begin_run();
    for (int i = 0; i <= 40; ++i) {
      TruthSample truth;
      truth.time_s = 0.5 * i;
      truth.angle_rad = truth.bias_rad = Eigen::VectorXd::Zero(1);
      truth.T_camera_ee = {Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()};
      run.truth.push_back(truth);
      for (std::size_t m = 0; m < 2; ++m) {
        const bool fusion = m == 1;
        ScoredSample x;
        x.time_s = truth.time_s;
        const double right = fusion ? (k == 1 && truth.time_s >= 12 ? 0.3 : 0.002) : 0.04;
        x.end_effectors = {{fusion ? 0.002 : 0.04, 0.01}, {right, 0.01}};
        x.end_effector_in_view = {true, truth.time_s < 16};  // the right hand leaves at 16 s
        x.angle_error_rad = {0.003};
        x.angle_std_rad = {fusion ? (truth.time_s < 10 ? 0.001 : angle_std_from_10s_rad) : 0.01};
        x.bias_error_rad = {0.0};
        x.bias_std_rad = {fusion ? 0.01 : 0.0};
        r.method_results[m].scores.add(x);
        EstimateSample s;  // the same errors and standard deviations
        s.angle_rad = Eigen::VectorXd::Constant(1, x.angle_error_rad[0]);
        s.angle_std_rad = Eigen::VectorXd::Constant(1, x.angle_std_rad[0]);
        s.bias_rad = Eigen::VectorXd::Zero(1);
        s.bias_std_rad = Eigen::VectorXd::Constant(1, x.bias_std_rad[0]);
        s.ee_error = x.end_effectors;
        run.methods[m].samples.push_back(s);
      }
    }
    r.runs.push_back(run);
  }
  for (MethodResult& m : r.method_results)
    m.summary = m.scores.summary(r.scoring, &r.method_results[0].scores);
  return r;
}

TEST(RunOutputs, EveryEndEffectorHasItsRowsAndTheWorstAndLostRunsAreCounted) {
  const ScenarioResult r = two_hands_result();
  // summary.json: per end effector, the worst at the top, lost runs listed.
  const std::string json = summary_json(r);
  const std::string fusion = json.substr(json.find("\"full_fusion\": {"));
  for (const char* key :
       {"\"end_effectors\": {", "\"left_ee\": {", "\"right_ee\": {", "\"lost_runs\": 1",
        "\"runs\": 1", "\"of\": 2", "\"end_effector\": \"right_ee\"", "\"seed\": 22",
        "\"from_s\": 12.0", "\"duration_s\": 8.0", "\"out_of_view_share\": 0.529",
        "\"stretches\": 1", "\"total_s\": 8.0", "\"angles\": 0.0", "\"biases\": 1.0",
        "\"camera_offset\": null", "\"camera\": null", "\"angle_within_2sigma\": 0.0"})
    EXPECT_NE(fusion.find(key), std::string::npos) << key;
  const std::string encoders = json.substr(0, json.find("\"full_fusion\": {"));
  EXPECT_NE(encoders.find("\"biases\": null"), std::string::npos);  // not estimated, not 0%
  EXPECT_NE(encoders.find("\"angles\": 1.0"), std::string::npos);
  EXPECT_NE(json.find("\"lost_threshold_m\": 0.02"), std::string::npos);
  // The worst's p99 is the lost hand's 300 mm; the left hand's stays 2 mm.
  EXPECT_NEAR(r.method("full_fusion")->summary.all.translation_m.p99, 0.3, 1e-12);
  EXPECT_NEAR(r.method("full_fusion")->summary.end_effectors[0].all.translation_m.p99, 0.002,
              1e-12);

  // The terminal: a row per hand and the worst, per method.
  std::ostringstream table;
  print_summary_table(table, r);
  const std::string t = table.str();
  std::vector<std::string> rows;
  std::istringstream lines(t);
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  auto row_of = [&](const std::string& method, const std::string& ee) {
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rows[i].starts_with(method))
        for (std::size_t k = i; k < i + 3 && k < rows.size(); ++k)
          if (rows[k].find(" " + ee + " ") != std::string::npos) return rows[k];
    return std::string();
  };
  for (const char* m : {"encoders_only", "full_fusion"})
    for (const char* e : {"left_ee", "right_ee", "worst"})
      EXPECT_NE(row_of(m, e), "") << m << " " << e << "\n" << t;
  EXPECT_TRUE(row_of("full_fusion", "worst").ends_with("1 of 2")) << t;
  EXPECT_TRUE(row_of("full_fusion", "right_ee").ends_with("1 of 2")) << t;
  EXPECT_TRUE(row_of("full_fusion", "left_ee").ends_with("0 of 2")) << t;
  EXPECT_NE(row_of("full_fusion", "worst").find("300.0"), std::string::npos) << t;
  EXPECT_EQ(row_of("full_fusion", "left_ee").find("300.0"), std::string::npos) << t;
  // Out of view from 16 s: 9 of the span's 17 samples (12, 12.5, ..., 20 s).
  EXPECT_NE(t.find("full_fusion lost 1 of 2: run 1 (seed 22): right_ee from 12.0 s for 8.0 s "
                   "(out of the camera's view for 53% of it)\n"),
            std::string::npos)
      << t;

  // The report: the same rows, the lost run, consistency.
  const std::string html = report_html(r);
  EXPECT_EQ(count_occurrences(html, "<td class=\"m\">right_ee</td>"), 4u);  // 2 methods x 2 tables
  EXPECT_EQ(count_occurrences(html, "<td class=\"m\">worst</td>"), 4u);
  EXPECT_NE(html.find("<td>1 of 2</td>"), std::string::npos);
  EXPECT_NE(html.find("<li>full_fusion: run 1 (seed 22), right_ee, from 12.00&nbsp;s"),
            std::string::npos);
  EXPECT_NE(html.find("view for 53% of it</li>"), std::string::npos);
  EXPECT_NE(html.find("<td>not estimated</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>0.0%</td>"), std::string::npos);
  EXPECT_NE(html.find("worst of left_ee, right_ee"), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");
}

// Consistency over all samples and from the converged window on: too sure
// for the first 10 s (3 mrad off, 1 mrad claimed), honest after (10 mrad).
TEST(RunOutputs, ConsistencyIsShownOverAllSamplesAndFromTheConvergedWindow) {
  const ScenarioResult r = two_hands_result(0.01);
  const MethodSummary& fusion = r.method("full_fusion")->summary;
  EXPECT_NEAR(fusion.all.angle_coverage.fraction(), 21.0 / 41, 1e-12);  // 10, 10.5, ..., 20 s
  EXPECT_EQ(fusion.converged.angle_coverage.fraction(), 1.0);

  std::ostringstream table;
  print_summary_table(table, r);
  const std::string t = table.str();
  EXPECT_NE(t.find("truth within 2 sigma, all samples"), std::string::npos) << t;
  const std::size_t row = t.find("\nfull_fusion                51.2%");
  ASSERT_NE(row, std::string::npos) << t;
  EXPECT_NE(t.find("\n  from 10 s on            100.0%      100.0%", row), std::string::npos) << t;
  // No camera truth here: no line of the camera's axes (the CLI test
  // cli_accuracy_table_pool reads them from a run that has one).
  EXPECT_EQ(t.find("camera within 2 sigma"), std::string::npos) << t;

  const std::string html = report_html(r);
  EXPECT_NE(html.find("within 2&sigma;, from 10.0&nbsp;s on"), std::string::npos);
  // Over time, in 5 s bins from the runs' samples: what the scorer counts.
  const std::vector<ConsistencyBin> bins = consistency_over_time(r, "full_fusion", 5.0);
  ASSERT_EQ(bins.size(), 4u);
  Coverage pooled;
  for (std::size_t b = 0; b < bins.size(); ++b) {
    EXPECT_EQ(bins[b].from_s, 5.0 * double(b));
    EXPECT_EQ(bins[b].angles.fraction(), b < 2 ? 0.0 : 1.0) << b;
    EXPECT_EQ(bins[b].biases.fraction(), 1.0) << b;
    EXPECT_EQ(bins[b].camera.estimated, 0u);  // no camera truth
    pooled += bins[b].angles;
  }
  EXPECT_EQ(bins[3].angles.estimated, 2u * 11);  // 15, 15.5, ..., 20 s (the end in the last)
  EXPECT_EQ(pooled.estimated, fusion.all.angle_coverage.estimated);
  EXPECT_EQ(pooled.within, fusion.all.angle_coverage.within);
  EXPECT_TRUE(consistency_over_time(r, "full_fusion", 0.0).empty());
  EXPECT_NE(chart(html, "consistency-time"), "");
  // Angles, biases, camera, end-effector position and rotation (no
  // covariance in these samples), then the converged window's.
  EXPECT_NE(html.find("<td>51.2%</td><td>100.0%</td><td>not estimated</td><td>not estimated</td>"
                      "<td>not estimated</td><td>100.0%</td>"),
            std::string::npos);
  EXPECT_EQ(html.find("camera offset within 2&sigma; per axis"), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");

  // With camera truth, one row per such method: every axis, all samples /
  // converged (pitch never covered, the rest always, here).
  ScenarioResult with_camera = r;
  for (MethodResult& m : with_camera.method_results) {
    if (m.method != "full_fusion") continue;
    for (std::size_t k = 0; k < 6; ++k) {
      m.summary.all.camera_axis_coverage[k] = Coverage{10, k == 4 ? 0u : 10u};
      m.summary.converged.camera_axis_coverage[k] = Coverage{4, k == 4 ? 0u : 4u};
      m.summary.all.camera_offset_coverage += m.summary.all.camera_axis_coverage[k];
    }
  }
  const std::string camera_html = report_html(with_camera);
  EXPECT_NE(camera_html.find("camera offset within 2&sigma; per axis"), std::string::npos);
  EXPECT_NE(camera_html.find("<th>roll</th><th>pitch</th><th>yaw</th>"), std::string::npos);
  EXPECT_NE(camera_html.find("<tr><td class=\"m\">full_fusion</td><td>100.0% / 100.0%</td>"),
            std::string::npos);
  EXPECT_NE(camera_html.find("<td>0.0% / 0.0%</td><td>100.0% / 100.0%</td></tr>"),
            std::string::npos);
  EXPECT_EQ(count_occurrences(camera_html, "<td>100.0% / 100.0%</td>"),
            5u);  // encoders_only has no row
  EXPECT_EQ(tag_problem(camera_html), "");
}

// TrackingHealth::links: per link, the median of the runs' last estimates
// over the runs that pinned (sized) it, named in summary.json, the
// terminal table (the three furthest, the three scales furthest from 0)
// and the report; a method without the list has none.
TEST(RunOutputs, TheLinksFurthestFromTheModelAreNamed) {
  ScenarioResult r = two_hands_result();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // full_fusion's last samples: run 0 and run 1. "hand" is pinned in run 1
  // only; "base" in none; an earlier sample (run 0) must not count. The
  // forearm is sized in both runs, the hand in run 0, the others in none.
  const std::vector<std::vector<TrackingHealth::LinkModelError>> last = {
      {{"base", nan, 0},
       {"forearm", 0.004, 30, 0.03, 30},
       {"upper", 0.001, 30},
       {"hand", nan, 0, -0.02, 40}},
      {{"base", nan, 0},
       {"forearm", 0.006, 30, 0.05, 30},
       {"upper", 0.003, 30},
       {"hand", 0.0015, 4}}};
  for (std::size_t k = 0; k < 2; ++k) {
    std::vector<EstimateSample>& samples = r.runs[k].methods[1].samples;
    samples[samples.size() - 2].health.links = {{"forearm", 0.05, 1}};
    samples.back().health.links = last[k];
  }
  for (std::size_t m = 0; m < r.method_results.size(); ++m)
    r.method_results[m].links = link_model_fits(r.runs, m);
  EXPECT_TRUE(r.method_results[0].links.empty());  // encoders_only reports none
  const std::vector<LinkModelFit>& fits = r.method_results[1].links;
  ASSERT_EQ(fits.size(), 4u);
  EXPECT_EQ(fits[0].runs_pinned, 0);
  EXPECT_TRUE(std::isnan(fits[0].median_shift_m));
  EXPECT_EQ(fits[1].link, "forearm");
  EXPECT_EQ(fits[1].runs_pinned, 2);
  EXPECT_NEAR(fits[1].median_shift_m, 0.005, 1e-12);
  EXPECT_NEAR(fits[2].median_shift_m, 0.002, 1e-12);
  EXPECT_EQ(fits[3].runs_pinned, 1);
  EXPECT_NEAR(fits[3].median_shift_m, 0.0015, 1e-12);
  EXPECT_EQ(fits[0].runs_scaled, 0);
  EXPECT_TRUE(std::isnan(fits[0].median_scale));
  EXPECT_EQ(fits[1].runs_scaled, 2);
  EXPECT_NEAR(fits[1].median_scale, 0.04, 1e-12);
  EXPECT_EQ(fits[3].runs_scaled, 1);
  EXPECT_NEAR(fits[3].median_scale, -0.02, 1e-12);

  const std::string json = summary_json(r);
  EXPECT_NE(json.find("\"links_model_error\": {\n        \"base\": {\n          "
                      "\"pinned_shift_m\": null,\n          \"runs_pinned\": 0"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"forearm\": {\n          \"pinned_shift_m\": 0.005,\n          "
                      "\"runs_pinned\": 2,\n          \"scale\": 0.04,\n          "
                      "\"runs_scaled\": 2"),
            std::string::npos)
      << json;
  EXPECT_EQ(count_occurrences(json, "links_model_error"), 1u);  // full_fusion only
  std::ostringstream table;
  print_summary_table(table, r);
  EXPECT_NE(table.str().find("full_fusion, links furthest from the model (pinned surface shift, "
                             "median of the runs' last estimates): forearm 5.0 mm, upper 2.0 mm, "
                             "hand 1.5 mm; 1 of 4 links never pinned\n"),
            std::string::npos)
      << table.str();
  EXPECT_NE(table.str().find("full_fusion, links whose size differs most from the model (scale, "
                             "median of the runs' last estimates): forearm +4.0%, hand -2.0%; 2 "
                             "of 4 links never sized\n"),
            std::string::npos)
      << table.str();
  // A model that fits: no link is named.
  ScenarioResult exact = r;
  for (LinkModelFit& l : exact.method_results[1].links)
    if (l.runs_pinned > 0) l.median_shift_m = 0.0;
  std::ostringstream exact_table;
  print_summary_table(exact_table, exact);
  EXPECT_NE(exact_table.str().find("median of the runs' last estimates): none, every pinned link "
                                   "within 0.1 mm; 1 of 4 links never pinned\n"),
            std::string::npos)
      << exact_table.str();
  const std::string html = report_html(r);
  EXPECT_NE(html.find("<tr><td class=\"m\">forearm</td><td>5.0&nbsp;mm (2/2), scale "
                      "+4.0%</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"m\">hand</td><td>1.5&nbsp;mm (1/2), scale -2.0%</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"m\">base</td><td>not pinned</td></tr>"), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");
}

// two_hands_result() whose full_fusion measured each run's encoder noise
// (0.003 and 0.005 in the readings' unit, and 1.0 just before: not the
// last estimate), with the methods' medians.
ScenarioResult measured_noise_result() {
  ScenarioResult r = two_hands_result();
  for (std::size_t k = 0; k < 2; ++k) {
    std::vector<EstimateSample>& samples = r.runs[k].methods[1].samples;
    samples[samples.size() - 2].health.encoder_noise_measured_rad = {1.0};  // must not count
    samples.back().health.encoder_noise_measured_rad = {k == 0 ? 0.003 : 0.005};
  }
  for (std::size_t m = 0; m < r.method_results.size(); ++m)
    r.method_results[m].encoder_noise_rad = encoder_noise_medians_rad(r.runs, m);
  return r;
}

// TrackingHealth::encoder_noise_measured_rad: per joint, the median of the
// runs' last estimates, in summary.json, the terminal table and the
// report (degrees, the unit of encoder_noise_deg); a method whose
// estimates have none gets none of them.
TEST(RunOutputs, TheEncodersNoiseIsReportedAsMeasured) {
  const ScenarioResult r = measured_noise_result();
  EXPECT_TRUE(r.method_results[0].encoder_noise_rad.empty());
  ASSERT_EQ(r.method_results[1].encoder_noise_rad.size(), 1u);
  EXPECT_NEAR(r.method_results[1].encoder_noise_rad[0], 0.004, 1e-12);

  const std::string json = summary_json(r);
  EXPECT_NE(json.find("\"encoder_noise_measured_rad\": {\n        \"j\": 0.004\n      }"),
            std::string::npos)
      << json;
  EXPECT_EQ(count_occurrences(json, "encoder_noise_measured_rad"), 1u);
  std::ostringstream table;
  print_summary_table(table, r);
  EXPECT_NE(table.str().find("full_fusion, encoders' white noise as measured (median of the runs' "
                             "last estimates): 0.2292 deg (j)\n"),
            std::string::npos)
      << table.str();
  EXPECT_EQ(table.str().find("encoders_only, encoders'"), std::string::npos);
  EXPECT_NE(json.find("\"prismatic_joints\": []"), std::string::npos) << json;
  const std::string html = report_html(r);
  EXPECT_NE(html.find("<tr><td class=\"m\">j</td><td>deg</td><td>0.2292</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("bias, deg"), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");
}

// A prismatic joint's readings are metres: its measured noise is printed in
// mm, apart from the revolute joints', its bias is drawn in mm, and
// summary.json names it among prismatic_joints.
TEST(RunOutputs, APrismaticJointIsReportedInMillimetres) {
  ScenarioResult r = measured_noise_result();
  r.prismatic = {1};
  std::ostringstream table;
  print_summary_table(table, r);
  EXPECT_NE(table.str().find("full_fusion, encoders' white noise as measured (median of the runs' "
                             "last estimates): prismatic joints 4.000 mm (j)\n"),
            std::string::npos)
      << table.str();
  EXPECT_NE(summary_json(r).find("\"prismatic_joints\": [\n    \"j\"\n  ]"), std::string::npos)
      << summary_json(r);
  const std::string html = report_html(r);
  EXPECT_NE(html.find("<tr><td class=\"m\">j</td><td>mm</td><td>4.000</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("bias, mm"), std::string::npos);
  EXPECT_EQ(html.find("bias, deg"), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");
}

// TrackingHealth's counters: each run's last estimate (the counts so far),
// summed over runs, in summary.json and the terminal table; a method that
// counted nothing (encoders only) gets no line.
TEST(RunOutputs, TheTrackersCountsAreSummedOverRuns) {
  ScenarioResult r = two_hands_result();
  for (std::size_t k = 0; k < 2; ++k) {
    std::vector<EstimateSample>& samples = r.runs[k].methods[1].samples;
    TrackingHealth& earlier = samples[samples.size() - 2].health;  // must not count
    earlier.acquisitions = 100, earlier.hand_searches = 1000;
    TrackingHealth& last = samples.back().health;
    last.acquisitions = int(k) + 1, last.chains_reacquired = int(k);
    last.refinements_accepted = 40 + int(k);
    last.unseen_priors_kept = 7 * int(k);
    last.images_with_unseen_motion = 5 + 3 * int(k);
    last.hand_searches = 300, last.hand_shifts_accepted = k == 0 ? 100 : 125;
  }
  for (std::size_t m = 0; m < r.method_results.size(); ++m)
    r.method_results[m].counts = health_counts(r.runs, m);
  const HealthCounts& c = r.method_results[1].counts;
  EXPECT_EQ(c.runs, 2);
  EXPECT_EQ(c.acquisitions, 3);
  EXPECT_EQ(c.chains_reacquired, 1);
  EXPECT_EQ(c.refinements_accepted, 81);
  EXPECT_EQ(c.unseen_priors_kept, 7);
  EXPECT_EQ(c.images_with_unseen_motion, 13);
  EXPECT_EQ(c.hand_searches, 600);
  EXPECT_EQ(c.hand_shifts_accepted, 225);
  EXPECT_EQ(r.method_results[0].counts.hand_searches, 0);

  const std::string json = summary_json(r);
  EXPECT_NE(
      json.find("\"health_counts\": {\n        \"runs\": 2,\n        \"acquisitions\": 3,\n"
                "        \"chains_reacquired\": 1,\n        \"refinements_accepted\": 81,\n"
                "        \"unseen_priors_kept\": 7,\n        \"images_with_unseen_motion\": "
                "13,\n        \"hand_searches\": 600,\n        \"hand_shifts_accepted\": 225\n"
                "      }"),
      std::string::npos)
      << json;
  EXPECT_EQ(count_occurrences(json, "health_counts"),
            2u);  // every method, encoders_only's zeros too
  std::ostringstream table;
  print_summary_table(table, r);
  EXPECT_NE(table.str().find("full_fusion, counts summed over runs (2): searches 3 (chains that "
                             "took one's result 1), refinement steps taken 81 (images with a "
                             "motion they cannot see 13), joints unseen kept "
                             "at their prior 7, hand fits searched along the hand 600 "
                             "(shifted 225, 38%)\n"),
            std::string::npos)
      << table.str();
  EXPECT_EQ(table.str().find("encoders_only, counts"), std::string::npos);
}

// Two hands, two runs of 20 s, each estimate scored by score_estimate as a
// run scores it. full_fusion's pose errors spread 2 mm and 10 mrad per
// component; it reports half that before 10 s (too sure) and that after,
// and 0 (not estimated) for the right hand's z position. encoders_only
// reports no pose covariance.
ScenarioResult scored_poses_result() {
  ScenarioResult r = two_hands_frame("scored_poses", {5, 6});
  std::vector<MethodScores> scores;
  for (const std::string& m : r.methods) scores.emplace_back(m, r.joint_names, r.end_effectors);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 2; ++k) {
    RunResult run;
    run.run = k;
    run.seed = r.seeds[k];
    for (const std::string& m : r.methods) run.methods.push_back({m, {}, {}, {}, {}});
    for (MethodScores& s : scores) s.begin_run();
    for (int i = 0; i <= 40; ++i) {
      TruthSample truth;
      truth.time_s = 0.5 * i;
      truth.angle_rad = truth.bias_rad = Eigen::VectorXd::Zero(1);
      for (int e = 0; e < 2; ++e) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.translate(Eigen::Vector3d(e ? 0.2 : -0.2, 0.1, 0.8));
        T.rotate(Eigen::AngleAxisd(0.3 + 0.05 * i, Eigen::Vector3d(1, 2, 3).normalized()));
        truth.T_camera_ee.push_back(T);
      }
      for (std::size_t m = 0; m < r.methods.size(); ++m) {
        TrackerEstimate est;
        est.angle_rad = est.bias_rad = est.bias_std_rad = Eigen::VectorXd::Zero(1);
        est.angle_std_rad = Eigen::VectorXd::Constant(1, 0.01);
        for (int e = 0; e < 2; ++e) {
          PoseErrorVector error, sd;
          for (int c = 0; c < 6; ++c) error[c] = (c < 3 ? 0.002 : 0.01) * normal(rng);
          sd << 0.002, 0.002, e == 1 ? 0.0 : 0.002, 0.01, 0.01, 0.01;
          if (truth.time_s < 10) sd *= 0.5;
          Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
          T.translation() = truth.T_camera_ee[e].translation() + error.head<3>();
          T.linear() = Eigen::AngleAxisd(error.tail<3>().norm(), error.tail<3>().normalized())
                           .toRotationMatrix() *
                       truth.T_camera_ee[e].linear();
          est.T_camera_ee.push_back(T);
          if (r.methods[m] == "full_fusion")
            est.T_camera_ee_covariance.push_back(sd.cwiseAbs2().asDiagonal());
        }
        ScoredSample scored;
        run.methods[m].samples.push_back(score_estimate(est, truth, nullptr, true, true, scored));
        scores[m].add(scored);
      }
      run.truth.push_back(truth);
    }
    r.runs.push_back(run);
  }
  summarise_methods(r, scores, true);
  return r;
}

// The end-effector poses over time: the bins count what the scorer's
// ErrorStats count (pooled over the end effectors), and the chart draws
// them as its legend says.
TEST(Report, ConsistencyOverTimeCountsTheEndEffectorPosesAsTheScorerDoes) {
  const ScenarioResult r = scored_poses_result();
  const MethodSummary& fusion = r.method("full_fusion")->summary;
  ASSERT_EQ(r.scoring.converged_after_s, 10.0);
  const std::vector<ConsistencyBin> bins = consistency_over_time(r, "full_fusion", 5.0);
  ASSERT_EQ(bins.size(), 4u);
  Coverage position, rotation, converged_position, converged_rotation;
  for (std::size_t b = 0; b < bins.size(); ++b) {
    position += bins[b].end_effector_position;
    rotation += bins[b].end_effector_rotation;
    if (bins[b].from_s >= r.scoring.converged_after_s) {
      converged_position += bins[b].end_effector_position;
      converged_rotation += bins[b].end_effector_rotation;
    }
    // Too sure before 10 s (within 2 claimed sigma: within 1 true), honest after.
    for (const Coverage* c : {&bins[b].end_effector_position, &bins[b].end_effector_rotation}) {
      if (b < 2)
        EXPECT_LT(c->fraction(), 0.85) << b;
      else
        EXPECT_GT(c->fraction(), 0.85) << b;
    }
  }
  // Every sample of both runs and both hands: three position components but
  // the right hand's z, three rotation components.
  EXPECT_EQ(position.estimated, 2u * 41 * (3 + 2));
  EXPECT_EQ(rotation.estimated, 2u * 41 * 6);
  const auto expect_same = [](const Coverage& bins, const Coverage& scorer, const char* what) {
    EXPECT_EQ(bins.estimated, scorer.estimated) << what;
    EXPECT_EQ(bins.within, scorer.within) << what;
  };
  expect_same(position, fusion.all.end_effector_position_coverage, "position");
  expect_same(rotation, fusion.all.end_effector_rotation_coverage, "rotation");
  expect_same(converged_position, fusion.converged.end_effector_position_coverage,
              "converged position");
  expect_same(converged_rotation, fusion.converged.end_effector_rotation_coverage,
              "converged rotation");
  // No covariance reported: nothing counted, here or by the scorer.
  EXPECT_EQ(r.method("encoders_only")->summary.all.end_effector_position_coverage.estimated, 0u);
  for (const ConsistencyBin& b : consistency_over_time(r, "encoders_only", 5.0)) {
    EXPECT_EQ(b.end_effector_position.estimated, 0u);
    EXPECT_EQ(b.end_effector_rotation.estimated, 0u);
  }

  // full_fusion's two lines, in the strokes the legend gives them.
  const std::string html = report_html(r);
  const std::string lines = chart(html, "consistency-time");
  const std::string legend = chart(html, "consistency-legend");
  for (const char* dash : {"8 3 1.5 3", "8 3 1.5 3 1.5 3"}) {
    const std::string attribute = std::string("stroke-dasharray=\"") + dash + "\"";
    EXPECT_EQ(count_occurrences(lines, attribute), 1u) << dash;
    EXPECT_EQ(count_occurrences(legend, attribute), 1u) << dash;
  }
  // The legend's sample of an entry: its markup after the previous entry's name.
  const auto sample_of = [&legend](const std::string& name) {
    const std::size_t at = legend.find(">" + name + "</text>");
    if (at == std::string::npos) return std::string();
    const std::size_t from = legend.rfind("</text>", at);
    return from == std::string::npos ? legend.substr(0, at) : legend.substr(from, at - from);
  };
  EXPECT_NE(sample_of("end-effector position").find("stroke-dasharray=\"8 3 1.5 3\""),
            std::string::npos);
  EXPECT_NE(sample_of("end-effector rotation").find("stroke-dasharray=\"8 3 1.5 3 1.5 3\""),
            std::string::npos);
  EXPECT_NE(html.find("three position and three rotation components"), std::string::npos);
  EXPECT_EQ(tag_problem(html), "");
}

TEST(Report, EmbeddedFrameShowsDepthAndSilhouette) {
  const std::string html = report_html(synthetic_result());
  const std::string key = "src=\"data:image/png;base64,";
  const std::size_t at = html.find(key);
  ASSERT_NE(at, std::string::npos);
  const std::size_t begin = at + key.size();
  int w = 0, h = 0;
  const std::vector<std::uint8_t> rgb =
      test::decode_png_rgb(base64_decode(html.substr(begin, html.find('"', begin) - begin)), w, h);
  ASSERT_EQ(w, 40);
  ASSERT_EQ(h, 30);
  auto pixel = [&](int u, int v) {
    const std::uint8_t* p = &rgb[(std::size_t(v) * 40 + u) * 3];
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  const std::array<int, 3> white{255, 255, 255}, black{0, 0, 0};
  EXPECT_EQ(pixel(0, 0), black);    // no return
  EXPECT_EQ(pixel(15, 14), white);  // the estimate's left edge
  EXPECT_EQ(pixel(22, 10), white);  // its top edge
  EXPECT_EQ(pixel(29, 19), white);  // its corner
  EXPECT_NE(pixel(22, 14), white);  // inside: the observed depth shows
  EXPECT_NE(pixel(22, 14), black);
  EXPECT_NE(pixel(5, 5), white);  // outside
  // Near is red, far is blue.
  EXPECT_GT(pixel(3, 25)[0], pixel(3, 25)[2]);
  EXPECT_LT(pixel(39, 25)[0], pixel(39, 25)[2]);
}

TEST(Report, WritesTheFileOrNamesIt) {
  const ScenarioResult r = synthetic_result();
  const test_support::ScratchDir scratch("report_test");
  const fs::path& dir = scratch.path();
  write_report_html(dir / "report.html", r);
  std::ifstream in(dir / "report.html", std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), report_html(r));
  try {
    write_report_html(dir / "no_such_dir" / "report.html", r);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_dir"), std::string::npos);
  }
}

}  // namespace
}  // namespace arttrack::sim
