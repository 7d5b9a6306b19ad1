// Full fusion does not settle in wrong modes (issue 10): on the default
// scenario, both hands scored, no run is lost, over several seeds and at
// several particle counts, so that neither a change of random-number order
// nor more computation can hide or cause one. Before the annealed
// acquisition the right arm was lost in 6 of 6 seeds (converged p50 105 mm).
#include <gtest/gtest.h>

#include "short_run.h"

namespace arttrack::sim::test {
namespace {

void expect_never_lost(const std::string& seed, const std::string& particles) {
  SCOPED_TRACE(seed + " " + particles);
  const ScenarioResult r =
      run_short("default", 8, {"full_fusion"},
                {seed, "scoring.converged_after_s=4",
                 "tracker_overrides={particle_filter.particles: " + particles + "}"});
  const MethodSummary& s = method(r, "full_fusion").summary;
  ASSERT_EQ(r.end_effectors.size(), 2u);  // both hands, the worst per sample
  EXPECT_EQ(s.lost_runs(), 0u);
  // Measured (160x120 camera, 8 s, seeds 1-6, 20/46/92 particles): worst
  // hand converged p75 5.6-6.5 mm, p99 7-26 mm, none lost.
  EXPECT_LT(s.converged.translation_m.p75, 9 * kMm);
  EXPECT_LT(s.converged.translation_m.p99, 40 * kMm);
}

TEST(WrongModes, DefaultScenarioBothHandsNeverLost) {
  for (const char* seed : {"seed=1", "seed=2", "seed=3"}) expect_never_lost(seed, "20");
}

// The default scenario at its own 640x480 camera, where a still wrist
// once settled in a wrong mode that the 160x120 runs above did not show:
// with every block moment-matched after its own ratios
// (particle_filter.block_moments_below_nats: .inf) seed 1's right hand
// roll went 56 degrees off within 0.5 s and stayed (docs/accuracy.md,
// "Moments after each block"), and this test fails. About 13 s.
TEST(WrongModes, DefaultScenarioAtItsOwnCameraNeverLost) {
  for (const char* seed : {"seed=1", "seed=2"}) {
    SCOPED_TRACE(seed);
    const ScenarioResult r =
        run_short("default", 5, {"full_fusion"},
                  {seed, "camera.width=640", "camera.height=480", "scoring.converged_after_s=2"});
    const MethodSummary& s = method(r, "full_fusion").summary;
    ASSERT_EQ(r.end_effectors.size(), 2u);
    EXPECT_EQ(s.lost_runs(), 0u);
    // Measured (seeds 1, 2): worst hand converged p99 1.2 and 0.9 mm; with
    // .inf seed 1 is lost, p99 51.7 mm.
    EXPECT_LT(s.converged.translation_m.p99, 10 * kMm);
  }
}

TEST(WrongModes, MoreParticlesDoNotHurt) {
  // 2024 evaluations per image (92 particles x 22 blocks), where the old
  // tracker never converged.
  expect_never_lost("seed=5", "92");
}

}  // namespace
}  // namespace arttrack::sim::test
