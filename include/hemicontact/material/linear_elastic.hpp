#pragma once
/// @file linear_elastic.hpp  Isotropic linear elasticity: plane stress (the paper's law), plane strain, 3D.

#include <hemicontact/material/material.hpp>

namespace hemicontact {

/// 2D hypothesis for a linear isotropic law.
enum class PlaneMode { STRESS, STRAIN, NONE_3D };

/// σ = a tr(ε) I + b ε. In the paper's plane stress (§5):
/// \f$(\mathcal F\tau)_{\alpha\beta} = \frac{E\kappa}{1-\kappa^2}(\tau_{11}+\tau_{22})\delta_{\alpha\beta} +
/// \frac{E}{1+\kappa}\tau_{\alpha\beta}\f$, i.e. a = Eκ/(1−κ²), b = E/(1+κ); plane strain and 3D: a = λ =
/// Eν/((1+ν)(1−2ν)), b = 2μ = E/(1+ν). As an operator on symmetric tensors its eigenvalues are b (deviatoric) and b +
/// d·a (spherical), so m_F = min and L_F = max of the two.
class LinearElastic : public Material {
 public:
  /// @param E Young's modulus (> 0); @param nu Poisson's ratio (−1 < ν < 0.5);
  /// @param mode plane stress/strain in 2D, NONE_3D for 3D.
  /// @throws Error naming material.E / material.nu when out of range.
  LinearElastic(double E, double nu, PlaneMode mode);
  int dim() const override { return m_mode == PlaneMode::NONE_3D ? 3 : 2; }
  bool is_linear() const override { return true; }
  double energy_density(const Vec& strain) const override;
  Vec stress(const Vec& strain) const override;
  Mat tangent(const Vec& strain) const override { return m_D; }
  double m_F() const override;
  double L_F() const override;
  std::string describe() const override;
  /// @return the constant Voigt matrix D (σ = D ε).
  const Mat& D() const { return m_D; }
  /// @return Lamé-type coefficients (a, b) of σ = a tr(ε) I + b ε.
  double a() const { return m_a; }
  /// @return b, see a().
  double b() const { return m_b; }

 private:
  double m_E, m_nu, m_a, m_b;
  PlaneMode m_mode;
  Mat m_D;
};

}  // namespace hemicontact
