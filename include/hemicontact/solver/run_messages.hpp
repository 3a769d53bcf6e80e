#pragma once
/// @file run_messages.hpp  The messages both engines (solver/solve.cpp, the petsc engine) end a run
/// with, written once so that their reports say the same thing in the same words.

#include <hemicontact/core/format.hpp>
#include <hemicontact/problem/solution.hpp>

#include <string>

namespace hemicontact {

/// @return the stop message of a minimization that failed: the backend, the outer iteration, the
/// backend's status and its own message.
inline std::string backend_failure(const std::string& backend, const OuterIteration& rec) {
  return "backend " + backend + " failed at outer iteration " + std::to_string(rec.k) + ": " +
         to_string(rec.backend.status) + " (" + rec.backend.message + ")";
}

/// The verdict once the certificate is in (sol.certificate): a backend failure that the certificate
/// overrules says so, and a run without a stop message gets "converged" with the certificate's word.
inline void state_verdict(Solution& sol) {
  if (!sol.backend_ok && sol.certificate.passed)
    sol.message += "; the certificate passed all the same (max residual " + fmt(sol.certificate.max_residual, 3) +
                   "), so the answer is accepted";
  if (sol.message.empty())
    sol.message = sol.certificate.passed ? "converged; certificate passed"
                                         : "converged, but the certificate failed (max residual " +
                                               fmt(sol.certificate.max_residual, 3) + ")";
}

}  // namespace hemicontact
