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
/// coupling converges linearly, as the fixed point does, until the statuses cycle: then the
/// globalization below takes it in). The answer is judged by the certificate.

#include <hemicontact/problem/model.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

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

/// ssn's globalization (both engines). Plain ssn takes full steps: fast where it converges, but on
/// some scenes its statuses cycle for ever (random scene 152: slip reversals of neighbouring Γ3
/// nodes taking turns with period 2; held longer at stick, a node switching between separated and
/// sliding, its F_b(x_ν) on and off, with period 3). Measured on the 1000 random scenes
/// (docs/performance.md), a line search from the first step slowed a tenth of the scenes and lost
/// some plain ssn certified; so the globalization waits for the cycle itself: once a status
/// signature seen in the last SSN_CYCLE_MEMORY steps comes back (SsnCycleWatch), every later step
///  - is shortened by backtracking (ssn_step_length) on the merit ‖·‖∞ of the true semismooth
///    residual (check/status_equations.hpp's ssn_node_merit on Γ3, K x − f elsewhere), and
///  - takes the slip force's dependence on x_ν into the Newton matrix (ssn_coupling, w F_b'(x_ν) t):
///    with λ held, the coupling converges linearly at ~0.5 per step (seed 152 with the line search
///    alone: 50 steps), with it quadratically (15 steps in all, the first 8 plain before the cycle
///    shows). That column is unsymmetric, so those steps use GMRES (the cholmod
///    engine: preconditioned by the factor of the symmetric part; the petsc engine: by its AMG).
/// A run that never revisits a signature is plain ssn, step for step.
inline constexpr int SSN_CYCLE_MEMORY = 3;  ///< steps back a repeated status signature is looked for
inline constexpr double SSN_ARMIJO = 1e-4;  ///< sufficient decrease: merit(θ) < (1 − SSN_ARMIJO θ) merit(0)
inline constexpr int SSN_HALVINGS = 5;      ///< θ = 1, ½, …, 1/16 tried; 1/32 taken if none decreases
/// F_b's slope probe for the coupling column (ssn_coupling's central difference): this × ‖x‖∞, the
/// polishes' 1e-7 of the length scale (F_b is piecewise linear: exact up to round-off off a kink).
inline constexpr double SSN_SLOPE_PROBE = 1e-7;

/// One node's part of a step's status signature: the signatures of the nodes (and of the ranks)
/// are summed, so the sum does not depend on their order or partition. A hash of (node, code).
uint64_t ssn_node_signature(Index node, int code);

/// Watches the status signatures step by step; cycling() is true from the first step whose statuses
/// changed to a signature seen in the SSN_CYCLE_MEMORY steps before it, and stays true.
class SsnCycleWatch {
 public:
  /// @param signature this step's (the sum of ssn_node_signature) @param changed status changes
  void see(uint64_t signature, long changed);
  bool cycling() const { return m_cycling; }

 private:
  std::vector<uint64_t> m_recent;
  bool m_cycling = false;
};

/// The backtracking rule: the first θ = 1, ½, …, 2^−(SSN_HALVINGS−1) with
/// merit_at(θ) < (1 − SSN_ARMIJO θ) @p merit_now, else 2^−SSN_HALVINGS.
double ssn_step_length(double merit_now, const std::function<double(double)>& merit_at);

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
