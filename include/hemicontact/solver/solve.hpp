#pragma once
/// @file solve.hpp  The design's solve: min Π_λ subject to u_ν ≤ g, smoothed, handed to an NLP
/// backend, inside the outer fixed point λ_i = F_b(u_ν,i) (docs/model.md §2), then the exact solver.
/// ContactSolver::solve() is this, one named step per line (src/solver/solve.cpp). The default path
/// (solver.backend = auto, solver.exact.enabled, the condensed formulation of a linear material):
///
///   set-up (constructor): condense onto Γ3 (one CHOLMOD factorization), the smallness condition
///                (21), whether Φ_λ is strongly convex (λ_min(S − αW_ν) > 0), the ε schedule
///   exact_first: Φ_λ strongly convex → no backend stage: the exact solver from the start (below;
///                solver.exact.start = always does this on any condensed problem);
///                certified → done, and the report says why the backend did not run; not certified
///                → that answer and its reason stand (solver.exact.fallback = false)
///   start:       z ← z0 projected onto the bounds; λ ← F_b(u_ν(z))
///   stage 0 (ε = solver.continuation.eps_start · U_s):                               run_stage
///     set_smoothing(ε)
///     z ← argmin Π_λ,ε by the backend (Ipopt; to solver.exact.stage_tol,
///         at most solver.exact.stage_max_iter iterations), warm-started             minimize
///     λ ← (1−θ)λ + θ F_b(u_ν(z))   (one lagged update on a coarse stage; θ =
///                                  solver.fixed_point.relaxation, 1)                relax_lambda
///   hand over (after stage 0, solver.exact.after_stage; also when the backend stalls): exact_due
///     the polish on the stage's statuses, if that is certified → done ("ipopt+polish"); else
///     exact_solve ("ipopt+exact"), from z, no smoothing:
///       repeat: inner solve   x ← argmin Φ_λ exactly (sweeps + active-set Newton)  exact_inner_solve
///               stop test     coupled residual (λ = F_b(u_ν)) ≤ solver.exact.tol, or at its
///                             round-off floor below check.certificate_tol          exact_converged
///               Anderson      λ ← Anderson mixing of λ and F_b(u_ν(x))             anderson_relax
///   polish:      the unsmoothed conditions of (22) on the identified statuses (polish.hpp), kept
///                only if the statuses hold and the certificate is not worse; skipped where the
///                coupled residual is at round-off already (solver.exact.polish_above)
///   certify:     the certificate of u (docs/model.md §4) decides; timings and the verdict
///   last resort: not certified after a hand-over → the exact solver from the start; kept only
///                if certified
///
/// Off the default path: solver.exact.enabled = false runs every stage of the continuation (ε large
/// → small, warm-started; at the final ε the fixed point until ‖Δz_Γ3‖/‖z_Γ3‖ ≤ tol_u and
/// ‖Δλ‖/‖λ‖ ≤ tol_u, or the cap / the non-contraction test stops it with a message naming the
/// remedy), then the polish and the certificate; a stage that barely moved the answer
/// (solver.continuation.certify_below) tries the polish and ends there when it is certified. The
/// full formulation (a nonlinear material) has no exact solver and no polish: the continuation, then
/// the certificate. A named backend (--backend) always runs its first stage.
///
/// Every minimization is recorded with its solver (OuterIteration::solver): reports count the
/// backend's own work apart from the exact solver's (Solution::work_of, solved_by).
/// Skipped when not needed (and said so in the report): no friction or F_b independent of u_ν →
/// no outer loop; no soft layer → no j_ν term; g = ∞ → no bounds; nothing to smooth → no continuation.

#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <string>

#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hemicontact {

struct NodalDofs;

/// The solver, set up once per model (backend, formulation: factorization and condensation,
/// smallness condition, continuation schedule) and run from any number of starting points —
/// the factorization is reused across outer iterations, ε-steps and starts.
class ContactSolver {
 public:
  /// @throws Error for bad options (unknown backend, condensed formulation with a nonlinear material).
  ContactSolver(const Model& model, const SolveOptions& options);
  ~ContactSolver();
  ContactSolver(const ContactSolver&) = delete;
  ContactSolver& operator=(const ContactSolver&) = delete;
  /// Solve from @p z0 (solver unknowns; nullptr: zero), projected onto the bounds first.
  Solution solve(const Vec* z0 = nullptr);
  /// @return the number of solver unknowns (condensed: d per Γ3 node; full: all free dofs).
  Index size() const;
  /// @return "condensed", "full", or empty for a linear solve.
  const std::string& formulation() const;
  /// @return U_s, the length that sets the smoothing widths (solver.eps_nu · U_s, ...): the
  /// unconstrained elastic solution's largest |z|, or solver.x_scale; 0 where the solver has none
  /// (the full formulation's ssn factorizes no elastic solution at its set-up, and runs with 1).
  double length_scale() const;
  /// @return the solver unknowns of a reduced vector x (its Γ3 tail when condensed).
  Vec to_unknowns(const Vec& x) const;
  /// @return where each Γ3 node's (ν, τ) unknowns are in the solver unknowns.
  const NodalDofs& contact_dofs() const;
  /// The lagged problem's energy at a solution, for second-order checks (studies/minima.hpp).
  struct LaggedEnergy {
    const NlpObjective& f;  ///< Π_λ,ε in solver unknowns (unscaled), final widths, λ frozen at z
    Vec z;                  ///< the solution in solver unknowns
    const NodalDofs& nd;    ///< where each Γ3 node's (ν, τ) unknowns are in z
  };
  /// Set the final smoothing widths, freeze λ_i = F_b(u_ν,i) at @p sol, and return that energy.
  /// Not for a linear solve (formulation() empty).
  LaggedEnergy lagged_energy(const Solution& sol);
  /// Switch the NLP backend, keeping the factorization and everything else (minima over backends).
  void set_backend(const std::string& name);
  /// Switch solver.exact.start ("auto", "convex", "always", "never"), keeping the factorization: minima
  /// runs the exact solver's own path from zero beside the design's (a default solve's answers).
  void set_exact_start(const std::string& when);
  /// Evaluate the smallness condition (21) for the model as the constructor does when
  /// check.smallness is on: from this solver's condensation (the bracket, no factorization) when
  /// there is one and check.smallness_method = auto in 2D, exactly otherwise. For callers that
  /// decide only after the solve whether they want it (the adaptive loop's final mesh).
  SmallnessReport smallness() const;
  /// Solve from now on for loads @p s × the original model's, keeping the factorization: only
  /// y = K⁻¹f scales. @p scaled is the original model with f, fx scaled by s (the certificate is
  /// evaluated on it); it must outlive the solves. Used by load paths.
  void set_loads(const Model& scaled, double s);

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

/// Solve the model. Never throws for non-convergence: the verdict is in the Solution.
/// @throws Error for bad options (unknown backend, ...).
Solution solve(const Model& model, const SolveOptions& options);

}  // namespace hemicontact
