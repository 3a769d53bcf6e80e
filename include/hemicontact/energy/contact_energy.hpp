#pragma once
/// @file contact_energy.hpp  The nodal contact terms on Γ3 (docs/model.md §2), kernels on NodalTerm:
///   normal compliance  Σ_i w_i j_ε(x_ν,i)                (soft layer, eqs. (32)-(33) mollified)
///   lagged friction     Σ_i w_i λ_i f0(|x_τ,i|, ε_τ)      (eq. (6), |·| smoothed)
/// Both are separable per node in the local frame, so their Hessians are nodal blocks inside
/// K's pattern (one ν entry for the normal term; the τ-block for friction).
///
/// Each term is complete from its constructor on: the law and the smoothing width are arguments,
/// and the only later changes are the width (ε-continuation, set_eps) and, for friction, the frozen
/// bounds λ (re-lagging, set_lambda), each replacing one piece of data the term owns.

#include <hemicontact/contact/mollified_law.hpp>
#include <hemicontact/energy/nodal_term.hpp>

#include <memory>
#include <string>

namespace hemicontact {

/// @brief Σ_i w_i j_ε(x_ν,i) for the mollified law j_ε of an exact piecewise-linear law.
class NormalComplianceEnergy : public NodalTerm {
 public:
  /// @param layout the Γ3 nodes and their Hessian positions (shared with the other nodal terms)
  /// @param law    the C² law (held; not null): its j, p, dp are used, and set_eps() re-mollifies
  ///               its exact law
  /// @throws Error (internal) if @p layout or @p law is null
  NormalComplianceEnergy(std::shared_ptr<const NodalLayout> layout, std::shared_ptr<const MollifiedLaw> law);
  std::string name() const override { return "normal_compliance"; }

  /// @brief w_k j_ε(x_ν,k). @param k node @param xk its local unknowns @return the summand
  double node_value(Index k, const NodalVector& xk) const override;
  /// @brief ∂/∂x_ν = w_k p_ε(x_ν,k); zero in τ. @param k node @param xk its local unknowns @return ∇e_k
  NodalVector node_gradient(Index k, const NodalVector& xk) const override;
  /// @brief ∂²/∂x_ν² = w_k p_ε′(x_ν,k), the only nonzero; negative on the softening branch (c2 < 0):
  /// clamped to 0 for Psd::CLAMP. @param k node @param xk its local unknowns @param psd clamp or not
  /// @return ∇²e_k
  NodalMatrix node_hessian(Index k, const NodalVector& xk, Psd psd) const override;

  /// @brief Set the smoothing width (ε-continuation): the law becomes the same exact law mollified
  /// with @p eps_nu. The term is never without a law.
  /// @param eps_nu ε_ν > 0 (absolute, a length) @param context key path for the error message
  /// @throws Error (input) if eps_nu is not a finite number > 0
  void set_eps(double eps_nu, const std::string& context = "eps_nu");
  /// @return the mollified law in use.
  const MollifiedLaw& law() const { return *m_law; }

 private:
  std::shared_ptr<const MollifiedLaw> m_law;
};

/// @brief Σ_i w_i λ_i f0(|x_τ,i|, ε_τ) with frozen friction bounds λ_i = F_b(u_ν,i) (lagged, eq. (6)).
///
/// The bounds are the lagging boundary (ipc-toolkit's frozen normal forces): data the term owns,
/// replaced whole by set_lambda() to re-lag; the term never reads u_ν.
class FrictionEnergy : public NodalTerm {
 public:
  /// @param layout  the Γ3 nodes and their Hessian positions (shared with the other nodal terms)
  /// @param eps_tau smoothing width ε_τ > 0 (absolute, a length)
  /// @param lambda  the frozen bounds λ_i ≥ 0, one per node (zero: no friction at that node)
  /// @throws Error (internal) if @p layout is null, eps_tau is not finite > 0 or lambda has the wrong size
  FrictionEnergy(std::shared_ptr<const NodalLayout> layout, double eps_tau, Vec lambda);
  std::string name() const override { return "friction"; }
  bool is_lagged() const override { return true; }

  /// @brief w_k λ_k f0(|x_τ,k|). @param k node @param xk its local unknowns @return the summand
  double node_value(Index k, const NodalVector& xk) const override;
  /// @brief ∇_τ = w_k λ_k f1(y)/y · x_τ,k, y = |x_τ,k| (no 0/0 at y = 0: f1/y is closed form); zero in ν.
  /// @param k node @param xk its local unknowns @return ∇e_k
  NodalVector node_gradient(Index k, const NodalVector& xk) const override;
  /// @brief ∇²_ττ = w_k λ_k (f1/y I + f2_term x_τ x_τᵀ); convex, so PSD as is (@p psd is ignored).
  /// @param k node @param xk its local unknowns @param psd ignored @return ∇²e_k
  NodalMatrix node_hessian(Index k, const NodalVector& xk, Psd psd) const override;

  /// @brief Re-lag: replace the frozen bounds. @param lambda λ_i, one per node
  /// @throws Error (internal) if lambda has the wrong size
  void set_lambda(Vec lambda);
  /// @return the frozen bounds λ_i.
  const Vec& lambda() const { return m_lambda; }
  /// @brief Set the smoothing width (ε-continuation). @param eps_tau ε_τ > 0 (absolute, a length)
  /// @throws Error (internal) if eps_tau is not a finite number > 0
  void set_eps(double eps_tau);
  /// @return the smoothing width ε_τ.
  double eps() const { return m_eps; }

 private:
  double m_eps;
  Vec m_lambda;
};

}  // namespace hemicontact
