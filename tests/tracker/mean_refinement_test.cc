// MeanRefinement's step along a direction the image does not see
// (mean_refinement.h): checked against the step's own stationarity
// condition, not against the projection that computes it.
#include <gtest/gtest.h>

#include <vector>

#include <Eigen/Core>

#include "../count_allocations.h"
#include "mean_refinement.h"

namespace arttrack {
namespace {

// Three states: a camera-like state and two joints. Moving state 0 by +1
// and state 1 by -1 moves no surface (v below): the motion field's
// information F has v in its null space, as a camera orbiting an
// axisymmetric base link has with the joint that turns it.
struct UnseenDirectionProblem {
  Eigen::Vector3d v{1, -1, 0};
  Eigen::Matrix3d prior, field, artefact_information;
  Eigen::Vector3d x{0.02, -0.01, 0.03}, seen_gradient, artefact_gradient;
  std::vector<int> pixels{500, 500, 500};
  std::vector<double> spread{10, 10, 10};  // no shortening

  UnseenDirectionProblem() {
    prior << 4e-4, 1e-4, 0, 1e-4, 3e-4, 5e-5, 0, 5e-5, 2e-4;
    // F = A^T A with A v = 0: rows orthogonal to v.
    Eigen::Matrix<double, 2, 3> a;
    a << 30, 30, 5, -4, -4, 60;
    field = a.transpose() * a;
    seen_gradient = a.transpose() * Eigen::Vector2d(0.7, -1.1);  // v^T g = 0
    // What central differences one DOF at a time add: information and a
    // gradient along v (edges a step moves across pixel centres, read as
    // slopes, on different pixels per DOF).
    const Eigen::Vector3d edges(2, -1.5, 0.3);
    artefact_information = 800 * edges * edges.transpose();
    artefact_gradient = 9 * edges;
  }

  Eigen::VectorXd step(double unseen_ratio, const Eigen::Matrix3d& information,
                       const Eigen::Vector3d& gradient, int* unseen = nullptr) const {
    MeanRefinement solver(Eigen::VectorXd::Zero(3), 1, 1.0, unseen_ratio);
    EXPECT_TRUE(solver.solve(prior, x, information, gradient, field, pixels, spread));
    if (unseen) *unseen = solver.unseen_directions();
    return solver.step();
  }
  // The prior's pull along v at the stepped mean: v^T P^-1 (x + delta),
  // zero when the step along v is the prior's alone.
  double prior_pull_along_v(const Eigen::VectorXd& delta) const {
    return v.dot(prior.ldlt().solve(x + delta));
  }
};

TEST(MeanRefinement, AlongADirectionThatMovesNoSurfaceTheMeanFollowsThePriorAlone) {
  const UnseenDirectionProblem p;
  ASSERT_LT((p.field * p.v).norm(), 1e-9);
  const Eigen::Matrix3d information = p.field + p.artefact_information;
  const Eigen::Vector3d gradient = p.seen_gradient + p.artefact_gradient;

  // Without the option the edges' information moves the mean along v,
  // away from where the prior puts it.
  const Eigen::VectorXd off = p.step(0, information, gradient);
  EXPECT_GT(std::abs(p.prior_pull_along_v(off)), 1.0);

  // With it, one direction is unseen and the step meets the projected
  // problem's stationarity along v: P^-1 (x + delta) has no component
  // along v, whatever the edges said there.
  int unseen = 0;
  const Eigen::VectorXd on = p.step(0.01, information, gradient, &unseen);
  EXPECT_EQ(unseen, 1);
  EXPECT_NEAR(p.prior_pull_along_v(on), 0, 1e-6);
}

TEST(MeanRefinement, WhereTheCentralDifferencesAgreeWithTheFieldNothingChanges) {
  // The image's information is the motion field's, v's included (0 in
  // both, to round-off, so v may or may not count as unseen): the step is
  // the same either way.
  const UnseenDirectionProblem p;
  const Eigen::VectorXd off = p.step(0, p.field, p.seen_gradient);
  const Eigen::VectorXd on = p.step(0.01, p.field, p.seen_gradient);
  EXPECT_LT((on - off).norm(), 1e-9 * off.norm());
}

TEST(MeanRefinement, EveryDirectionSeenLeavesTheStepAsItWas) {
  // A field with no null direction (every eigenvalue of L^T F L far above
  // the ratio times the central differences' information along it, edges
  // included): nothing is projected.
  UnseenDirectionProblem p;
  p.field += 5000 * p.v * p.v.transpose();
  const Eigen::Matrix3d information = p.field + p.artefact_information;
  const Eigen::Vector3d gradient = p.seen_gradient + p.artefact_gradient;
  int unseen = -1;
  const Eigen::VectorXd on = p.step(0.01, information, gradient, &unseen);
  EXPECT_EQ(unseen, 0);
  EXPECT_EQ(on, p.step(0, information, gradient));
}

TEST(MeanRefinement, WeakInformationTheCentralDifferencesAgreeWithIsKept) {
  // Along v the field reads a thousandth of the prior's information, and
  // the central differences read the same: a small image's real, weak
  // information about a prior that many images have narrowed. Nothing is
  // unseen (below a fraction of the prior's alone it was, and a planar
  // arm's camera stayed 6 sigma off).
  UnseenDirectionProblem p;
  p.field += 2 * p.v * p.v.transpose();  // v^T P v = 5e-4: whitened 1e-3
  const Eigen::Vector3d gradient = p.seen_gradient + 0.05 * p.v;
  int unseen = -1;
  const Eigen::VectorXd on = p.step(0.01, p.field, gradient, &unseen);
  EXPECT_EQ(unseen, 0);
  EXPECT_EQ(on, p.step(0, p.field, gradient));
}

TEST(MeanRefinement, ADirectionTheFieldSeesIsKeptWhereTheCentralDifferencesReadFarMore) {
  // Along v the field reads about the prior's information, and the central
  // differences ten thousand times more (a mesh's facets and edges). Below
  // a fraction of the central differences' alone it was unseen, and the
  // sculpted dual arm's camera converged over 30 s instead of 2.
  UnseenDirectionProblem p;
  p.field += 2000 * p.v * p.v.transpose();  // whitened about 1
  const Eigen::Matrix3d information = p.field + 1e4 * p.artefact_information;
  const Eigen::Vector3d gradient = p.seen_gradient + p.artefact_gradient;
  int unseen = -1;
  const Eigen::VectorXd on = p.step(0.01, information, gradient, &unseen);
  EXPECT_EQ(unseen, 0);
  EXPECT_EQ(on, p.step(0, information, gradient));
}

TEST(MeanRefinement, AStepWithAnUnseenDirectionAllocatesNothingOnceSized) {
  // The default's path on every image of arm7: the whitening, the
  // eigenvectors, the central differences' information along the
  // candidates and the projection, into the solver's kept workspace.
  const UnseenDirectionProblem p;
  const Eigen::MatrixXd prior = p.prior, field = p.field,
                        information = p.field + p.artefact_information;
  const Eigen::VectorXd x = p.x, gradient = p.seen_gradient + p.artefact_gradient;
  MeanRefinement solver(Eigen::VectorXd::Zero(3), 1, 1.0, 0.01);
  const long sizing = g_allocations.load();
  ASSERT_TRUE(solver.solve(prior, x, information, gradient, field, p.pixels, p.spread));
  EXPECT_GT(g_allocations.load(), sizing);  // the first step sizes the workspace
  const long before = g_allocations.load();
  bool solved = true;
  for (int k = 0; k < 10; ++k)
    solved = solver.solve(prior, x, information, gradient, field, p.pixels, p.spread) && solved;
  const long allocations = g_allocations.load() - before;
  EXPECT_TRUE(solved);
  EXPECT_EQ(solver.unseen_directions(), 1);
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace arttrack
