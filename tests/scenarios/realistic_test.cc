// The realistic family (scenarios/realistic/README.md): a noisy camera and a
// robot a few millimetres off its URDF. What a program that gates a grasp on
// the reported hand pose reads must be honest there too (issue 28).
// realistic/both__other_origins_off's length errors sit on origins near the
// shoulders, which no image pins, and its hands are 4% bigger and smaller
// than their meshes: the rigid end-effector fit sits 2-2.4 mm off along the
// camera's x and 1.3-1.9 mm along y. The pooled model error, estimated from
// the links that fit, reads 0 there, so before end_effector_fit.link_scales
// (stop 99) the reported sd was 0.8-0.9 mm per axis and the hands' positions
// were within 2 sigma 63.8-66.5% of the time on seeds 1-5 (20 s, two runs
// each). Short runs (160x120, the 80x60 likelihood, 12 s), two seeds. About
// 30 s.
#include <gtest/gtest.h>

#include <string>

#include "short_run.h"

namespace arttrack::sim::test {
namespace {

TEST(Realistic, TheHandsOfADualArmOffItsUrdfAreWithinTwoSigmaAsOftenAsClaimed) {
  for (const int seed : {1, 2}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const ScenarioResult r = run_short("realistic/both__other_origins_off", 12, {"full_fusion"},
                                       {"seed=" + std::to_string(seed)});
    const MethodSummary& fusion = method(r, "full_fusion").summary;
    EXPECT_EQ(fusion.lost_runs(), 0u);
    const Coverage& hands = fusion.all.end_effector_position_coverage;
    ASSERT_GT(hands.estimated, 0u);
    std::cout << "hands' positions within 2 sigma: " << 100 * hands.fraction() << "%\n";
    EXPECT_GT(hands.fraction(), 0.85);
    EXPECT_LT(hands.fraction(), 0.995);
  }
}

}  // namespace
}  // namespace arttrack::sim::test
