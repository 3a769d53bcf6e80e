#pragma once
/// @file ssn.hpp  The exact solver in the full space (backend "ssn" of the cholmod engine): the
/// semismooth Newton method of the petsc engine's ssn on the unsmoothed conditions of (22), every
/// status read again at each step from the iterate by check/status_equations.hpp's ssn_reading
/// (the same node rows in both engines), with a CHOLMOD factorization of the Newton matrix as the
/// linear solve (analysed once: the Γ3 blocks lie in K's pattern, and the fixed unknowns' rows and
/// columns are zeroed in place, so only the numeric factorization repeats; a step whose statuses
/// held changes J only in the slip blocks' directions, and is solved by CG with the last factor as
/// preconditioner, refactorized only if that does not converge in a few iterations). No smoothing, no
/// continuation, no outer loop: λ = F_b(x_ν) is read at every step (held in the Jacobian, so the
/// coupling converges linearly, as the fixed point does). The answer is judged by the certificate.

#include <hemicontact/problem/model.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace hemicontact {

/// The stop rules of ssn, from the options both engines read (SolveOptions::ssn, whose
/// solver.ssn.max_iters and solver.ssn.tol are documented there and in the scene schema).
struct SsnLimits {
  int max_iters = 0;  ///< Newton steps (solver.ssn.max_iters)
  double tol = 0;     ///< converged without a step: statuses held and ‖rhs‖∞/F ≤ tol (solver.ssn.tol)
  /// A step whose statuses held is solved by CG preconditioned with the last factorization, to
  /// this relative residual (solver.petsc.ksp_rtol, as the petsc engine's steps there).
  double rtol = 0;
  /// The Newton matrices' fill-reducing ordering (solver.ordering; fem/sparse_cholesky.hpp).
  std::string ordering = "auto";
};

/// ssn's own stop after a step: the statuses have held for two steps and the step reached round-off
/// (1e-14 relative), or stopped decreasing near it (below 1e-10 and no smaller than the last).
inline bool ssn_step_settled(int unchanged, double rel, double step, double prev_step) {
  return unchanged >= 2 && (rel <= 1e-14 || (rel <= 1e-10 && step >= prev_step));
}

/// What a run of ssn gives.
struct SsnOutcome {
  Vec x;                  ///< the reduced unknowns
  bool converged = false;
  int steps = 0;          ///< Newton steps taken
  std::string message;    ///< why it stopped
  nlohmann::json record = nlohmann::json::array();  ///< per step: status changes, residual, step
  double seconds = 0;
};

/// Run ssn on the model's reduced system (K_x, f_x; a linear material) from @p x0 (reduced
/// unknowns; nullptr: zero).
SsnOutcome ssn_full(const Model& md, const SsnLimits& limits, const Vec* x0);

}  // namespace hemicontact
