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

/// Evaluate (21) for a model (one extra sparse factorization of the ε:ε Gram matrix).
SmallnessReport evaluate_smallness(const Model& model);

}  // namespace hemicontact
