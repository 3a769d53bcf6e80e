#pragma once
/// @file total_energy.hpp  Π_λ(x) = Σ enabled terms (polyfem's composite form), as an NlpObjective.

#include <hemicontact/energy/energy_term.hpp>

#include <memory>
#include <vector>

namespace hemicontact {

/// The composite energy. The Hessian pattern is fixed once (K's lower triangle; nodal contact
/// blocks lie inside it since they couple dofs of one node).
class TotalEnergy : public NlpObjective {
 public:
  /// @param n number of unknowns; @param pattern lower-triangular Hessian pattern (values ignored).
  TotalEnergy(Index n, SpMat pattern);
  /// Add a term (shared so the driver can keep a handle to update lagged data).
  void add(std::shared_ptr<EnergyTerm> term) { m_terms.push_back(std::move(term)); }
  /// @return the terms.
  const std::vector<std::shared_ptr<EnergyTerm>>& terms() const { return m_terms; }

  Index size() const override { return m_n; }
  double value(const Vec& x) const override;
  void gradient(const Vec& x, Vec& g) const override;
  const SpMat& hessian_pattern() const override { return m_pattern; }
  void hessian(const Vec& x, SpMat& H, Psd psd) const override;

 private:
  Index m_n;
  SpMat m_pattern;
  std::vector<std::shared_ptr<EnergyTerm>> m_terms;
};

/// f̃(x̃) = f(s_x x̃)/s_f: a backend-independent rescaling so every backend sees O(1) unknowns and
/// gradients (the printed scene has u ~ 1e-7, loads ~ 1e-5; absolute tolerances would be meaningless).
/// A view, like Eigen::Ref: it refers to f and owns nothing.
class ScaledObjective : public NlpObjective {
 public:
  /// @param f the objective, referred to, not copied: it must outlive this view (the solver owns
  ///        both, the view built after and released before f); @param s_x unknown scale;
  /// @param s_f value scale (> 0).
  ScaledObjective(const NlpObjective& f, double s_x, double s_f) : m_f(f), m_sx(s_x), m_sf(s_f) {}
  Index size() const override { return m_f.size(); }
  double value(const Vec& x) const override { return m_f.value(m_sx * x) / m_sf; }
  void gradient(const Vec& x, Vec& g) const override;
  const SpMat& hessian_pattern() const override { return m_f.hessian_pattern(); }
  void hessian(const Vec& x, SpMat& H, Psd psd) const override;
  /// @return s_x.
  double x_scale() const { return m_sx; }
  /// @return s_f.
  double f_scale() const { return m_sf; }

 private:
  const NlpObjective& m_f;
  double m_sx, m_sf;
};

}  // namespace hemicontact
