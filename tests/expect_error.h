// GoogleTest's side of error_of.h: expects an InputError that names the field,
// key or file at fault, as the bad-input tests of the simulator's modules check
// their messages.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "error_of.h"

namespace arttrack::test_support {

// Expects f() to throw an InputError whose message holds `field`; a failure
// says which field had no error, or shows the message that lacks it.
template <class F>
void expect_error_naming(F&& f, const std::string& field) {
  const std::string message = error_of(f);
  if (message.empty())
    ADD_FAILURE() << "no error for " << field;
  else
    EXPECT_NE(message.find(field), std::string::npos) << message;
}

}  // namespace arttrack::test_support
