#pragma once
/// @file smallness.hpp  The smallness condition (21) of the paper, which guarantees a unique solution:
///
///   L_Fb / λ_{1,ν} + α_jν / λ_{1ν,ν} < m_F,
///
/// with m_F the strong-monotonicity constant of F (12)(b), L_Fb the Lipschitz constant of F_b
/// (15)(a), α_jν the one-sided Lipschitz constant of ∂j_ν (13)(d), and the smallest eigenvalues of
///   ∫Ω ε(u):ε(v) = λ ∫Γ3 u·v       (λ_{1,ν})   and   ∫Ω ε(u):ε(v) = λ ∫Γ3 u_ν v_ν   (λ_{1ν,ν})
/// over V. Discretely both are small dense generalized eigenproblems on the Γ3 unknowns: the
/// ε:ε Gram matrix is statically condensed onto Γ3 (the right-hand sides live there), with the
/// nodal-quadrature mass diag(w_i). For λ_{1ν,ν} the tangential unknowns are condensed out too.
/// When (21) fails the problem may have several solutions (local minima, saddles).

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/reports.hpp>

namespace hemicontact {

/// @brief Smallest eigenvalue of a symmetric positive definite dense matrix @p B. Up to 400 rows
/// Eigen's dense solver; beyond, Lanczos on B⁻¹ (a Cholesky factor, full reorthogonalization)
/// stopped at a Ritz residual of 1e-13 relative — O(n³/3) instead of the dense solver's ~9n³,
/// which at h = 1/1024 (2 050 Γ3 unknowns) took the (21) bracket from 1.2 s to 0.2 s — with
/// the dense solver as the fallback when Lanczos does not converge or B is not definite.
double smallest_eigenvalue_spd(const Mat& B);

/// Evaluate (21) for a model exactly (one extra sparse factorization of the ε:ε Gram matrix).
SmallnessReport evaluate_smallness(const Model& model);

/// Decide (21) from the Schur complement S_K of the model's stiffness onto Γ3 (the solver's
/// condensation, same unknowns and order as the Gram matrix's), without factorizing anything.
///
/// Why it brackets: F is strongly monotone and Lipschitz (12)(b), so its tangent C obeys
/// m_F ε:ε ≤ ε:Cε ≤ L_F ε:ε, hence m_F G ≤ K ≤ L_F G for the full matrices, and Schur complements
/// keep that order: m_F S_G ≤ S_K ≤ L_F S_G. The Rayleigh quotients then give
///   λ(S_K)/L_F ≤ λ(S_G) ≤ λ(S_K)/m_F
/// for both eigenvalues, i.e. a bracket [lhs_lower, lhs_upper] of the left side of (21). If
/// lhs_upper < m_F, (21) holds; if lhs_lower ≥ m_F, it fails; otherwise the bracket cannot decide
/// and, unless @p allow_exact is false, the exact evaluation is made (method "exact"). For linear
/// isotropic elasticity L_F/m_F = 1 + dλ/(2μ) (2.5 at ν = 0.3 in plane strain), and the paper's
/// scenes are decided by the bracket (fig2: lhs ≤ 1.16e3 < m_F = 1.43e3).
/// @param model the model @param S_K the condensed stiffness (d·n_Γ3 square, node-major ν, τ...)
/// @param allow_exact compute exactly when the bracket is inconclusive
SmallnessReport evaluate_smallness(const Model& model, const Mat& S_K, bool allow_exact = true);

}  // namespace hemicontact
