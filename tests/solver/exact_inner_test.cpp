// The exact inner solver (solver/exact_inner.hpp): exactness on small condensed problems
// (its stationarity residual, and no feasible perturbation lowers the exact energy), the convexity
// check and Anderson acceleration against closed forms, and through the solver: the hand-over
// agrees with the polished continuation on the paper's scenes in 2D and 3D, and certifies a scene
// whose plain fixed point does not converge.
#include <hemicontact/config.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/exact_inner.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace hemicontact;

namespace {

// A random SPD "Schur complement" with a dominant diagonal of size ~ kappa and smooth coupling,
// node by node d unknowns, and a random load y: the shape of a condensed contact problem.
struct Random {
  Mat S;
  ExactInnerProblem P;
  PiecewiseLinearLaw law = PiecewiseLinearLaw::paper(100, -100, 400, 0.1, 0.15);
};

Random random_problem(unsigned seed, int d, Index nc, double kappa, double mu, double g) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Random r;
  const Index m = d * nc;
  Mat B(m, m);
  for (Index i = 0; i < m; ++i)
    for (Index j = 0; j < m; ++j) B(i, j) = U(rng);
  r.S = B * B.transpose() / static_cast<double>(m) + kappa * Mat::Identity(m, m);
  r.P.S = &r.S;
  r.P.d = d;
  r.P.y = Vec(m);
  for (Index i = 0; i < m; ++i) r.P.y[i] = 0.2 * U(rng);
  for (Index k = 0; k < nc; ++k) r.P.y[d * k] = 0.12 + 0.1 * U(rng);  // around the kinks r1, r2 and g
  r.P.w = Vec::Constant(nc, 0.5);
  r.P.g = Vec::Constant(nc, g);
  r.P.lambda = Vec(nc);
  for (Index k = 0; k < nc; ++k) r.P.lambda[k] = mu * (1 + 0.5 * U(rng));
  r.P.traction_scale = 1;
  return r;
}

// Exactness: the residual is at the solver's tolerance and no feasible perturbation of one or
// two unknowns (steps 1e-3..1e-7) lowers Φ_λ below the answer's value (a local minimizer of the
// unsmoothed energy, not a smoothed one: a smoothed answer loses against these steps at the kinks).
void expect_exact_minimizer(Random& r, unsigned seed) {
  // the law must outlive P: attach after the move
  r.P.law = &r.law;
  Vec x = Vec::Zero(r.S.rows());
  const ExactInnerOptions opt;
  const ExactInnerResult R = exact_inner_solve(r.P, x, opt);
  ASSERT_TRUE(R.converged) << R.note << " residual " << R.residual;
  EXPECT_LE(exact_inner_residual(r.P, x), opt.tol);
  const double E = exact_inner_energy(r.P, x);
  EXPECT_NEAR(E, R.energy, 1e-12 * std::abs(E));
  std::mt19937 rng(seed + 1000);
  std::uniform_int_distribution<Index> pick(0, r.S.rows() - 1);
  for (double h : {1e-3, 1e-5, 1e-7})
    for (int trial = 0; trial < 40; ++trial) {
      Vec z = x;
      z[pick(rng)] += (trial % 2 ? h : -h);
      z[pick(rng)] += (trial % 3 ? h : -h) * 0.5;
      for (Index k = 0; k < r.P.w.size(); ++k) z[r.P.d * k] = std::min(z[r.P.d * k], r.P.g[k]);
      // Round-off of Φ at the answer: ~1e-15 of its terms.
      EXPECT_GE(exact_inner_energy(r.P, z), E - 1e-13 * (1 + std::abs(E))) << "h " << h;
    }
}

}  // namespace

// 2D and 3D, with and without the obstacle, strongly convex (kappa large against the softening
// α w = 50) and not: the answer is a minimizer of the exact energy to round-off.
TEST(ExactInner, MinimizesTheUnsmoothedEnergy2D) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    Random r = random_problem(seed, 2, 12, seed % 2 ? 200.0 : 20.0, 0.5 * seed, seed % 2 ? 0.15 : INF);
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_exact_minimizer(r, seed);
  }
}

TEST(ExactInner, MinimizesTheUnsmoothedEnergy3D) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    Random r = random_problem(seed, 3, 8, seed % 2 ? 200.0 : 20.0, 0.5 * seed, seed % 2 ? 0.15 : INF);
    SCOPED_TRACE("seed " + std::to_string(seed));
    expect_exact_minimizer(r, seed);
  }
}

// One node, S diagonal: the exact answer in closed form. Normal: S_νν (x − y_ν) + w p(x) = 0 with
// p on its piece; y_ν = 0.5 beyond g = 0.15 → contact x_ν = g; tangential: soft threshold
// x_τ = y_τ − w λ/S_ττ·sign (slip) or 0 (stick when |S_ττ y_τ| ≤ w λ).
// A kept factor (ExactInnerFactor, the outer loop's λ updates): in 2D a second solve with λ moved
// slightly, from the first answer, needs no factorization where its statuses stay, and lands on the
// same minimizer as a solve that factors afresh; a λ that moves the statuses (friction off: every
// stick node slips) factors again where its Newton steps need it, and still lands where a fresh
// solve does: no stale factor is used.
TEST(ExactInner, AKeptFactorServesTheNextLambdaWhereTheStatusesStay) {
  int refactored = 0;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    Random r = random_problem(seed, 2, 12, 200.0, 0.5, 0.15);
    r.P.law = &r.law;
    ExactInnerFactor keep;
    Vec x = Vec::Zero(r.S.rows());
    ASSERT_TRUE(exact_inner_solve(r.P, x, {}, &keep).converged);
    r.P.lambda *= 1 + 1e-9;  // a converging outer loop's last update
    Vec kept = x, fresh = x;
    const ExactInnerResult K = exact_inner_solve(r.P, kept, {}, &keep);
    const ExactInnerResult F = exact_inner_solve(r.P, fresh);
    ASSERT_TRUE(K.converged && F.converged) << K.note << F.note;
    EXPECT_EQ(K.factorizations, 0) << "seed " << seed;
    EXPECT_EQ(K.newton_steps, F.newton_steps);
    EXPECT_LE((kept - fresh).cwiseAbs().maxCoeff(), 1e-12 * (1 + fresh.cwiseAbs().maxCoeff())) << "seed " << seed;
    r.P.lambda.setZero();
    Vec moved = x, moved_fresh = x;
    const ExactInnerResult M = exact_inner_solve(r.P, moved, {}, &keep);
    ASSERT_TRUE(M.converged && exact_inner_solve(r.P, moved_fresh).converged) << M.note;
    EXPECT_LE((moved - moved_fresh).cwiseAbs().maxCoeff(), 1e-12 * (1 + moved_fresh.cwiseAbs().maxCoeff()));
    refactored += M.factorizations;
  }
  EXPECT_GT(refactored, 0);
}

TEST(ExactInner, SingleNodeClosedForms) {
  const PiecewiseLinearLaw law = PiecewiseLinearLaw::paper(100, -100, 400, 0.1, 0.15);
  Mat S = Mat::Zero(2, 2);
  S(0, 0) = 1000;
  S(1, 1) = 500;
  ExactInnerProblem P;
  P.S = &S;
  P.d = 2;
  P.w = Vec::Constant(1, 0.5);
  P.g = Vec::Constant(1, 0.15);
  P.law = &law;
  P.lambda = Vec::Constant(1, 10.0);
  P.traction_scale = 100;
  // contact and slip: 500·(x_τ − 0.3) + 0.5·10 = 0
  P.y = Vec(2);
  P.y << 0.5, 0.3;
  Vec x = Vec::Zero(2);
  ASSERT_TRUE(exact_inner_solve(P, x).converged);
  EXPECT_EQ(x[0], 0.15);
  EXPECT_NEAR(x[1], 0.3 - 0.5 * 10 / 500, 1e-15);
  // compliance on (0, r1]: 1000 (x − 0.05) + 0.5·100 x = 0 → x = 50/1050; stick: 500·0.005 ≤ 5
  P.y << 0.05, 0.005;
  x.setZero();
  ASSERT_TRUE(exact_inner_solve(P, x).converged);
  EXPECT_NEAR(x[0], 50.0 / 1050.0, 1e-15);
  EXPECT_EQ(x[1], 0.0);
  // separated: y_ν < 0 → x_ν = y_ν, p = 0
  P.y << -0.2, 0.0;
  x.setConstant(0.1);
  ASSERT_TRUE(exact_inner_solve(P, x).converged);
  EXPECT_NEAR(x[0], -0.2, 1e-15);
}

// The check of strong convexity against a diagonal S: λ_min(S − α W_ν) in closed form.
TEST(ExactInner, ConvexityCheckClosedForm) {
  const PiecewiseLinearLaw law = PiecewiseLinearLaw::paper(100, -100, 400, 0.1, 0.15);  // α = 100
  Mat S = Mat::Zero(4, 4);
  S.diagonal() << 300, 80, 500, 90;  // two 2D nodes: normal rows 0, 2
  const Vec w = Vec::Constant(2, 0.5);  // α w = 50
  InnerConvexity c = inner_convexity(S, w, 2, &law, 100);
  ASSERT_TRUE(c.checked);
  EXPECT_TRUE(c.strongly_convex);
  EXPECT_DOUBLE_EQ(c.softening, 100);
  // Inverse iteration stops when its Rayleigh quotient changes by ≤ 1e-10 relative; at the
  // eigenvalue ratio 80/90 the quotient converges like (80/90)² ≈ 0.79 per step, so its error is
  // ≤ 0.79/(1 − 0.79) ≈ 4 times the last change: 4e-10 relative, 1e-8 absolute at 80 with margin.
  EXPECT_NEAR(c.min_eigenvalue, 80, 4e-10 * 80 * 2);  // min(300 − 50, 80, 500 − 50, 90)
  S(0, 0) = 20;                             // 20 − 50 = −30 < 0
  c = inner_convexity(S, w, 2, &law, 100);
  EXPECT_FALSE(c.strongly_convex);
  EXPECT_NEAR(c.min_eigenvalue, -30, 1e-8);  // shifted: 20 of 130, ratio 0.15, fast
  EXPECT_FALSE(inner_convexity(S, w, 2, &law, 3).checked);  // above the size cap
}

// Anderson on a linear map λ ↦ A λ + b whose plain iteration diverges (spectral radius 1.5):
// with memory ≥ n it is a Krylov method and reaches the fixed point in a few steps.
TEST(ExactInner, AndersonConvergesWhereThePlainIterationDiverges) {
  Mat A(3, 3);
  A << -1.5, 0.2, 0.0, 0.1, -1.2, 0.3, 0.0, 0.2, 0.5;
  const Vec b = Vec::Constant(3, 5.0);
  const Vec fixed = (Mat::Identity(3, 3) - A).partialPivLu().solve(b);
  ASSERT_GT(fixed.minCoeff(), 0);  // inside the clamp λ ≥ 0
  const auto run = [&](int memory) {
    Anderson aa(memory);
    Vec l = Vec::Constant(3, 1.0);
    for (int it = 0; it < 12; ++it) l = aa.next(l, A * l + b);
    return (l - fixed).norm();
  };
  EXPECT_LT(run(5), 1e-10 * fixed.norm());
  EXPECT_GT(run(0), 1.0);
}

// The mixing θ (solver.fixed_point.relaxation) on the same map. Memory 0: λ ← (1 − θ) λ + θ G(λ),
// whose iteration matrix (1 − θ) I + θ A has, at θ = 0.5, the eigenvalues −0.280, −0.087 and 0.767
// (A's: −1.560, −1.174, 0.535; real, A being similar to a symmetric matrix by a diagonal scaling):
// 200 steps shrink the error by 0.767^200 ≈ 1e-23.
// Memory 5: the damped Anderson step stays a Krylov method on a linear map (the extrapolated
// update's mixing changes the next Krylov vector, not the space), so it still converges fast.
TEST(ExactInner, AndersonsMixingDampsTheIteration) {
  Mat A(3, 3);
  A << -1.5, 0.2, 0.0, 0.1, -1.2, 0.3, 0.0, 0.2, 0.5;
  const Vec b = Vec::Constant(3, 5.0);
  const Vec fixed = (Mat::Identity(3, 3) - A).partialPivLu().solve(b);
  const auto run = [&](int memory, double theta, int steps) {
    Anderson aa(memory, theta);
    Vec l = Vec::Constant(3, 1.0);
    for (int it = 0; it < steps; ++it) l = aa.next(l, A * l + b);
    return (l - fixed).norm();
  };
  EXPECT_GT(run(0, 1.0, 200), 1.0);  // the plain iteration diverges
  EXPECT_LT(run(0, 0.5, 200), 1e-10 * fixed.norm());
  EXPECT_LT(run(5, 0.5, 12), 1e-10 * fixed.norm());
  // One relaxed step is exactly (1 − θ) λ + θ G(λ).
  Anderson one(0, 0.25);
  const Vec l0 = Vec::Constant(3, 1.0);
  EXPECT_LT((one.next(l0, A * l0 + b) - (0.75 * l0 + 0.25 * (A * l0 + b))).norm(), 1e-14 * fixed.norm());
}

namespace {

Solution solve_scene(const std::string& file, const std::vector<std::string>& o, Model& md) {
  const nlohmann::json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/" + file, o);
  md = build_model(s, ".");
  return solve(md, solve_options_from_scene(s));
}

// The sliding scene of tests/stress/fixed_point_test.cpp (no obstacle, no Γ2 traction, a body force
// that pushes the body sideways over the layer) at friction coefficient @p mu, plus @p extra.
std::vector<std::string> sliding_scene(const std::string& mu, std::vector<std::string> extra) {
  std::vector<std::string> o{"mesh.n=16",          "check.smallness=false", "contact.gap=null",
                             "boundary.gamma2=[]", "loads.body_force=[20000,-500]", "contact.friction.mu=" + mu};
  o.insert(o.end(), extra.begin(), extra.end());
  return o;
}

// u of two solutions agree to @p rel of the larger.
void expect_same_u(const Solution& a, const Solution& b, double rel) {
  const double s = std::max(a.u.cwiseAbs().maxCoeff(), b.u.cwiseAbs().maxCoeff());
  EXPECT_LE((a.u - b.u).cwiseAbs().maxCoeff(), rel * s);
}

}  // namespace

// The hand-over forced right after stage 0 (solver.exact.stage_max_iter = 1: every stage "stalls";
// solver.exact.start = never: no start before stage 0) reaches the answer of the continuation +
// polish alone (solver.exact.enabled = false), to round-off: both are certified solutions of the
// same problem, unique here by (21).
TEST(ExactHandover, AgreesWithThePolishedContinuation2D) {
  for (const std::string file : {"sofonea2017-fig2.json", "sofonea2017-printed.json"}) {
    SCOPED_TRACE(file);
    Model md;
    const Solution ref = solve_scene(file, {"mesh.n=8", "solver.exact.enabled=false"}, md);  // the continuation + polish
    ASSERT_TRUE(ref.ok()) << ref.message;
    const Solution ex = solve_scene(
        file, {"mesh.n=8", "solver.exact.enabled=true", "solver.exact.start=\"never\"", "solver.exact.stage_max_iter=1"}, md);
    ASSERT_TRUE(ex.ok()) << ex.message;
    EXPECT_TRUE(ex.handover.used);
    EXPECT_EQ(ex.handover.after_stage, 0);
    EXPECT_NE(ex.handover.reason.find("stalled"), std::string::npos) << ex.handover.reason;
    EXPECT_TRUE(ex.handover.fixed_point_converged);
    // The exact solver stops at the stationarity residual solver.exact.tol = 1e-10 (traction
    // units); the condensed stiffness's condition on Γ3 (~10² at n = 8) makes that ≤ 1e-8 in u.
    expect_same_u(ref, ex, 1e-8);
    for (size_t k = 0; k < ref.status.size(); ++k) EXPECT_EQ(ref.status[k].str(), ex.status[k].str()) << k;
    // (21) holds for the paper's data; the inner problem is strongly convex a fortiori.
    EXPECT_TRUE(ex.inner_convexity.checked);
    EXPECT_TRUE(ex.inner_convexity.strongly_convex);
  }
}

TEST(ExactHandover, AgreesWithThePolishedContinuation3D) {
  Model md;
  const std::vector<std::string> o{"mesh.n=4", "check.smallness=false"};
  std::vector<std::string> o1 = o;
  o1.push_back("solver.exact.enabled=false");  // the continuation + polish alone
  const Solution ref = solve_scene("sofonea2017-3d.json", o1, md);
  ASSERT_TRUE(ref.ok()) << ref.message;
  std::vector<std::string> o2 = o;
  o2.insert(o2.end(), {"solver.exact.enabled=true", "solver.exact.start=\"never\"", "solver.exact.stage_max_iter=1"});
  const Solution ex = solve_scene("sofonea2017-3d.json", o2, md);
  ASSERT_TRUE(ex.ok()) << ex.message;
  EXPECT_TRUE(ex.handover.used);
  expect_same_u(ref, ex, 1e-8);  // as in 2D
  for (size_t k = 0; k < ref.status.size(); ++k) EXPECT_EQ(ref.status[k].str(), ex.status[k].str()) << k;
}

// solver.exact.start = convex (what minima uses): the paper scenes' inner problems are strongly
// convex (smallest eigenvalue of S − α W_ν > 0), so the exact solver starts at once, no ε-stage
// runs, and the answer is the continuation's (solver.exact.enabled = false) to the same margin as
// above.
TEST(ExactStart, StronglyConvexScenesNeedNoContinuation) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"sofonea2017-fig2.json", {"mesh.n=8", "solver.exact.start=\"convex\""}},
      {"sofonea2017-printed.json", {"mesh.n=8", "solver.exact.start=\"convex\""}},
      {"sofonea2017-3d.json", {"mesh.n=4", "check.smallness=false", "solver.exact.start=\"convex\""}}};
  for (const auto& [file, o] : cases) {
    SCOPED_TRACE(file);
    Model md;
    std::vector<std::string> o1 = o;
    o1.push_back("solver.exact.enabled=false");
    const Solution ref = solve_scene(file, o1, md);
    ASSERT_TRUE(ref.ok()) << ref.message;
    EXPECT_FALSE(ref.handover.used);
    const Solution ex = solve_scene(file, o, md);
    ASSERT_TRUE(ex.ok()) << ex.message;
    ASSERT_TRUE(ex.inner_convexity.checked && ex.inner_convexity.strongly_convex);
    EXPECT_TRUE(ex.handover.used);
    EXPECT_EQ(ex.handover.after_stage, -1);
    EXPECT_NE(ex.handover.reason.find("strongly convex"), std::string::npos) << ex.handover.reason;
    EXPECT_TRUE(ex.handover.fixed_point_converged);
    for (const auto& h : ex.history) EXPECT_EQ(h.stage, -1);  // no ε-stage ran
    EXPECT_EQ(static_cast<int>(ex.history.size()), ex.handover.outer_iterations);
    bool said = false;
    const std::string backend = HEMICONTACT_HAS_IPOPT ? "ipopt" : "newton";  // solver.backend = auto
    for (const auto& s : ex.skipped)
      said = said || s.rfind("backend: " + backend + " not run: the inner problem is strongly convex", 0) == 0;
    EXPECT_TRUE(said);
    EXPECT_FALSE(ex.backend_use.ran);
    expect_same_u(ref, ex, 1e-8);
    for (size_t k = 0; k < ref.status.size(); ++k) EXPECT_EQ(ref.status[k].str(), ex.status[k].str()) << k;
  }
}

// With solver.exact.fallback = true, when the exact solver's start is not certified, it is
// forgotten and the continuation runs from the same start, and the report says so. The sliding
// scene below with the plain fixed point (anderson_memory = 0, which oscillates there) fails from
// the start; the continuation then runs (its minimizations are stage ≥ 0) and, with the same plain
// iteration, also fails, loudly.
TEST(ExactStart, NotCertifiedFromTheStartTheContinuationRuns) {
  const std::vector<std::string> o = sliding_scene(
      "8", {"solver.exact.start=\"always\"", "solver.fixed_point.anderson_memory=0", "solver.exact.fallback=true"});
  Model md;
  const Solution p = solve_scene("sofonea2017-fig2.json", o, md);
  EXPECT_FALSE(p.ok());
  EXPECT_NE(p.handover.note.find("the exact solver from the start was not certified"), std::string::npos)
      << p.handover.note;
  bool continuation_ran = false;
  for (const auto& h : p.history) continuation_ran = continuation_ran || h.stage >= 0;
  EXPECT_TRUE(continuation_ran);
}

// The default (start = auto, fallback = false): the same failing scene stops after the exact
// solver's start, with no ε-stage, not certified, its reason (the fixed point) in the message and
// the key that would try the continuation in `skipped`.
TEST(ExactStart, DefaultStopsAfterAStartThatIsNotCertified) {
  const std::vector<std::string> o = sliding_scene("8", {"solver.fixed_point.anderson_memory=0"});
  Model md;
  const Solution p = solve_scene("sofonea2017-fig2.json", o, md);
  EXPECT_FALSE(p.ok());
  EXPECT_FALSE(p.fixed_point_converged);
  EXPECT_NE(p.message.find("fixed point"), std::string::npos) << p.message;
  ASSERT_FALSE(p.history.empty());
  for (const auto& h : p.history) EXPECT_EQ(h.stage, -1);  // no ε-stage ran
  bool said = false;
  for (const auto& s : p.skipped) said = said || s.find("solver.exact.fallback = false") != std::string::npos;
  EXPECT_TRUE(said);
}

// start = auto: on a scene whose inner problem is not strongly convex (minima-softening: a layer
// that breaks through, α_jν = 1e5) the design's path runs — the backend's ε-stage 0, then the exact
// solver takes over — and the answer is certified; where the inner problem is strongly convex the
// backend's stage is skipped and the reason says so (the minimizer is unique).
TEST(ExactStart, AutoRunsTheBackendStageOnANotStronglyConvexScene) {
  const std::vector<std::string> o{"check.smallness=false"};
  Model md;
  const Solution a = solve_scene("minima-softening.json", o, md);
  ASSERT_TRUE(a.inner_convexity.checked);
  ASSERT_FALSE(a.inner_convexity.strongly_convex);
  ASSERT_TRUE(a.ok()) << a.message;
  EXPECT_TRUE(a.backend_use.ran);
  // Handed over after stage 0: to the polish on Ipopt's statuses here (certified at once), else the
  // exact solver.
  EXPECT_TRUE(a.polish.accepted || a.handover.after_stage == 0);
  ASSERT_FALSE(a.history.empty());
  EXPECT_EQ(a.history.front().stage, 0);
  EXPECT_EQ(a.history.front().solver, a.backend);
  const Solution c = solve_scene("sofonea2017-fig2.json", {"mesh.n=8"}, md);
  ASSERT_TRUE(c.ok()) << c.message;
  EXPECT_NE(c.handover.reason.find("strongly convex"), std::string::npos) << c.handover.reason;
  EXPECT_FALSE(c.backend_use.ran);
}

// solver.exact.polish_above: the polish runs after the exact solver only when the coupled residual
// is above it. With 0 it always runs (on an answer already at round-off it may be accepted or
// rejected: a rejected polish leaves the answer as it was); with 1e-3 (above solver.exact.tol, so
// every converged answer qualifies) it is skipped and `skipped` says why. Both are certified, with
// the same u to round-off of the certificate's scale.
TEST(ExactHandover, PolishAfterTheExactSolverOnlyAboveRoundOff) {
  Model md;
  const Solution always = solve_scene("sofonea2017-fig2.json", {"mesh.n=8", "solver.exact.polish_above=0"}, md);
  ASSERT_TRUE(always.ok()) << always.message;
  EXPECT_TRUE(always.polish.attempted);
  const Solution skip = solve_scene("sofonea2017-fig2.json", {"mesh.n=8", "solver.exact.polish_above=1e-3"}, md);
  ASSERT_TRUE(skip.ok()) << skip.message;
  EXPECT_FALSE(skip.polish.attempted);
  bool said = false;
  for (const auto& k : skip.skipped) said = said || k.rfind("polish: the exact solver's coupled residual", 0) == 0;
  EXPECT_TRUE(said);
  EXPECT_LE(skip.certificate.max_residual, 1e-10);  // solver.exact.tol, and the certificate's margin
  EXPECT_LE((skip.u - always.u).cwiseAbs().maxCoeff(), 1e-9 * always.u.cwiseAbs().maxCoeff());
}

// The Anderson fixed point at its cap (solver.fixed_point.max_iters) with the coupled residual
// already below check.certificate_tol: the certificate decides, as at the round-off floor. The
// sliding scene with the layer ×10 and μ = 12 (docs/stress/theta.md) needs about 50 updates from
// the start; with a cap of 20 and certificate_tol 1e-12 — far below its residual there — it is
// still refused, naming the fixed point.
TEST(ExactHandover, AtTheCapTheCertificateDecides) {
  const std::vector<std::string> o = sliding_scene(
      "12", {"contact.normal_law.c1=1000", "contact.normal_law.c2=-1000", "contact.normal_law.c3=4000"});
  Model md;
  const Solution a = solve_scene("sofonea2017-fig2.json", o, md);
  ASSERT_TRUE(a.ok()) << a.message;
  EXPECT_LE(a.certificate.max_residual, 1e-8);
  if (a.handover.outer_iterations >= 50) {
    EXPECT_NE(a.handover.note.find("below check.certificate_tol"), std::string::npos) << a.handover.note;
  }
  std::vector<std::string> tight = o;
  tight.insert(tight.end(), {"solver.fixed_point.max_iters=20", "check.certificate_tol=1e-12"});
  const Solution t = solve_scene("sofonea2017-fig2.json", tight, md);
  EXPECT_FALSE(t.ok());
  EXPECT_FALSE(t.fixed_point_converged);
  EXPECT_NE(t.message.find("fixed point"), std::string::npos) << t.message;
}

// The sliding scene of tests/stress/fixed_point_test.cpp at μ = 8: the plain λ = F_b(u_ν)
// oscillates (ρ ≈ 1) and fails, with the backend or with the exact solver (anderson_memory = 0);
// with the defaults the exact solver's Anderson-accelerated fixed point converges and certifies.
TEST(ExactHandover, AndersonCertifiesWhereThePlainFixedPointFails) {
  const std::vector<std::string> o = sliding_scene("8", {"solver.exact.enabled=true"});
  Model md;
  std::vector<std::string> plain = o;
  plain.push_back("solver.fixed_point.anderson_memory=0");
  const Solution p = solve_scene("sofonea2017-fig2.json", plain, md);
  EXPECT_FALSE(p.ok());
  EXPECT_NE(p.message.find("fixed point"), std::string::npos) << p.message;
  const Solution a = solve_scene("sofonea2017-fig2.json", o, md);
  ASSERT_TRUE(a.ok()) << a.message;
  EXPECT_TRUE(a.handover.used);
  EXPECT_TRUE(a.handover.fixed_point_converged);
  // solver.exact.tol = 1e-10 on the exact solver's residual; the certificate recomputes the
  // tractions from the recovered u (another solve's round-off) with its own scale: a few times that.
  EXPECT_LT(a.certificate.max_residual, 1e-9);
  // report.json says what the exact solver did and whether the inner problem was strongly convex.
  const SolveOptions defaults;  // a named object: GCC 12 warns about a temporary's string members
  const nlohmann::json rep = make_report(md, a, defaults);
  EXPECT_TRUE(rep.at("inner").at("handover").at("used").get<bool>());
  EXPECT_TRUE(rep.at("inner_convexity").contains("strongly_convex"));
}

// solver.fixed_point.relaxation reaches the exact solver's fixed point (it was read by the
// continuation's λ update only): on the same scene the plain iteration (memory 0, θ = 1)
// oscillates and fails, the relaxed one (θ = 0.5) converges and certifies.
TEST(ExactHandover, RelaxationDampsTheExactSolversFixedPoint) {
  Model md;
  const Solution plain = solve_scene("sofonea2017-fig2.json", sliding_scene("8", {"solver.fixed_point.anderson_memory=0"}), md);
  EXPECT_FALSE(plain.ok());
  EXPECT_NE(plain.message.find("a smaller solver.fixed_point.relaxation (1 now), e.g. 0.5"), std::string::npos)
      << plain.message;
  const Solution relaxed = solve_scene(
      "sofonea2017-fig2.json",
      sliding_scene("8", {"solver.fixed_point.anderson_memory=0", "solver.fixed_point.relaxation=0.5"}), md);
  ASSERT_TRUE(relaxed.ok()) << relaxed.message;
  EXPECT_TRUE(relaxed.handover.used);
  EXPECT_TRUE(relaxed.handover.fixed_point_converged);
  EXPECT_LT(relaxed.certificate.max_residual, 1e-9);  // as AndersonCertifiesWhereThePlainFixedPointFails
}
