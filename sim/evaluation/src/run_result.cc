#include "arttrack/sim/run_result.h"

namespace arttrack::sim {

const MethodResult* ScenarioResult::method(const std::string& name) const {
  for (const MethodResult& m : method_results)
    if (m.method == name) return &m;
  return nullptr;
}

}  // namespace arttrack::sim
