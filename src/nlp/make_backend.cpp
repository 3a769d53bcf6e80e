// The backend registry: make_backend(name) and available_backends() (polysolve's Solver::create).
//
// One table lists every backend hemicontact knows about, compiled in or not, so that a known name
// whose library was missing at build time gets an actionable message ("install X and rebuild")
// instead of "unknown backend".

#include <hemicontact/core/error.hpp>
#include <hemicontact/nlp/backend.hpp>

#include "nlp/backend_factories.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace hemicontact {

namespace {

/// A factory receives the full requested name, so a family ("nlopt:ALGO") can read its suffix.
using Factory = std::unique_ptr<NlpBackend> (*)(const std::string& name);

struct Entry {
  const char* name;         // exact name, or a family prefix ending in ':' (e.g. "nlopt:")
  const char* shown_name;   // how available_backends() prints it (nullptr: not listed)
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
  // The family is not listed by name (a template is no backend name): the G_MLSL entries above say
  // how to name their local algorithm.
  r.push_back({"nlopt:", nullptr,
               "NLopt MLSL global search with the local algorithm LOCAL named, e.g. "
               "nlopt:G_MLSL_LDS+LD_MMA (also G_MLSL+LOCAL)",
               "install libnlopt-cxx-dev and rebuild", nlopt});

  // TAO's bound-constrained Newton methods belong to the PETSc engine (hemicontact-mpi, a process
  // of its own): listed here so that `hemicontact backends` shows them, and refused in this process
  // with the remedy.
#if HEMICONTACT_HAS_PETSC
  const Factory tao = [](const std::string& n) -> std::unique_ptr<NlpBackend> {
    throw Error("backend '" + n + "' runs in the petsc engine: add --set solver.engine='\"petsc\"' (hemicontact-mpi)",
                EXIT_INPUT);
  };
#else
  const Factory tao = nullptr;
#endif
  const char* const tao_missing = "install libpetsc-real-dev and rebuild: the petsc engine (hemicontact-mpi)";
  // ssn runs in both engines, outside the NLP interface (ContactSolver runs it): listed, and
  // refused as an NLP backend (minima's backend switch).
  r.push_back({SSN_BACKEND, SSN_BACKEND,
               "semismooth Newton on the unsmoothed statuses in the full space: cholmod engine with a CHOLMOD "
               "factorization per status change; petsc engine (its default) with CG + GAMG",
               "", [](const std::string&) -> std::unique_ptr<NlpBackend> {
                 throw Error("backend 'ssn' is the full-space exact solver, not an NLP backend: give it as "
                             "solver.backend = ssn (--backend ssn) of a solve",
                             EXIT_INPUT);
               }});
  r.push_back({"tao:bnls", "tao:bnls",
               "petsc engine (solver.engine = petsc, MPI): TAO bounded Newton line search, CG + BoomerAMG",
               tao_missing, tao});
  r.push_back({"tao:bntr", "tao:bntr", "petsc engine (MPI): TAO bounded Newton trust region, CG + BoomerAMG",
               tao_missing, tao});
  r.push_back({"tao:bntl", "tao:bntl",
               "petsc engine (MPI): TAO bounded Newton trust region with line search, CG + BoomerAMG", tao_missing,
               tao});

  // "auto" (solver.backend's default): Ipopt, the design's backend, where it was compiled in, else
  // our own Newton; listed first in `hemicontact backends`.
#if HEMICONTACT_HAS_IPOPT
  const char* const auto_doc =
      "the default: ipopt; under auto the backend's stage is skipped where the inner problem is strongly "
      "convex (unique minimizer), and the report says so; name a backend to run it always";
#else
  const char* const auto_doc =
      "the default: newton (Ipopt not compiled in); under auto the backend's stage is skipped where the inner "
      "problem is strongly convex (unique minimizer), and the report says so";
#endif
  r.insert(r.begin(), Entry{AUTO_BACKEND, AUTO_BACKEND, auto_doc, "", [](const std::string&) {
                              return make_backend(HEMICONTACT_HAS_IPOPT ? "ipopt" : "newton");
                            }});
  return r;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Names match case-insensitively ("IPOPT", "nlopt:ld_mma"): the factory reads the suffix as given.
bool matches(const Entry& e, const std::string& requested) {
  const std::string key = lower(e.name), name = lower(requested);
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
    if (e.create != nullptr && e.shown_name != nullptr) out.emplace_back(e.shown_name, e.description);
  return out;
}

}  // namespace hemicontact
