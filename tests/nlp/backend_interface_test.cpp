// The one entry point of every backend, NlpBackend::minimize (nlp/backend.hpp): it checks the
// problem, projects the start, answers n = 0 itself, times the run and reports one residual,
// SolveResult::kkt_norm = max_i min(|g_i|, room to the bound −g_i points to), whatever the backend.
#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/nlp/backend.hpp>

#include "nlp/test_problems.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hemicontact::test {
namespace {

std::vector<std::string> backends() {
  std::vector<std::string> b = {"newton"};
  if (HEMICONTACT_HAS_IPOPT) b.push_back("ipopt");
  if (HEMICONTACT_HAS_NLOPT) b.insert(b.end(), {"nlopt:LD_LBFGS", "nlopt:LD_MMA", "nlopt:LD_SLSQP"});
  return b;
}

/// The residual written out independently of nlp/: the distance from x to the projection of x − g.
double projected_step(const Vec& x, const Vec& g, const Vec& lower, const Vec& upper) {
  return (x - (x - g).cwiseMax(lower).cwiseMin(upper)).cwiseAbs().maxCoeff();
}

// The box QP's answer has lower, upper and inactive bounds: kkt_norm is the same residual for
// every backend, and it is the projected-step norm at the returned x to round-off.
TEST(BackendInterface, KktNormIsOneResidualForEveryBackend) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  const NlpProblem p = make_problem(f, q.lower, q.upper);
  BackendOptions opt;
  opt.tol = 1e-8;
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    Vec x = Vec::Zero(6);
    const SolveResult r = make_backend(name)->minimize(p, x, opt);
    Vec g;
    f.gradient(x, g);
    EXPECT_EQ(r.kkt_norm, first_order_residual(x, g, q.lower, q.upper));
    EXPECT_NEAR(r.kkt_norm, projected_step(x, g, q.lower, q.upper), 1e-15 * (1 + g.cwiseAbs().maxCoeff()));
    EXPECT_GE(r.seconds, 0.0);
  }
}

TEST(BackendInterface, EmptyProblemIsConvergedAtOnce) {
  const QuadraticObjective f(Mat(0, 0), Vec(0));
  const NlpProblem p = make_problem(f, Vec(0), Vec(0));
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    Vec x(0);
    const SolveResult r = make_backend(name)->minimize(p, x, BackendOptions());
    EXPECT_EQ(r.status, SolveStatus::CONVERGED);
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ(r.kkt_norm, 0.0);
    EXPECT_NE(r.message.find("empty problem"), std::string::npos) << r.message;
  }
}

TEST(BackendInterface, MalformedProblemsAreRefusedNamingTheBackend) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    const auto backend = make_backend(name);
    Vec x = Vec::Zero(5);  // one short
    try {
      backend->minimize(make_problem(f, q.lower, q.upper), x, BackendOptions());
      ADD_FAILURE() << "a start of the wrong size was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), EXIT_INTERNAL);
      EXPECT_EQ(std::string(e.what()).rfind(name + ": sizes differ", 0), 0u) << e.what();
    }
    Vec lower = q.lower;
    lower[2] = 2.0;  // above upper[2] = 1
    x = Vec::Zero(6);
    try {
      backend->minimize(make_problem(f, lower, q.upper), x, BackendOptions());
      ADD_FAILURE() << "empty bounds were accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), EXIT_INPUT);
      EXPECT_NE(std::string(e.what()).find(name + ": empty bounds at unknown 2"), std::string::npos) << e.what();
    }
  }
}

// A start outside the box is projected before the algorithm sees it: with max_iter = 1 an
// algorithm cannot go far, and every backend's answer lies inside the bounds.
TEST(BackendInterface, StartIsProjectedOntoTheBounds) {
  const BoxQp q = make_box_qp();
  const QuadraticObjective f(q.A, q.b);
  const NlpProblem p = make_problem(f, q.lower, q.upper);
  BackendOptions opt;
  opt.max_iter = 1;
  for (const std::string& name : backends()) {
    SCOPED_TRACE(name);
    Vec x = Vec::Constant(6, 50.0);
    make_backend(name)->minimize(p, x, opt);
    for (Index i = 0; i < 6; ++i) {
      EXPECT_GE(x[i], q.lower[i]) << i;
      EXPECT_LE(x[i], q.upper[i]) << i;
    }
  }
}

}  // namespace
}  // namespace hemicontact::test
