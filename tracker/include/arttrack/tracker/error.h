// Errors a user can cause: a file, key, name, value or time stamp that is
// wrong. The message names the item and what would be right; callers at the
// edge (the command line) print it on one line and exit non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace arttrack {

// Bad input: malformed files, unknown names, impossible values, time stamps
// out of order. Never a programming error (those are assertions).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace arttrack
