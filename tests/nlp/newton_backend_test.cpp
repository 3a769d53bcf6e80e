// Tests of the "newton" backend (projected Newton with a binding set, src/nlp/newton_backend.cpp)
// on the small problems of tests/nlp/test_problems.hpp that the Ipopt backend is tested on, its
// agreement with Ipopt, the sparse (CHOLMOD) and dense linear algebra, warm starts, the iteration
// cap, and the paper's Fig. 2 scene end to end in both formulations.

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include "nlp/test_problems.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <ostream>
#include <regex>
#include <string>
#include <vector>

namespace hemicontact::test {
namespace {

#define HEMICONTACT_REQUIRE_IPOPT_HERE() \
  if (!HEMICONTACT_HAS_IPOPT) GTEST_SKIP() << "Ipopt backend not compiled in: the comparison needs it"


BackendOptions accurate(const std::string& linear_solver = "") {
  BackendOptions o;
  o.tol = 1e-12;
  if (!linear_solver.empty()) o.extra["linear_solver"] = linear_solver;
  return o;
}

/// First-order residual max_i min(|g_i|, room to the bound −g_i points to) (the driver's measure).
double residual(const NlpObjective& f, const Vec& x, const Vec& l, const Vec& u) {
  Vec g;
  f.gradient(x, g);
  double r = 0;
  for (Index i = 0; i < x.size(); ++i)
    r = std::max(r, std::min(std::abs(g[i]), std::max(0.0, g[i] < 0 ? u[i] - x[i] : x[i] - l[i])));
  return r;
}

/// @return the number in "N analyses" of a newton message (−1 if absent).
int analyses_in(const std::string& message) {
  std::smatch m;
  return std::regex_search(message, m, std::regex("([0-9]+) analyses")) ? std::stoi(m[1]) : -1;
}

/// @brief The same objective on a larger lower-triangular pattern (explicit zeros), e.g. a
/// sparse problem presented with the dense pattern the condensed formulation uses.
class RepatternedObjective : public NlpObjective {
 public:
  /// @param inner the objective (referenced); @param mask n×n, lower part ⊇ inner's pattern.
  RepatternedObjective(const NlpObjective& inner, const Mat& mask)
      : m_inner(inner), m_pattern(lower_pattern_from_mask(mask)) {}
  Index size() const override { return m_inner.size(); }
  double value(const Vec& x) const override { return m_inner.value(x); }
  void gradient(const Vec& x, Vec& g) const override { m_inner.gradient(x, g); }
  const SpMat& hessian_pattern() const override { return m_pattern; }
  void hessian(const Vec& x, SpMat& H, Psd psd) const override {
    SpMat Hi = m_inner.hessian_pattern();
    m_inner.hessian(x, Hi, psd);
    if (H.rows() != m_pattern.rows() || H.nonZeros() != m_pattern.nonZeros()) H = m_pattern;
    std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
    for (int k = 0; k < Hi.outerSize(); ++k)
      for (SpMat::InnerIterator it(Hi, k); it; ++it) H.coeffRef(it.row(), it.col()) += it.value();
  }

 private:
  const NlpObjective& m_inner;
  SpMat m_pattern;
};

/// @brief DoubleWellObjective with the Psd contract of the energy terms: under Psd::CLAMP the
/// nonconvex part of ∂²/∂x² (x² − 1)² = 12x² − 4 is clamped to 0, as NormalComplianceEnergy
/// clamps w·p_ν′ (the coupling (y − x/2)² is convex and kept). Counts the calls of each kind.
class ClampedDoubleWell : public DoubleWellObjective {
 public:
  void hessian(const Vec& x, SpMat& H, Psd psd) const override {
    DoubleWellObjective::hessian(x, H, psd);
    if (psd == Psd::CLAMP) {
      ++clamp_calls;
      H.coeffRef(0, 0) = std::max(0.0, 12.0 * x[0] * x[0] - 4.0) + 0.5;
    } else {
      ++exact_calls;
    }
  }
  mutable int clamp_calls = 0;  ///< hessian() calls with Psd::CLAMP
  mutable int exact_calls = 0;  ///< hessian() calls with Psd::NONE
};

Mat dense_mask(Index n) { return Mat::Ones(n, n); }

// ------------------------------------------------------------------ registry

TEST(NewtonBackend, CreatedByNameAndListed) {
  const auto backend = make_backend("newton");
  EXPECT_EQ(backend->name(), "newton");
  EXPECT_TRUE(backend->uses_hessian());
  const auto list = available_backends();
  const auto it = std::find_if(list.begin(), list.end(), [](const auto& e) { return e.first == "newton"; });
  ASSERT_NE(it, list.end());
  EXPECT_NE(it->second.find("CHOLMOD"), std::string::npos) << it->second;
  EXPECT_NE(it->second.find("Psd::CLAMP"), std::string::npos) << it->second;
}

// ------------------------------------------------------------------ quadratic

TEST(NewtonBackend, BoxQpMatchesEnumeratedSolution) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  Vec x = Vec::Zero(6);
  const SolveResult r = make_backend("newton")->minimize(make_problem(f, q.lower, q.upper), x, accurate());
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-12) << "x = " << x.transpose() << "\nexact = " << exact.transpose();
  EXPECT_NEAR(r.f, f.value(exact), 1e-12 * (1.0 + std::abs(f.value(exact))));
  EXPECT_LE(r.kkt_norm, 1e-12);
  EXPECT_EQ(r.kkt_norm, residual(f, x, q.lower, q.upper));
  EXPECT_GT(r.iterations, 0);
  EXPECT_LE(r.iterations, 10);  // a projected Newton method identifies the active set quickly
  EXPECT_GE(r.evaluations, r.iterations);
  EXPECT_GT(r.seconds, 0.0);
  EXPECT_NE(r.message.find("dense"), std::string::npos) << "dense pattern → dense LLT: " << r.message;
  EXPECT_TRUE(((x - q.lower).array() >= 0).all() && ((q.upper - x).array() >= 0).all());
}

// A quadratic: once the active set is right, the Newton step on the free set is exact.
TEST(NewtonBackend, BoxQpFinishesInFewIterationsOnceTheActiveSetIsRight) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  std::vector<bool> at_lower, at_upper;
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper, &at_lower, &at_upper);
  for (const std::string ls : {"dense", "cholmod"}) {
    SCOPED_TRACE(ls);
    Vec x = Vec::Zero(6);  // the free unknowns away from the answer, the active ones on their bounds
    for (Index i = 0; i < 6; ++i) {
      if (at_lower[size_t(i)]) x[i] = q.lower[i];
      if (at_upper[size_t(i)]) x[i] = q.upper[i];
    }
    const SolveResult r = make_backend("newton")->minimize(make_problem(f, q.lower, q.upper), x, accurate(ls));
    EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
    EXPECT_GE(r.iterations, 1);
    EXPECT_LE(r.iterations, 3);
    EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(NewtonBackend, StartOutsideBoundsIsProjected) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  Vec x = Vec::Constant(6, 50.0);
  const SolveResult r = make_backend("newton")->minimize(make_problem(f, q.lower, q.upper), x, accurate());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(NewtonBackend, FixedVariable) {
  BoxQp q = make_box_qp();
  q.lower[2] = q.upper[2] = 0.3;
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  for (const std::string ls : {"dense", "cholmod"}) {
    SCOPED_TRACE(ls);
    Vec x = Vec::Zero(6);
    const SolveResult r = make_backend("newton")->minimize(make_problem(f, q.lower, q.upper), x, accurate(ls));
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(x[2], 0.3);
    EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// ------------------------------------------------------------------ sparse vs dense

// The same problem through CHOLMOD (sparse pattern) and the dense LLT (dense pattern, or forced):
// the same iterates up to round-off, so the same answer.
TEST(NewtonBackend, SparseAndDensePatternsGiveTheSameAnswer) {
  const Index n = 10;
  const RosenbrockObjective sparse(n);                      // tridiagonal pattern → CHOLMOD
  const RepatternedObjective dense(sparse, dense_mask(n));  // same function, dense pattern → LLT
  const Vec lower = Vec::Zero(n), upper = (Vec::Constant(n, 2.0)).eval();
  Vec upper_active = upper;
  upper_active[4] = 0.8;  // an active upper bound in the middle of the chain
  for (const Vec& u : {upper, upper_active}) {
    Vec xs = Vec::Constant(n, 0.5), xd = xs;
    const SolveResult rs = make_backend("newton")->minimize(make_problem(sparse, lower, u), xs, accurate());
    const SolveResult rd = make_backend("newton")->minimize(make_problem(dense, lower, u), xd, accurate());
    ASSERT_EQ(rs.status, SolveStatus::CONVERGED) << rs.message;
    ASSERT_EQ(rd.status, SolveStatus::CONVERGED) << rd.message;
    EXPECT_NE(rs.message.find("cholmod"), std::string::npos) << rs.message;
    EXPECT_NE(rd.message.find("dense"), std::string::npos) << rd.message;
    EXPECT_LE((xs - xd).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(rs.iterations, rd.iterations);
    EXPECT_LE(rs.kkt_norm, 1e-11);  // tol, or 10·tol at the documented round-off floor
  }
  // The box QP (dense pattern) forced through CHOLMOD agrees with its dense solve.
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  Vec xc = Vec::Zero(6), xd = Vec::Zero(6);
  const SolveResult rc = make_backend("newton")->minimize(make_problem(f, q.lower, q.upper), xc, accurate("cholmod"));
  const SolveResult rd = make_backend("newton")->minimize(make_problem(f, q.lower, q.upper), xd, accurate("dense"));
  ASSERT_TRUE(rc.ok() && rd.ok()) << rc.message << " / " << rd.message;
  EXPECT_NE(rc.message.find("cholmod"), std::string::npos) << rc.message;
  EXPECT_LE((xc - xd).cwiseAbs().maxCoeff(), 1e-12);
}

// CHOLMOD's symbolic analysis is done once per pattern and kept across calls (the driver calls the
// backend tens of times on one pattern), and redone for a different pattern.
TEST(NewtonBackend, CholmodAnalysisIsKeptWhileThePatternIsUnchanged) {
  const Index n = 10;
  const RosenbrockObjective f(n), other(n);
  const auto backend = make_backend("newton");
  const NlpProblem p = make_problem(f, Vec::Zero(n), Vec::Constant(n, 2.0));
  Vec x = Vec::Constant(n, 0.5);
  const SolveResult first = backend->minimize(p, x, accurate());
  ASSERT_TRUE(first.ok()) << first.message;
  EXPECT_EQ(analyses_in(first.message), 1) << first.message;
  x = Vec::Constant(n, 0.4);
  const SolveResult again = backend->minimize(p, x, accurate());
  ASSERT_TRUE(again.ok()) << again.message;
  EXPECT_GT(again.iterations, 0);
  EXPECT_EQ(analyses_in(again.message), 0) << again.message;
  x = Vec::Constant(n, 0.5);
  const SolveResult changed =
      backend->minimize(make_problem(other, Vec::Zero(n), Vec::Constant(n, 2.0)), x, accurate());
  ASSERT_TRUE(changed.ok()) << changed.message;
  EXPECT_EQ(analyses_in(changed.message), 1) << "another pattern object: " << changed.message;
}

// ------------------------------------------------------------------ nonconvex and Rosenbrock

class NewtonDoubleWell : public ::testing::TestWithParam<DoubleWellCase> {};

// With the energy terms' Psd contract (negative curvature clamped to 0), Newton makes progress
// from a start of negative curvature and ends at a first-order point. Default "exact_first": the
// exact Hessian where it is positive definite, the clamped one where not (the two nonconvex
// starts); "clamp": only the clamped one (the method as specified, linear convergence where
// the clamp is active).
TEST_P(NewtonDoubleWell, ClampedHessianReachesClosedFormMinimizer) {
  const DoubleWellCase c = GetParam();
  const Vec lower = (Vec(2) << c.lower_x, -INF).finished();
  const Vec upper = (Vec(2) << c.upper_x, INF).finished();
  for (const std::string mode : {"exact_first", "clamp"}) {
    SCOPED_TRACE(mode);
    const ClampedDoubleWell f;
    Vec x = (Vec(2) << c.x0, c.y0).finished();
    BackendOptions opt = accurate();
    opt.extra["hessian"] = mode;
    const SolveResult r = make_backend("newton")->minimize(make_problem(f, lower, upper), x, opt);
    ASSERT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
    EXPECT_NEAR(x[0], c.x_star, 1e-10);
    EXPECT_NEAR(x[1], c.y_star, 1e-10);
    EXPECT_LE(r.kkt_norm, 1e-12);
    EXPECT_LE(residual(f, x, lower, upper), 1e-12);
    EXPECT_EQ(r.f, f.value(x));
    if (mode == "clamp") {
      // One Psd::CLAMP Hessian per iteration, plus possibly one whose Newton step was below
      // round-off (the "round-off floor" stop); never the exact one.
      EXPECT_EQ(f.exact_calls, 0);
      EXPECT_GE(f.clamp_calls, r.iterations);
      EXPECT_LE(f.clamp_calls, r.iterations + 1);
    } else {
      EXPECT_GE(f.exact_calls, r.iterations);
      // f_xx = 12 x0² − 3.5 < 0 at the two starts inside |x| < 0.54: the clamp must step in.
      if (std::abs(c.x0) < 0.5) {
        EXPECT_GT(f.clamp_calls, 0);
      }
    }
  }
}

// The same with the true (indefinite) Hessian: the diagonal shift takes over.
TEST_P(NewtonDoubleWell, IndefiniteHessianIsShifted) {
  const DoubleWellCase c = GetParam();
  const DoubleWellObjective f;
  const Vec lower = (Vec(2) << c.lower_x, -INF).finished();
  const Vec upper = (Vec(2) << c.upper_x, INF).finished();
  Vec x = (Vec(2) << c.x0, c.y0).finished();
  const SolveResult r = make_backend("newton")->minimize(make_problem(f, lower, upper), x, accurate());
  ASSERT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_NEAR(x[0], c.x_star, 1e-10);
  EXPECT_NEAR(x[1], c.y_star, 1e-10);
}

TEST_P(NewtonDoubleWell, AgreesWithIpopt) {
  HEMICONTACT_REQUIRE_IPOPT_HERE();
  const DoubleWellCase c = GetParam();
  const ClampedDoubleWell f;
  const NlpProblem p = make_problem(f, (Vec(2) << c.lower_x, -INF).finished(), (Vec(2) << c.upper_x, INF).finished());
  Vec xn = (Vec(2) << c.x0, c.y0).finished(), xi = xn;
  ASSERT_TRUE(make_backend("newton")->minimize(p, xn, accurate()).ok());
  ASSERT_TRUE(make_backend("ipopt")->minimize(p, xi, accurate()).ok());
  EXPECT_LE((xn - xi).cwiseAbs().maxCoeff(), 1e-8) << xn.transpose() << " vs " << xi.transpose();
}

INSTANTIATE_TEST_SUITE_P(Cases, NewtonDoubleWell, ::testing::ValuesIn(double_well_cases()),
                         [](const ::testing::TestParamInfo<DoubleWellCase>& info) {
                           return std::string(info.param.name);
                         });

TEST(NewtonBackend, RosenbrockWithActiveBound) {
  const RosenbrockObjective f(2);
  const Vec lower = (Vec(2) << -1.5, -1.5).finished();
  const Vec upper = (Vec(2) << 0.5, 2.0).finished();
  Vec x = (Vec(2) << -1.2, 1.0).finished();  // the classic start
  const SolveResult r = make_backend("newton")->minimize(make_problem(f, lower, upper), x, accurate());
  ASSERT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_NEAR(x[0], 0.5, 1e-12);
  EXPECT_NEAR(x[1], 0.25, 1e-12);
  EXPECT_NEAR(r.f, 0.25, 1e-12);
}

TEST(NewtonBackend, ChainedRosenbrockInactiveBounds) {
  const Index n = 10;
  const RosenbrockObjective f(n);
  Vec x = Vec::Constant(n, 0.5);
  const SolveResult r =
      make_backend("newton")->minimize(make_problem(f, Vec::Zero(n), Vec::Constant(n, 2.0)), x, accurate());
  ASSERT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_LE((x - Vec::Ones(n)).cwiseAbs().maxCoeff(), 1e-10);
}

// Newton and Ipopt on each test problem: the same minimizer to 1e-8.
TEST(NewtonBackend, AgreesWithIpoptOnTheTestProblems) {
  HEMICONTACT_REQUIRE_IPOPT_HERE();
  const BoxQp q = make_box_qp();
  const QuadraticObjective quad(q.A, q.b);
  const RosenbrockObjective rosen2(2), rosen10(10);
  struct Case {
    const char* name;
    const NlpObjective* f;
    Vec lower, upper, x0;
  };
  const std::vector<Case> cases = {
      {"box_qp", &quad, q.lower, q.upper, Vec::Zero(6)},
      {"rosenbrock_bound", &rosen2, (Vec(2) << -1.5, -1.5).finished(), (Vec(2) << 0.5, 2.0).finished(),
       (Vec(2) << -1.2, 1.0).finished()},
      {"chained_rosenbrock", &rosen10, Vec::Zero(10), Vec::Constant(10, 2.0), Vec::Constant(10, 0.5)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const NlpProblem p = make_problem(*c.f, c.lower, c.upper);
    Vec xn = c.x0, xi = c.x0;
    const SolveResult rn = make_backend("newton")->minimize(p, xn, accurate());
    const SolveResult ri = make_backend("ipopt")->minimize(p, xi, accurate());
    ASSERT_TRUE(rn.ok() && ri.ok()) << rn.message << " / " << ri.message;
    EXPECT_LE((xn - xi).cwiseAbs().maxCoeff(), 1e-8) << xn.transpose() << "\n vs " << xi.transpose();
    EXPECT_LE(rn.kkt_norm, ri.kkt_norm + 1e-12) << "Newton ends on the bounds, Ipopt just inside";
  }
}

// ------------------------------------------------------------------ warm start, caps, failures

TEST(NewtonBackend, WarmStartFromTheSolutionTakesAtMostOneIteration) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective quad(q.A, q.b);
  const RosenbrockObjective rosen(10);
  const std::vector<std::pair<const NlpObjective*, NlpProblem>> problems = {
      {&quad, make_problem(quad, q.lower, q.upper)},
      {&rosen, make_problem(rosen, Vec::Zero(10), Vec::Constant(10, 2.0))}};
  for (const auto& [f, p] : problems) {
    const auto backend = make_backend("newton");
    Vec x = Vec::Constant(f->size(), 0.5);
    const SolveResult cold = backend->minimize(p, x, accurate());
    ASSERT_TRUE(cold.ok()) << cold.message;
    const Vec x_cold = x;
    const SolveResult warm = backend->minimize(p, x, accurate());
    ASSERT_TRUE(warm.ok()) << warm.message;
    EXPECT_LE(warm.iterations, 1) << "cold start took " << cold.iterations;
    EXPECT_LE((x - x_cold).cwiseAbs().maxCoeff(), 1e-12);
    const SolveResult fresh = make_backend("newton")->minimize(p, x, accurate());  // no state needed
    EXPECT_LE(fresh.iterations, 1);
  }
}

TEST(NewtonBackend, MaxIterationsIsRespected) {
  const RosenbrockObjective f(2);
  for (const int cap : {0, 1, 3}) {
    Vec x = (Vec(2) << -1.2, 1.0).finished();
    BackendOptions opt;
    opt.max_iter = cap;
    const SolveResult r =
        make_backend("newton")->minimize(make_problem(f, Vec::Constant(2, -INF), Vec::Constant(2, INF)), x, opt);
    EXPECT_EQ(r.status, SolveStatus::MAX_ITERATIONS) << r.message;
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.iterations, cap);
    EXPECT_EQ(r.f, f.value(x));
    EXPECT_EQ(r.kkt_norm, residual(f, x, Vec::Constant(2, -INF), Vec::Constant(2, INF)));
  }
}

// A gradient inconsistent with the values: no step decreases f, and the backend says so instead
// of looping until max_iter.
TEST(NewtonBackend, LineSearchFailureIsReported) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective quad(q.A, q.b);
  const WrongGradientObjective wrong(quad, 1.0);
  Vec x = q.A.llt().solve(q.b);  // the true unconstrained minimizer: every move increases f
  BackendOptions opt;
  opt.max_iter = 1000;
  const SolveResult r =
      make_backend("newton")->minimize(make_problem(wrong, Vec::Constant(6, -INF), Vec::Constant(6, INF)), x, opt);
  EXPECT_EQ(r.status, SolveStatus::FAILED) << r.message;
  EXPECT_NE(r.message.find("line search"), std::string::npos) << r.message;
  // Steps of ~1e-11 may pass on the noise of f (the true change is ~α², below round-off), but
  // they cannot add up: the backend gives up long before max_iter, near where it started.
  EXPECT_LT(r.iterations, 50);
  EXPECT_LE((x - q.A.llt().solve(q.b)).cwiseAbs().maxCoeff(), 1e-7);
}

/// @brief A quadratic whose value() errs by η·Σx_i, a smooth error that the gradient does not
/// share: along a Newton step it can outweigh the true decrease, as the round-off of a 3D body's
/// energy (a sum of 10⁴ cell energies) rose by 2.6e-12 along a step whose predicted decrease was
/// 1.5e-16 (3D Hencky at mesh.n = 16, where r then stalled at 1e-8 for 3000 iterations).
class ErringValueObjective : public QuadraticObjective {
 public:
  ErringValueObjective(Mat A, Vec b, double eta) : QuadraticObjective(std::move(A), std::move(b)), m_eta(eta) {}
  double value(const Vec& x) const override { return QuadraticObjective::value(x) + m_eta * x.sum(); }

 private:
  double m_eta;
};

// From x* − 1e-6: the Newton step's true decrease, ½dᵀAd ≈ 2e-11, is less than the error it
// adds to f, η·Σd = 6e-11, so no step passes the exact Armijo test. Hager and Zhang's
// approximate test reads the decrease from the gradients and takes the step.
TEST(NewtonBackend, ANewtonStepBelowTheErrorOfFIsTakenOnItsGradients) {
  const BoxQp q = make_box_qp();
  const ErringValueObjective f(q.A, q.b, 1e-5);
  const Vec free = Vec::Constant(6, INF);
  const Vec exact = q.A.llt().solve(q.b);
  Vec x = exact - Vec::Constant(6, 1e-6);
  const SolveResult r = make_backend("newton")->minimize(make_problem(f, -free, free), x, accurate());
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_EQ(r.iterations, 1) << r.message;
  EXPECT_LE(r.kkt_norm, 1e-12);
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-13 * exact.cwiseAbs().maxCoeff());
}

TEST(NewtonBackend, OptionsAreChecked) {
  const DoubleWellObjective f;
  const NlpProblem p = make_problem(f, Vec::Constant(2, -2.0), Vec::Constant(2, 2.0));
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"linear_solver", "lu"}, {"hessian", "bfgs"}, {"mu_strategy", "adaptive"}}) {
    BackendOptions opt;
    opt.extra[key] = value;
    Vec x = Vec::Constant(2, 0.3);
    try {
      make_backend("newton")->minimize(p, x, opt);
      ADD_FAILURE() << key << " = " << value << " did not throw";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_EQ(e.code(), EXIT_INPUT);
    }
  }
}

TEST(NewtonBackend, ObjectiveExceptionsPropagate) {
  const DoubleWellObjective well;
  const ThrowingObjective f(well, 3);
  Vec x = Vec::Constant(2, 0.3);
  EXPECT_THROW(make_backend("newton")->minimize(make_problem(f, Vec::Constant(2, -2.0), Vec::Constant(2, 2.0)), x,
                                                BackendOptions{}),
               std::runtime_error);
}

TEST(NewtonBackend, RejectsMismatchedSizesAndEmptyBounds) {
  const DoubleWellObjective f;
  const auto backend = make_backend("newton");
  Vec x = Vec::Zero(3);
  EXPECT_THROW(backend->minimize(make_problem(f, Vec::Zero(2), Vec::Ones(2)), x, BackendOptions{}), Error);
  x = Vec::Zero(2);
  EXPECT_THROW(backend->minimize(make_problem(f, Vec::Ones(2), Vec::Zero(2)), x, BackendOptions{}), Error);
}

// ------------------------------------------------------------------ the paper scene end to end

struct SceneRun {
  Model md;
  Solution sol;
};
SceneRun run_fig2(const std::string& backend, const std::string& formulation) {
  const nlohmann::json scene =
      load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json",
                 {"mesh.n=16", "solver.backend=" + backend, "solver.formulation=" + formulation});
  SceneRun s{build_model(scene, HEMICONTACT_SOURCE_DIR "/problems"), {}};
  s.sol = solve(s.md, solve_options_from_scene(scene));
  return s;
}

class NewtonFig2 : public ::testing::TestWithParam<std::string> {};

// Fig. 2 at mesh.n = 16: Newton passes the certificate and gives Ipopt's statuses and u.
TEST_P(NewtonFig2, CertificateAndAgreementWithIpopt) {
  const std::string formulation = GetParam();
  const SceneRun n = run_fig2("newton", formulation);
  ASSERT_TRUE(n.sol.backend_ok && n.sol.fixed_point_converged) << n.sol.message;
  EXPECT_EQ(n.sol.backend, "newton");
  EXPECT_EQ(n.sol.formulation, formulation);
  EXPECT_TRUE(n.sol.certificate.passed) << n.sol.message;
  int analyses = 0;
  for (const auto& h : n.sol.history) {
    EXPECT_TRUE(h.backend.ok()) << h.backend.message;
    analyses += std::max(0, analyses_in(h.backend.message));
  }
  EXPECT_EQ(analyses, formulation == "full" ? 1 : 0) << "CHOLMOD analyses over the whole continuation";
  if (!HEMICONTACT_HAS_IPOPT) GTEST_SKIP() << "Ipopt not compiled in: comparison skipped";
  const SceneRun i = run_fig2("ipopt", formulation);
  ASSERT_TRUE(i.sol.backend_ok && i.sol.fixed_point_converged) << i.sol.message;
  ASSERT_EQ(n.sol.status.size(), i.sol.status.size());
  for (size_t k = 0; k < n.sol.status.size(); ++k)
    EXPECT_EQ(n.sol.status[k].str(), i.sol.status[k].str()) << "node " << k;
  const double U = i.sol.u.cwiseAbs().maxCoeff();
  EXPECT_LE((n.sol.u - i.sol.u).cwiseAbs().maxCoeff(), 1e-9 * U);
}

INSTANTIATE_TEST_SUITE_P(Formulations, NewtonFig2, ::testing::Values("full", "condensed"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace hemicontact::test
