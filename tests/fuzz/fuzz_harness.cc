// libFuzzer harness around one target of fuzz_targets.h, chosen at compile
// time by ARTTRACK_FUZZ_TARGET (e.g. urdf_one): one executable per target.
#include <cstddef>
#include <cstdint>

#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  arttrack::fuzz::ARTTRACK_FUZZ_TARGET({reinterpret_cast<const char*>(data), size});
  return 0;
}
