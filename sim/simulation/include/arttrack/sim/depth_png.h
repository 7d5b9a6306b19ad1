// Depth images as PNG files: 16-bit greyscale in millimetres (0 = no
// return; the usual format of depth datasets), and an 8-bit false-colour
// preview for looking at; and any 8-bit RGB image as a PNG in memory (the
// run report's embedded frames).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "arttrack/tracker/camera.h"

namespace arttrack::sim {

// Writes depth as 16-bit millimetres, rounded; depths beyond 65.535 m are
// clamped, non-finite or non-positive depths become 0. Errors (cannot
// write): InputError naming the file.
void write_depth_png_mm(const std::filesystem::path& path, const DepthImage& depth);

// Largest width or height read_depth_png_mm accepts, pixels (checked on the
// header, before anything is allocated): beyond any depth camera.
inline constexpr int kMaxDepthPngSide = 8192;

// Reads a 16-bit single-channel PNG of millimetres as metres. Missing file,
// not a PNG, colour or alpha channels, another bit depth than 16, more than
// kMaxDepthPngSide pixels wide or high: InputError naming the file.
DepthImage read_depth_png_mm(const std::filesystem::path& path);

// Rounds every depth to whole millimetres, exactly as a 16-bit millimetre
// PNG stores it (write_depth_png_mm then read_depth_png_mm): clamped to
// 65.535 m; non-finite or non-positive depths become 0.
void quantise_depth_mm(DepthImage& image);

// Writes an RGB preview in the simulator's colour map (Turbo): near red ...
// far blue between min_m and max_m (both 0: the image's own valid range),
// black where there is no return.
void write_depth_preview_png(const std::filesystem::path& path, const DepthImage& depth,
                             double min_m = 0, double max_m = 0);

// An 8-bit RGB image (row-major, 3 bytes per pixel, width * height * 3
// bytes) encoded as a PNG file in memory. Throws InputError on a size
// mismatch or an empty image.
std::vector<std::uint8_t> encode_png_rgb(int width, int height, std::span<const std::uint8_t> rgb);

}  // namespace arttrack::sim
