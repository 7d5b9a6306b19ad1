#include "arttrack/sim/run_result.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace arttrack::sim {

std::vector<LinkModelFit> link_model_fits(const std::vector<RunResult>& runs, std::size_t method) {
  std::vector<LinkModelFit> fits;
  std::vector<std::vector<double>> shifts_m, scales;  // per link, over runs
  for (const RunResult& run : runs) {
    if (method >= run.methods.size()) continue;
    const std::vector<EstimateSample>& samples = run.methods[method].samples;
    const auto last = std::find_if(samples.rbegin(), samples.rend(),
                                   [](const EstimateSample& e) { return !e.health.links.empty(); });
    if (last == samples.rend()) continue;
    const auto& links = last->health.links;
    if (fits.empty()) {
      for (const TrackingHealth::LinkModelError& l : links) fits.push_back({l.link});
      shifts_m.resize(links.size());
      scales.resize(links.size());
    }
    for (std::size_t g = 0; g < links.size() && g < fits.size(); ++g) {
      if (std::isfinite(links[g].shift_m)) shifts_m[g].push_back(links[g].shift_m);
      if (std::isfinite(links[g].scale)) scales[g].push_back(links[g].scale);
    }
  }
  for (std::size_t g = 0; g < fits.size(); ++g) {
    fits[g].runs_pinned = int(shifts_m[g].size());
    if (!shifts_m[g].empty()) fits[g].median_shift_m = percentiles(shifts_m[g]).p50;
    fits[g].runs_scaled = int(scales[g].size());
    if (!scales[g].empty()) fits[g].median_scale = percentiles(scales[g]).p50;
  }
  return fits;
}

std::vector<char> prismatic_joints(const RobotModel& robot,
                                   const std::vector<std::string>& joint_names) {
  std::vector<char> prismatic;
  for (const std::string& name : joint_names)
    prismatic.push_back(robot.joint_type(robot.joint_index(name)) == JointType::kPrismatic);
  return prismatic;
}

std::vector<double> encoder_noise_medians_rad(const std::vector<RunResult>& runs,
                                              std::size_t method) {
  std::vector<std::vector<double>> noise_rad;  // per joint, over runs
  for (const RunResult& run : runs) {
    if (method >= run.methods.size() || run.methods[method].samples.empty()) continue;
    const std::vector<double>& last =
        run.methods[method].samples.back().health.encoder_noise_measured_rad;
    if (noise_rad.size() < last.size()) noise_rad.resize(last.size());
    for (std::size_t j = 0; j < last.size(); ++j)
      if (std::isfinite(last[j])) noise_rad[j].push_back(last[j]);
  }
  std::vector<double> medians(noise_rad.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t j = 0; j < noise_rad.size(); ++j)
    if (!noise_rad[j].empty()) medians[j] = percentiles(noise_rad[j]).p50;
  return medians;
}

HealthCounts health_counts(const std::vector<RunResult>& runs, std::size_t method) {
  HealthCounts counts;
  for (const RunResult& run : runs) {
    if (method >= run.methods.size() || run.methods[method].samples.empty()) continue;
    const TrackingHealth& h = run.methods[method].samples.back().health;  // counts so far
    ++counts.runs;
    counts.acquisitions += h.acquisitions;
    counts.chains_reacquired += h.chains_reacquired;
    counts.refinements_accepted += h.refinements_accepted;
    counts.unseen_priors_kept += h.unseen_priors_kept;
    counts.images_with_unseen_motion += h.images_with_unseen_motion;
    counts.hand_searches += h.hand_searches;
    counts.hand_shifts_accepted += h.hand_shifts_accepted;
  }
  return counts;
}

const MethodResult* ScenarioResult::method(const std::string& name) const {
  for (const MethodResult& m : method_results)
    if (m.method == name) return &m;
  return nullptr;
}

}  // namespace arttrack::sim
