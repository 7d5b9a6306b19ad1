// screenshot_check PNG [MIN_COLOURFUL_PERCENT]: whether a screenshot of a
// page shows something. Prints the share of pixels that are not the page's
// white, the share that are colourful (channels spread by more than 80:
// chart lines, boxes, heat maps, depth frames) and the number of distinct
// colours; exits 1 if the page is blank (under 1% not white or under 16
// colours) or less than MIN_COLOURFUL_PERCENT (default 0.2) is colourful, 2
// if the file cannot be read as a PNG. Used by tools/check_pages.sh.
#include <png.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: screenshot_check PNG [MIN_COLOURFUL_PERCENT]\n");
    return 2;
  }
  const double min_colourful = argc == 3 ? std::atof(argv[2]) : 0.2;
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, argv[1])) {
    std::fprintf(stderr, "%s: cannot read as PNG: %s\n", argv[1], img.message);
    return 2;
  }
  img.format = PNG_FORMAT_RGB;
  std::vector<unsigned char> rgb(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, rgb.data(), 0, nullptr)) {
    std::fprintf(stderr, "%s: cannot decode: %s\n", argv[1], img.message);
    return 2;
  }
  const std::size_t n = std::size_t(img.width) * img.height;
  std::size_t not_white = 0, colourful = 0;
  std::set<unsigned> colours;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char* p = &rgb[3 * i];
    if (p[0] < 250 || p[1] < 250 || p[2] < 250) ++not_white;
    const int spread = std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]});
    if (spread > 80) ++colourful;
    if (colours.size() < 100000) colours.insert(unsigned(p[0]) << 16 | unsigned(p[1]) << 8 | p[2]);
  }
  const double not_white_pct = n ? 100.0 * double(not_white) / double(n) : 0;
  const double colourful_pct = n ? 100.0 * double(colourful) / double(n) : 0;
  std::printf("%s: %ux%u, %.2f%% not white, %.2f%% colourful, %zu colours\n", argv[1], img.width,
              img.height, not_white_pct, colourful_pct, colours.size());
  if (not_white_pct < 1.0 || colours.size() < 16) {
    std::printf("%s: blank\n", argv[1]);
    return 1;
  }
  if (colourful_pct < min_colourful) {
    std::printf("%s: under %.2f%% colourful: no chart colours drawn\n", argv[1], min_colourful);
    return 1;
  }
  return 0;
}
