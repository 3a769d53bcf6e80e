#pragma once
/// @file energy_term.hpp  One additive term of the discrete energy Π_λ (docs/model.md §2), in the
/// solver's reduced unknowns x (free dofs; Γ3 nodes in their local (ν, τ) frame).
///
/// polyfem's "form" shape: value, gradient, Hessian, and a hook to re-freeze lagged data; the
/// composite TotalEnergy sums enabled terms. Contact terms are nodal (nodal quadrature on Γ3),
/// evaluated by a per-node kernel on the node's local components (ipc-toolkit's local/global split):
/// NodalTerm (nodal_term.hpp) assembles them.

#include <hemicontact/nlp/nlp_problem.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// Where each Γ3 node's local components live in x, and its quadrature weight (NodalLayout adds
/// where the node's Hessian block lies in a pattern).
struct NodalDofs {
  int dim = 2;               ///< d: components per node (ν, τ[, τ2])
  std::vector<Index> first;  ///< x index of component ν of node k; τ follow consecutively
  Vec w;                     ///< nodal quadrature weights w_k
  /// @return the number of nodes.
  Index size() const { return static_cast<Index>(first.size()); }
};

/// A term of the energy.
class EnergyTerm {
 public:
  virtual ~EnergyTerm() = default;
  /// @return a short name ("elastic", "load", "normal_compliance", "friction").
  virtual std::string name() const = 0;
  /// @return the term's value at x.
  virtual double value(const Vec& x) const = 0;
  /// Add the term's gradient at x to @p g (sized n).
  virtual void add_gradient(const Vec& x, Vec& g) const = 0;
  /// Add the term's Hessian (lower triangle) at x into @p H, whose pattern is the composite's
  /// fixed pattern; @p psd selects the true Hessian or one with nonconvex parts clamped.
  virtual void add_hessian(const Vec& x, SpMat& H, Psd psd) const = 0;
  /// @return true if the term holds lagged data that freeze() updates (friction bounds λ_i).
  virtual bool is_lagged() const { return false; }
};

/// @return the position in H.valuePtr() of entry (row, col) with row >= col.
/// @throws Error (internal) if the entry is not in the pattern.
Index pattern_position(const SpMat& H, Index row, Index col);

}  // namespace hemicontact
