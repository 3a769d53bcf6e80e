// Tests of the backend registry (make_backend, available_backends) and of the "ipopt" backend on
// small problems with known minimizers (tests/nlp/test_problems.hpp). Ipopt tests skip when the
// backend was not compiled in; they reach Ipopt only through make_backend("ipopt"), so this file
// needs no Ipopt header.

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/nlp/backend.hpp>

#include "nlp/test_problems.hpp"
#include "support/fd_check.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace hemicontact::test {
namespace {

#define HEMICONTACT_REQUIRE_IPOPT()                                                                             \
  if (!HEMICONTACT_HAS_IPOPT) GTEST_SKIP() << "Ipopt backend not compiled in (install coinor-libipopt-dev and " \
                                              "rebuild)"

/// Options for tests that compare with an exact answer to 1e-9. An interior point stops at a
/// distance ≈ tol·G/z from an active bound (G = max(1, ‖∇f(x0)‖∞), z the multiplier), ~1e-9 for
/// the default tol = 1e-10 and these O(10-200) gradients; 1e-12 leaves a margin of 10-100.
BackendOptions accurate_ipopt() {
  BackendOptions o;
  o.tol = 1e-12;
  return o;
}


/// A per-process file name in the test temp directory: other build trees run this same test
/// program at the same time. Ipopt lower-cases "output_file" names, so keep it lower case.
std::string temp_path(const std::string& stem) {
  return ::testing::TempDir() + "hemicontact_" + stem + "_" + std::to_string(::getpid()) + ".log";
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// ------------------------------------------------------------------ registry (always built)

TEST(MakeBackend, UnknownNameListsAvailable) {
  try {
    make_backend("nope");
    FAIL() << "make_backend(\"nope\") did not throw";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("nope"), std::string::npos) << msg;
    EXPECT_EQ(e.code(), EXIT_INPUT);
    if (HEMICONTACT_HAS_IPOPT) {
      EXPECT_NE(msg.find("ipopt"), std::string::npos) << msg;
    }
  }
}

TEST(MakeBackend, AvailableBackendsMatchesBuild) {
  const auto list = available_backends();
  const bool has_ipopt =
      std::any_of(list.begin(), list.end(), [](const auto& e) { return e.first == "ipopt" && !e.second.empty(); });
  EXPECT_EQ(has_ipopt, bool(HEMICONTACT_HAS_IPOPT));
  for (const auto& [name, description] : list) {
    EXPECT_FALSE(description.empty()) << name;
    EXPECT_EQ(description.find('\n'), std::string::npos) << name << ": one line only";
  }
}

TEST(MakeBackend, IpoptByNameOrNotCompiledInError) {
  if (HEMICONTACT_HAS_IPOPT) {
    const auto backend = make_backend("ipopt");
    EXPECT_EQ(backend->name(), "ipopt");
    EXPECT_TRUE(backend->uses_hessian());
    return;
  }
  try {
    make_backend("ipopt");
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("was not compiled in (install coinor-libipopt-dev"), std::string::npos)
        << e.what();
  }
}

TEST(SolveStatus, ToString) {
  EXPECT_STREQ(to_string(SolveStatus::CONVERGED), "converged");
  EXPECT_STREQ(to_string(SolveStatus::ACCEPTABLE), "acceptable");
  EXPECT_STREQ(to_string(SolveStatus::MAX_ITERATIONS), "max_iterations");
  EXPECT_STREQ(to_string(SolveStatus::FAILED), "failed");
}

// ------------------------------------------------------------------ test problems themselves

// The reference answers are only as good as the test objectives' derivatives: check them by
// finite differences at several points (tests/support/fd_check.hpp, the checker of the energy terms).
TEST(TestProblems, DerivativesMatchFiniteDifferences) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective quad(q.A, q.b);
  const DoubleWellObjective well;
  const RosenbrockObjective rosen2(2), rosen7(7);
  const std::vector<const NlpObjective*> objectives = {&quad, &well, &rosen2, &rosen7};
  std::srand(7);
  for (const NlpObjective* f : objectives) {
    for (int trial = 0; trial < 10; ++trial) {
      const Vec x = 1.5 * Vec::Random(f->size());
      SCOPED_TRACE("n = " + std::to_string(f->size()) + ", trial " + std::to_string(trial));
      Vec g;
      f->gradient(x, g);
      EXPECT_TRUE(near_rel(g, fd_gradient([f](const Vec& y) { return f->value(y); }, x), 1e-6, 1e-7));
      const Mat J = fd_jacobian(
          [f](const Vec& y) {
            Vec gy;
            f->gradient(y, gy);
            return gy;
          },
          x);
      EXPECT_TRUE(near_rel(full_hessian(*f, x), J, 1e-5, 1e-6));
    }
  }
}

TEST(TestProblems, EnumeratedQpSolutionHasMixedActiveSet) {
  const BoxQp q = make_box_qp();
  std::vector<bool> at_lower, at_upper;
  const Vec x = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper, &at_lower, &at_upper);
  // The QP test is only meaningful if both kinds of bounds are active and some unknowns are free.
  EXPECT_TRUE(std::count(at_lower.begin(), at_lower.end(), true) >= 1);
  EXPECT_TRUE(std::count(at_upper.begin(), at_upper.end(), true) >= 1);
  EXPECT_TRUE(std::count(at_lower.begin(), at_lower.end(), false) +
                  std::count(at_upper.begin(), at_upper.end(), false) >
              Index(at_lower.size()));
  // Strict complementarity with O(1) multipliers keeps the interior-point error at tol/|z|.
  const Vec g = q.A * x - q.b;
  for (Index i = 0; i < x.size(); ++i)
    if (at_lower[i] || at_upper[i]) {
      EXPECT_GT(std::abs(g[i]), 0.1) << "unknown " << i;
    }
}

// ------------------------------------------------------------------ the Ipopt backend

TEST(IpoptBackend, BoxQpMatchesEnumeratedSolution) {
  HEMICONTACT_REQUIRE_IPOPT();
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  const auto backend = make_backend("ipopt");
  Vec x = Vec::Zero(6);
  const SolveResult r = backend->minimize(make_problem(f, q.lower, q.upper), x, accurate_ipopt());
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_TRUE(r.ok());
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-9) << "x = " << x.transpose() << "\nexact = " << exact.transpose();
  EXPECT_NEAR(r.f, f.value(exact), 1e-9 * (1.0 + std::abs(f.value(exact))));
  EXPECT_LE(r.kkt_norm, 1e-8);
  EXPECT_GT(r.iterations, 0);
  EXPECT_GE(r.evaluations, r.iterations);
  EXPECT_GT(r.seconds, 0.0);
  EXPECT_TRUE(((x - q.lower).array() >= 0).all() && ((q.upper - x).array() >= 0).all());
}

TEST(IpoptBackend, StartOutsideBoundsIsProjected) {
  HEMICONTACT_REQUIRE_IPOPT();
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  Vec x = Vec::Constant(6, 50.0);
  const SolveResult r = make_backend("ipopt")->minimize(make_problem(f, q.lower, q.upper), x, accurate_ipopt());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(IpoptBackend, FixedVariableAndWarmStartWithIt) {
  HEMICONTACT_REQUIRE_IPOPT();
  // lower == upper: Ipopt removes the unknown (fixed_variable_treatment make_parameter) while
  // the Hessian structure still lists it; the answer is the QP with that unknown eliminated.
  BoxQp q = make_box_qp();
  q.lower[2] = q.upper[2] = 0.3;
  const QuadraticObjective f(q.A, q.b);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  const auto backend = make_backend("ipopt");
  Vec x = Vec::Zero(6);
  const SolveResult r = backend->minimize(make_problem(f, q.lower, q.upper), x, accurate_ipopt());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(x[2], 0.3);
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-9);
  const SolveResult warm = backend->minimize(make_problem(f, q.lower, q.upper), x, accurate_ipopt());
  ASSERT_TRUE(warm.ok()) << warm.message;
  EXPECT_LE(warm.iterations, 5);
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-9);
}

class IpoptDoubleWell : public ::testing::TestWithParam<DoubleWellCase> {};

TEST_P(IpoptDoubleWell, ReachesClosedFormMinimizer) {
  HEMICONTACT_REQUIRE_IPOPT();
  const DoubleWellCase c = GetParam();
  const DoubleWellObjective f;
  const Vec lower = (Vec(2) << c.lower_x, -INF).finished();
  const Vec upper = (Vec(2) << c.upper_x, INF).finished();
  Vec x = (Vec(2) << c.x0, c.y0).finished();
  const SolveResult r = make_backend("ipopt")->minimize(make_problem(f, lower, upper), x, accurate_ipopt());
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_NEAR(x[0], c.x_star, 1e-9);
  EXPECT_NEAR(x[1], c.y_star, 1e-9);
  EXPECT_LE(r.kkt_norm, 1e-8);
}

INSTANTIATE_TEST_SUITE_P(Cases, IpoptDoubleWell, ::testing::ValuesIn(double_well_cases()),
                         [](const ::testing::TestParamInfo<DoubleWellCase>& info) {
                           return std::string(info.param.name);
                         });

TEST(IpoptBackend, RosenbrockWithActiveBound) {
  HEMICONTACT_REQUIRE_IPOPT();
  const RosenbrockObjective f(2);
  const Vec lower = (Vec(2) << -1.5, -1.5).finished();
  const Vec upper = (Vec(2) << 0.5, 2.0).finished();
  Vec x = (Vec(2) << -1.2, 1.0).finished();  // the classic start
  const SolveResult r = make_backend("ipopt")->minimize(make_problem(f, lower, upper), x, accurate_ipopt());
  ASSERT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_NEAR(x[0], 0.5, 1e-9);
  EXPECT_NEAR(x[1], 0.25, 1e-9);
  EXPECT_NEAR(r.f, 0.25, 1e-9);
}

TEST(IpoptBackend, ChainedRosenbrockInactiveBounds) {
  HEMICONTACT_REQUIRE_IPOPT();
  // Tridiagonal Hessian pattern; the bounds [0, 2] exclude the spurious local minimizer near
  // x_0 = −1 of the chained function and are inactive at (1, …, 1).
  const Index n = 10;
  const RosenbrockObjective f(n);
  Vec x = Vec::Constant(n, 0.5);
  const SolveResult r =
      make_backend("ipopt")->minimize(make_problem(f, Vec::Zero(n), Vec::Constant(n, 2.0)), x, accurate_ipopt());
  ASSERT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_LE((x - Vec::Ones(n)).cwiseAbs().maxCoeff(), 1e-8);
}

// Ipopt's own derivative checker (derivative_test, on in this one test: Ipopt itself confirms that
// the adapter hands it the right derivatives). Ipopt only reports what it finds and carries on, so
// its report is sent to a file and read back; the negative case shows the check would catch a wrong
// gradient.
TEST(IpoptBackend, IpoptDerivativeTestPasses) {
  HEMICONTACT_REQUIRE_IPOPT();
  const DoubleWellObjective well;
  const RosenbrockObjective rosen(5);
  const std::vector<const NlpObjective*> objectives = {&well, &rosen};
  const std::string log = temp_path("ipopt_derivative_test");
  for (const NlpObjective* f : objectives) {
    const Index n = f->size();
    BackendOptions opt;
    opt.extra["derivative_test"] = "second-order";
    opt.extra["derivative_test_print_all"] = "no";
    opt.extra["output_file"] = log;
    opt.extra["file_print_level"] = "4";  // J_WARNING: where the checker reports
    Vec x = Vec::Constant(n, 0.3);
    const SolveResult r =
        make_backend("ipopt")->minimize(make_problem(*f, Vec::Constant(n, -2.0), Vec::Constant(n, 2.0)), x, opt);
    EXPECT_TRUE(r.ok()) << r.message;
    const std::string report = read_file(log);
    EXPECT_NE(report.find("No errors detected by derivative checker"), std::string::npos) << "n = " << n << ":\n"
                                                                                          << report;
  }
  std::remove(log.c_str());
}

TEST(IpoptBackend, IpoptDerivativeTestCatchesWrongGradient) {
  HEMICONTACT_REQUIRE_IPOPT();
  const DoubleWellObjective well;
  const WrongGradientObjective wrong(well, 0.1);
  const std::string log = temp_path("ipopt_derivative_test_bad");
  BackendOptions opt;
  opt.extra["derivative_test"] = "first-order";
  opt.extra["output_file"] = log;
  opt.extra["file_print_level"] = "4";
  opt.max_iter = 5;  // the run itself is beside the point
  Vec x = Vec::Constant(2, 0.3);
  make_backend("ipopt")->minimize(make_problem(wrong, Vec::Constant(2, -2.0), Vec::Constant(2, 2.0)), x, opt);
  const std::string report = read_file(log);
  EXPECT_NE(report.find("Derivative checker detected"), std::string::npos) << report;
  std::remove(log.c_str());
}

TEST(IpoptBackend, WarmStartFromSolutionTakesFewIterations) {
  HEMICONTACT_REQUIRE_IPOPT();
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  const NlpProblem p = make_problem(f, q.lower, q.upper);
  const Vec exact = solve_box_qp_by_enumeration(q.A, q.b, q.lower, q.upper);
  const auto backend = make_backend("ipopt");
  Vec x = Vec::Zero(6);
  const SolveResult cold = backend->minimize(p, x, accurate_ipopt());
  ASSERT_TRUE(cold.ok()) << cold.message;
  const SolveResult warm = backend->minimize(p, x, accurate_ipopt());  // same object: keeps z
  ASSERT_TRUE(warm.ok()) << warm.message;
  EXPECT_LE(warm.iterations, 5) << "cold start took " << cold.iterations;
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_LE((x - exact).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(IpoptBackend, WarmStartAfterSmallChangeBeatsColdStart) {
  HEMICONTACT_REQUIRE_IPOPT();
  // What the fixed-point loop does: re-solve a slightly changed problem from the last answer.
  const BoxQp q = make_box_qp();
  const QuadraticObjective f1(q.A, q.b);
  const Vec b2 = q.b + 0.01 * Vec::Ones(6);
  const QuadraticObjective f2(q.A, b2);
  const Vec exact2 = solve_box_qp_by_enumeration(q.A, b2, q.lower, q.upper);
  const auto backend = make_backend("ipopt");
  Vec x = Vec::Zero(6);
  ASSERT_TRUE(backend->minimize(make_problem(f1, q.lower, q.upper), x, accurate_ipopt()).ok());
  const SolveResult warm = backend->minimize(make_problem(f2, q.lower, q.upper), x, accurate_ipopt());
  Vec x_cold = Vec::Zero(6);
  const SolveResult cold = make_backend("ipopt")->minimize(make_problem(f2, q.lower, q.upper), x_cold, accurate_ipopt());
  ASSERT_TRUE(warm.ok() && cold.ok()) << warm.message << " / " << cold.message;
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_LE((x - exact2).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(IpoptBackend, MaxIterationsIsReported) {
  HEMICONTACT_REQUIRE_IPOPT();
  const RosenbrockObjective f(2);
  Vec x = (Vec(2) << -1.2, 1.0).finished();
  BackendOptions opt;
  opt.max_iter = 3;
  const SolveResult r =
      make_backend("ipopt")->minimize(make_problem(f, Vec::Constant(2, -INF), Vec::Constant(2, INF)), x, opt);
  EXPECT_EQ(r.status, SolveStatus::MAX_ITERATIONS) << r.message;
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.iterations, 3);
  EXPECT_NE(r.message.find("Maximum_Iterations_Exceeded"), std::string::npos) << r.message;
}

TEST(IpoptBackend, InvalidPassThroughOptionsThrowNamingThem) {
  HEMICONTACT_REQUIRE_IPOPT();
  const DoubleWellObjective f;
  const NlpProblem p = make_problem(f, Vec::Constant(2, -2.0), Vec::Constant(2, 2.0));
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"mu_strategy", "bogus"},  // not in the option's list of values
      {"not_an_option", "1"},    // not registered
      {"max_iter", "abc"},       // integer option, not an integer
      {"max_iter", "10x"},       // integer option, only a prefix parses
      {"tol", "-1"},             // numeric option out of range (tol > 0)
  };
  for (const auto& [key, value] : bad) {
    BackendOptions opt;
    opt.extra[key] = value;
    Vec x = Vec::Constant(2, 0.3);
    try {
      make_backend("ipopt")->minimize(p, x, opt);
      ADD_FAILURE() << key << " = " << value << " did not throw";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_EQ(e.code(), EXIT_INPUT) << e.what();
    }
  }
}

TEST(IpoptBackend, PassThroughOptionsOfEachType) {
  HEMICONTACT_REQUIRE_IPOPT();
  const DoubleWellObjective f;
  BackendOptions opt;
  opt.extra["mu_strategy"] = "monotone";  // string
  opt.extra["max_soc"] = "2";             // integer
  opt.extra["obj_scaling_factor"] = "2";  // numeric although it parses as an integer
  opt.extra["mu_init"] = "1e-2";          // numeric
  Vec x = (Vec(2) << 0.3, 0.0).finished();
  const SolveResult r =
      make_backend("ipopt")->minimize(make_problem(f, Vec::Constant(2, -INF), (Vec(2) << 0.5, INF).finished()), x, opt);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_NEAR(x[0], 0.5, 1e-8);
}

TEST(IpoptBackend, IgnoresIpoptOptFileInWorkingDirectory) {
  HEMICONTACT_REQUIRE_IPOPT();
  // Initialize() without a file name would read ./ipopt.opt; ours passes "" so it must not.
  char old_dir[4096];
  ASSERT_NE(::getcwd(old_dir, sizeof old_dir), nullptr);
  std::string dir = ::testing::TempDir() + "hemicontact_ipopt_opt_XXXXXX";
  ASSERT_NE(::mkdtemp(dir.data()), nullptr);  // private directory: no clash with parallel runs
  ASSERT_EQ(::chdir(dir.c_str()), 0);
  {
    std::ofstream opt_file("ipopt.opt");
    opt_file << "max_iter 0\n";
  }
  const RosenbrockObjective f(2);
  Vec x = (Vec(2) << -1.2, 1.0).finished();
  SolveResult r;
  try {
    r = make_backend("ipopt")->minimize(make_problem(f, Vec::Constant(2, -INF), Vec::Constant(2, INF)), x,
                                        BackendOptions{});
  } catch (...) {
    std::remove("ipopt.opt");
    EXPECT_EQ(::chdir(old_dir), 0);
    ::rmdir(dir.c_str());
    throw;
  }
  std::remove("ipopt.opt");
  ASSERT_EQ(::chdir(old_dir), 0);
  ::rmdir(dir.c_str());
  EXPECT_EQ(r.status, SolveStatus::CONVERGED) << r.message;
  EXPECT_GT(r.iterations, 0);
}

TEST(IpoptBackend, ObjectiveExceptionsPropagate) {
  HEMICONTACT_REQUIRE_IPOPT();
  const DoubleWellObjective well;
  const ThrowingObjective f(well, 3);
  Vec x = Vec::Constant(2, 0.3);
  EXPECT_THROW(make_backend("ipopt")->minimize(make_problem(f, Vec::Constant(2, -2.0), Vec::Constant(2, 2.0)), x,
                                               BackendOptions{}),
               std::runtime_error);
}

TEST(IpoptBackend, RejectsMismatchedSizesAndEmptyBounds) {
  HEMICONTACT_REQUIRE_IPOPT();
  const DoubleWellObjective f;
  const auto backend = make_backend("ipopt");
  Vec x = Vec::Zero(3);
  EXPECT_THROW(backend->minimize(make_problem(f, Vec::Zero(2), Vec::Ones(2)), x, BackendOptions{}), Error);
  x = Vec::Zero(2);
  EXPECT_THROW(backend->minimize(make_problem(f, Vec::Ones(2), Vec::Zero(2)), x, BackendOptions{}), Error);
}

}  // namespace
}  // namespace hemicontact::test
