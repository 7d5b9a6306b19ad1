#include "arttrack/sim/depth_png.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <new>
#include <string>
#include <vector>

#include "arttrack/sim/internal/colour_map.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

// libpng reports errors by longjmp. The functions that call it hold no C++
// object with a destructor in their own frame, so the jump skips nothing.
struct PngError {
  char message[256] = "";
};

void on_error(png_structp png, png_const_charp msg) {
  auto* e = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(e->message, sizeof(e->message), "%s", msg);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}

void on_memory_write(png_structp png, png_bytep data, png_size_t n) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  bool ok = true;
  try {
    out->insert(out->end(), data, data + n);
  } catch (const std::bad_alloc&) {
    ok = false;
  }
  if (!ok) png_error(png, "out of memory");  // outside the handler: no exception left behind
}

void on_memory_flush(png_structp) {}

// Writes an image through libpng to `fp`, or to `memory` if fp is null.
bool write_rows(FILE* fp, std::vector<std::uint8_t>* memory, int width, int height, int bit_depth,
                int color_type, png_bytep* rows, PngError* err) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, err, on_error, on_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    std::snprintf(err->message, sizeof(err->message), "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  if (fp)
    png_init_io(png, fp);
  else
    png_set_write_fn(png, memory, on_memory_write, on_memory_flush);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), bit_depth, color_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

bool write_raw(const char* path, int width, int height, int bit_depth, int color_type,
               png_bytep* rows, PngError* err) {
  FILE* fp = std::fopen(path, "wb");
  if (!fp) {
    std::snprintf(err->message, sizeof(err->message), "cannot open for writing");
    return false;
  }
  const bool ok = write_rows(fp, nullptr, width, height, bit_depth, color_type, rows, err);
  if (std::fclose(fp) != 0 && ok) {
    std::snprintf(err->message, sizeof(err->message), "write failed");
    return false;
  }
  return ok;
}

struct RawImage {
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
  std::vector<unsigned char> bytes;
  std::vector<png_bytep> rows;
};

bool read_raw(const char* path, RawImage* img, PngError* err) {
  FILE* fp = std::fopen(path, "rb");
  if (!fp) {
    std::snprintf(err->message, sizeof(err->message), "cannot open for reading");
    return false;
  }
  unsigned char signature[8];
  if (std::fread(signature, 1, 8, fp) != 8 || png_sig_cmp(signature, 0, 8) != 0) {
    std::fclose(fp);
    std::snprintf(err->message, sizeof(err->message), "not a PNG file");
    return false;
  }
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, err, on_error, on_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(fp);
    std::snprintf(err->message, sizeof(err->message), "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(fp);
    return false;
  }
  png_init_io(png, fp);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  img->width = png_get_image_width(png, info);
  img->height = png_get_image_height(png, info);
  img->bit_depth = png_get_bit_depth(png, info);
  img->color_type = png_get_color_type(png, info);
  // The header's size is the file's claim: check it before allocating.
  if (img->width > png_uint_32(kMaxDepthPngSide) || img->height > png_uint_32(kMaxDepthPngSide)) {
    std::snprintf(err->message, sizeof(err->message),
                  "the header claims %lux%lu pixels; at most %dx%d are allowed",
                  (unsigned long)img->width, (unsigned long)img->height, kMaxDepthPngSide,
                  kMaxDepthPngSide);
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(fp);
    return false;
  }
  if (img->color_type == PNG_COLOR_TYPE_GRAY && img->bit_depth < 8)
    png_set_expand_gray_1_2_4_to_8(png);
  png_read_update_info(png, info);
  const size_t stride = png_get_rowbytes(png, info);
  img->bytes.resize(stride * img->height);
  img->rows.resize(img->height);
  for (png_uint_32 v = 0; v < img->height; ++v) img->rows[v] = img->bytes.data() + v * stride;
  png_read_image(png, img->rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(fp);
  return true;
}

[[noreturn]] void fail_png(const fs::path& path, const std::string& what) {
  throw InputError(path.string() + ": " + what);
}

// A depth as the 16-bit millimetre count a PNG stores: rounded, clamped to
// 65535; non-finite or non-positive depths 0.
long depth_mm(float z) {
  return std::isfinite(z) && z > 0 ? std::min(65535L, std::lround(z * 1000.0)) : 0;
}

}  // namespace

void write_depth_png_mm(const fs::path& path, const DepthImage& depth) {
  if (depth.width <= 0 || depth.height <= 0) fail_png(path, "cannot write an empty depth image");
  std::vector<unsigned char> bytes(size_t(depth.width) * depth.height * 2);
  std::vector<png_bytep> rows(depth.height);
  for (int v = 0; v < depth.height; ++v) {
    rows[v] = bytes.data() + size_t(v) * depth.width * 2;
    for (int u = 0; u < depth.width; ++u) {
      const long mm = depth_mm(depth.at(u, v));
      rows[v][2 * u] = (unsigned char)(mm >> 8);  // PNG samples are big-endian
      rows[v][2 * u + 1] = (unsigned char)(mm & 0xff);
    }
  }
  PngError err;
  if (!write_raw(path.c_str(), depth.width, depth.height, 16, PNG_COLOR_TYPE_GRAY, rows.data(),
                 &err))
    fail_png(path, std::string("cannot write depth PNG: ") + err.message);
}

DepthImage read_depth_png_mm(const fs::path& path) {
  if (!fs::is_regular_file(path)) fail_png(path, "depth PNG not found");
  RawImage img;
  PngError err;
  if (!read_raw(path.c_str(), &img, &err))
    fail_png(path, std::string("cannot read PNG: ") + err.message);
  if (img.color_type != PNG_COLOR_TYPE_GRAY)
    fail_png(path, "a depth PNG must be single-channel greyscale (no colour, no alpha)");
  // 8 bits of millimetres reach 0.255 m: such a file is a picture, not depth.
  if (img.bit_depth != 16)
    fail_png(path, "a " + std::to_string(img.bit_depth) +
                       "-bit PNG is not a depth image: depth PNGs are 16-bit millimetres");
  DepthImage depth(int(img.width), int(img.height));
  for (int v = 0; v < depth.height; ++v)
    for (int u = 0; u < depth.width; ++u) {
      const unsigned char* p = img.rows[v] + 2 * u;
      depth.at(u, v) = float(((p[0] << 8) | p[1]) * 1e-3);
    }
  return depth;
}

void quantise_depth_mm(DepthImage& image) {
  // The arithmetic of write_depth_png_mm followed by read_depth_png_mm.
  for (float& z : image.depth_m) z = float(int(depth_mm(z)) * 1e-3);
}

void write_depth_preview_png(const fs::path& path, const DepthImage& depth, double min_m,
                             double max_m) {
  if (depth.width <= 0 || depth.height <= 0) fail_png(path, "cannot write an empty depth image");
  if (min_m == 0 && max_m == 0) {
    min_m = INFINITY;
    max_m = -INFINITY;
    for (float z : depth.depth_m)
      if (std::isfinite(z) && z > 0) {
        min_m = std::min(min_m, double(z));
        max_m = std::max(max_m, double(z));
      }
  }
  const double span = max_m > min_m ? max_m - min_m : 1.0;
  std::vector<unsigned char> bytes(size_t(depth.width) * depth.height * 3, 0);
  std::vector<png_bytep> rows(depth.height);
  for (int v = 0; v < depth.height; ++v) {
    rows[v] = bytes.data() + size_t(v) * depth.width * 3;
    for (int u = 0; u < depth.width; ++u) {
      const float z = depth.at(u, v);
      if (!(std::isfinite(z) && z > 0)) continue;  // black: no return
      const Rgb c = turbo(1.0 - std::clamp((z - min_m) / span, 0.0, 1.0));
      rows[v][3 * u] = c.r, rows[v][3 * u + 1] = c.g, rows[v][3 * u + 2] = c.b;
    }
  }
  PngError err;
  if (!write_raw(path.c_str(), depth.width, depth.height, 8, PNG_COLOR_TYPE_RGB, rows.data(), &err))
    fail_png(path, std::string("cannot write preview PNG: ") + err.message);
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
  PngError err;
  if (!write_rows(nullptr, &out, width, height, 8, PNG_COLOR_TYPE_RGB, rows.data(), &err))
    throw InputError(std::string("PNG encoding failed: ") + err.message);
  return out;
}

}  // namespace arttrack::sim
