#pragma once
/// @file mollified_law.hpp  C¹ mollification of a piecewise-linear p_ν (paper (32)–(33)) for the NLP.
///
/// PiecewiseLinearLaw writes \f$ p_\nu = a + b r + \sum_k \Delta s_k (r-r_k)_+ + \sum_k J_k H(r-r_k) \f$.
/// MollifiedLaw replaces, inside the window |r − r_k| < ε (ε = eps_nu), each ramp by the
/// C¹ quadratic ramp q_ε and each Heaviside step by the C¹ cubic smoothstep S_ε:
/// \f[ q_\varepsilon(x) = \begin{cases} 0 & x \le -\varepsilon \\ \frac{(x+\varepsilon)^2}{4\varepsilon} & |x| <
/// \varepsilon
///     \\ x & x \ge \varepsilon \end{cases} \qquad
///     S_\varepsilon(x) = \begin{cases} 0 & x \le -\varepsilon \\ t^2(3-2t),\ t = \frac{x+\varepsilon}{2\varepsilon} &
///     |x| < \varepsilon
///     \\ 1 & x \ge \varepsilon \end{cases} \f]
/// so that \f$ p_\varepsilon = a + b r + \sum_k \Delta s_k q_\varepsilon(r-r_k) + \sum_k J_k S_\varepsilon(r-r_k) \f$
/// is C¹, \f$ j_\varepsilon(r) = \int_0^r p_\varepsilon \f$ is C², and all three are closed-form.
///
/// Error bounds (each term is exact outside its own window):
///  - \f$ p_\varepsilon = p_\nu \f$ outside all windows; inside the window of r_k (windows disjoint),
///    \f$ |p_\varepsilon - p_\nu| \le |\Delta s_k|\,\varepsilon/4 + |J_k|/2 \f$
///    (|q_ε − (x)_+| = (ε − |x|)²/(4ε) ≤ ε/4 and |S_ε − H| ≤ 1/2). The spec's looser "≤ |J|" holds a fortiori.
///  - \f$ |j_\varepsilon - j_\nu| \le \sum_k \big(|\Delta s_k|\,\varepsilon^2/6 + 3|J_k|\,\varepsilon/16\big) \f$
///    everywhere; beyond the windows j_ε − j_ν is piecewise constant (∫(q_ε − (x)_+) = ε²/6,
///    ∫(S_ε − H) = 0 over a window).
///  - p_ε′ interpolates the neighbouring slopes linearly across a kink window, so without jumps
///    and with disjoint windows α_jν (13)(d) is unchanged; a jump J_k < 0 gives the finite but large
///    slope \f$ \approx 3J_k/(4\varepsilon) \f$ (the exact law has α = +INF).
/// Windows of neighbouring breakpoints may overlap when ε exceeds half their distance; the
/// formulas stay valid (a sum of C¹ terms) but the p-bound becomes the sum over all k.

#include <hemicontact/contact/normal_law.hpp>
#include <hemicontact/contact/piecewise_linear_law.hpp>

#include <memory>
#include <string>

namespace hemicontact {

/// @brief The 1-D mollifiers used by MollifiedLaw (exposed for tests and for other smoothed laws).
namespace mollifier {

/// @brief C¹ ramp \f$ q_\varepsilon \f$ (= max(0,x) for |x| ≥ ε). @param x argument @param eps ε > 0
/// @return q_ε(x)
double smooth_ramp(double x, double eps);
/// @brief \f$ q_\varepsilon'(x) \f$ = clamp((x+ε)/(2ε), 0, 1). @param x argument @param eps ε > 0
/// @return q_ε′(x)
double smooth_ramp_d1(double x, double eps);
/// @brief Antiderivative \f$ \int_{-\infty}^x q_\varepsilon \f$: 0, (x+ε)³/(12ε), x²/2 + ε²/6.
/// @param x argument @param eps ε > 0 @return ∫ q_ε up to x
double smooth_ramp_integral(double x, double eps);
/// @brief C¹ smoothstep \f$ S_\varepsilon \f$ (= H(x) for |x| ≥ ε). @param x argument @param eps ε > 0
/// @return S_ε(x)
double smooth_step(double x, double eps);
/// @brief \f$ S_\varepsilon'(x) = 3t(1-t)/\varepsilon \f$ inside the window, 0 outside.
/// @param x argument @param eps ε > 0 @return S_ε′(x)
double smooth_step_d1(double x, double eps);
/// @brief Antiderivative \f$ \int_{-\infty}^x S_\varepsilon = \varepsilon t^3 (2-t) \f$ inside, (x)_+ outside.
/// @param x argument @param eps ε > 0 @return ∫ S_ε up to x
double smooth_step_integral(double x, double eps);

}  // namespace mollifier

/// @brief Smooth (C¹ p_ν, C² j_ν) version of a PiecewiseLinearLaw, exact outside ε-windows.
class MollifiedLaw : public NormalLaw {
 public:
  /// @brief Mollify @p law with window half-width @p eps_nu.
  /// @param law     the exact law (shared, not copied); must not be null
  /// @param eps_nu  ε_ν > 0, the half-width of the windows around breakpoints
  /// @param context key path for the error message (e.g. "solver.eps_nu")
  /// @throws Error (EXIT_INPUT) if eps_nu is not a finite positive number or law is null
  MollifiedLaw(std::shared_ptr<const PiecewiseLinearLaw> law, double eps_nu, const std::string& context = "eps_nu");
  /// @brief Convenience overload: copies @p law into a shared pointer.
  /// @param law the exact law @param eps_nu ε_ν > 0 @param context key path for errors
  MollifiedLaw(const PiecewiseLinearLaw& law, double eps_nu, const std::string& context = "eps_nu");

  /// @brief \f$ j_\varepsilon(r) = P_\varepsilon(r) - P_\varepsilon(0) \f$. @param r u_ν @return j_ε(r), j_ε(0) = 0
  double j(double r) const override;
  /// @brief \f$ p_\varepsilon(r) \f$. @param r u_ν @return p_ε(r)
  double p(double r) const override;
  /// @brief \f$ p_\varepsilon'(r) = b + \sum_k \Delta s_k q_\varepsilon'(r-r_k) + \sum_k J_k S_\varepsilon'(r-r_k) \f$.
  /// @param r u_ν @return p_ε′(r) (continuous)
  double dp(double r) const override;
  /// @brief p_ε is continuous, so ∂j_ε(r) = {p_ε(r)}. @param r u_ν @return [p_ε(r), p_ε(r)]
  Interval subdifferential(double r) const override;
  /// @brief \f$ \alpha = \max(0, -\min_r p_\varepsilon'(r)) \f$, computed exactly: p_ε′ is a
  /// polynomial of degree ≤ 2 between consecutive window edges.
  /// @return α_jν of the mollified law (finite)
  double one_sided_lipschitz() const override;
  /// @brief The exact law's description plus ε. @return description
  std::string describe() const override;

  /// @brief The exact law being mollified. @return reference to it
  const PiecewiseLinearLaw& exact() const { return *m_law; }
  /// @brief Shared handle to the exact law. @return pointer (never null)
  const std::shared_ptr<const PiecewiseLinearLaw>& exact_ptr() const { return m_law; }
  /// @brief Window half-width. @return ε_ν
  double eps_nu() const { return m_eps; }
  /// @brief Whether two windows overlap (ε > half the smallest gap between breakpoints).
  /// @return true if some r_{k+1} − r_k < 2ε
  bool windows_overlap() const;
  /// @brief Bound on \f$ \sup_r |p_\varepsilon - p_\nu| \f$ (see file comment).
  /// @return max_k (|Δs_k| ε/4 + |J_k|/2), or the sum over k when windows overlap
  double p_error_bound() const;
  /// @brief Bound on \f$ \sup_r |j_\varepsilon - j_\nu| \f$. @return Σ_k (|Δs_k| ε²/6 + 3|J_k| ε/16)
  double j_error_bound() const;

 private:
  /// Unnormalised antiderivative of p_ε.
  double antiderivative(double r) const;

  std::shared_ptr<const PiecewiseLinearLaw> m_law;  ///< exact law (kinks, jumps)
  double m_eps;                                     ///< ε_ν
  double m_P0 = 0.0;                                ///< P_ε(0), so that j_ε(0) = 0
};

}  // namespace hemicontact
