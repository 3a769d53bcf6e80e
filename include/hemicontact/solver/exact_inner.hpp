#pragma once
/// @file exact_inner.hpp  Exact solver of the condensed inner problem with the friction bound λ
/// frozen, no smoothing:
///
///   min Φ_λ(x) = ½ (x − y)ᵀ S (x − y) + Σ_k w_k j_ν(x_ν,k) + Σ_k w_k λ_k |x_τ,k|,  x_ν,k ≤ g_k,
///
/// the discrete energy Π_λ of docs/model.md §2 after static condensation (fem/condensation.hpp; S the
/// Schur complement, y = (K⁻¹f)_C). j_ν is piecewise quadratic (p_ν piecewise linear, eqs. (32),
/// (33), with kinks and jumps), the friction term is a weighted norm, the bound a box: the
/// optimality system is piecewise linear (2D) or piecewise smooth (3D, the disk |σ_τ| ≤ λ).
///
/// Two kinds of steps, both exact on the unsmoothed Φ_λ and both monotone in Φ_λ:
///  * proximal coordinate steps: node by node, the exact global minimizer of Φ_λ along the normal
///    unknown (a 1-D piecewise quadratic on (−∞, g], minimized piece by piece, breakpoints included:
///    the exact proximal map of j_ν plus the indicator of x_ν ≤ g), then along the tangential
///    unknown(s) (2D: the soft threshold, the exact proximal map of w λ |·|; 3D: a proximal-gradient
///    step on the 2×2 tangential block with the disk shrink, majorized by its largest eigenvalue).
///    They fix the statuses: exact zeros for sticking nodes, exact g for contact, exact
///    breakpoints where a node sits on a kink or a jump of p_ν.
///  * active-set Newton steps on the statuses the last sweep identified: pinned unknowns (x_ν = g,
///    x_ν at a breakpoint, x_τ = 0 sticking, rollers) are held, p_ν is affine on each node's piece,
///    slipping nodes carry −σ_τ = λ t (eq. (6)): in 2D a linear system, solved in one step; in 3D
///    the exact Jacobian of t = x_τ/|x_τ|, (I − t tᵀ)/|x_τ|. The step is taken with a backtracking
///    search on Φ_λ (exact), projected on x_ν ≤ g. In 2D the factorization of the reduced Hessian
///    is kept while the pinned set and the slopes of p_ν stay the same.
///
/// It stops when the stationarity residual of Φ_λ (the certificate of docs/model.md §4 with λ held
/// fixed, in the certificate's traction units) is at most ExactInnerOptions::tol. From any start
/// the energy decreases monotonically; for a strongly convex Φ_λ (see inner_convexity) the
/// minimizer is unique and the sweeps alone converge to it, Newton only makes it fast.

#include <hemicontact/contact/piecewise_linear_law.hpp>
#include <hemicontact/core/types.hpp>
#include <hemicontact/problem/reports.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <memory>
#include <string>
#include <vector>

namespace hemicontact {

// ExactInnerOptions (the settings) live in problem/solve_options.hpp, beside every other setting.

/// The condensed inner problem with frozen λ (file comment). Pointers are borrowed.
struct ExactInnerProblem {
  const Mat* S = nullptr;                  ///< Schur complement, m×m SPD
  Vec y;                                   ///< unconstrained minimizer y_C (loads included)
  int d = 2;                               ///< space dimension: node k owns x[d k .. d k + d − 1], ν first
  Vec w;                                   ///< nodal quadrature weights w_k
  Vec g;                                   ///< gaps g_k (+inf: no obstacle)
  Vec lambda;                              ///< frozen friction bounds λ_k ≥ 0
  const PiecewiseLinearLaw* law = nullptr;  ///< exact p_ν; null: no soft layer (j_ν = 0)
  std::vector<unsigned> fixed;             ///< per node, bit c set: local unknown c held at 0 (roller)
  double traction_scale = 1;               ///< the certificate's traction scale (docs/model.md §4)
};

/// What the exact inner solve did.
struct ExactInnerResult {
  bool converged = false;   ///< residual ≤ tol
  int rounds = 0;           ///< sweep + Newton rounds
  int newton_steps = 0;     ///< accepted Newton steps
  int factorizations = 0;   ///< reduced-Hessian factorizations (2D reuses them)
  double residual = 0;      ///< final stationarity residual / traction scale
  double energy = 0;        ///< final Φ_λ (without the constant −½ fᵀy)
  std::string note;         ///< why it stopped when not converged
};

/// Φ_λ(x) (file comment), exact: the unsmoothed j_ν and |x_τ|; +inf if x_ν > g somewhere.
double exact_inner_energy(const ExactInnerProblem& P, const Vec& x);

/// The λ-fixed stationarity residual at @p x (max over nodes, divided by the traction scale):
/// normal |σ_ν + ξ| with ξ ∈ ∂j_ν(x_ν) below g, max(0, σ_ν + min ∂j_ν) at g; tangential
/// max(0, |σ_τ| − λ) where x_τ = 0, |σ_τ + λ x_τ/|x_τ|| elsewhere; wσ = S(x − y).
double exact_inner_residual(const ExactInnerProblem& P, const Vec& x);

/// The reduced Hessian's factor, kept from one exact_inner_solve to the next on the same problem
/// but λ (the outer loop's λ updates): in 2D it depends on the active set alone (|x_τ| has no
/// curvature off 0), so an update whose statuses stay needs no new factorization. Opaque.
class ExactInnerFactor {
 public:
  ExactInnerFactor();
  ~ExactInnerFactor();
  ExactInnerFactor(const ExactInnerFactor&) = delete;
  ExactInnerFactor& operator=(const ExactInnerFactor&) = delete;
  struct Impl;
  std::unique_ptr<Impl> m;
};

/// Minimize Φ_λ from @p x (projected on the bounds first); @p x returns the answer. @p keep: the
/// factor of the previous solve of this problem (S, w, g, law, fixed the same; λ may differ), used
/// where its active set comes back, and left with this solve's.
ExactInnerResult exact_inner_solve(const ExactInnerProblem& P, Vec& x, const ExactInnerOptions& opt = {},
                                   ExactInnerFactor* keep = nullptr);

/// Decide InnerConvexity (problem/reports.hpp): one dense Cholesky of S − α W_ν (positive definite or not), then, when
/// it is, the smallest eigenvalue by inverse iteration on that factor (each step one pair of
/// triangular solves). Skipped above @p max_unknowns (the dense factorization costs m³/3).
InnerConvexity inner_convexity(const Mat& S, const Vec& w, int d, const PiecewiseLinearLaw* law, Index max_unknowns);

/// Anderson acceleration (type II, memory m) of a fixed-point iteration λ = G(λ) (the outer
/// map λ ↦ F_b(u_ν(λ)) need not contract). Each call takes λ_k and G(λ_k) and returns
/// λ_{k+1} = G(λ_k) − ΔG γ − (1 − θ)(f_k − ΔF γ), γ = argmin ‖f_k − ΔF γ‖₂ over the last m
/// differences of f = G(λ) − λ and of G: the extrapolated λ plus θ times the extrapolated update
/// (θ = solver.fixed_point.relaxation, the mixing of damped Anderson); with m = 0 it is the
/// relaxed iteration λ_{k+1} = (1 − θ) λ_k + θ G(λ_k), with θ = 1 the plain one.
class Anderson {
 public:
  explicit Anderson(int memory, double theta = 1.0) : m_memory(memory), m_theta(theta) {}
  /// @return the next iterate, clamped at 0 below (a friction bound is ≥ 0, (15c)).
  Vec next(const Vec& lambda, const Vec& G);
  /// Forget the history (after a step that made the residual grow).
  void reset() { m_dF.clear(), m_dG.clear(), m_has_prev = false; }

 private:
  int m_memory;
  double m_theta;
  std::vector<Vec> m_dF, m_dG;
  Vec m_prev_f, m_prev_G;
  bool m_has_prev = false;
};

}  // namespace hemicontact
