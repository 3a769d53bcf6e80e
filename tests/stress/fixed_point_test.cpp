// The outer fixed point λ = F_b(u_ν) (docs/model.md §2) under stress: its measured contraction factor,
// a scene where it does not contract and says so, and what the relaxed update θ < 1 buys.
//
// Scene: fig2 at n = 16 without rigid obstacle and without side tractions, with a large horizontal
// body force, so every Γ3 node slips the same way (slip+; all but the
// corner node in normal compliance). On that fixed
// status set u is affine in λ, so the map λ ↦ μ p_ν(u_ν(λ)) has the derivative μ·J with J fixed:
// the contraction factor is proportional to μ. Measured: ρ ≈ 0.13 μ (0.39 at μ = 3, 0.66 at μ = 5);
// at μ = 8 the iterates oscillate with ρ ≈ 1, and θ = 0.5 brings ρ to ≈ 0.48 (bench/stress_report
// sweeps θ × μ).
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace hemicontact;

namespace {

struct SlidingRun {
  Model md;
  SolveOptions opt;
  Solution sol;
};

SlidingRun solve_sliding(double mu, double theta) {
  const std::vector<std::string> o{"mesh.n=16",
                                   "check.smallness=false",
                                   "contact.gap=null",
                                   "boundary.gamma2=[]",
                                   "loads.body_force=[20000,-500]",
                                   "contact.friction.mu=" + std::to_string(mu),
                                   "solver.fixed_point.relaxation=" + std::to_string(theta),
                                   // The continuation's own fixed point is what is measured here; the
                                   // exact solver (on by default) would take over after stage 0.
                                   // Its Anderson-accelerated fixed point: tests/solver/exact_inner_test.cpp.
                                   "solver.exact.enabled=false"};
  const nlohmann::json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", o);
  SlidingRun r;
  r.md = build_model(s, ".");
  r.opt = solve_options_from_scene(s);
  r.sol = solve(r.md, r.opt);
  return r;
}

}  // namespace

// Below the threshold the loop contracts, with ρ < 1 measured on every final-stage iteration, and
// ρ(μ = 5)/ρ(μ = 3) = 5/3 because the derivative of the map is μ·J on a fixed status set.
TEST(FixedPointContraction, FactorBelowOneAndProportionalToMu) {
  const SlidingRun a = solve_sliding(3, 1);
  ASSERT_TRUE(a.sol.ok()) << a.sol.message;
  for (const auto& st : a.sol.status) ASSERT_EQ(to_string(st.tangential), std::string("slip+"));
  int measured = 0;
  for (const auto& h : a.sol.history)
    if (!std::isnan(h.contraction)) {
      EXPECT_LT(h.contraction, 1.0);
      ++measured;
    }
  EXPECT_GE(measured, 5);
  const double rho3 = a.sol.contraction_estimate;
  EXPECT_LT(rho3, 1.0);
  // (At μ = 5, ρ ≈ 0.66 needs ~60 iterations, more than the default 50: only ρ is used here.)
  const SlidingRun b = solve_sliding(5, 1);
  const double rho5 = b.sol.contraction_estimate;
  ASSERT_TRUE(std::isfinite(rho5));
  // 2%: the ratio of two geometric means of ρ_k, each constant to ~1e-3 over the iterations.
  EXPECT_NEAR(rho5 / rho3, 5.0 / 3.0, 0.02 * 5.0 / 3.0) << "rho3 " << rho3 << ", rho5 " << rho5;

  // report.json carries the factors: one entry per outer iteration (null where undefined) and
  // the estimate.
  const nlohmann::json rep = make_report(a.md, a.sol, a.opt);
  const auto& fp = rep.at("fixed_point");
  ASSERT_EQ(fp.at("contraction").size(), a.sol.history.size());
  EXPECT_TRUE(fp.at("contraction").at(0).is_null());  // stage 0: one update, no ratio
  EXPECT_DOUBLE_EQ(fp.at("contraction_estimate").get<double>(), rho3);
  EXPECT_EQ(fp.at("relaxation").get<double>(), 1.0);
  EXPECT_TRUE(fp.at("history").back().contains("contraction"));
}

// μ = 8: the plain update oscillates (ρ ≈ 1); the solver stops, says the fixed point does not
// contract and suggests relaxation, and the answer is not accepted. With θ = 0.5 it converges and
// is certified.
TEST(FixedPointContraction, NonContractingLoopSaysSoAndRelaxationConverges) {
  const SlidingRun plain = solve_sliding(8, 1);
  EXPECT_FALSE(plain.sol.fixed_point_converged);
  EXPECT_FALSE(plain.sol.ok());
  EXPECT_NE(plain.sol.message.find("fixed point lambda = F_b(u_nu) does not contract"), std::string::npos)
      << plain.sol.message;
  EXPECT_NE(plain.sol.message.find("solver.fixed_point.relaxation"), std::string::npos) << plain.sol.message;
  EXPECT_GT(plain.sol.contraction_estimate, plain.opt.stall_ratio - 0.05);

  const SlidingRun relaxed = solve_sliding(8, 0.5);
  EXPECT_TRUE(relaxed.sol.fixed_point_converged) << relaxed.sol.message;
  ASSERT_TRUE(relaxed.sol.ok()) << relaxed.sol.message;
  EXPECT_LE(relaxed.sol.certificate.max_residual, relaxed.sol.certificate.tol);
  EXPECT_LT(relaxed.sol.contraction_estimate, 0.75);
}

// What relaxation buys, predicted from the plain loop's factor. The map's Jacobian on the fixed
// slip set has (measured) eigenvalues in [−a, ≈0] with a = ρ(θ = 1) (the iterates oscillate); the
// relaxed map λ ↦ (1−θ)λ + θ F_b(u_ν(λ)) has eigenvalues 1 − θ(1 − j) ∈ [1 − θ(1 + a), 1 − θ],
// so ρ(θ) = max(1 − θ, |1 − θ(1 + a)|), smallest at θ* = 2/(2 + a). At μ = 5 (a ≈ 0.66, θ* ≈ 0.75)
// θ = 0.75 must cut ρ to ≈ 0.25 and converge well within the cap the plain loop exhausts.
TEST(FixedPointContraction, RelaxedFactorMatchesPredictionFromPlainFactor) {
  const SlidingRun plain = solve_sliding(5, 1);
  const double a = plain.sol.contraction_estimate;
  ASSERT_TRUE(std::isfinite(a));
  const double theta = 0.75;
  const SlidingRun relaxed = solve_sliding(5, theta);
  ASSERT_TRUE(relaxed.sol.ok()) << relaxed.sol.message;
  const double predicted = std::max(1 - theta, std::abs(1 - theta * (1 + a)));
  // 15%: the geometric mean over ~15 ratios that scatter by ±20% around the asymptotic factor
  // (the top of the spectrum is slightly below 0, which lowers the measured factor).
  EXPECT_NEAR(relaxed.sol.contraction_estimate, predicted, 0.15 * predicted)
      << "a = " << a << ", measured " << relaxed.sol.contraction_estimate;
  EXPECT_LT(relaxed.sol.history.size(), plain.sol.history.size() / 2);
}
