// The exact inner solver's local descent (ExactInnerOptions::local_descent, for path following):
// on one node with two minima along its normal unknown it stays in the start's basin, where the
// default's proximal steps jump to the lower minimum along the line; both against closed forms.
//
// One node (d = 2), frictionless, the table law of problems/minima-one-node.json (p rises with
// slope 1e4 to 1000 at r = 0.1, falls to 0 at 0.12, stays 0 up to g = 0.3), w = 1, and
//   Φ(x) = ½ (x − y)ᵀ S (x − y) + j(x_ν),  S = [[a, b], [b, c]],  y = (0.5, 0.05).
// Stationary on piece 1 (p = s₁ x_ν): (S + diag(s₁, 0)) x = S y, a local minimum when that point
// lies in (0, 0.1); at the bound x_ν = g: x_τ = y_τ − (b/c)(g − y_ν). With a = 1000 the minimum at
// g is the lower one (Φ = ½(a − b²/c)(g − y_ν)² + j(g) = 80 − ...): the default finds it from
// x = 0, the local descent stays on piece 1.
#include <hemicontact/solver/exact_inner.hpp>

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>

namespace hemicontact {
namespace local_descent_test {

struct OneNode {
  Mat S = (Mat(2, 2) << 1000, 200, 200, 800).finished();
  PiecewiseLinearLaw law{{{0.0, 0.0}, {0.1, 1000.0}, {0.12, 0.0}}, 0.0, 0.0};
  ExactInnerProblem P;
  OneNode() {
    P.S = &S;
    P.d = 2;
    P.y = (Vec(2) << 0.5, 0.05).finished();
    P.w = Vec::Constant(1, 1.0);
    P.g = Vec::Constant(1, 0.3);
    P.lambda = Vec::Zero(1);
    P.law = &law;
    P.traction_scale = 1000;
  }
  Vec solve_from(double xn, bool local) const {
    Vec x = (Vec(2) << xn, 0.0).finished();
    ExactInnerOptions o;
    o.local_descent = local;
    const ExactInnerResult R = exact_inner_solve(P, x, o);
    EXPECT_TRUE(R.converged) << R.note;
    EXPECT_LE(exact_inner_residual(P, x), o.tol);
    return x;
  }
};

TEST(LocalDescent, StaysInTheStartsBasinWhereTheProximalStepJumps) {
  const OneNode n;
  const double s1 = 1e4;  // slope of p on piece 1
  const Mat A = n.S + (Mat(2, 2) << s1, 0, 0, 0).finished();
  const Vec branch1 = A.fullPivLu().solve(n.S * n.P.y);
  ASSERT_GT(branch1[0], 0.0);
  ASSERT_LT(branch1[0], 0.1);
  const double g = n.P.g[0];
  const Vec at_g = (Vec(2) << g, n.P.y[1] - n.S(0, 1) / n.S(1, 1) * (g - n.P.y[0])).finished();
  ASSERT_LT(exact_inner_energy(n.P, at_g), exact_inner_energy(n.P, branch1)) << "the minimum at g is the lower";
  const Vec global = n.solve_from(0.0, false), local = n.solve_from(0.0, true);
  EXPECT_NEAR(global[0], g, 1e-14);
  EXPECT_NEAR(global[1], at_g[1], 1e-12);
  EXPECT_NEAR(local[0], branch1[0], 1e-12);
  EXPECT_NEAR(local[1], branch1[1], 1e-12);
  // From the softening piece (p falls): φ' > 0 there at 0.11, so downhill is back to piece 1; from
  // the flat piece (p = 0) at 0.2 downhill is the bound.
  const Vec back = n.solve_from(0.11, true), on = n.solve_from(0.2, true);
  EXPECT_NEAR(back[0], branch1[0], 1e-12);
  EXPECT_NEAR(on[0], g, 1e-14);
  EXPECT_NEAR(on[1], at_g[1], 1e-12);
}

}  // namespace local_descent_test
}  // namespace hemicontact
