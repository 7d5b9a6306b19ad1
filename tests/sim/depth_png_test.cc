// Depth PNG files: millimetre round trip, the preview's colours, RGB images
// encoded in memory, and errors that name the file.
#include "arttrack/sim/depth_png.h"

#include <gtest/gtest.h>

#include <png.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "../expect_error.h"
#include "../scratch_dir.h"
#include "arttrack/tracker/error.h"
#include "png_rgb.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;
using test_support::expect_error_naming;

fs::path test_path(const std::string& name) { return test_support::program_scratch_dir() / name; }

TEST(DepthPng, MillimetreRoundTrip) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> depth(0.05f, 65.0f);
  DepthImage image(37, 23);
  for (float& z : image.depth_m) z = depth(rng);
  image.at(0, 0) = 0;
  image.at(1, 0) = -1;       // invalid: no return
  image.at(2, 0) = NAN;      // invalid: no return
  image.at(3, 0) = 70.f;     // beyond 16 bits of millimetres: clamped
  image.at(4, 0) = 1.2344f;  // rounds to 1234 mm
  image.at(5, 0) = 1.2346f;  // rounds to 1235 mm
  const fs::path path = test_path("roundtrip.png");
  write_depth_png_mm(path, image);
  const DepthImage back = read_depth_png_mm(path);
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  EXPECT_EQ(back.at(0, 0), 0.f);
  EXPECT_EQ(back.at(1, 0), 0.f);
  EXPECT_EQ(back.at(2, 0), 0.f);
  EXPECT_FLOAT_EQ(back.at(3, 0), 65.535f);
  EXPECT_FLOAT_EQ(back.at(4, 0), 1.234f);
  EXPECT_FLOAT_EQ(back.at(5, 0), 1.235f);
  for (int v = 1; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u)
      ASSERT_NEAR(back.at(u, v), image.at(u, v), 0.5e-3 + 1e-6) << u << ", " << v;
}

// Reads an 8-bit RGB PNG with libpng's simplified API (independent of the
// code under test).
std::vector<unsigned char> read_rgb(const fs::path& path, int& w, int& h) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  return test::decode_png_rgb(bytes, w, h);
}

// The preview is in Turbo: nearest its dark red end, farthest its dark blue
// end (the published table's last and first entries, 8-bit), no return black.
TEST(DepthPng, PreviewColours) {
  DepthImage image(4, 1);
  image.at(0, 0) = 1.0f;  // nearest: red
  image.at(1, 0) = 0.0f;  // no return: black
  image.at(2, 0) = 3.0f;  // farthest: blue
  image.at(3, 0) = 2.0f;  // middle: green-yellow
  const fs::path path = test_path("preview.png");
  write_depth_preview_png(path, image);
  int w, h;
  const auto rgb = read_rgb(path, w, h);
  ASSERT_EQ(w, 4);
  ASSERT_EQ(h, 1);
  EXPECT_EQ(std::vector<int>(rgb.begin(), rgb.begin() + 3), (std::vector<int>{122, 4, 3}));
  EXPECT_EQ(rgb[3] + rgb[4] + rgb[5], 0);
  EXPECT_EQ(std::vector<int>(rgb.begin() + 6, rgb.begin() + 9), (std::vector<int>{48, 18, 59}));
  EXPECT_GT(rgb[10], 200);  // the middle of Turbo is bright green
  EXPECT_GT(rgb[10], rgb[11]);
}

TEST(DepthPng, RgbImageEncodesInMemoryAndDecodes) {
  std::vector<std::uint8_t> rgb(7 * 5 * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = std::uint8_t(i * 37);
  int w = 0, h = 0;
  EXPECT_EQ(test::decode_png_rgb(encode_png_rgb(7, 5, rgb), w, h), rgb);
  EXPECT_EQ(w, 7);
  EXPECT_EQ(h, 5);
  EXPECT_THROW(encode_png_rgb(7, 5, std::span(rgb).first(10)), InputError);
  EXPECT_THROW(encode_png_rgb(0, 5, {}), InputError);
}

TEST(DepthPng, ErrorsNameTheFile) {
  const fs::path missing = test_path("missing.png");
  expect_error_naming([&] { read_depth_png_mm(missing); }, "missing.png");
  const fs::path text = test_path("not_a_png.png");
  std::ofstream(text) << "hello";
  expect_error_naming([&] { read_depth_png_mm(text); }, "not_a_png.png");
  expect_error_naming([&] { read_depth_png_mm(text); }, "not a PNG");
  const fs::path colour = test_path("colour.png");
  write_depth_preview_png(colour, DepthImage(4, 4, 1.f));
  expect_error_naming([&] { read_depth_png_mm(colour); }, "colour.png");
  expect_error_naming(
      [&] { write_depth_png_mm(test_path("no_such_dir") / "x.png", DepthImage(2, 2)); }, "x.png");
}

std::string read_error(const fs::path& path) {
  return test_support::error_of([&] { read_depth_png_mm(path); });
}

// An 8-bit greyscale PNG is not millimetres (it would read as 0..0.255 m).
TEST(DepthPng, EightBitIsAnErrorNamingFileAndBitDepth) {
  const fs::path path = test_path("eight_bit.png");
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 4;
  image.height = 3;
  image.format = PNG_FORMAT_GRAY;
  const std::vector<png_byte> pixels(12, 200);
  ASSERT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr));
  const std::string e = read_error(path);
  EXPECT_NE(e.find("eight_bit.png"), std::string::npos) << e;
  EXPECT_NE(e.find("8-bit"), std::string::npos) << e;
}

std::uint32_t crc32(const unsigned char* p, size_t n) {
  std::uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return ~c;
}

// A header that claims more pixels than the bound is refused before the
// image is allocated (here 9000 x 9000 in a file of a few bytes).
TEST(DepthPng, HugeHeaderIsRefusedBeforeAllocating) {
  const fs::path path = test_path("huge.png");
  write_depth_png_mm(path, DepthImage(2, 2, 1.f));
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  // Signature (8), IHDR length (4), "IHDR" (4), width, height (4 each, big
  // endian), 5 more header bytes, then the CRC of "IHDR" + data.
  ASSERT_EQ(bytes.substr(12, 4), "IHDR");
  auto* b = reinterpret_cast<unsigned char*>(bytes.data());
  for (int o : {16, 20}) {
    const std::uint32_t side = 9000;
    b[o] = side >> 24, b[o + 1] = (side >> 16) & 0xff, b[o + 2] = (side >> 8) & 0xff,
    b[o + 3] = side & 0xff;
  }
  const std::uint32_t crc = crc32(b + 12, 17);
  b[29] = crc >> 24, b[30] = (crc >> 16) & 0xff, b[31] = (crc >> 8) & 0xff, b[32] = crc & 0xff;
  std::ofstream(path, std::ios::binary) << bytes;
  const std::string e = read_error(path);
  EXPECT_NE(e.find("huge.png"), std::string::npos) << e;
  EXPECT_NE(e.find("9000x9000"), std::string::npos) << e;
  EXPECT_NE(e.find(std::to_string(kMaxDepthPngSide)), std::string::npos) << e;
}

}  // namespace
}  // namespace arttrack::sim
