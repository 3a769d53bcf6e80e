#pragma once
/// @file solution.hpp  Everything a solve produces, passed read-only to the checks' callers, the
/// studies and the writers: the displacement, the Γ3 state and statuses, the certificate, the
/// energies, the history of every minimization and the timings.

#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/problem/contact_state.hpp>
#include <hemicontact/problem/reports.hpp>

#include <limits>
#include <map>
#include <string>
#include <vector>

namespace hemicontact {

/// One minimization inside the continuation / fixed point.
struct OuterIteration {
  int k = 0;                 ///< running index
  int stage = 0;             ///< continuation stage
  double eps_tau = 0;        ///< absolute ε_τ used
  double eps_nu = 0;         ///< absolute ε_ν used
  double change_u = 0;       ///< ‖Δx_Γ3‖∞/‖x_Γ3‖∞ against the previous minimization
  double change_lambda = 0;  ///< ‖Δλ‖∞/‖λ‖∞ of the update after this minimization
  double grad_norm = 0;      ///< first-order residual max_i min(|∇Π̃_i|, room to the bound) in scaled units
  double delta_lambda = 0;   ///< ‖λ^{k+1} − λ^k‖∞ of the (relaxed) update after this minimization, absolute
  /// ρ_k = ‖λ^{k+1} − λ^k‖∞ / ‖λ^k − λ^{k−1}‖∞, the observed contraction factor of the relaxed map
  /// λ ↦ (1−θ)λ + θ F_b(u_ν(λ)) at the final ε; NaN where undefined (first iteration of the final
  /// stage, coarse stages, no lagged friction, or the previous update below contraction_floor).
  double contraction = std::numeric_limits<double>::quiet_NaN();
  SolveResult backend;  ///< what the solver of this minimization said
  /// Who did this minimization: the NLP backend's name (a smoothed ε-stage), or EXACT_SOLVER (an
  /// inner solve of the exact solver, no smoothing). Reports count a backend's work from these.
  std::string solver;
};

/// OuterIteration::solver of the exact solver's inner solves (solver/exact_inner.hpp).
inline constexpr const char* EXACT_SOLVER = "exact";

/// Whether the NLP backend ran, and why not when it did not: what a report says of it.
struct BackendUse {
  std::string requested;  ///< solver.backend as given ("auto" or a name)
  bool ran = false;       ///< at least one smoothed minimization by the backend
  std::string not_run;    ///< why it did not run (empty when it ran)
};

/// The work of one solver over a solve: the backend's ε-stages, or the exact solver's inner solves.
struct SolverWork {
  int minimizations = 0;
  long long iterations = 0, evaluations = 0;
  double seconds = 0;
};

/// Everything a solve produces; writers take it read-only.
struct Solution {
  /// The plain solve's second-order verdict where other certified solutions may exist
  /// (output/report.hpp's uniqueness_warning; studies/scene_solve.cpp runs the check of
  /// `minima`); "unchecked" otherwise.
  SecondOrderCheck second_order;
  Vec x;                           ///< reduced unknowns (unscaled)
  Vec u;                           ///< full displacement
  ContactState state;              ///< Γ3 quantities
  std::vector<NodeStatus> status;  ///< per Γ3 node
  /// The statuses counted over the whole model (on the petsc engine's pieces: over every rank's
  /// owned nodes, where `status` holds the piece's nodes only).
  StatusCounts counts{};
  CertificateReport certificate;   ///< docs/model.md §4
  double energy = 0;  ///< Π = ∫W(ε(u)) − f(u) + Σ w j_ν(u_ν) + Σ w F_b(u_ν)|u_τ| (unsmoothed; ∫W = ½a(u,u) if linear)
  double energy_norm = 0;                                   ///< sqrt(a(u,u))
  double a_uu = 0, f_u = 0, j_term = 0, friction_term = 0;  ///< the parts of energy
  /// ∫ W(ε(u)), the elastic part of energy: ½ a_uu for a linear F; for a nonlinear F, a_uu and
  /// energy_norm use the small-strain stiffness K(0) (an equivalent norm), this the true W.
  double elastic_energy = 0;
  double max_u_nu = 0;                  ///< max_i u_ν,i
  std::vector<OuterIteration> history;  ///< every minimization
  bool fixed_point_converged = true;    ///< false if the outer loop hit its cap or stalled
  /// Estimated contraction factor of the outer fixed point: the geometric mean of the defined
  /// ρ_k (OuterIteration::contraction); NaN if none is defined (no loop, or converged at once).
  double contraction_estimate = std::numeric_limits<double>::quiet_NaN();
  bool backend_ok = true;                 ///< false if the last minimization failed
  std::string message;                    ///< human-readable verdict
  std::string backend;                    ///< the NLP backend's name (what "auto" resolved to)
  BackendUse backend_use;                 ///< requested, ran, why not
  std::vector<std::string> skipped;       ///< what was not needed and not done
  std::string formulation;                ///< "full" or "condensed" (empty for a linear solve)
  MethodChoice method_choice;             ///< how formulation (and the auto backend) was chosen, and why
  PolishResult polish;                    ///< what the exact polish did
  HandoverReport handover;                ///< the exact solver's part
  InnerConvexity inner_convexity;         ///< is the inner problem (λ frozen) strongly convex?
  SmallnessReport smallness;              ///< the smallness condition (21)
  double start_energy = 0;                ///< smoothed energy at the start (first ε, λ frozen there)
  double x_scale = 1, f_scale = 1;        ///< the nondimensionalization used
  std::map<std::string, double> timings;  ///< seconds
  /// @return true when the answer is accepted: the outer fixed point converged and the certificate
  /// passed. A backend's own failure status does not decide: the certificate does.
  bool ok() const { return fixed_point_converged && certificate.passed; }
  /// @return the work of the minimizations in history whose solver is @p solver.
  SolverWork work_of(const std::string& solver) const;
  /// @return a short label of what produced the answer, for tables and progress lines: e.g.
  /// "ipopt+exact" (the backend's ε-stages, then the exact solver), "exact" (the backend not run),
  /// "ipopt+polish" (the backend, then the polish on its statuses), "ipopt" (the backend alone),
  /// "linear".
  std::string solved_by() const;
  /// @return `counts` keyed separated, compliance, contact, stick, slip+, slip- (and slip in 3D).
  std::map<std::string, int> status_counts() const;
};

}  // namespace hemicontact
