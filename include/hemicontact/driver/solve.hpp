#pragma once
/// @file solve.hpp  The design's solve: min Π_λ subject to u_ν ≤ g, smoothed, handed to an NLP
/// backend, with ε-continuation and the outer fixed point λ_i = F_b(u_ν,i) (MODEL.md §2).
///
///   for ε in the continuation schedule (large → small, warm-started):
///     repeat: freeze λ ← (1−θ)λ + θ F_b(u_ν); x ← argmin Π_λ,ε (backend, warm start)
///     — once per coarse ε, until ‖Δx_Γ3‖/‖x_Γ3‖ ≤ tol_u and ‖Δλ‖/‖λ‖ ≤ tol_u at the final ε.
/// Skipped when not needed (and said so in the report): no friction or F_b independent of u_ν →
/// no outer loop; no soft layer → no j_ν term; g = ∞ → no bounds; nothing to smooth → no continuation.

#include <hemicontact/check/certificate.hpp>
#include <hemicontact/check/smallness.hpp>
#include <hemicontact/driver/model.hpp>
#include <hemicontact/nlp/backend.hpp>

#include <string>

namespace hemicontact {
/// What the exact polish (driver/polish.hpp) did.
struct PolishResult {
  bool attempted = false;  ///< false without a condensation or with nothing to polish
  bool accepted = false;   ///< statuses kept and certificate not worse
  int iterations = 0;      ///< 2D: λ fixed-point iterations on the linear status system; 3D: Newton steps
  double before = 0;       ///< certificate max residual before
  double after = 0;        ///< after (of the candidate)
  std::string note;        ///< why not accepted, if not
};
}  // namespace hemicontact

#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hemicontact {

/// Solver settings, read from the scene's "solver", "check" blocks (defaults live in the schema).
struct SolveOptions {
  std::string backend = "ipopt";   ///< NLP backend name
  std::string formulation = "auto";  ///< "full", "condensed" or "auto" (condensed for linear materials)
  bool polish = true;              ///< exact polish on identified statuses (condensed formulation)
  BackendOptions backend_options;  ///< tolerance, iteration cap, pass-through options
  double eps_tau = 1e-10;          ///< final friction smoothing width, relative to U_s
  double eps_nu = 1e-10;           ///< final mollification width of p_ν, relative to U_s
  double eps_start = 1e-2;         ///< first continuation width, relative to U_s
  double eps_factor = 1e-2;        ///< ε multiplied by this per continuation step
  double tol_u = 1e-12;            ///< fixed point: relative change of x on Γ3 and of λ
  int max_outer = 50;              ///< fixed point: iteration cap
  double relaxation = 1.0;         ///< θ in λ ← (1−θ)λ + θ F_b(u_ν)
  /// Fixed-point updates ‖Δλ‖∞ at or below this × ‖λ‖∞ are the inner solves' round-off (backend
  /// tol 1e-12 on O(1) scaled unknowns), not the map's contraction: they enter no ratio ρ_k.
  double contraction_floor = 1e-9;
  /// Non-contraction: the update ‖Δλ‖∞ has not shrunk by this factor for `stall_iters`
  /// consecutive outer iterations (ρ_k > stall_ratio) → stop and say so.
  double stall_ratio = 0.99;
  int stall_iters = 5;             ///< see stall_ratio
  bool allow_not_converged = false;  ///< exit 0 even if the fixed point did not converge
  double certificate_tol = 1e-8;   ///< acceptance tolerance of the certificate
  double status_tol = 1e-8;        ///< status decisions, relative to U
  bool smallness = true;           ///< evaluate the smallness condition (21)
};

/// @return the options of an effective scene.
SolveOptions solve_options_from_scene(const nlohmann::json& scene);

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
  SolveResult backend;       ///< what the backend said
};

/// Everything a solve produces; writers take it read-only.
struct Solution {
  Vec x;                             ///< reduced unknowns (unscaled)
  Vec u;                             ///< full displacement
  ContactState state;                ///< Γ3 quantities
  std::vector<NodeStatus> status;    ///< per Γ3 node
  CertificateReport certificate;     ///< MODEL.md §4
  double energy = 0;                 ///< Π = ∫W(ε(u)) − f(u) + Σ w j_ν(u_ν) + Σ w F_b(u_ν)|u_τ| (unsmoothed; ∫W = ½a(u,u) if linear)
  double energy_norm = 0;            ///< sqrt(a(u,u))
  double a_uu = 0, f_u = 0, j_term = 0, friction_term = 0;  ///< the parts of energy
  /// ∫ W(ε(u)), the elastic part of energy: ½ a_uu for a linear F; for a nonlinear F, a_uu and
  /// energy_norm use the small-strain stiffness K(0) (an equivalent norm), this the true W.
  double elastic_energy = 0;
  double max_u_nu = 0;               ///< max_i u_ν,i
  std::vector<OuterIteration> history;  ///< every minimization
  bool fixed_point_converged = true; ///< false if the outer loop hit its cap or stalled
  /// Estimated contraction factor of the outer fixed point: the geometric mean of the defined
  /// ρ_k (OuterIteration::contraction); NaN if none is defined (no loop, or converged at once).
  double contraction_estimate = std::numeric_limits<double>::quiet_NaN();
  bool backend_ok = true;            ///< false if the last minimization failed
  std::string message;               ///< human-readable verdict
  std::string backend;               ///< backend name
  std::vector<std::string> skipped;  ///< what was not needed and not done
  std::string formulation;           ///< "full" or "condensed" (empty for a linear solve)
  PolishResult polish;               ///< what the exact polish did
  SmallnessReport smallness;         ///< the smallness condition (21)
  double start_energy = 0;           ///< smoothed energy at the start (first ε, λ frozen there)
  double x_scale = 1, f_scale = 1;   ///< the nondimensionalization used
  std::map<std::string, double> timings;  ///< seconds
  /// @return true when the answer is accepted: the outer fixed point converged and the certificate
  /// passed. A backend's own failure status does not decide (issue: "the certificate decides").
  bool ok() const { return fixed_point_converged && certificate.passed; }
  /// @return status counts keyed separated, compliance, contact, stick, slip+, slip- (and slip in 3D).
  std::map<std::string, int> status_counts() const;
};

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
