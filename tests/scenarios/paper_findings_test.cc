// The paper's findings (Garcia Cifuentes et al. 2017, Sec. VI) as numbers, on
// short versions of the paper scenarios (scenarios/paper/): the same files,
// shortened and cheapened through overrides (a 160x120 camera, the tracker's
// 80x60 likelihood, one run, a few seconds) so the suite fits in CI.
//
//   - encoders only is centimetres off under the constant bias and the head
//     error; full fusion reaches millimetres once converged, and follows the
//     time-varying bias;
//   - without bias, estimating the camera offset fixes the head error;
//   - out of view and under heavy occlusion, full fusion is never much worse
//     than encoders only, and recovers when the arm is back in view;
//   - vision only loses track where the paper says it does: occlusion, out of
//     view, fast motion.
//
// Thresholds are set from measured values with a margin; the measured values
// (these overrides, one run with the file's seed, some with other seeds via
// --seed) are in the comments. With the Apollo-like head error and the 8.6
// degree bias, full fusion's first image can land in a wrong mode,
// decimetres off for good: 2 of 15 ten-second runs of arm__constant_bias
// with the paper's occluder model and head biases estimated, 5 of 15 with the
// independent occluder model (the head tilted the arm out of view), 1 of 15
// (47 mm) with the head's biases fixed at 0 as models/scene_default.yaml
// now has it. A tracker change that reshuffles its random numbers can still
// hit one and fail these tests. To see a test fail on
// purpose, see ARTTRACK_SCENARIO_TEST_SET in short_run.h.
#include <gtest/gtest.h>

#include <cstddef>
#include <iostream>
#include <string>
#include <vector>

#include "short_run.h"

namespace arttrack::sim::test {
namespace {

// A short run of scenarios/paper/<name>.yaml (short_run.h).
ScenarioResult run_paper(const std::string& name, double duration_s,
                         const std::vector<std::string>& methods,
                         std::vector<std::string> overrides = {}) {
  return run_short("paper/" + name, duration_s, methods, std::move(overrides));
}

// Constant 8.6 degree bias on every arm joint, head error and camera offset,
// the arm moving slowly (paper Fig. 5, "arm"): encoders only is off by
// decimetres, estimating the camera offset alone helps by centimetres at
// most, full fusion is at millimetres after it converged.
TEST(PaperFindings, ConstantBiasEncodersAreCentimetresOffFullFusionMillimetres) {
  const ScenarioResult r =
      run_paper("arm__constant_bias", 15, {"encoders_only", "camera_offset_only", "full_fusion"},
                {"scoring.converged_after_s=8"});
  // Measured (seed 1, [seed 2]): p50 encoders only 251.6 mm [251.2], camera
  // offset only 232.5 mm [247.7]; full fusion after 8 s p50 5.4 mm [5.5], p99
  // 8.9 mm [8.6] (over the whole run p99 76.6 mm: the first second).
  EXPECT_GT(all(r, "encoders_only").p50, 150 * kMm);
  // The camera offset's help is the paper's claim for the moving (left) arm;
  // with both hands scored, the worst is the still right arm's, which a
  // camera offset fitted to the whole image does not bring closer.
  const auto left = [&](const char* m) {
    return method(r, m).summary.end_effectors.at(0).all.translation_m;
  };
  EXPECT_LT(left("camera_offset_only").p50, left("encoders_only").p50);
  EXPECT_GT(all(r, "camera_offset_only").p50, 100 * kMm);
  EXPECT_LT(converged(r, "full_fusion").p50, 10 * kMm);
  EXPECT_LT(converged(r, "full_fusion").p99, 20 * kMm);
}

// No bias, the head moving with its wrong kinematics (paper Fig. 4, real
// data): encoders only is centimetres off, the camera offset estimate brings
// it to millimetres, and full fusion is about as good.
TEST(PaperFindings, NoBiasCameraOffsetFixesTheHeadError) {
  const ScenarioResult r =
      run_paper("head__no_bias", 15, {"encoders_only", "camera_offset_only", "full_fusion"},
                {"scoring.converged_after_s=8"});
  // Measured (seeds 1, 2, 3): encoders only p1 28.3, 28.4, 27.3 mm (p50
  // 33.1, 33.3, 33.3 mm); after 8 s p50 camera offset only 4.5, 4.6, 4.6 mm,
  // full fusion 5.1, 5.4, 5.3 mm.
  EXPECT_GT(all(r, "encoders_only").p01, 20 * kMm);
  EXPECT_LT(converged(r, "camera_offset_only").p50, 8 * kMm);
  EXPECT_LT(converged(r, "camera_offset_only").p50, all(r, "encoders_only").p50 / 4);
  EXPECT_LT(converged(r, "full_fusion").p50, 10 * kMm);
}

// The arm leaves the view and comes back (paper Fig. 7b, "in/out/in", with
// the constant bias), shortened: out of view from 8 s to 13 s, back at 15 s.
// Out of view, full fusion is pulled towards the encoders but never worse
// than them; back in view it recovers. Vision only has nothing to follow
// while the arm is away and does not find it again.
//
// Three seeds, the finding to hold in at least two: with one seed, a change
// of random-number order alone (3 searches per acquisition instead of 1)
// turned seed 1 from back at 5.7 mm into 510 mm (the arm re-entering the
// view at the image edge, where hiding it still scores better), while over
// seeds 2-5 the same change went from 1 of 4 such runs to none
// (docs/accuracy.md). Coming back into view is not reliable in every run;
// the test says how often, and fails when it is the exception.
TEST(PaperFindings, OutOfViewFullFusionRecoversVisionOnlyIsLost) {
  int holds = 0;
  for (const char* seed : {"seed=1", "seed=2", "seed=3"}) {
    const ScenarioResult r = run_paper(
        "in_out_in__constant_bias", 20, {"encoders_only", "full_fusion", "vision_only"},
        {"scoring.converged_after_s=8", seed,
         "motion.out_of_view=[{joints: [left_arm_joint_2], out_of_view_deg: [0], leave_s: 6, "
         "return_s: 13, move_duration_s: 2}]"});
    const Percentiles encoders_out = window(r, "encoders_only", 8.5, 13);
    const Percentiles fusion_out = window(r, "full_fusion", 8.5, 13);
    const Percentiles fusion_back = window(r, "full_fusion", 16.5, 20);
    const Percentiles vision_back = window(r, "vision_only", 16.5, 20);
    // Measured before the seeds (seed 1, one search): out of view, encoders
    // only p1 196.5 mm, full fusion p50 39.3 mm and p99 80.7 mm; back in
    // view, full fusion p50 5.7 mm, vision only p50 1035.6 mm. Before the
    // particle filter kept the prior of joints without evidence, full fusion
    // random-walked out of view (p99 313 mm, worse than encoders).
    const bool holds_here = fusion_out.p99 < encoders_out.p01 && fusion_out.p99 < 150 * kMm &&
                            fusion_back.p50 < 12 * kMm && vision_back.p50 > 100 * kMm &&
                            vision_back.p50 > 5 * fusion_back.p50;
    std::cout << seed << (holds_here ? ": holds" : ": does not hold") << "\n";
    holds += holds_here;
  }
  EXPECT_GE(holds, 2) << "the out-of-view finding held in " << holds << " of 3 seeds";
}

// Fast arm motion (paper Fig. 5, "arm++", constant bias): full fusion keeps
// its millimetres, vision only loses the arm.
TEST(PaperFindings, FastMotionVisionOnlyLosesTrackFullFusionDoesNot) {
  const ScenarioResult r =
      run_paper("arm_fast__constant_bias", 12, {"encoders_only", "full_fusion", "vision_only"},
                {"scoring.converged_after_s=6"});
  // Measured after 6 s (seed 1, [seed 2]): full fusion p50 5.6 mm [5.4] and
  // 1.2 degrees [1.2]; vision only p50 53.2 mm [215.6] and 17 to 55 degrees
  // over tracker versions [142.6]: the hand turned the wrong way.
  const MethodSummary& fusion = method(r, "full_fusion").summary;
  const MethodSummary& vision = method(r, "vision_only").summary;
  std::cout << "rotation after 6 s, p50: full fusion "
            << fusion.converged.rotation_rad.p50 / kRadPerDeg << " deg, vision only "
            << vision.converged.rotation_rad.p50 / kRadPerDeg << " deg\n";
  EXPECT_LT(fusion.converged.translation_m.p50, 10 * kMm);
  EXPECT_GT(vision.converged.translation_m.p50, 15 * kMm);
  EXPECT_GT(vision.converged.translation_m.p50, 3 * fusion.converged.translation_m.p50);
  EXPECT_GT(vision.converged.rotation_rad.p50, 5 * kRadPerDeg);
  EXPECT_GT(vision.converged.rotation_rad.p50, 5 * fusion.converged.rotation_rad.p50);
}

// The head three times as fast ("both++", no bias): its axes are off the
// URDF's by 1.5 and 2.5 degrees (base/apollo.yaml), so the true camera offset
// turns as the head turns. The offset walks with the head's motion
// (camera_offset.rotation_diffusion_deg_per_sqrt_rad), so it follows, and
// claims no more than it has.
TEST(PaperFindings, AFastHeadsCameraIsFollowedAndHonest) {
  const ScenarioResult r =
      run_paper("both_fast__no_bias", 12, {"full_fusion"}, {"scoring.converged_after_s=5"});
  // Measured after 5 s (seed 1, [seed 2]): camera frame p50 0.8 mm [0.8] and
  // 0.12 degrees [0.12], the six offsets within 2 sigma 100% [100%]; with a
  // time diffusion alone (0 per sqrt(rad)) 1.8 mm [1.7], 0.29 degrees [0.25]
  // and 94.2% [71.4%].
  const MethodSummary& fusion = method(r, "full_fusion").summary;
  EXPECT_LT(fusion.converged.camera_rotation_rad.p50, 0.18 * kRadPerDeg);
  EXPECT_LT(fusion.converged.camera_translation_m.p50, 1.3 * kMm);
  EXPECT_GE(fusion.converged.camera_offset_coverage.fraction(), 0.95);
}

// The time-varying bias (paper Fig. 6 and 7d, "arm"): +5 degrees, then a 1 s
// ramp at 9 s to -5. Full fusion follows the change and is at millimetres
// again a few seconds later; encoders only stays decimetres off.
TEST(PaperFindings, VaryingBiasFullFusionFollowsTheSteps) {
  const ScenarioResult r = run_paper("arm__varying_bias", 19, {"encoders_only", "full_fusion"});
  const Percentiles encoders = window(r, "encoders_only", 13, 19);
  const Percentiles fusion = window(r, "full_fusion", 13, 19);
  // Measured from 13 to 19 s: encoders only p50 155.5 mm, full fusion p50
  // 4.9 mm, p99 7.7 mm (an earlier tracker sat in a 68 mm wrong mode until
  // 9 s, then followed the step within 15 mm).
  EXPECT_GT(encoders.p50, 100 * kMm);
  EXPECT_LT(fusion.p50, 10 * kMm);
  EXPECT_LT(fusion.p99, 20 * kMm);
}

// Heavy, long occlusion of the moving arm (paper Fig. 7c): a panel hides the
// forearm and hand from 11.5 s on.
//
// The paper's finding under occlusion: full fusion "stays at least as
// accurate as the encoders-only method, even when the visual information is
// not reliable", and better most of the time, with the constant bias and
// without bias. With
// the paper's truncated occluder density (depth_model.occluder_model:
// truncated) it does not hold: hidden robot pixels score log 1 / (1 -
// exp(-lambda r)), about +0.8 each, hypotheses that tuck the arm behind the
// panel win, and the hidden joints' biases run away (constant bias, 12 to 17
// s: full fusion p50 237.4 mm, p99 286.4 mm, worse than encoders only).
//
// And full fusion is lost (scoring.h: a hand above 2 cm for more than 1 s
// from 10 s on) in none of the six runs. With the bias diffusion at 3.2
// degrees per square-root second (before 08d8795) the partly hidden wrist
// drifted 10-15 degrees and 7 of 10 such 20 s runs were lost
// (docs/accuracy.md, "The bias process").
//
// Vision only, with nothing but the image, loses the arm (constant bias,
// every seed). One test for both: the methods share the runs' simulation,
// which is two thirds of a run's time, and each has its own random draws,
// so running them together gives each the numbers it has alone.
TEST(PaperFindings, OcclusionFullFusionNeverMuchWorseThanEncodersVisionOnlyLoses) {
  // Three seeds per variant, the finding to hold in at least two (see the
  // out-of-view test: one seed flips with the random-number order).
  for (const char* variant : {"occlusion__constant_bias", "occlusion__no_bias"}) {
    SCOPED_TRACE(variant);
    int holds = 0;
    std::size_t lost = 0;
    const bool constant_bias = std::string(variant) == "occlusion__constant_bias";
    std::vector<std::string> methods = {"encoders_only", "full_fusion"};
    if (constant_bias) methods.push_back("vision_only");
    for (const char* seed : {"seed=1", "seed=2", "seed=3"}) {
      const ScenarioResult r = run_paper(variant, 17, methods, {seed});
      lost += method(r, "full_fusion").summary.lost_runs();
      if (constant_bias) {
        SCOPED_TRACE(seed);
        // Vision only's p50 from 12 to 17 s, seeds 1, 2, 3, against 2 to 10
        // s: 290.5, 93.1, 86.6 mm against 14.5, 24.8, 15.4 mm (478edcf; with
        // particle_filter.block_moments_below_nats .inf 145.7, 78.9, 204.8 mm
        // against 14.0, 14.6, 24.8). Lost by the scorer's measure (2 cm) with
        // a wide margin, and several times worse than before the panel.
        const Percentiles before = window(r, "vision_only", 2, 10);
        const Percentiles occluded = window(r, "vision_only", 12, 17);
        EXPECT_GT(occluded.p50, 50 * kMm);
        EXPECT_GT(occluded.p50, 2.5 * before.p50);
      }
      const Percentiles encoders = window(r, "encoders_only", 12, 17);
      const Percentiles fusion = window(r, "full_fusion", 12, 17);
      // Measured from 12 to 17 s (seed 1, [seed 2], [seed 3]), one search
      // per acquisition, no refinement: constant bias, encoders only p50
      // 251.4 mm [249.1] [250.8], p99 266.5 mm [261.6] [262.3]; full fusion
      // p50 65.5 mm [6.3] [7.8], p99 83.0 mm [29.6] [42.5] (the hidden
      // joints' bias estimates decay towards 0 while hidden, 5% per second).
      // No bias: encoders only p50 33.0 mm [33.3] [32.9], p99 34.7 mm [34.5]
      // [34.3]; full fusion p50 12.1 mm [6.6] [12.3], p99 43.1 mm [46.9]
      // [67.0]. Better most of the time, up to about 3 cm worse in its worst
      // moments (the panel's arrival).
      const bool holds_here = fusion.p99 < encoders.p99 + 40 * kMm && fusion.p50 < encoders.p50 / 2;
      std::cout << variant << ' ' << seed << (holds_here ? ": holds" : ": does not hold") << "\n";
      holds += holds_here;
    }
    EXPECT_GE(holds, 2) << "the occlusion finding held in " << holds << " of 3 seeds";
    EXPECT_EQ(lost, 0u) << "full fusion lost in " << lost << " of 3 runs";
  }
}

}  // namespace
}  // namespace arttrack::sim::test
