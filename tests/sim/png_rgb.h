// PNG images decoded to 8-bit RGB for the tests, by libpng's simplified
// API: independent of the encoders under test (depth_png.cc's libpng write
// path). Header-only; each test file that includes it links libpng.
#pragma once

#include <gtest/gtest.h>

#include <png.h>

#include <cstdint>
#include <vector>

namespace arttrack::sim::test {

// The RGB bytes of a PNG held in memory, row-major; width and height out.
// Empty (and a test failure recorded) if it does not decode.
inline std::vector<std::uint8_t> decode_png_rgb(const std::vector<std::uint8_t>& png, int& width,
                                                int& height) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  width = height = 0;
  if (!png_image_begin_read_from_memory(&img, png.data(), png.size())) {
    ADD_FAILURE() << "not a PNG: " << img.message;
    return {};
  }
  img.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> rgb(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, rgb.data(), 0, nullptr)) {
    ADD_FAILURE() << "PNG does not decode: " << img.message;
    return {};
  }
  width = int(img.width);
  height = int(img.height);
  return rgb;
}

}  // namespace arttrack::sim::test
