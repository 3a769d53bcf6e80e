#pragma once
/// @file nodal_term.hpp  The shared layer of the nodal contact terms on Γ3 (the scatter written
/// once for every term, as in ipc-toolkit's `Potential`): a term Σ_k e_k(x_k) whose every summand
/// depends only on the d local unknowns x_k = (x_ν, x_τ[, x_τ2]) of one Γ3 node k (nodal
/// quadrature, docs/model.md §2). A derived term writes the per-node kernel (value e_k, gradient
/// ∇e_k ∈ R^d, Hessian ∇²e_k ∈ R^{d×d}); this base sums the kernels into the global value and
/// gradient and scatters the nodal blocks into the fixed lower-triangular Hessian pattern:
/// \f[ E(x) = \sum_k e_k(x_k), \qquad \nabla E = \sum_k P_k^T \nabla e_k, \qquad
///     \nabla^2 E = \sum_k P_k^T \nabla^2 e_k P_k, \f]
/// P_k selecting node k's unknowns. Where each block entry lies in the pattern's value array is
/// computed once per pattern, in a NodalLayout that every nodal term of one energy shares.

#include <hemicontact/energy/energy_term.hpp>

#include <memory>
#include <vector>

namespace hemicontact {

/// @brief Local unknowns of one Γ3 node, (x_ν, x_τ[, x_τ2]): size d ∈ {2, 3}, stored on the stack.
/// d is a property of the mesh known at run time, so the storage is fixed (3) and the size dynamic.
using NodalVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 3, 1>;
/// @brief A nodal d×d block (symmetric Hessian of one node's kernel), stored on the stack.
using NodalMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 3, 3>;

/// @brief The Γ3 nodes' unknowns and where their d×d Hessian blocks lie in one fixed Hessian pattern.
///
/// Immutable once built: the positions are computed in the constructor from the pattern the
/// composite energy owns (TotalEnergy::hessian_pattern()), and every nodal term of that energy holds
/// the same `std::shared_ptr<const NodalLayout>`, so the pattern is searched once for all of them.
class NodalLayout {
 public:
  /// @brief Locate every node's lower block entries in @p pattern.
  /// @param dofs    where each node's components are in x, and the nodal weights (copied)
  /// @param pattern the lower-triangular (row ≥ col), compressed Hessian pattern the terms will add
  ///                into; only its index arrays are read, and nothing is kept of it
  /// @throws Error (internal) if dofs is inconsistent (d ∉ {2, 3}, sizes differ, a component
  ///         outside the pattern) or the pattern is not square and compressed
  NodalLayout(NodalDofs dofs, const SpMat& pattern);

  /// @return the nodes' dofs and weights.
  const NodalDofs& dofs() const { return m_dofs; }
  /// @return d, the components per node.
  int dim() const { return m_dofs.dim; }
  /// @return the number of nodes.
  Index size() const { return m_dofs.size(); }
  /// @return the number of unknowns n (the pattern is n×n).
  Index n() const { return m_n; }
  /// @brief Position of node k's block entry (a, b), a ≥ b, in the pattern's value array.
  /// @param k node @param a row in the block @param b column in the block (b ≤ a)
  /// @return the position, or −1 if the pattern lacks that entry (a kernel must then add 0 there)
  Index position(Index k, int a, int b) const { return m_pos[k * m_block + a * (a + 1) / 2 + b]; }
  /// @brief Does @p H carry the pattern the positions were computed for? Checks the size, nnz and
  /// that every cached position still addresses its entry: O(nodes·d²), and it catches a different
  /// pattern in the same buffer (which a key on the buffer's address would miss).
  /// @param H a lower-triangular Hessian
  /// @return true if the cached positions are valid for @p H
  bool matches(const SpMat& H) const;

 private:
  NodalDofs m_dofs;
  Index m_n = 0, m_nnz = 0;
  int m_block = 0;           ///< lower entries per block, d(d+1)/2
  std::vector<Index> m_pos;  ///< node k, entry (a, b): m_pos[k·m_block + a(a+1)/2 + b]
};

/// @brief A term Σ_k e_k(x_k) over the Γ3 nodes (ipc-toolkit's local/global split): derived terms
/// write the per-node kernels, this base assembles them.
class NodalTerm : public EnergyTerm {
 public:
  /// @param layout the nodes and their Hessian positions, shared by the energy's nodal terms (not null)
  /// @throws Error (internal) if @p layout is null
  explicit NodalTerm(std::shared_ptr<const NodalLayout> layout);

  /// @return Σ_k e_k(x_k).
  double value(const Vec& x) const final;
  /// Adds Σ_k P_kᵀ ∇e_k(x_k) to @p g.
  void add_gradient(const Vec& x, Vec& g) const final;
  /// Adds the lower triangle of Σ_k P_kᵀ ∇²e_k(x_k) P_k to @p H by the layout's cached positions.
  /// @throws Error (internal) if @p H does not carry the layout's pattern, or a kernel puts a
  ///         nonzero where the pattern has no entry
  void add_hessian(const Vec& x, SpMat& H, Psd psd) const final;
  /// @brief The same Hessian as triplets (row ≥ col, global indices): the reference assembly,
  /// independent of any pattern (tests compare it with add_hessian).
  /// @param x point @param out triplets appended to @param psd as for add_hessian
  void add_hessian_triplets(const Vec& x, Triplets& out, Psd psd) const;

  /// @return the layout (nodes, weights, Hessian positions).
  const NodalLayout& layout() const { return *m_layout; }
  /// @return the shared handle to the layout.
  const std::shared_ptr<const NodalLayout>& layout_ptr() const { return m_layout; }
  /// @return node k's local unknowns x_k = (x_ν, x_τ[, x_τ2]) of @p x.
  NodalVector local(const Vec& x, Index k) const;

  /// @brief Kernel: node k's summand e_k. @param k node @param xk its local unknowns @return e_k(x_k)
  virtual double node_value(Index k, const NodalVector& xk) const = 0;
  /// @brief Kernel: ∇e_k. @param k node @param xk its local unknowns @return the d-vector ∇e_k(x_k)
  virtual NodalVector node_gradient(Index k, const NodalVector& xk) const = 0;
  /// @brief Kernel: ∇²e_k (symmetric; the base reads its lower triangle).
  /// @param k node @param xk its local unknowns @param psd true Hessian or nonconvex parts clamped
  /// @return the d×d block
  virtual NodalMatrix node_hessian(Index k, const NodalVector& xk, Psd psd) const = 0;

 private:
  std::shared_ptr<const NodalLayout> m_layout;
};

}  // namespace hemicontact
