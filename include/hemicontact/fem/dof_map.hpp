#pragma once
/// @file dof_map.hpp  Full ↔ reduced unknowns: Dirichlet elimination and the Γ3 local frames.
///
/// The solver vector x holds the free dofs: first every free component of the non-contact nodes
/// (node-major), then for each Γ3 node k its local components (x_ν, x_τ[, x_τ2]) — contact dofs
/// last, which is the ordering static condensation wants. With R_k = [ν_k τ_k (ν_k×τ_k)] the map is
/// u = T x (u_D = 0 on Γ1, eq. (3)); T has orthonormal columns, so x = Tᵀ u for any u that vanishes
/// on Γ1, gradients map as g_x = Tᵀ g_u and Hessians as H_x = Tᵀ H_u T (docs/model.md §2). The bound
/// u_ν,k ≤ g_k is then the variable bound x_ν,k ≤ g_k.

#include <hemicontact/contact/contact_nodes.hpp>

#include <vector>

namespace hemicontact {

/// Maps between full nodal displacements and the solver's reduced unknowns.
class DofMap {
 public:
  DofMap() = default;
  /// @param mesh the mesh; @param clamped per-node Γ1 flag; @param contact the Γ3 nodes (not clamped).
  DofMap(const Mesh& mesh, const std::vector<bool>& clamped, const ContactNodes& contact);
  /// @return the number of full dofs N·d.
  Index n_full() const { return m_T.rows(); }
  /// @return the number of reduced (free) unknowns.
  Index n_free() const { return m_T.cols(); }
  /// @return the number of free non-contact unknowns (they come first in x).
  Index n_interior() const { return m_n_interior; }
  /// @return the index in x of local component @p comp (0 = ν, 1.. = τ) of contact node @p k.
  Index contact_dof(Index k, int comp) const { return m_n_interior + m_dim * k + comp; }
  /// @return the sparse map T (n_full × n_free).
  const SpMat& T() const { return m_T; }
  /// @return u = T x.
  Vec to_full(const Vec& x) const { return m_T * x; }
  /// @return Tᵀ v (reduced gradient of a full gradient; or x of a u that vanishes on Γ1).
  Vec to_reduced(const Vec& v) const { return m_T.transpose() * v; }
  /// @return Tᵀ A T (reduced stiffness of a full one). Fast path for matrices with full d×d node
  /// blocks (every FE stiffness); otherwise computed by sparse products.
  MovableSpMat reduce(const SpMat& A) const;
  /// @return for each full dof its index in x, −1 if eliminated (Γ1, rollers); a Γ3 node's d
  /// Cartesian components get its d local slots (contact_dof(k, 0..d−1)), before the rotation
  /// into (ν, τ...) that rotate_to_contact_frames applies. Interior indices increase with the full
  /// dof; Γ3 ones come last. What assembly needs to build Tᵀ K T without the full K.
  std::vector<Index> cartesian_selection() const;
  /// A ← R_kᵀ A R_k on every Γ3 node block, in place: turns the selected, renumbered (Cartesian)
  /// matrix into Tᵀ K T. @return false, with A untouched, if A (n_free × n_free, compressed,
  /// sorted) lacks full d×d Γ3 node blocks.
  bool rotate_to_contact_frames(SpMat& A) const;
  /// @return Tᵀ A T by two sparse products (reference implementation, any pattern).
  SpMat reduce_by_products(const SpMat& A) const;

 private:
  int m_dim = 2;
  Index m_n_interior = 0;
  MovableSpMat m_T;  // moves with the DofMap (core/types.hpp)
};

}  // namespace hemicontact
