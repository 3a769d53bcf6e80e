// The outer algorithm both engines run (solver/outer_loop.hpp), on a stepper whose fixed point is
// known in closed form: the minimizer u(λ) = c − bλ and the bound F_b(u) = μu make the relaxed map
// λ ↦ (1−θ)λ + θμ(c − bλ) affine, with contraction factor ρ = |1 − θ(1 + μb)| and fixed point
// λ* = μc / (1 + μb). The loop's verdicts (converged, capped, not contracting, backend failure,
// early certified stop, hand-over) are then exact statements about ρ, not about a mesh.
#include <hemicontact/solver/outer_loop.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

using namespace hemicontact;

namespace {

struct AffineStepper : OuterStepper {
  SolveOptions opt;
  Solution sol;
  size_t n_stages = 3;
  bool is_lagged = true;
  double c = 1, b = 1, mu = -0.5;  // ρ = |1 − θ(1 + μb)|
  double lambda = 0, u = 0, u_prev = 0;
  int fail_at = -1;            // the minimization (k) whose backend fails
  bool polish_ok = true;       // certified_copy returns a copy
  bool has_polish = true;
  bool has_exact = false;
  int exact_after = -1;        // exact_due says "due" after this stage
  int k = 0, finishes = 0, copies = 0, exact_stage = -1;
  std::vector<size_t> smoothed;

  Solution& solution() override { return sol; }
  size_t stage_count() const override { return n_stages; }
  bool lagged() const override { return is_lagged; }
  std::string backend_name() const override { return "fake"; }
  void set_smoothing(size_t stage) override { smoothed.push_back(stage); }
  OuterIteration minimize(size_t stage) override {
    OuterIteration rec;
    rec.k = k++;
    rec.stage = static_cast<int>(stage);
    u = is_lagged ? c - b * lambda : c;
    const double s = std::max(std::abs(u), std::abs(u_prev));
    rec.change_u = s > 0 ? std::abs(u - u_prev) / s : 0.0;
    u_prev = u;
    rec.backend.status = rec.k == fail_at ? SolveStatus::FAILED : SolveStatus::CONVERGED;
    rec.backend.message = "fake backend";
    return rec;
  }
  LambdaChange relax_lambda() override {
    const double l = (1 - opt.relaxation) * lambda + opt.relaxation * mu * u;
    const LambdaChange c{std::abs(l - lambda), std::max(std::abs(l), std::abs(lambda))};
    lambda = l;
    return c;
  }
  bool polish_exists() const override { return has_polish; }
  std::optional<Solution> certified_copy() override {
    ++copies;
    if (!polish_ok) return std::nullopt;
    Solution t = sol;
    t.message = "copy";
    return t;
  }
  Solution finish() override {
    ++finishes;
    return sol;
  }
  bool exact_available() const override { return has_exact; }
  std::string exact_due(size_t stage, bool failed) override {
    return failed || static_cast<int>(stage) >= exact_after ? "due" : "";
  }
  Solution exact_finish(size_t stage, const std::string&) override {
    exact_stage = static_cast<int>(stage);
    Solution t = sol;
    t.message = "exact";
    return t;
  }
  size_t final_stage_minimizations() const {
    return static_cast<size_t>(std::count_if(sol.history.begin(), sol.history.end(), [&](const OuterIteration& h) {
      return h.stage == static_cast<int>(n_stages) - 1;
    }));
  }
};

TEST(OuterLoop, TheFixedPointConvergesAtTheMeasuredContraction) {
  AffineStepper s;  // θ = 1, μb = −0.5: ρ = 0.5
  s.opt.certify_below = 0;  // no early stop: every stage runs
  const Solution r = run_outer(s, s.opt);
  EXPECT_EQ(s.finishes, 1);
  EXPECT_TRUE(r.fixed_point_converged);
  EXPECT_TRUE(r.message.empty()) << r.message;
  EXPECT_EQ(s.smoothed, (std::vector<size_t>{0, 1, 2}));
  // One lagged update per coarse stage, then the fixed point.
  EXPECT_EQ(s.sol.history.size(), 2 + s.final_stage_minimizations());
  int measured = 0;
  for (const auto& h : s.sol.history)
    if (std::isfinite(h.contraction)) {
      // Each ρ_k is a ratio of two differences of an affine map: exact up to the cancellation in
      // Δλ, whose relative error is ~ε_mach |λ| / |Δλ| ≤ ε_mach / contraction_floor.
      EXPECT_NEAR(h.contraction, 0.5, 1e-6);
      ++measured;
    }
  EXPECT_GE(measured, 3);
  EXPECT_NEAR(r.contraction_estimate, 0.5, 1e-6);
  // Stopped at a change ≤ tol_u: the distance to λ* is at most ρ/(1−ρ) times the last step.
  const double lambda_star = s.mu * s.c / (1 + s.mu * s.b);
  EXPECT_LE(std::abs(s.lambda - lambda_star), 2 * s.opt.tol_u * std::abs(lambda_star));
}

TEST(OuterLoop, AnOscillatingMapIsStoppedByTheNonContractionTest) {
  AffineStepper s;
  s.mu = 1;  // ρ = |1 − (1 + 1)| = 1: λ alternates between two values, every change the same
  s.opt.certify_below = 0;
  s.opt.max_outer = 1000;
  const Solution r = run_outer(s, s.opt);
  EXPECT_FALSE(r.fixed_point_converged);
  EXPECT_NE(r.message.find("does not contract"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("contraction factor 1 (last 1)"), std::string::npos) << r.message;
  // From the second iteration on no change shrinks: stall_iters slow iterations after the first.
  EXPECT_EQ(s.final_stage_minimizations(), static_cast<size_t>(s.opt.stall_iters) + 1);
  EXPECT_EQ(s.finishes, 1);
}

TEST(OuterLoop, ASlowMapStopsAtTheCapAndSaysSo) {
  AffineStepper s;
  s.mu = -0.02;  // ρ = 0.98
  s.opt.certify_below = 0;
  s.opt.max_outer = 5;
  const Solution r = run_outer(s, s.opt);
  EXPECT_FALSE(r.fixed_point_converged);
  EXPECT_NE(r.message.find("did not converge in 5 outer iterations"), std::string::npos) << r.message;
  EXPECT_EQ(s.final_stage_minimizations(), 5u);
}

TEST(OuterLoop, ABackendFailureStopsTheRunAndTheCertificateStillJudges) {
  AffineStepper s;
  s.fail_at = 1;
  s.opt.certify_below = 0;
  const Solution r = run_outer(s, s.opt);
  EXPECT_EQ(s.sol.history.size(), 2u);  // stage 0, then the failing stage 1; stage 2 never runs
  EXPECT_FALSE(r.backend_ok);
  EXPECT_EQ(r.message.rfind("backend fake failed at outer iteration 1", 0), 0u) << r.message;
  EXPECT_EQ(s.finishes, 1);  // polished and certified all the same
}

TEST(OuterLoop, ASettledStageEndsTheRunWhenItsPolishedCopyIsCertified) {
  AffineStepper s;
  s.is_lagged = false;  // u = c from the first minimization on: stage 1 does not move it
  s.n_stages = 4;
  const Solution r = run_outer(s, s.opt);
  EXPECT_EQ(s.sol.history.size(), 2u);
  EXPECT_EQ(s.copies, 1);
  EXPECT_EQ(s.finishes, 0);
  EXPECT_EQ(r.message, "copy");
  ASSERT_FALSE(r.skipped.empty());
  EXPECT_NE(r.skipped.back().find("stages 2..3 not run"), std::string::npos) << r.skipped.back();
  // Without a polish there is nothing to certify early: every stage runs.
  AffineStepper t;
  t.is_lagged = false;
  t.n_stages = 4;
  t.has_polish = false;
  run_outer(t, t.opt);
  EXPECT_EQ(t.sol.history.size(), 4u);
  EXPECT_EQ(t.copies, 0);
  EXPECT_EQ(t.finishes, 1);
}

TEST(OuterLoop, TheExactSolverTakesOverWhenDueAfterThePolishFails) {
  AffineStepper s;
  s.has_exact = true;
  s.exact_after = 1;
  s.polish_ok = false;
  s.opt.certify_below = 0;
  const Solution r = run_outer(s, s.opt);
  EXPECT_EQ(s.exact_stage, 1);
  EXPECT_EQ(s.copies, 1);  // the polish first: cheaper, often enough
  EXPECT_EQ(r.message, "exact");
  EXPECT_EQ(s.finishes, 0);
  // A polish that passes ends the run there, on the last stage without the "not run" note.
  AffineStepper t;
  t.has_exact = true;
  t.exact_after = 2;
  t.opt.certify_below = 0;
  const Solution q = run_outer(t, t.opt);
  EXPECT_EQ(q.message, "copy");
  EXPECT_EQ(t.exact_stage, -1);
  EXPECT_TRUE(q.skipped.empty());
}

}  // namespace
