#pragma once
/// @file reports.hpp  The records the checks and the polish leave on a solution: the certificate
/// (docs/model.md §4, check/certificate.hpp), the smallness condition (21) (check/smallness.hpp) and
/// the exact polish (solver/polish.hpp). Plain data; the writers read them.

#include <hemicontact/core/types.hpp>

#include <map>
#include <string>
#include <vector>

namespace hemicontact {

/// One residual of the certificate.
struct CertificateResidual {
  std::string name;  ///< "feasibility", "normal", "complementarity", "friction_cone", "slip_direction", "equilibrium"
  double value = 0;  ///< normalized max over nodes/dofs
  Index worst = -1;  ///< contact node (or dof for equilibrium) where it is attained
};

/// The certificate of a displacement.
struct CertificateReport {
  std::vector<CertificateResidual> residuals;  ///< in the order listed in the file comment
  double max_residual = 0;                     ///< max over residuals
  double tol = 0;                              ///< acceptance tolerance (check.certificate_tol)
  bool passed = false;                         ///< max_residual <= tol
  double length_scale = 0;                     ///< U
  double force_scale = 0;                      ///< F
  double traction_scale = 0;                   ///< S
};

/// The terms of (21).
struct SmallnessReport {
  bool computed = false;  ///< false when there is no Γ3 or nothing nonconvex/nonmonotone to check
  double m_F = 0;         ///< (12)(b)
  double L_Fb = 0;        ///< (15)(a); 0 without friction; +inf for a discontinuous F_b
  double alpha_j = 0;     ///< (13)(d); 0 without layer; +inf for a downward jump of p_ν
  double lambda_1 = 0;    ///< λ_{1,ν}: smallest eigenvalue with ∫Γ3 u·v
  double lambda_1nu = 0;  ///< λ_{1ν,ν}: smallest eigenvalue with ∫Γ3 u_ν v_ν
  double lhs = 0;         ///< L_Fb/λ_{1,ν} + α_jν/λ_{1ν,ν}
  bool holds = false;     ///< lhs < m_F: uniqueness guaranteed
  double seconds = 0;     ///< time to compute
  /// "exact": λ's from the ε:ε Gram matrix (one more factorization); "bound": decided by the
  /// bracket below without it (lambda_1, lambda_1nu, lhs are then the bounds that decided:
  /// the lower bounds of λ and the upper bound of lhs when (21) holds, the other ones when not).
  std::string method;
  double lhs_lower = 0;  ///< bracket of lhs from the condensed stiffness (equal to lhs when exact)
  double lhs_upper = 0;  ///< (see lhs_lower)
  /// How the eigenvalues were obtained when not from a dense matrix (Lanczos on the solver's own
  /// factor above check.dense_max_unknowns), or why (21) was not decided; empty otherwise.
  std::string note;
};

/// What the exact polish (solver/polish.hpp) did.
struct PolishResult {
  bool attempted = false;  ///< false without a condensation or with nothing to polish
  bool accepted = false;   ///< statuses kept and certificate not worse
  int iterations = 0;      ///< 2D: λ fixed-point iterations on the linear status system; 3D: Newton steps
  double before = 0;       ///< certificate max residual before
  double after = 0;        ///< after (of the candidate)
  std::string note;        ///< why not accepted, if not
};
/// Whether the inner problem Φ_λ (solver/exact_inner.hpp) is strongly convex: the smallest
/// eigenvalue of S − α W_ν, the condensed Hessian of the convex part minus the softening of j_ν
/// (α = the one-sided Lipschitz constant of ∂j_ν, (13)(d), W_ν = the weights on the normal rows),
/// is positive. The friction term and the bound are convex and do not enter.
struct InnerConvexity {
  bool checked = false;         ///< false: not evaluated (note says why)
  bool strongly_convex = false;  ///< min_eigenvalue > 0
  double softening = 0;         ///< α_jν (+inf for a downward jump of p_ν)
  /// λ_min(S − α W_ν) (−inf for a downward jump). Above check.dense_max_unknowns (note says
  /// "Lanczos") it is λ_min(W^-1/2 S_ν W^-1/2) − α instead, S_ν the Schur complement of S onto the
  /// normal unknowns: the same sign (S − αW_ν ≻ 0 ⟺ S_ν − αW ≻ 0), without a dense matrix.
  double min_eigenvalue = 0;
  std::string note;             ///< how it was decided
};

/// How solver.formulation (and, with it, the backend under solver.backend = auto) was chosen:
/// from the scene's own numbers before any numeric work (solver/method_choice.hpp), or as given.
struct MethodChoice {
  std::string chosen;   ///< "condensed" or "full" (empty: a linear solve, nothing to choose)
  std::string backend;  ///< the backend auto resolves to with this choice ("" : the engine's default)
  bool automatic = false;  ///< chosen by solver.formulation = auto (false: set explicitly)
  std::string reason;      ///< why, with the deciding numbers in words
  std::map<std::string, double> numbers;  ///< what it decided on (dofs, Γ3 unknowns, flops, bytes, ...)
};

/// The hand-over from the smoothed continuation to the exact inner solver (solver/exact_inner.hpp).
struct HandoverReport {
  bool used = false;           ///< the exact solver produced the answer
  int after_stage = -1;        ///< continuation stage after which it took over
  std::string reason;          ///< why then: statuses settled, backend stalled or failed, last stage
  int outer_iterations = 0;    ///< λ updates (Anderson-accelerated fixed point λ = F_b(u_ν))
  int inner_rounds = 0;        ///< sweep + Newton rounds, summed over the outer iterations
  int newton_steps = 0;        ///< accepted Newton steps, summed
  int factorizations = 0;      ///< reduced-Hessian factorizations, summed
  bool inner_converged = false;  ///< the last inner solve reached solver.exact.tol
  bool fixed_point_converged = false;  ///< the coupled residual (λ = F_b(u_ν)) reached solver.exact.tol
  double residual = 0;         ///< last coupled stationarity residual / traction scale
  double seconds = 0;          ///< wall time of the exact solver
  std::string note;            ///< why it stopped when not converged
};

/// Second-order check of a certified solution.
///
/// At the solution's solver unknowns z: the final smoothing widths are set and the friction
/// bounds are frozen at z (ContactSolver::lagged_energy: λ_i = F_b(u_ν,i)), and the
/// true Hessian H = ∇²Π_λ,ε(z) (Psd::NONE) is formed densely. Removed from it are
///  - ν unknowns at the bound u_ν = g (contact): with a positive rigid reaction the critical cone
///    has d_ν = 0 there; at a degenerate contact (zero reaction) removing them makes the test a
///    necessary condition only (counted in `degenerate`);
///  - τ unknowns of stick nodes with λ_i > 0: the exact |u_τ| has a kink there, and the smoothed
///    curvature 2w_iλ_i/ε_τ (smooth_norm.hpp) is an artefact of ε — huge and positive, it would
///    only inflate the scale. Strictly inside the cone (|σ_τ| < λ) the kink makes the energy grow
///    at first order in d_τ, so d_τ = 0 in the critical cone.
/// The smallest eigenvalue of what remains decides: λ_min ≥ −tol·scale → "local minimum", else
/// "saddle". Off the law's ε-windows the smoothed Hessian is the exact one (MollifiedLaw is exact
/// there); a node sitting on a downward jump of p_ν sees the mollified slope ≈ 3J/(4ε) < 0 — a
/// saddle, as it should be (j_ν has a concave kink there). With the full formulation the
/// interior unknowns are kept: by Sylvester's law the inertia is that of the condensed Hessian,
/// so the verdict is the same (the value of λ_min is not).
struct SecondOrderCheck {
  std::string verdict = "unchecked";  ///< "local minimum", "saddle" or "unchecked"
  double lambda_min = 0;              ///< smallest eigenvalue of the reduced Hessian (energy/length²)
  double scale = 0;                   ///< max_i (K_x)_ii: the largest diagonal stiffness
  Index kept = 0;                     ///< unknowns in the free subspace
  Index removed_contact = 0;          ///< ν unknowns removed at u_ν = g
  Index removed_stick = 0;            ///< τ unknowns removed at stick nodes (λ > 0)
  Index degenerate = 0;               ///< of removed_contact: zero rigid reaction (weakly active)
  std::string note;                   ///< why "unchecked", or other remarks
};

}  // namespace hemicontact
