#pragma once
/// @file material.hpp  Elasticity operator σ = F(ε) (paper eq. (1)), in Voigt notation.
///
/// Voigt convention: strain (ε11, ε22, 2ε12) in 2D, (ε11, ε22, ε33, 2ε23, 2ε13, 2ε12) in 3D
/// (engineering shears), stress (σ11, σ22, σ12) resp. (σ11, σ22, σ33, σ23, σ13, σ12), so that
/// σ·ε in Voigt equals the tensor contraction σ:ε.

#include <hemicontact/core/types.hpp>

#include <string>

namespace hemicontact {

/// An elasticity law with a stored energy W, F = ∂W/∂ε, satisfying the paper's (12):
/// Lipschitz with constant L_F and strongly monotone with constant m_F.
class Material {
 public:
  virtual ~Material() = default;
  /// @return the spatial dimension the law is written for (2 or 3).
  virtual int dim() const = 0;
  /// @return true if F is linear (then tangent() is constant and static condensation is exact).
  virtual bool is_linear() const = 0;
  /// @return W(ε), the stored energy density.
  virtual double energy_density(const Vec& strain) const = 0;
  /// @return σ = F(ε) in Voigt notation.
  virtual Vec stress(const Vec& strain) const = 0;
  /// @return ∂σ/∂ε (Voigt), symmetric.
  virtual Mat tangent(const Vec& strain) const = 0;
  /// @return m_F of (12)(b), w.r.t. the Frobenius inner product on symmetric tensors.
  virtual double m_F() const = 0;
  /// @return L_F of (12)(a).
  virtual double L_F() const = 0;
  /// @return a one-line description for logs and the report.
  virtual std::string describe() const = 0;
};

/// @return the number of Voigt components for dimension @p dim (3 or 6).
constexpr int voigt_size(int dim) { return dim == 2 ? 3 : 6; }

}  // namespace hemicontact
