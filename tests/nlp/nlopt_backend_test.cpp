// Tests of the "nlopt:ALGO" backends (src/nlp/nlopt_backend.cpp): the registry entries, the
// refusals (unknown / derivative-free / unbounded algorithms, SLSQP above its size limit, unknown
// options), each local algorithm on small problems with known minimizers
// (tests/nlp/test_problems.hpp), MLSL on a double well, and the paper's scenes end to end against
// the ipopt backend. Everything skips when NLopt was not compiled in; NLopt is reached only
// through make_backend(), so this file needs no NLopt header.

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include "nlp/test_problems.hpp"
#include "support/polish_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace hemicontact::test {
namespace {

#define HEMICONTACT_REQUIRE_NLOPT() \
  if (!HEMICONTACT_HAS_NLOPT) GTEST_SKIP() << "NLopt backends not compiled in (install libnlopt-cxx-dev and rebuild)"

/// The main bound-constrained local algorithms, plus the other Luksan codes offered.
const std::vector<std::string> NAMED_LOCAL = {"LD_MMA", "LD_CCSAQ", "LD_SLSQP", "LD_LBFGS"};
const std::vector<std::string> ALL_LOCAL = {
    "LD_MMA",  "LD_CCSAQ",   "LD_SLSQP",           "LD_LBFGS",           "LD_VAR1",
    "LD_VAR2", "LD_TNEWTON", "LD_TNEWTON_RESTART", "LD_TNEWTON_PRECOND", "LD_TNEWTON_PRECOND_RESTART"};


/// f(x) = ½‖x‖² − 1ᵀx on a diagonal pattern, any n (the SLSQP size limit needs n > 3000 without
/// a dense test matrix).
class SeparableQuadratic : public NlpObjective {
 public:
  explicit SeparableQuadratic(Index n) {
    m_pattern.resize(int(n), int(n));
    m_pattern.setIdentity();
  }
  Index size() const override { return m_pattern.rows(); }
  double value(const Vec& x) const override { return 0.5 * x.squaredNorm() - x.sum(); }
  void gradient(const Vec& x, Vec& g) const override { g = x - Vec::Ones(x.size()); }
  const SpMat& hessian_pattern() const override { return m_pattern; }
  void hessian(const Vec&, SpMat& H, Psd) const override { H = m_pattern; }

 private:
  SpMat m_pattern;
};

/// Expects make_backend(name) to throw an input Error whose message contains every @p part.
void expect_error(const std::string& name, const std::vector<std::string>& parts) {
  SCOPED_TRACE(name);
  try {
    make_backend(name);
    ADD_FAILURE() << "make_backend(\"" << name << "\") did not throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT) << e.what();
    for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

/// Expects minimize() to throw an input Error whose message contains every @p part.
void expect_minimize_error(const std::string& name, const NlpProblem& p, Vec x, const BackendOptions& opt,
                           const std::vector<std::string>& parts) {
  SCOPED_TRACE(name);
  try {
    make_backend(name)->minimize(p, x, opt);
    ADD_FAILURE() << name << ": minimize() did not throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT) << e.what();
    for (const auto& s : parts) EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------ registry and refusals

TEST(NloptBackend, ListedOneLineEach) {
  const auto list = available_backends();
  std::map<std::string, std::string> by_name(list.begin(), list.end());
  for (const std::string a : {"LD_MMA", "LD_CCSAQ", "LD_SLSQP", "LD_LBFGS", "G_MLSL_LDS"}) {
    const auto it = by_name.find("nlopt:" + a);
    EXPECT_EQ(it != by_name.end(), bool(HEMICONTACT_HAS_NLOPT)) << a;
    if (it == by_name.end()) continue;
    EXPECT_FALSE(it->second.empty());
    EXPECT_EQ(it->second.find('\n'), std::string::npos) << a;
  }
  if (HEMICONTACT_HAS_NLOPT) {
    EXPECT_NE(by_name["nlopt:LD_LBFGS"].find("per active bound"), std::string::npos);
    EXPECT_NE(by_name["nlopt:LD_LBFGS"].find("vector_storage"), std::string::npos);
    EXPECT_NE(by_name["nlopt:LD_SLSQP"].find("3000"), std::string::npos);
    EXPECT_NE(by_name["nlopt:G_MLSL_LDS"].find("global"), std::string::npos);
    EXPECT_NE(by_name["nlopt:LD_MMA"].find("local"), std::string::npos);
  }
}

TEST(NloptBackend, ByNameOrNotCompiledInError) {
  if (!HEMICONTACT_HAS_NLOPT) {
    expect_error("nlopt:LD_MMA", {"was not compiled in", "libnlopt-cxx-dev"});
    return;
  }
  for (const auto& a : ALL_LOCAL) {
    const auto b = make_backend("nlopt:" + a);
    EXPECT_EQ(b->name(), "nlopt:" + a);
    EXPECT_FALSE(b->uses_hessian());
  }
  EXPECT_EQ(make_backend("nlopt:G_MLSL_LDS")->name(), "nlopt:G_MLSL_LDS");
  EXPECT_EQ(make_backend("nlopt:G_MLSL_LDS+LD_MMA")->name(), "nlopt:G_MLSL_LDS+LD_MMA");
  EXPECT_EQ(make_backend("nlopt:G_MLSL+LD_CCSAQ")->name(), "nlopt:G_MLSL+LD_CCSAQ");
}

TEST(NloptBackend, UnknownOrRefusedAlgorithmsSayWhy) {
  HEMICONTACT_REQUIRE_NLOPT();
  // Unknown: the message lists the supported names.
  expect_error("nlopt:LD_BOGUS", {"LD_BOGUS", "unknown", "LD_MMA", "LD_CCSAQ", "LD_SLSQP", "LD_LBFGS", "G_MLSL_LDS"});
  expect_error("nlopt:mmaa", {"MMAA", "unknown", "LD_MMA"});  // names are case-insensitive (BackendNames.*)
  // Known to NLopt, refused with the reason.
  expect_error("nlopt:LN_COBYLA", {"LN_COBYLA", "derivative-free"});
  expect_error("nlopt:LN_NEWUOA", {"LN_NEWUOA", "ignores bound"});
  expect_error("nlopt:GN_DIRECT_L", {"GN_DIRECT_L", "derivative-free"});
  expect_error("nlopt:LD_AUGLAG", {"LD_AUGLAG", "bounds only"});
  expect_error("nlopt:LD_LBFGS_NOCEDAL", {"LD_LBFGS_NOCEDAL", "LD_LBFGS"});
  expect_error("nlopt:GD_STOGO", {"GD_STOGO", "G_MLSL_LDS"});
  // '+LOCAL' only after MLSL, and the local algorithm is checked like any other.
  expect_error("nlopt:LD_MMA+LD_LBFGS", {"LD_MMA+LD_LBFGS", "G_MLSL"});
  expect_error("nlopt:G_MLSL_LDS+LN_COBYLA", {"LN_COBYLA", "derivative-free"});
  expect_error("nlopt:G_MLSL_LDS+NOPE", {"NOPE", "unknown"});
}

TEST(NloptBackend, SlsqpRefusedAboveSizeLimit) {
  HEMICONTACT_REQUIRE_NLOPT();
  const SeparableQuadratic big(3001);
  const NlpProblem p = make_problem(big, Vec::Constant(3001, -INF), Vec::Constant(3001, INF));
  expect_minimize_error("nlopt:LD_SLSQP", p, Vec::Zero(3001), BackendOptions{},
                        {"LD_SLSQP", "3001", "3000", "condensed"});
  expect_minimize_error("nlopt:G_MLSL_LDS", p, Vec::Zero(3001), BackendOptions{}, {"3001", "condensed"});
  // The limit is SLSQP's: a first-order method takes the same problem (f = ½‖x − 1‖² − n/2).
  Vec x = Vec::Zero(3001);
  const SolveResult r = make_backend("nlopt:LD_LBFGS")->minimize(p, x, BackendOptions{});
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_LE((x - Vec::Ones(3001)).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(NloptBackend, OptionsAreCheckedNotIgnored) {
  HEMICONTACT_REQUIRE_NLOPT();
  const DoubleWellObjective f;
  const NlpProblem p = make_problem(f, Vec::Constant(2, -2.0), Vec::Constant(2, 2.0));
  const Vec x0 = Vec::Constant(2, 0.3);
  const auto with = [](const std::string& k, const std::string& v) {
    BackendOptions o;
    o.extra[k] = v;
    return o;
  };
  expect_minimize_error("nlopt:LD_MMA", p, x0, with("mu_strategy", "adaptive"),
                        {"mu_strategy", "vector_storage", "maxeval"});
  expect_minimize_error("nlopt:LD_MMA", p, x0, with("vector_storage", "5"), {"vector_storage", "LD_MMA"});
  expect_minimize_error("nlopt:LD_MMA", p, x0, with("box_radius", "1"), {"box_radius", "MLSL"});
  expect_minimize_error("nlopt:LD_LBFGS", p, x0, with("population", "10"), {"population"});
  expect_minimize_error("nlopt:LD_LBFGS", p, x0, with("vector_storage", "5x"), {"vector_storage", "5x"});
  expect_minimize_error("nlopt:LD_LBFGS", p, x0, with("maxeval", "0"), {"maxeval"});
  expect_minimize_error("nlopt:G_MLSL_LDS", p, x0, with("box_radius", "-1"), {"box_radius"});
  expect_minimize_error("nlopt:G_MLSL_LDS", p, x0, with("local_algorithm", "LN_BOBYQA"),
                        {"LN_BOBYQA", "derivative-free"});
  expect_minimize_error("nlopt:G_MLSL_LDS+LD_MMA", p, x0, with("local_algorithm", "LD_LBFGS"),
                        {"local_algorithm", "contradicts"});
  // Numbers beyond what NLopt can size (vector_storage = 2^31 - 1 overflowed its int
  // work-array size and corrupted the heap; population = 2^31 - 1 hung MLSL) are refused with the
  // key and the range, before NLopt runs.
  for (const char* algo : {"nlopt:LD_LBFGS", "nlopt:LD_VAR1"})
    expect_minimize_error(algo, p, x0, with("vector_storage", "2147483647"),
                          {"solver.options.vector_storage", "1..1000", "2147483647"});
  expect_minimize_error("nlopt:G_MLSL_LDS", p, x0, with("population", "2147483647"),
                        {"solver.options.population", "0..100000"});
  expect_minimize_error("nlopt:LD_LBFGS", p, x0, with("maxeval", "2147483647"), {"solver.options.maxeval", "1..100000000"});
  expect_minimize_error("nlopt:G_MLSL_LDS", p, x0, with("box_radius", "1e300"), {"solver.options.box_radius"});
  {  // n·vector_storage is bounded too (the int product NLopt forms): 200 001 unknowns · 1000 pairs.
    const SeparableQuadratic big(200001);
    const NlpProblem pb = make_problem(big, Vec::Constant(200001, -INF), Vec::Constant(200001, INF));
    expect_minimize_error("nlopt:LD_LBFGS", pb, Vec::Zero(200001), with("vector_storage", "1000"),
                          {"vector_storage = 1000", "200001", "at most 499"});
  }
  // Accepted values do what they say.
  Vec x = x0;
  const SolveResult r = make_backend("nlopt:LD_LBFGS")->minimize(p, x, with("vector_storage", "3"));
  EXPECT_TRUE(r.ok()) << r.message;
  x = (Vec(2) << -1.2, 1.0).finished();
  const RosenbrockObjective rosen(2);
  const SolveResult capped =
      make_backend("nlopt:LD_MMA")
          ->minimize(make_problem(rosen, Vec::Constant(2, -INF), Vec::Constant(2, INF)), x, with("maxeval", "7"));
  EXPECT_EQ(capped.status, SolveStatus::MAX_ITERATIONS) << capped.message;
  EXPECT_NE(capped.message.find("MAXEVAL_REACHED"), std::string::npos) << capped.message;
  EXPECT_LE(capped.evaluations, 7 + 2);  // + f(x0) + the residual at the returned point
}

// ------------------------------------------------------------------ local algorithms

class NloptLocal : public ::testing::TestWithParam<std::string> {};

// Tolerance: NLopt's algorithms accept a step only when f decreases, so they stall where the
// decrease left, ~r²/(2c), drops below the round-off of f (≈ ε_mach·|f| ≈ 1e-15 here): at
// r ≈ sqrt(2e-15·c) ≈ 3e-8 to 6e-8 for this QP (c <= 5); see src/nlp/nlopt_backend.cpp. So the
// runs ask for tol = 1e-7, which every algorithm reaches (CONVERGED, by the first-order stop).
// Error bound for a μ-strongly convex QP with ‖A‖₂ = L on a box: ‖x − x*‖₂ <= (1 + L)/μ · ‖x −
// P(x − g)‖₂, and |x_i − P(x − g)_i| = min(|g_i|, room_i) = r_i <= r, so
// ‖x − x*‖∞ <= (1 + L)/μ · √n · tol, computed below (≈ 6e-7).
TEST_P(NloptLocal, BoxQpMatchesEnumeratedSolution) {
  HEMICONTACT_REQUIRE_NLOPT();
  const BoxQp q = make_box_qp();
  const Vec eig = Eigen::SelfAdjointEigenSolver<Mat>(q.A).eigenvalues();
  const double bound = (1.0 + eig.maxCoeff()) / eig.minCoeff() * std::sqrt(6.0) * 1e-7;
  ASSERT_LT(bound, 1e-6);
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  BackendOptions opt;
  opt.tol = 1e-7;
  Vec x = Vec::Zero(6);
  const SolveResult r = make_backend("nlopt:" + GetParam())->minimize(make_problem(f, q.lower, q.upper), x, opt);
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_LE(r.kkt_norm, opt.tol);
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), bound)
      << "x = " << x.transpose() << "\nexact = " << exact.transpose() << "\n"
      << r.message;
  // f is flat at the minimizer: |f(x) − f*| <= ‖g‖‖x − x*‖ + L‖x − x*‖²/2 with |g_i| O(1) on
  // the active bounds.
  EXPECT_NEAR(r.f, f.value(exact), 1e-5);
  EXPECT_NEAR(r.f, f.value(x), 1e-14 * (1 + std::abs(r.f)));
  EXPECT_EQ(r.iterations, r.evaluations);
  EXPECT_GT(r.evaluations, 1);
  EXPECT_GT(r.seconds, 0.0);
  EXPECT_TRUE(((x - q.lower).array() >= 0).all() && ((q.upper - x).array() >= 0).all());

  // A warm start at the answer stops at the first evaluation with a gradient (f(x0) + 1, or + 2
  // for an algorithm whose first call asks for f alone).
  const SolveResult warm = make_backend("nlopt:" + GetParam())->minimize(make_problem(f, q.lower, q.upper), x, opt);
  EXPECT_EQ(warm.status, SolveStatus::CONVERGED) << warm.message;
  EXPECT_LE(warm.evaluations, 3) << warm.message;
}

// Rosenbrock from the classic start with x_0 <= 1/2 active (multiplier 1, see test_problems.hpp).
// r <= tol = 1e-7 puts x_0 within 1e-7 of the bound, and the free x_1 within r/200
// (∂²f/∂x_1² = 200) of x_0², which moves by 2·x_0·δ = δ: both errors <= 1.1e-7, checked at 1e-6.
TEST_P(NloptLocal, RosenbrockWithActiveBound) {
  HEMICONTACT_REQUIRE_NLOPT();
  const RosenbrockObjective f(2);
  const Vec lower = (Vec(2) << -1.5, -1.5).finished();
  const Vec upper = (Vec(2) << 0.5, 2.0).finished();
  Vec x = (Vec(2) << -1.2, 1.0).finished();
  BackendOptions opt;
  opt.tol = 1e-7;
  const SolveResult r = make_backend("nlopt:" + GetParam())->minimize(make_problem(f, lower, upper), x, opt);
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_NEAR(x[0], 0.5, 1e-6) << r.message;
  EXPECT_NEAR(x[1], 0.25, 1e-6) << r.message;
  EXPECT_NEAR(r.f, 0.25, 1e-6);
}

TEST_P(NloptLocal, FixedVariableAndStartOutsideBounds) {
  HEMICONTACT_REQUIRE_NLOPT();
  BoxQp q = make_box_qp();
  q.lower[2] = q.upper[2] = 0.3;  // lower == upper
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  BackendOptions opt;
  opt.tol = 1e-7;
  Vec x = Vec::Constant(6, 50.0);  // projected first
  const SolveResult r = make_backend("nlopt:" + GetParam())->minimize(make_problem(f, q.lower, q.upper), x, opt);
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_EQ(x[2], 0.3);
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-6) << r.message;  // bound as in the QP test
}

INSTANTIATE_TEST_SUITE_P(Algorithms, NloptLocal, ::testing::ValuesIn(ALL_LOCAL),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// Luksan's codes stop on their own max projected gradient <= 1e-8 (fixed inside NLopt); the
// backend scales f so that this cannot end a run before tol. LD_LBFGS reaches r ≈ 1.5e-12 on
// the QP (measured), so tol = 1e-10 is CONVERGED, with the bound of the QP test at 1e-10.
TEST(NloptBackend, LuksanGradientTestDoesNotPreemptTol) {
  HEMICONTACT_REQUIRE_NLOPT();
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  BackendOptions opt;
  opt.tol = 1e-10;
  Vec x = Vec::Zero(6);
  const SolveResult r = make_backend("nlopt:LD_LBFGS")->minimize(make_problem(f, q.lower, q.upper), x, opt);
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-8) << r.message;
}

// Below the round-off floor (≈ 3e-8 for MMA on this QP) the verdict comes from r, and the
// message says why it stopped.
TEST(NloptBackend, BelowRoundoffFloorIsAcceptableOrFailedWithReason) {
  HEMICONTACT_REQUIRE_NLOPT();
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  BackendOptions opt;
  opt.tol = 1e-12;
  Vec x = Vec::Zero(6);
  const SolveResult r = make_backend("nlopt:LD_MMA")->minimize(make_problem(f, q.lower, q.upper), x, opt);
  EXPECT_FALSE(r.status == SolveStatus::CONVERGED) << r.message;
  EXPECT_EQ(r.status, r.kkt_norm <= 1e3 * opt.tol ? SolveStatus::ACCEPTABLE : SolveStatus::FAILED);
  EXPECT_NE(r.message.find("stalled"), std::string::npos) << r.message;
  EXPECT_GT(r.kkt_norm, opt.tol);
  EXPECT_LT(r.kkt_norm, 1e-6);  // it still got to the floor
}

// max_iter maps to maxeval = 10·max_iter (evaluations, the only count NLopt has).
TEST(NloptBackend, MaxIterMapsToEvaluationBudget) {
  HEMICONTACT_REQUIRE_NLOPT();
  const RosenbrockObjective f(2);
  for (const std::string a : {"LD_MMA", "LD_LBFGS", "LD_SLSQP"}) {
    Vec x = (Vec(2) << -1.2, 1.0).finished();
    BackendOptions opt;
    opt.max_iter = 2;
    const SolveResult r =
        make_backend("nlopt:" + a)->minimize(make_problem(f, Vec::Constant(2, -INF), Vec::Constant(2, INF)), x, opt);
    EXPECT_EQ(r.status, SolveStatus::MAX_ITERATIONS) << r.message;
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.message.find("maxeval 20"), std::string::npos) << r.message;
    EXPECT_LE(r.evaluations, 20 + 2) << r.message;  // + f(x0) + the residual at the answer
    EXPECT_EQ(r.iterations, r.evaluations);
  }
}

// The cost of LD_LBFGS's active-set strategy, reported as is: a line search stops at the first
// bound it meets, so ½‖x − c‖² with x <= 1 and c_i = 2 + i (from 0, the bounds are met one after
// another along −∇f) costs ~1 evaluation per bound; MMA's subproblem takes them all at once.
TEST(NloptBackend, LbfgsPaysAboutOneEvaluationPerActiveBound) {
  HEMICONTACT_REQUIRE_NLOPT();
  const Index n = 50;
  Vec c(n);
  for (Index i = 0; i < n; ++i) c[i] = 2.0 + double(i);
  const QuadraticObjective f(Mat::Identity(n, n), c);
  const NlpProblem p = make_problem(f, Vec::Constant(n, -INF), Vec::Constant(n, 1.0));
  BackendOptions opt;
  opt.tol = 1e-7;
  Vec x = Vec::Zero(n);
  const SolveResult lbfgs = make_backend("nlopt:LD_LBFGS")->minimize(p, x, opt);
  EXPECT_EQ(lbfgs.status, SolveStatus::CONVERGED) << lbfgs.message;
  EXPECT_LE((x - Vec::Ones(n)).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_GE(lbfgs.evaluations, n / 2) << lbfgs.message;  // measured: n + 3
  x = Vec::Zero(n);
  const SolveResult mma = make_backend("nlopt:LD_MMA")->minimize(p, x, opt);
  EXPECT_EQ(mma.status, SolveStatus::CONVERGED) << mma.message;
  EXPECT_LE(mma.evaluations, 10) << mma.message;  // measured: 4
}

TEST(NloptBackend, ObjectiveExceptionsPropagate) {
  HEMICONTACT_REQUIRE_NLOPT();
  const DoubleWellObjective well;
  const ThrowingObjective f(well, 3);
  for (const std::string a : {"LD_MMA", "LD_LBFGS", "G_MLSL_LDS"}) {
    Vec x = Vec::Constant(2, 0.3);
    EXPECT_THROW(make_backend("nlopt:" + a)
                     ->minimize(make_problem(f, Vec::Constant(2, -2.0), Vec::Constant(2, 2.0)), x, BackendOptions{}),
                 std::runtime_error)
        << a;
  }
}

TEST(NloptBackend, RejectsMismatchedSizesAndEmptyBounds) {
  HEMICONTACT_REQUIRE_NLOPT();
  const DoubleWellObjective f;
  const auto backend = make_backend("nlopt:LD_MMA");
  Vec x = Vec::Zero(3);
  EXPECT_THROW(backend->minimize(make_problem(f, Vec::Zero(2), Vec::Ones(2)), x, BackendOptions{}), Error);
  x = Vec::Zero(2);
  EXPECT_THROW(backend->minimize(make_problem(f, Vec::Ones(2), Vec::Zero(2)), x, BackendOptions{}), Error);
}

// ------------------------------------------------------------------ MLSL

// The double well (x² − 1)² + (y − x/2)² with x <= 1/2: from (0.3, 0) a local method descends to
// the bound, (1/2, 1/4) with f = 9/16 (test_problems.hpp); the global minimum is the left well
// (−1, −1/2), f = 0. MLSL's box is the warm start ± box_radius (2) where bounds are infinite:
// x ∈ [−1.7, 0.5], y ∈ [−2, 2], which contains it. tol = 1e-7 (the local tests' floor); the
// left well's Hessian [[8.5, −1], [−1, 2]] has λ_min > 1.8, so the distance is < 1e-7, checked
// at 1e-6. max_iter = 100 gives the global phase 1000 evaluations (MLSL always spends all of
// them; its bookkeeping grows like their square: 5000 took 0.25 s).
TEST(NloptMlsl, FindsGlobalMinimumWhereLocalMethodDoesNot) {
  HEMICONTACT_REQUIRE_NLOPT();
  const DoubleWellObjective f;
  const NlpProblem p = make_problem(f, Vec::Constant(2, -INF), (Vec(2) << 0.5, INF).finished());
  BackendOptions opt;
  opt.tol = 1e-7;
  opt.max_iter = 100;
  const Vec x0 = (Vec(2) << 0.3, 0.0).finished();

  Vec x = x0;
  const SolveResult local = make_backend("nlopt:LD_LBFGS")->minimize(p, x, opt);
  EXPECT_EQ(local.status, SolveStatus::CONVERGED) << local.message;
  EXPECT_NEAR(x[0], 0.5, 1e-6);
  EXPECT_NEAR(x[1], 0.25, 1e-6);

  for (const std::string name : {"nlopt:G_MLSL_LDS", "nlopt:G_MLSL_LDS+LD_MMA", "nlopt:G_MLSL"}) {
    SCOPED_TRACE(name);
    x = x0;
    const SolveResult global = make_backend(name)->minimize(p, x, opt);
    EXPECT_EQ(global.status, SolveStatus::CONVERGED) << global.message;
    EXPECT_NEAR(x[0], -1.0, 1e-6) << global.message;
    EXPECT_NEAR(x[1], -0.5, 1e-6) << global.message;
    EXPECT_NEAR(global.f, 0.0, 1e-12);
    EXPECT_NE(global.message.find("3 infinite bounds replaced"), std::string::npos) << global.message;
    EXPECT_GE(global.evaluations, 1000);  // the whole global budget, reported
    EXPECT_EQ(global.iterations, global.evaluations);
  }

  // Options: local algorithm, population, budget and box (x ∈ [−1.2, 0.5] still holds −1).
  BackendOptions o2 = opt;
  o2.extra["local_algorithm"] = "LD_SLSQP";
  o2.extra["population"] = "8";
  o2.extra["maxeval"] = "500";
  o2.extra["box_radius"] = "1.5";
  x = x0;
  const SolveResult r2 = make_backend("nlopt:G_MLSL_LDS")->minimize(p, x, o2);
  EXPECT_EQ(r2.status, SolveStatus::CONVERGED) << r2.message;
  EXPECT_NEAR(x[0], -1.0, 1e-6) << r2.message;
  EXPECT_NE(r2.message.find("+- 1.5"), std::string::npos) << r2.message;
}

// ------------------------------------------------------------------ the paper's scenes

struct Solved {
  Model md;
  SolveOptions opt;
  Solution sol;
  double seconds = 0;
};

Solved solve_scene(const std::string& name, const std::vector<std::string>& overrides) {
  const auto t0 = std::chrono::steady_clock::now();
  const nlohmann::json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/" + name + ".json", overrides);
  Solved s{build_model(scene, HEMICONTACT_SOURCE_DIR "/problems"), solve_options_from_scene(scene), {}};
  s.sol = solve(s.md, s.opt);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

/// The reference: ipopt if compiled in, else newton (always built), with the scene's defaults.
const Solved& reference(const std::string& scene, int n) {
  static std::map<std::pair<std::string, int>, Solved> cache;
  const auto key = std::make_pair(scene, n);
  auto it = cache.find(key);
  if (it == cache.end()) {
    const std::string backend = HEMICONTACT_HAS_IPOPT ? "ipopt" : "newton";
    it = cache
             .emplace(key, solve_scene(scene, {"mesh.n=" + std::to_string(n), "solver.formulation=condensed",
                                               "solver.backend=" + backend}))
             .first;
  }
  return it->second;
}

/// The tolerance the NLopt backends are given on the scenes. They stall where f can no longer
/// resolve a decrease, r ≈ sqrt(ε_mach·|f|·c) (src/nlp/nlopt_backend.cpp): with |f| ≈ 10 and the
/// sticking node's curvature c ~ λ/ε_τ ~ 1e10 at the final ε_τ = 1e-10 U, r ≈ 1e-3 in the worst
/// direction; the warm start from the previous stage is usually better than that. Measured:
/// tol = 1e-6 is reached by MMA, CCSAQ, SLSQP and LBFGS on both scenes at n = 16 and 32; 1e-7
/// fails for all four on the printed scene at n = 32 (it has a sticking node); 1e-8 fails on
/// fig2 for most. The statuses only need the smoothed solution to be right to status_tol; the
/// polish then solves the unsmoothed conditions exactly.
const char* const NLOPT_SCENE_TOL = "solver.tol=1e-6";

struct SceneCase {
  std::string scene;
  int n;
  std::string backend;               // after "nlopt:"
  std::vector<std::string> options;  // extra overrides
};
void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.scene << " n=" << c.n << " nlopt:" << c.backend; }

class NloptScenes : public ::testing::TestWithParam<SceneCase> {};

// Every backend hands the polish (solver/polish.hpp) the same statuses, which then solves the
// unsmoothed conditions exactly, so u agrees with the reference to the round-off of that linear
// solve (certificates ~1e-14; 1e-8 relative leaves a wide margin) and the certificate passes.
TEST_P(NloptScenes, SameStatusesAndSolutionAsReference) {
  HEMICONTACT_REQUIRE_NLOPT();
  const SceneCase c = GetParam();
  const Solved& ref = reference(c.scene, c.n);
  ASSERT_TRUE(ref.sol.backend_ok && ref.sol.fixed_point_converged) << ref.sol.message;
  ASSERT_TRUE(ref.sol.certificate.passed) << ref.sol.message;

  std::vector<std::string> overrides = {"mesh.n=" + std::to_string(c.n), "solver.formulation=condensed",
                                        "solver.backend=nlopt:" + c.backend, NLOPT_SCENE_TOL};
  overrides.insert(overrides.end(), c.options.begin(), c.options.end());
  const Solved s = solve_scene(c.scene, overrides);
  // Not asserted: each minimization's own verdict. Whether an f-based method reaches tol = 1e-6
  // or stops at its budget just above it depends on the last bits of f, i.e. on the CPU and BLAS
  // kernel (LD_MMA on printed n = 32 ends at MAXEVAL with r = 4.2e-5 on one machine of this kind and
  // below 1e-6 on another). What matters is asserted instead: the polished answer is certified, has
  // the reference's statuses and agrees with its u.
  // The backend's minimizations; when the exact inner solver took over (a stage that stalled at
  // the round-off floor), its records follow them and are not NLopt's.
  const size_t n_backend = s.sol.history.size() - (s.sol.handover.used ? s.sol.handover.outer_iterations : 0);
  int evaluations = 0;
  bool all_ok = true;
  for (size_t i = 0; i < n_backend; ++i) {
    const OuterIteration& h = s.sol.history[i];
    evaluations += h.backend.evaluations;
    all_ok = all_ok && h.backend.ok();
    EXPECT_EQ(h.backend.iterations, h.backend.evaluations);
  }
  ASSERT_TRUE(s.sol.fixed_point_converged) << s.sol.message;
  EXPECT_TRUE(hemicontact::test::polished_or_at_roundoff(s.sol));
  EXPECT_TRUE(s.sol.certificate.passed) << s.sol.message;
  EXPECT_LE(s.sol.certificate.max_residual, s.opt.certificate_tol);
  ASSERT_EQ(s.sol.status.size(), ref.sol.status.size());
  for (size_t k = 0; k < s.sol.status.size(); ++k)
    EXPECT_EQ(s.sol.status[k].str(), ref.sol.status[k].str()) << "node " << k;
  const double U = ref.sol.u.cwiseAbs().maxCoeff();
  EXPECT_LE((s.sol.u - ref.sol.u).cwiseAbs().maxCoeff(), 1e-8 * U);
  std::printf(
      "[ nlopt    ] %s n=%d nlopt:%s: %zu minimizations%s, %d evaluations, %.2f s, "
      "backend %s, certificate %.1e\n",
      c.scene.c_str(), c.n, c.backend.c_str(), n_backend, s.sol.handover.used ? " + exact solver" : "", evaluations,
      s.seconds,
      all_ok ? "converged" : "stopped above tol (polished)", s.sol.certificate.max_residual);
}

std::vector<SceneCase> scene_cases() {
  std::vector<SceneCase> v;
  for (const std::string scene : {"sofonea2017-fig2", "sofonea2017-printed"})
    for (const int n : {16, 32})
      for (const std::string a : {"LD_MMA", "LD_CCSAQ", "LD_SLSQP", "LD_LBFGS"}) v.push_back({scene, n, a, {}});
  // The global search on the condensed problem, with a budget of 1000 evaluations per
  // minimization (the default, 10·max_iter = 30000, costs ~1 s per minimization).
  v.push_back({"sofonea2017-fig2", 16, "G_MLSL_LDS", {"solver.options.maxeval=1000"}});
  v.push_back({"sofonea2017-fig2", 16, "G_MLSL_LDS+LD_MMA", {"solver.options.maxeval=1000"}});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Paper, NloptScenes, ::testing::ValuesIn(scene_cases()),
                         [](const ::testing::TestParamInfo<SceneCase>& info) {
                           std::string s = info.param.scene.substr(info.param.scene.find('-') + 1) + "_n" +
                                           std::to_string(info.param.n) + "_" + info.param.backend;
                           std::replace(s.begin(), s.end(), '+', '_');
                           std::replace(s.begin(), s.end(), '-', '_');
                           return s;
                         });

// What the NLopt backends achieve at the scenes' default tol = 1e-12 (set for newton / ipopt) on
// the continuation alone (solver.exact.enabled = false, the design's path): they stall at the
// round-off floor above, the minimization is not ok, and the driver stops with a message that
// names the backend and says why.
TEST(NloptScenesDefaultTol, StallAtRoundoffFloorAndSaySo) {
  HEMICONTACT_REQUIRE_NLOPT();
  const Solved s = solve_scene("sofonea2017-fig2", {"mesh.n=16", "solver.formulation=condensed",
                                                    "solver.backend=nlopt:LD_MMA", "solver.exact.enabled=false"});
  EXPECT_FALSE(s.sol.backend_ok);
  EXPECT_FALSE(s.sol.handover.used);
  ASSERT_FALSE(s.sol.history.empty());
  const SolveResult& last = s.sol.history.back().backend;
  EXPECT_EQ(last.status, SolveStatus::FAILED) << last.message;
  EXPECT_GT(last.kkt_norm, 1e-9);  // above 1e3·tol: not even acceptable
  // but near the floor r ≈ sqrt(ε_mach·|f|·c) ≈ 1e-3 (above); where below it the stall lands
  // depends on rounding, so only the floor itself is asserted.
  EXPECT_LT(last.kkt_norm, 1e-3);
  EXPECT_NE(s.sol.message.find("stalled"), std::string::npos) << s.sol.message;
}

// With the exact inner solver behind the continuation (the default) the same stall is no
// failure: the first stage's answer, stopped at the algorithm's round-off floor, is the
// neighbourhood the exact solver starts from, and the answer is certified. Every local algorithm,
// both paper scenes, default tol: certified, the hand-over names the backend and why it handed
// over, and u agrees with the reference (ipopt) to the same margin as
// SameStatusesAndSolutionAsReference (both end on the exact polish of the same statuses).
// solver.exact.start = never: the paper scenes' inner problems are strongly convex, so by default
// the exact solver would answer before NLopt runs at all (ExactStart tests that path).
TEST(NloptScenesDefaultTol, DefaultPathCertifiesAnswersBelowTheRoundoffFloor) {
  HEMICONTACT_REQUIRE_NLOPT();
  for (const std::string scene : {"sofonea2017-fig2", "sofonea2017-printed"})
    for (const std::string a : {"LD_MMA", "LD_CCSAQ", "LD_SLSQP", "LD_LBFGS"}) {
      SCOPED_TRACE(scene + " nlopt:" + a);
      const Solved& ref = reference(scene, 16);
      const Solved s = solve_scene(scene, {"mesh.n=16", "solver.formulation=condensed", "solver.backend=nlopt:" + a,
                                           "solver.exact.start=\"never\""});
      EXPECT_TRUE(s.sol.ok()) << s.sol.message;
      EXPECT_LE(s.sol.certificate.max_residual, s.opt.certificate_tol);
      // Either a stage reached tol and the polish certified it, or the exact solver took over
      // and says from which backend and why.
      if (s.sol.handover.used) {
        EXPECT_NE(s.sol.handover.reason.find("nlopt:" + a), std::string::npos) << s.sol.handover.reason;
        EXPECT_TRUE(s.sol.handover.fixed_point_converged) << s.sol.handover.note;
      }
      ASSERT_EQ(s.sol.status.size(), ref.sol.status.size());
      for (size_t k = 0; k < s.sol.status.size(); ++k)
        EXPECT_EQ(s.sol.status[k].str(), ref.sol.status[k].str()) << "node " << k;
      const double U = ref.sol.u.cwiseAbs().maxCoeff();
      EXPECT_LE((s.sol.u - ref.sol.u).cwiseAbs().maxCoeff(), 1e-8 * U);
      std::printf("[ nlopt    ] %s n=16 nlopt:%s default tol: %s, certificate %.1e\n", scene.c_str(), a.c_str(),
                  s.sol.handover.used ? ("exact solver after stage " + std::to_string(s.sol.handover.after_stage)).c_str()
                                      : "continuation",
                  s.sol.certificate.max_residual);
    }
}

}  // namespace
}  // namespace hemicontact::test
