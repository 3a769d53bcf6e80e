#pragma once
/// @file backend_factories.hpp  Private factories of the compiled-in NLP backends.
///
/// Only src/nlp/make_backend.cpp (the registry) calls these. Each factory is declared only when its
/// backend is compiled in, so a missing optional dependency is a compile-time absence, never a
/// link error; make_backend() turns the absence into a clear "not compiled in" Error instead.
/// No Ipopt/NLopt header is included here (optional dependencies stay PRIVATE, STYLE.md §1).

#include <hemicontact/config.hpp>
#include <hemicontact/nlp/backend.hpp>

#include <memory>
#include <string>

namespace hemicontact {

#if HEMICONTACT_HAS_IPOPT
/// @brief Create the Ipopt interior-point backend (src/nlp/ipopt_backend.cpp).
/// @return a backend named "ipopt"; it keeps the bound multipliers of its last successful
///         solve for warm starts, so reuse one object across a fixed-point loop.
std::unique_ptr<NlpBackend> make_ipopt_backend();
#endif

// [newton] Declared here by the Newton backend work (always compiled: it needs only CHOLMOD):
//   /// @brief Create the projected/active-set Newton backend (src/nlp/newton_backend.cpp).
//   std::unique_ptr<NlpBackend> make_newton_backend();

// [nlopt:ALGO] Declared here by the NLopt backend work:
//   #if HEMICONTACT_HAS_NLOPT
//   /// @brief Create an NLopt backend; @param algorithm the part after "nlopt:", e.g. "LD_LBFGS".
//   std::unique_ptr<NlpBackend> make_nlopt_backend(const std::string& algorithm);
//   #endif

}  // namespace hemicontact
