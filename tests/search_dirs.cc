// Linked into every test program of the testbed: the source tree as the
// search folder of scenes and scenarios (search_paths.h), where the files
// they name relative to it and the default scene and scenario are, as the
// arttrack program sets it.
#include "arttrack/sim/search_paths.h"

namespace {

const bool kSearchDirsSet = [] {
  arttrack::sim::set_search_dirs({ARTTRACK_SOURCE_DIR});
  return true;
}();

}  // namespace
