// Counting a text's pieces, for the tests that check generated SVG, HTML and
// CSV by what they hold.
#pragma once

#include <cstddef>
#include <string>

namespace arttrack::test_support {

// How many times `what` occurs in `text`, overlapping occurrences included.
inline std::size_t count_occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace arttrack::test_support
