// A scenario run as one self-contained HTML page (DIR/report.html of
// `arttrack run`): inline SVG charts and CSS, depth frames embedded as PNG
// data URIs; no script, no network, no other file.
//
// The page shows: the scenario (name, file, duration, runs, seeds, methods);
// box plots per method of the end-effector translation (mm) and rotation
// (degrees) errors, over all samples and after convergence, as the paper's
// Fig. 5-7 (box p25-p75, ticks at p1, p50, p99; log axis when the values
// span more than about two decades); the translation error over time (run 0,
// or the median over runs); full_fusion's estimated against true encoder
// bias per joint (estimate +- one standard deviation); the camera offset
// estimates; the kept depth frames (observed depth in false colour, the
// estimate's silhouette edges in white); and the summary table (the numbers
// of summary.json) with the timings.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "arttrack/sim/scenario_runner.h"

namespace arttrack::sim {

// The report page as HTML text.
std::string report_html(const ScenarioResult& result);

// Writes report_html(result) to `file`. Cannot write: InputError naming the file.
void write_report_html(const std::filesystem::path& file, const ScenarioResult& result);

// Standard base64 (RFC 4648 alphabet, '=' padding, no line breaks).
std::string base64_encode(std::span<const std::uint8_t> bytes);

// An 8-bit RGB image (row-major, 3 bytes per pixel, width * height * 3
// bytes) encoded as a PNG file in memory. Throws InputError on a size
// mismatch or an empty image.
std::vector<std::uint8_t> encode_png_rgb(int width, int height, std::span<const std::uint8_t> rgb);

// Round axis ticks covering [lo, hi]: multiples of 1, 2 or 5 times a power of
// ten, at most max_ticks + 1 of them, first <= lo and last >= hi (the axis
// is widened to them). lo == hi gives a small range around the value.
std::vector<double> round_ticks(double lo, double hi, int max_ticks = 6);

}  // namespace arttrack::sim
