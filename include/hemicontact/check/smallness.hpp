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

#include <hemicontact/driver/model.hpp>

namespace hemicontact {

/// The terms of (21).
struct SmallnessReport {
  bool computed = false;     ///< false when there is no Γ3 or nothing nonconvex/nonmonotone to check
  double m_F = 0;            ///< (12)(b)
  double L_Fb = 0;           ///< (15)(a); 0 without friction; +inf for a discontinuous F_b
  double alpha_j = 0;        ///< (13)(d); 0 without layer; +inf for a downward jump of p_ν
  double lambda_1 = 0;       ///< λ_{1,ν}: smallest eigenvalue with ∫Γ3 u·v
  double lambda_1nu = 0;     ///< λ_{1ν,ν}: smallest eigenvalue with ∫Γ3 u_ν v_ν
  double lhs = 0;            ///< L_Fb/λ_{1,ν} + α_jν/λ_{1ν,ν}
  bool holds = false;        ///< lhs < m_F: uniqueness guaranteed
  double seconds = 0;        ///< time to compute
};

/// Evaluate (21) for a model (one extra sparse factorization of the ε:ε Gram matrix).
SmallnessReport evaluate_smallness(const Model& model);

}  // namespace hemicontact
