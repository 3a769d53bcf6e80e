#pragma once
/// @file solve.hpp  The design's solve: min Π_λ subject to u_ν ≤ g, smoothed, handed to an NLP
/// backend, with ε-continuation and the outer fixed point λ_i = F_b(u_ν,i) (MODEL.md §2).
///
///   for ε in the continuation schedule (large → small, warm-started):
///     repeat: freeze λ ← (1−θ)λ + θ F_b(u_ν); x ← argmin Π_λ,ε (backend, warm start)
///     — once per coarse ε, until ‖Δx_Γ3‖/‖x_Γ3‖ ≤ tol_u and ‖Δλ‖/‖λ‖ ≤ tol_u at the final ε.
/// Skipped when not needed (and said so in the report): no friction or F_b independent of u_ν →
/// no outer loop; no soft layer → no j_ν term; g = ∞ → no bounds; nothing to smooth → no continuation.

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
  /// @return the solver unknowns of a reduced vector x (its Γ3 tail when condensed).
  Vec to_unknowns(const Vec& x) const;
  /// @return the smoothed energy Π_λ,ε in solver unknowns (unscaled); its λ and ε are whatever the
  /// last solve or set_eps()/freeze_friction() left.
  const NlpObjective& energy() const;
  /// @return where each Γ3 node's (ν, τ) unknowns are in the solver unknowns.
  const NodalDofs& contact_dofs() const;
  /// @return the upper bounds (g_i on the ν unknowns, +inf elsewhere).
  const Vec& upper_bounds() const;
  /// Set the smoothing widths (relative to the displacement scale) of energy().
  void set_eps(double eps_tau, double eps_nu);
  /// Freeze λ_i = F_b(u_ν,i) at solver unknowns @p z in energy().
  void freeze_friction(const Vec& z);
  /// Switch the NLP backend, keeping the factorization and everything else (minima over backends).
  void set_backend(const std::string& name);
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

/// @return the geometric mean of the defined contraction factors ρ_k of @p history (NaN if none).
double contraction_estimate(const std::vector<OuterIteration>& history);

/// Unsmoothed energy parts and certificate of a given full displacement (fills the Solution's
/// state, status, certificate and energies).
void evaluate_solution(const Model& model, const SolveOptions& options, Solution& sol);

}  // namespace hemicontact
