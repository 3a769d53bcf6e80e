#pragma once
/// @file polish.hpp  Exact polish of a smoothed solution (condensed formulation, 2D and 3D).
///
/// The smoothed minimizer identifies the statuses; on fixed statuses the *unsmoothed* conditions of
/// (22) are linear in the condensed unknowns x_C (p_ν and F_b are piecewise linear):
///   contact:          x_ν = g                         (the rigid part takes the rest, eq. (5))
///   compliance/sep.:  σ_ν + p(x_ν) = 0,  p affine on the node's branch  (eq. (32))
///   stick:            x_τ = 0
///   slip s = ±1:      σ_τ + s λ = 0,  λ = F_b(x_ν)     (eq. (6))
/// with w σ = S (x_C − y_C) (the condensed nodal force). The matrix is fixed by the statuses, so it
/// is factored once; λ is iterated to its fixed point on the right-hand side. The result is kept
/// only if it keeps the statuses and lowers the certificate's residual; it then carries no
/// smoothing error (the certificate drops to round-off).
///
/// The statuses come from the smoothed answer, read at check.status_tol and, when the final ε is
/// larger, at 10 ε (a sticking node shows |u_τ| ~ ε U). A node with F_b = 0 on its branch gets the
/// frictionless row σ_τ = 0 whatever its u_τ. If no reading is self-consistent, up to 6
/// primal-dual active-set rounds follow, each from the previous rejected candidate: its own
/// statuses, with pulling contact nodes released, stick nodes outside the cone set slipping along
/// −σ_τ, and nodes whose slip reversed set sticking. The first self-consistent candidate whose
/// certificate beats the smoothed answer's is kept.
///
/// 3D: the slip condition −σ_τ = λ u_τ/|u_τ| is nonlinear in the two tangential unknowns; the same
/// status system is solved by Newton's method with the exact Jacobian of the unit vector
/// ((I − t tᵀ)/|u_τ|) and of λ = F_b(x_ν) (PolishResult::iterations counts Newton steps there).

#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/reports.hpp>
#include <hemicontact/problem/solve_options.hpp>

namespace hemicontact {

/// Polish the condensed unknowns @p x_C in place (kept unchanged if rejected); @p md carries the
/// loads @p load_scale × those @p cond was built with (ContactSolver::set_loads).
PolishResult polish_condensed(const Model& md, const Condensation& cond, const SolveOptions& opt, Vec& x_C,
                              double load_scale = 1.0);

}  // namespace hemicontact
