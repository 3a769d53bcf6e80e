#pragma once
/// @file prolongation.hpp  P1 interpolation of a nodal field from one mesh onto the nodes of
/// another, and the energy norm of a difference: what a convergence study needs to compare a
/// coarse solution u_h with a reference solution u_ref on a finer mesh.
///
/// For every fine node x the coarse cell T that contains it is found (point location through a
/// uniform bucket grid over the coarse cells' bounding boxes), its barycentric coordinates
/// λ_0..λ_d in T are computed, and
///   (P u_h)(x) = Σ_a λ_a(x) u_h(x_a),   a over the d+1 nodes of T, each of the d components.
/// On nested meshes (the fine mesh refines the coarse one) P is the exact embedding V_h ⊂ V_h/2 of
/// the coarse P1 space, so ‖u_ref − P u_h‖_E is the true energy-norm error a(e, e)^{1/2} of u_h
/// measured in the reference space (docs/model.md §5). On non-nested meshes it is the P1 interpolant of
/// u_h, which reproduces every affine field exactly.
///
/// Typical use (bench/study.cpp):
/// @code
///   const Vec Pu  = prolongate(coarse_model.mesh, sol_h.u, ref_model.mesh);
///   const Vec e = sol_ref.u - Pu;  // Model::a(e, e) = eᵀ K e (K_x inside the model)
///   const double rel = std::sqrt(ref_model.a(e, e)) / sol_ref.energy_norm;
/// @endcode

#include <hemicontact/core/types.hpp>
#include <hemicontact/mesh/mesh.hpp>

namespace hemicontact {

/// @brief P1 interpolation of a full nodal field from @p coarse onto the nodes of @p fine.
///
/// A fine node counts as inside a coarse cell when all its barycentric coordinates are
/// ≥ −1e-10 (dimensionless, so the tolerance does not depend on h); on an edge or vertex shared
/// by several cells the cell with the largest smallest coordinate is used, which gives the same
/// value since P1 functions are continuous. The meshes must have the same dimension; they need
/// not be nested.
/// @param coarse   the mesh @p u_coarse lives on (only points and cells are read)
/// @param u_coarse full nodal field, d components per node, node-major (index d·a + i)
/// @param fine     the mesh whose nodes receive values (only points are read)
/// @return the field on @p fine's nodes, same layout (size fine.num_nodes()·d)
/// @throws Error naming the first fine node (index and coordinates) that lies in no coarse cell,
///         or if the sizes or dimensions do not match
Vec prolongate(const Mesh& coarse, const Vec& u_coarse, const Mesh& fine);

/// @brief Energy norm of a difference: ‖a − b‖_E = sqrt((a − b)ᵀ K (a − b)).
/// @param K_fine  symmetric positive semidefinite stiffness of the mesh @p u_fine lives on
///                (full dofs, as Model::K)
/// @param u_fine  the reference field a
/// @param u_prolongated the field b on the same dofs (e.g. prolongate() of a coarse solution)
/// @return the norm (a tiny negative quadratic form from round-off is returned as 0)
/// @throws Error if the sizes do not match
double energy_norm_difference(const SpMat& K_fine, const Vec& u_fine, const Vec& u_prolongated);

}  // namespace hemicontact
