#pragma once
/// @file hencky.hpp  A Hencky-type nonlinear elastic law: bulk response linear, shear modulus
/// depending on the deviatoric strain and staying between two positive bounds (paper (12)).
///
/// Stored energy, with ε the (3D) small-strain tensor, dev ε = ε − (tr ε/3) I, s = |dev ε|²
/// (Frobenius):
/// \f[ W(\varepsilon) = \tfrac{\kappa}{2} (\mathrm{tr}\,\varepsilon)^2 + \Phi(s),\qquad
///     \Phi(s) = \mu_\infty s + 2(\mu_0 - \mu_\infty) s_0 \big(\sqrt{1 + s/s_0} - 1\big), \f]
/// so the secant shear modulus is
/// \f[ \mu(s) = \Phi'(s) = \mu_\infty + (\mu_0 - \mu_\infty)(1 + s/s_0)^{-1/2} \f]
/// (μ_0 at zero strain, μ_∞ for |dev ε| ≫ ε_ref = √s_0; μ_∞ < μ_0 softens, μ_∞ > μ_0 stiffens) and
/// \f[ \sigma = F(\varepsilon) = \kappa\,\mathrm{tr}\,\varepsilon\, I + 2\mu(s)\,\mathrm{dev}\,\varepsilon. \f]
/// With μ_0 = μ_∞ = μ and κ = λ + 2μ/3 this is exactly linear isotropic elasticity; for any μ_∞,
/// the small-strain limit (tangent at 0) is the linear law with bulk modulus κ and shear modulus
/// μ_0, i.e. E = 9κμ_0/(3κ + μ_0), ν = (3κ − 2μ_0)/(2(3κ + μ_0)).
///
/// Constants of (12). F = ∇W, so (12)(b) holds with m_F = inf over all ε of the smallest eigenvalue
/// of the tangent C(ε) = ∂F/∂ε and (12)(a) with L_F = sup of its largest (C is symmetric positive
/// definite). In 3D
///   C = 3κ P_sph + 2μ(s) (P_dev − n⊗n) + 2ψ(s) n⊗n,   n = dev ε/|dev ε|,
///   ψ(s) = μ(s) + 2 s μ'(s) = ½ d/dt[2μ(t²) t] at t = √s,
/// (the deviatoric part's tangent 2μ P_dev + 4μ' dev ε ⊗ dev ε). The exponent −1/2 in μ(s) is chosen
/// because it makes ψ(s) = μ_∞ + (μ_0 − μ_∞)(1 + s/s_0)^{-3/2}, so both μ and ψ run monotonically
/// from μ_0 to μ_∞ and lie in [μ_lo, μ_hi] = [min, max](μ_0, μ_∞):
///   3D:  m_F = min(3κ, 2μ_lo),  L_F = max(3κ, 2μ_hi).
/// Plane strain (ε33 = 0; F restricted to in-plane tensors, an isometric subspace e ↦ diag(e, 0)):
/// for a unit in-plane x let a = |P_sph x|² ∈ [0, 2/3] (2/3 for x = I₂/√2), c = (n·x)² ∈ [0, 1 − a];
/// then x·C x = 3κ a + 2μ(1 − a − c) + 2ψ c, linear in (a, c) and in μ, ψ ∈ [μ_lo, μ_hi], so its
/// extremes lie at the vertices: 2μ, 2ψ (a = 0) and 2κ + 2μ/3, 2κ + 2ψ/3 (a = 2/3):
///   2D:  m_F = min(2μ_lo, 2κ + 2μ_lo/3),  L_F = max(2μ_hi, 2κ + 2μ_hi/3),
/// which for μ_0 = μ_∞ are LinearElastic's min/max(b, b + 2a) with b = 2μ, a = λ. Both bounds are
/// attained or approached (pure in-plane shear strains with s → 0 or s → ∞, probed along the
/// in-plane spherical direction or orthogonally to dev ε), so they are sharp.
/// Plane stress would need a local solve for ε33 at every evaluation and is not provided.

#include <hemicontact/material/material.hpp>

namespace hemicontact {

/// The Hencky-type law above, in 2D plane strain (dim 2) or 3D (dim 3).
class Hencky : public Material {
 public:
  /// @param kappa bulk modulus κ (> 0); @param mu0 small-strain shear modulus μ_0 (> 0);
  /// @param mu_inf large-strain shear modulus μ_∞ (> 0); @param eps_ref reference deviatoric strain
  /// ε_ref = √s_0 (> 0); @param dim 2 (plane strain) or 3.
  /// @throws Error naming material.* when a constant is out of range.
  Hencky(double kappa, double mu0, double mu_inf, double eps_ref, int dim);
  /// The law whose small-strain limit is LinearElastic(E, nu): κ = E/(3(1−2ν)), μ_0 = E/(2(1+ν)),
  /// and μ_∞ = shear_ratio · μ_0.
  /// @throws Error naming material.E / material.nu / material.shear_ratio / material.eps_ref.
  static Hencky from_young(double E, double nu, double shear_ratio, double eps_ref, int dim);

  int dim() const override { return m_dim; }
  bool is_linear() const override { return false; }
  double energy_density(const Vec& strain) const override;
  Vec stress(const Vec& strain) const override;
  Mat tangent(const Vec& strain) const override;
  double m_F() const override;
  double L_F() const override;
  std::string describe() const override;

  /// @return μ(s), the secant shear modulus at s = |dev ε|².
  double mu(double s) const;
  /// @return μ'(s).
  double dmu(double s) const;
  /// @return Φ(s) = ∫₀ˢ μ.
  double Phi(double s) const;
  /// @return s = |dev ε|² (Frobenius, with ε33 = 0 in plane strain) of a Voigt strain.
  double dev_norm2(const Vec& strain) const;
  /// @return κ.
  double kappa() const { return m_kappa; }
  /// @return μ_0.
  double mu0() const { return m_mu0; }
  /// @return μ_∞.
  double mu_inf() const { return m_mu_inf; }

 private:
  // dev ε in stress-Voigt form (normal components, then tensor shears ε_ij = γ_ij/2), so that
  // s = Σ_normal d_i² + (3D: d33² among them; plane strain: + (tr/3)²) + 2 Σ_shear d_k².
  Vec dev_voigt(const Vec& strain, double& tr) const;
  // s = |dev ε|² from dev_voigt's output.
  double norm2_of(const Vec& dv, double tr) const;

  double m_kappa, m_mu0, m_mu_inf, m_s0;
  int m_dim;
};

}  // namespace hemicontact
