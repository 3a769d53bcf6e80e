// The backend registry: make_backend(name) and available_backends() (polysolve's Solver::create).
//
// One table lists every backend hemicontact knows about, compiled in or not, so that a known name
// whose library was missing at build time gets an actionable message ("install X and rebuild")
// instead of "unknown backend".

#include <hemicontact/core/error.hpp>
#include <hemicontact/nlp/backend.hpp>

#include "nlp/backend_factories.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

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

namespace {

/// A factory receives the full requested name, so a family ("nlopt:ALGO") can read its suffix.
using Factory = std::unique_ptr<NlpBackend> (*)(const std::string& name);

struct Entry {
  const char* name;         // exact name, or a family prefix ending in ':' (e.g. "nlopt:")
  const char* shown_name;   // how available_backends() and error messages print it
  const char* description;  // one line
  const char* missing;      // how to get it when it was not compiled in
  Factory create;           // nullptr: not compiled in
};

std::vector<Entry> registry() {
  std::vector<Entry> r;

  // Always compiled (needs only CHOLMOD).
  r.push_back({"newton", "newton",
               "projected Newton with active set, CHOLMOD (sparse) / dense Cholesky (condensed); "
               "exact Hessian if positive definite, else Psd::CLAMP",
               "", [](const std::string&) { return make_newton_backend(); }});

#if HEMICONTACT_HAS_IPOPT
  const Factory ipopt = [](const std::string&) { return make_ipopt_backend(); };
#else
  const Factory ipopt = nullptr;
#endif
  r.push_back({"ipopt", "ipopt", "Ipopt interior point, exact Hessian, bound multipliers kept for warm starts",
               "install coinor-libipopt-dev and rebuild", ipopt});

  // NLopt: one entry (and one line in `hemicontact backends`) per supported algorithm, then the
  // family, which takes "G_MLSL_LDS+LOCAL" and turns an unknown or refused algorithm into an
  // Error that says why.
#if HEMICONTACT_HAS_NLOPT
  const Factory nlopt = [](const std::string& n) { return make_nlopt_backend(n.substr(6)); };
  for (const NloptAlgorithmInfo& a : nlopt_backend_catalog())
    r.push_back({a.backend_name, a.backend_name, a.description, "", nlopt});
#else
  const Factory nlopt = nullptr;
#endif
  r.push_back({"nlopt:", "nlopt:G_MLSL_LDS+LOCAL",
               "NLopt MLSL global search with the local algorithm LOCAL named, e.g. "
               "nlopt:G_MLSL_LDS+LD_MMA (also G_MLSL+LOCAL)",
               "install libnlopt-cxx-dev and rebuild", nlopt});

  return r;
}

bool matches(const Entry& e, const std::string& name) {
  const std::string key = e.name;
  if (!key.empty() && key.back() == ':')  // a family: the prefix plus a non-empty suffix
    return name.size() > key.size() && name.compare(0, key.size(), key) == 0;
  return name == key;
}

std::string list_available() {
  std::string out;
  for (const auto& [name, description] : available_backends()) {
    (void)description;
    out += (out.empty() ? "" : ", ") + name;
  }
  return out.empty() ? "(none compiled in)" : out;
}

}  // namespace

std::unique_ptr<NlpBackend> make_backend(const std::string& name) {
  for (const Entry& e : registry()) {
    if (!matches(e, name)) continue;
    if (e.create == nullptr) throw Error("backend '" + name + "' was not compiled in (" + e.missing + ")", EXIT_INPUT);
    return e.create(name);
  }
  throw Error("unknown backend '" + name + "'; available: " + list_available(), EXIT_INPUT);
}

std::vector<std::pair<std::string, std::string>> available_backends() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const Entry& e : registry())
    if (e.create != nullptr) out.emplace_back(e.shown_name, e.description);
  return out;
}

}  // namespace hemicontact
