// What every NLP backend shares (nlp/backend.hpp): the status names, the first-order residual and
// the template method NlpBackend::minimize. Apart from the registry (make_backend.cpp), which links
// the optional backends, so that the petsc engine's program links this without Ipopt.

#include <hemicontact/core/error.hpp>
#include <hemicontact/nlp/backend.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace hemicontact {

const char* to_string(SolveStatus s) {
  switch (s) {
    case SolveStatus::CONVERGED: return "converged";
    case SolveStatus::ACCEPTABLE: return "acceptable";
    case SolveStatus::MAX_ITERATIONS: return "max_iterations";
    case SolveStatus::FAILED: return "failed";
  }
  return "failed";  // unreachable for valid enumerators; keeps -Wreturn-type quiet
}

SolveStatus solve_status_from(const std::string& name) {
  for (const SolveStatus s : {SolveStatus::CONVERGED, SolveStatus::ACCEPTABLE, SolveStatus::MAX_ITERATIONS, SolveStatus::FAILED})
    if (name == to_string(s)) return s;
  throw Error("no backend status '" + name + "'", EXIT_INTERNAL);
}

double first_order_residual(const Vec& x, const Vec& g, const Vec& lower, const Vec& upper) {
  double r = 0;
  for (Index i = 0; i < x.size(); ++i) {
    const double room = g[i] < 0 ? upper[i] - x[i] : x[i] - lower[i];
    r = std::max(r, std::min(std::abs(g[i]), std::max(0.0, room)));
  }
  return r;
}

double first_order_residual(const NlpProblem& problem, const Vec& x) {
  Vec g;
  problem.f->gradient(x, g);
  return first_order_residual(x, g, problem.lower, problem.upper);
}

SolveResult NlpBackend::minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string who = name();
  if (problem.f == nullptr) throw Error(who + ": NlpProblem has no objective", EXIT_INTERNAL);
  const Index n = problem.f->size();
  if (problem.lower.size() != n || problem.upper.size() != n || x.size() != n)
    throw Error(who + ": sizes differ: n = " + std::to_string(n) + ", lower " + std::to_string(problem.lower.size()) +
                    ", upper " + std::to_string(problem.upper.size()) + ", x " + std::to_string(x.size()),
                EXIT_INTERNAL);
  for (Index i = 0; i < n; ++i)
    if (!(problem.lower[i] <= problem.upper[i]))  // also catches NaN bounds
      throw Error(who + ": empty bounds at unknown " + std::to_string(i) + ": [" + std::to_string(problem.lower[i]) +
                      ", " + std::to_string(problem.upper[i]) + "]",
                  EXIT_INPUT);
  x = x.cwiseMax(problem.lower).cwiseMin(problem.upper);
  SolveResult result;
  if (n == 0) {  // nothing to minimize (Ipopt would even reject it: too few degrees of freedom)
    result.status = SolveStatus::CONVERGED;
    result.f = problem.f->value(x);
    result.evaluations = 1;
    result.message = who + ": empty problem (n = 0)";
  } else {
    result = do_minimize(problem, x, options);
    result.kkt_norm = first_order_residual(problem, x);
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace hemicontact
