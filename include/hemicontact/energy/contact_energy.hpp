#pragma once
/// @file contact_energy.hpp  The nodal contact terms on Γ3 (MODEL.md §2):
///   normal compliance  Σ_i w_i j_ε(x_ν,i)                (soft layer, eqs. (32)-(33) mollified)
///   lagged friction     Σ_i w_i λ_i f0(|x_τ,i|, ε_τ)      (eq. (6), |·| smoothed)
/// Both are separable per node in the local frame, so their Hessians are nodal blocks inside
/// K's pattern (diagonal in 2D; a τ-block in 3D).

#include <hemicontact/contact/normal_law.hpp>
#include <hemicontact/energy/energy_term.hpp>

#include <memory>

namespace hemicontact {

/// Σ_i w_i j(x_ν,i) for a smooth (mollified) law j.
class NormalComplianceEnergy : public EnergyTerm {
 public:
  /// @param dofs Γ3 node dofs/weights; @param law a C² law (MollifiedLaw) — its j, p, dp are used.
  NormalComplianceEnergy(NodalDofs dofs, std::shared_ptr<const NormalLaw> law);
  std::string name() const override { return "normal_compliance"; }
  double value(const Vec& x) const override;
  /// ∂/∂x_ν,i = w_i p(x_ν,i).
  void add_gradient(const Vec& x, Vec& g) const override;
  /// ∂²/∂x_ν,i² = w_i p'(x_ν,i); negative on the softening branch (c2 < 0): clamped to 0 for CLAMP.
  void add_hessian(const Vec& x, SpMat& H, Psd psd) const override;
  /// Replace the law (eps continuation) keeping the dofs.
  void set_law(std::shared_ptr<const NormalLaw> law) { m_law = std::move(law); }

 private:
  NodalDofs m_dofs;
  std::shared_ptr<const NormalLaw> m_law;
  mutable std::vector<Index> m_pos;  // H positions of the (ν,ν) entries, cached for one pattern
  mutable const void* m_pos_for = nullptr;
};

/// Σ_i w_i λ_i f0(|x_τ,i|, ε_τ) with frozen friction bounds λ_i = F_b(u_ν,i) (lagged, eq. (6)).
class FrictionEnergy : public EnergyTerm {
 public:
  /// @param dofs Γ3 node dofs/weights; @param eps_tau smoothing width (absolute, a length).
  FrictionEnergy(NodalDofs dofs, double eps_tau);
  std::string name() const override { return "friction"; }
  double value(const Vec& x) const override;
  /// ∇ = w_i λ_i f1(y)/y · x_τ,i, y = |x_τ,i| (no 0/0 at y = 0: f1/y is closed form).
  void add_gradient(const Vec& x, Vec& g) const override;
  /// ∇² = w_i λ_i (f1/y I + f2_term x_τ x_τᵀ); convex, so PSD as is.
  void add_hessian(const Vec& x, SpMat& H, Psd psd) const override;
  bool is_lagged() const override { return true; }
  /// Freeze the friction bounds (one per node).
  void set_lambda(const Vec& lambda) { m_lambda = lambda; }
  /// @return the frozen bounds λ_i.
  const Vec& lambda() const { return m_lambda; }
  /// Set the smoothing width (eps continuation).
  void set_eps(double eps_tau) { m_eps = eps_tau; }
  /// @return the smoothing width.
  double eps() const { return m_eps; }

 private:
  NodalDofs m_dofs;
  double m_eps;
  Vec m_lambda;
  mutable std::vector<Index> m_pos;  // H positions of the τ-block entries (lower), per node
  mutable const void* m_pos_for = nullptr;
};

}  // namespace hemicontact
