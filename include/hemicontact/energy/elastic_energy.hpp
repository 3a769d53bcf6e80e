#pragma once
/// @file elastic_energy.hpp  ½ a(u,u) − f(u) = ½ xᵀ K_x x − f_xᵀ x for a linear material.

#include <hemicontact/core/symmetric_matrix.hpp>
#include <hemicontact/energy/energy_term.hpp>

#include <memory>

namespace hemicontact {

/// The elastic energy ½ xᵀ K x (K = Tᵀ K_u T, reduced); its Hessian K is constant.
class ElasticEnergy : public EnergyTerm {
 public:
  /// @param K reduced stiffness (a copy of its lower triangle, which defines the pattern)
  explicit ElasticEnergy(SymmetricSpMat K) : m_K(std::move(K)) {}
  std::string name() const override { return "elastic"; }
  double value(const Vec& x) const override { return 0.5 * x.dot(m_K * x); }
  void add_gradient(const Vec& x, Vec& g) const override { g += m_K * x; }
  /// Adds K's lower triangle; @p H must have exactly lower_pattern()'s pattern.
  void add_hessian(const Vec& x, SpMat& H, Psd psd) const override;
  /// @return the lower triangle of K (the composite's Hessian pattern).
  const SpMat& lower() const { return m_K.lower(); }

 private:
  SymmetricSpMat m_K;
};

/// The condensed elastic energy ½ (x_C − y_C)ᵀ S (x_C − y_C) + c (fem/condensation.hpp): the
/// elastic energy minus the work of the loads, minimized over the interior for given Γ3 unknowns.
class CondensedElasticEnergy : public EnergyTerm {
 public:
  /// @param S Schur complement (dense SPD), shared, not copied (it is m×m, m = d·|Γ3|): the
  ///        Condensation that computed it can hand it out with an aliasing shared_ptr
  /// @param y_C Γ3 part of K⁻¹f; @param c constant −½fᵀy.
  /// @throws Error (internal) if @p S is null or not square
  CondensedElasticEnergy(std::shared_ptr<const Mat> S, Vec y_C, double c);
  std::string name() const override { return "condensed_elastic"; }
  double value(const Vec& x) const override;
  void add_gradient(const Vec& x, Vec& g) const override { g += *m_S * (x - m_y); }
  /// Adds S's lower triangle; @p H must have the pattern dense_lower_pattern(m).
  void add_hessian(const Vec& x, SpMat& H, Psd psd) const override;
  /// Replace y_C and c (loads scaled: y_C → s y_C, c → s² c).
  void set_load(Vec y_C, double c) {
    m_y = std::move(y_C);
    m_c = c;
  }

 private:
  std::shared_ptr<const Mat> m_S;
  Vec m_y;
  double m_c;
};

/// @return an m×m sparse matrix holding every lower-triangular entry (explicit zeros): the Hessian
/// pattern of a condensed problem.
SpMat dense_lower_pattern(Index m);

/// The work of the loads: −f(u) = −f_xᵀ x (eq. (17)); linear, no Hessian.
class LoadEnergy : public EnergyTerm {
 public:
  /// @param f reduced load vector Tᵀ f_u.
  explicit LoadEnergy(Vec f) : m_f(std::move(f)) {}
  std::string name() const override { return "load"; }
  double value(const Vec& x) const override { return -m_f.dot(x); }
  void add_gradient(const Vec& x, Vec& g) const override { g -= m_f; }
  void add_hessian(const Vec&, SpMat&, Psd) const override {}
  /// Replace the load vector.
  void set_load(Vec f) { m_f = std::move(f); }

 private:
  Vec m_f;
};

}  // namespace hemicontact
