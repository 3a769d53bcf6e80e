#pragma once
/// @file backend_factories.hpp  Private factories of the compiled-in NLP backends.
///
/// Only src/nlp/make_backend.cpp (the registry) calls these. Each factory is declared only when its
/// backend is compiled in, so a missing optional dependency is a compile-time absence, never a
/// link error; make_backend() turns the absence into a clear "not compiled in" Error instead.
/// No Ipopt/NLopt header is included here: optional dependencies stay PRIVATE to their backend's
/// source, so that nothing else needs them to compile.

#include <hemicontact/config.hpp>
#include <hemicontact/nlp/backend.hpp>

#include <memory>
#include <string>
#include <vector>

namespace hemicontact {

#if HEMICONTACT_HAS_IPOPT
/// @brief Create the Ipopt interior-point backend (src/nlp/ipopt_backend.cpp).
/// @return a backend named "ipopt"; it keeps the bound multipliers of its last successful
///         solve for warm starts, so reuse one object across a fixed-point loop.
std::unique_ptr<NlpBackend> make_ipopt_backend();
#endif

/// @brief Create the projected Newton / active-set backend (src/nlp/newton_backend.cpp); always
///        compiled, it needs only CHOLMOD.
/// @return a backend named "newton"; it keeps CHOLMOD's symbolic analysis while the Hessian
///         pattern is unchanged, so reuse one object across a continuation.
std::unique_ptr<NlpBackend> make_newton_backend();

#if HEMICONTACT_HAS_NLOPT
/// One NLopt algorithm offered as the backend "nlopt:<name>" (src/nlp/nlopt_backend.cpp).
struct NloptAlgorithmInfo {
  const char* backend_name;  ///< "nlopt:" + NLopt's name without NLOPT_, e.g. "nlopt:LD_LBFGS"
  const char* description;   ///< one line: local/global, bound handling, cost notes
};
/// @return every supported NLopt algorithm, in the order `hemicontact backends` lists them.
const std::vector<NloptAlgorithmInfo>& nlopt_backend_catalog();
/// @brief Create an NLopt backend (src/nlp/nlopt_backend.cpp).
/// @param algorithm the part after "nlopt:": a name from nlopt_backend_catalog(), or
///        "G_MLSL_LDS+LD_MMA" (a global search with its local algorithm).
/// @throws Error naming the algorithm if it is unknown or refused (no gradient, no bounds, ...).
std::unique_ptr<NlpBackend> make_nlopt_backend(const std::string& algorithm);
#endif

}  // namespace hemicontact
