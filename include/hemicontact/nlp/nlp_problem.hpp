#pragma once
/// @file nlp_problem.hpp  The bound-constrained minimization problem handed to an NLP backend.
///
/// Backends see only this: an objective with value, gradient and a sparse Hessian on a fixed
/// lower-triangular pattern, and simple bounds lower <= x <= upper (docs/model.md §2: with the Γ3
/// unknowns in their local (ν, τ) frame, u_ν <= g is a variable bound, so there are no
/// constraint functions). No Ipopt/NLopt header is included here.

#include <hemicontact/core/types.hpp>

namespace hemicontact {

/// How a Hessian should treat nonconvex contributions (c2 < 0 branch of p_ν).
enum class Psd {
  NONE,  ///< the true Hessian (Ipopt corrects the inertia itself)
  CLAMP  ///< negative nodal curvatures clamped to zero (our Newton backend asks for this)
};

/// A twice-differentiable objective f: R^n -> R.
class NlpObjective {
 public:
  virtual ~NlpObjective() = default;
  /// @return the number of unknowns n.
  virtual Index size() const = 0;
  /// @return f(x).
  virtual double value(const Vec& x) const = 0;
  /// @param x point; @param g output, resized to n: ∇f(x).
  virtual void gradient(const Vec& x, Vec& g) const = 0;
  /// Lower triangle (row >= col) sparsity pattern of the Hessian. It is fixed: hessian() must
  /// return a matrix with exactly this pattern (same outer/inner index arrays), explicit zeros kept.
  virtual const SpMat& hessian_pattern() const = 0;
  /// @param x point; @param H output: lower triangle of ∇²f(x) on hessian_pattern();
  /// @param psd whether to clamp nonconvex contributions.
  virtual void hessian(const Vec& x, SpMat& H, Psd psd) const = 0;
};

/// min f(x) subject to lower <= x <= upper (entries may be ±INF).
struct NlpProblem {
  const NlpObjective* f = nullptr;  ///< objective (not owned)
  Vec lower;                        ///< lower bounds, size n (-INF: none)
  Vec upper;                        ///< upper bounds, size n (+INF: none)
};

}  // namespace hemicontact
