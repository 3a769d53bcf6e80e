#pragma once
/// @file smooth_norm.hpp  C² mollifier of the slip norm |u_τ| (friction term of (20)/(22)), exact for |u_τ| ≥ ε.
///
/// The friction energy \f$ \sum_i w_i \lambda_i |u_{\tau,i}| \f$ (docs/model.md §2) is not differentiable at
/// u_τ = 0. Following ipc-toolkit's friction mollifier we replace |y| by
/// \f[ f_0(y) = \begin{cases} -\dfrac{y^3}{3\varepsilon^2} + \dfrac{y^2}{\varepsilon} + \dfrac{\varepsilon}{3}
///       = y + \dfrac{\varepsilon}{3}\Big(1-\dfrac{y}{\varepsilon}\Big)^3 & 0 \le y < \varepsilon
///       \\ y & y \ge \varepsilon \end{cases} \f]
/// which is C² at y = ε and EXACT for y ≥ ε, so slipping nodes with |u_τ| ≥ ε feel the true
/// friction force. Note the constant offset \f$ f_0(0) = \varepsilon/3 \f$: \f$ 0 \le f_0(y) - y \le \varepsilon/3 \f$,
/// the maximum error, attained at y = 0. It shifts the energy value only, never the gradient.
/// Derivatives (y = |u| ≥ 0, t = y/ε):
/// \f[ f_1 = f_0' = \begin{cases} t(2-t) & y<\varepsilon \\ 1 & y \ge \varepsilon \end{cases}, \quad
///     \frac{f_1}{y} = \begin{cases} \dfrac{2}{\varepsilon} - \dfrac{y}{\varepsilon^2} \\ \dfrac1y \end{cases}, \quad
///     f_1' = \begin{cases} \dfrac{2}{\varepsilon} - \dfrac{2y}{\varepsilon^2} \\ 0 \end{cases}, \quad
///     \frac{f_1' y - f_1}{y^3} = \begin{cases} -\dfrac{1}{\varepsilon^2 y} \\ -\dfrac{1}{y^3} \end{cases} \f]
/// and 0 ≤ f_1 ≤ 1 everywhere: the smoothed friction force \f$ \lambda \nabla f_0(|u_\tau|) \f$ never
/// leaves the friction cone |σ_τ| ≤ λ, which is what lets stick nodes satisfy it.
/// For u ∈ R^k (k = 1 in 2-D, k = 2 in 3-D):
/// \f[ \nabla f_0(|u|) = \frac{f_1(y)}{y} u, \qquad
///     \nabla^2 f_0(|u|) = \frac{f_1(y)}{y} I + \frac{f_1'(y) y - f_1(y)}{y^3} u u^T, \f]
/// with the limit \f$ \nabla^2 = (2/\varepsilon) I \f$ at u = 0.

#include <Eigen/Core>

#include <cassert>
#include <cmath>

namespace hemicontact {

/// @brief Mollified norm \f$ f_0(y) \f$ (see file comment). Exact (= y) for y ≥ ε; f_0(0) = ε/3.
/// @param y   a norm, y ≥ 0
/// @param eps mollifier width ε > 0
/// @return f_0(y) ∈ [y, y + ε/3]
inline double f0(double y, double eps) {
  assert(eps > 0.0 && y >= 0.0);
  if (y >= eps) return y;
  // y + ε(1 − t)³/3 equals −y³/(3ε²) + y²/ε + ε/3 but shows f0 ≥ y and has no cancellation.
  const double s = 1.0 - y / eps;
  return y + eps * s * s * s / 3.0;
}

/// @brief \f$ f_1(y) = f_0'(y) = t(2-t) \f$, t = y/ε, for y < ε; 1 for y ≥ ε.
/// @param y a norm, y ≥ 0 @param eps ε > 0
/// @return f_1(y) ∈ [0, 1]
inline double f1(double y, double eps) {
  assert(eps > 0.0 && y >= 0.0);
  if (y >= eps) return 1.0;
  // t(2 − t) rather than 1 − (1 − t)²: no cancellation for small t, and fl(t(2 − t)) ≤ 1.
  const double t = y / eps;
  return t * (2.0 - t);
}

/// @brief \f$ f_1(y)/y \f$ in closed form: 2/ε − y/ε² for y < ε (finite at y = 0), 1/y for y ≥ ε.
/// @param y a norm, y ≥ 0 @param eps ε > 0
/// @return f_1(y)/y; the value 2/ε at y = 0 is the limit
inline double f1_over_y(double y, double eps) {
  assert(eps > 0.0 && y >= 0.0);
  if (y >= eps) return 1.0 / y;
  return (2.0 - y / eps) / eps;
}

/// @brief \f$ f_1'(y) = f_0''(y) \f$: 2/ε − 2y/ε² for y < ε, 0 for y ≥ ε (continuous at ε: C²).
/// @param y a norm, y ≥ 0 @param eps ε > 0
/// @return f_1′(y) ∈ [0, 2/ε]
inline double df1(double y, double eps) {
  assert(eps > 0.0 && y >= 0.0);
  if (y >= eps) return 0.0;
  return 2.0 * (1.0 - y / eps) / eps;
}

/// @brief \f$ (f_1'(y)\,y - f_1(y))/y^3 \f$, the coefficient of u uᵀ in the Hessian.
///
/// Inner branch: \f$ ((2/\varepsilon - 2y/\varepsilon^2) y - 2y/\varepsilon + y^2/\varepsilon^2)/y^3 =
/// -1/(\varepsilon^2 y) \f$, which grows like 1/y but is only ever used multiplied by u uᵀ (norm y²), giving a term of
/// norm y/ε² → 0. At y = 0 we return 0, the value of that product's limit (explicit branch).
/// @param y a norm, y ≥ 0 @param eps ε > 0
/// @return −1/(ε² y) for 0 < y < ε, −1/y³ for y ≥ ε, 0 at y = 0
inline double f2_term(double y, double eps) {
  assert(eps > 0.0 && y >= 0.0);
  if (y >= eps) return -1.0 / (y * y * y);
  // y = 0: u = 0, so f2_term · u uᵀ = 0 whatever finite value we return; 0 keeps it exact.
  if (y == 0.0) return 0.0;
  return -1.0 / (eps * eps * y);
}

/// @brief Smoothed norm \f$ f_0(|u|) \f$ of a fixed-size vector (the tangential slip u_τ).
/// @tparam Derived fixed-size Eigen column vector (k = 1 or 2), or an expression of one
/// @param u   slip vector in the tangent frame
/// @param eps ε > 0
/// @return f_0(|u|)
template <typename Derived>
double smooth_norm(const Eigen::MatrixBase<Derived>& u, double eps) {
  static_assert(Derived::ColsAtCompileTime == 1 && Derived::RowsAtCompileTime != Eigen::Dynamic,
                "smooth_norm: u must be a fixed-size column vector");
  return f0(u.norm(), eps);
}

/// @brief Gradient \f$ \nabla_u f_0(|u|) = (f_1(y)/y)\,u \f$, y = |u|; 0 at u = 0; norm f_1(y) ≤ 1.
/// @tparam Derived fixed-size Eigen column vector
/// @param u slip vector @param eps ε > 0
/// @return the gradient (same size as u)
template <typename Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, 1> smooth_norm_gradient(const Eigen::MatrixBase<Derived>& u,
                                                                          double eps) {
  static_assert(Derived::ColsAtCompileTime == 1 && Derived::RowsAtCompileTime != Eigen::Dynamic,
                "smooth_norm_gradient: u must be a fixed-size column vector");
  // f1_over_y is finite at y = 0, so the stick limit needs no branch: gradient = (2/ε)·0 = 0.
  return f1_over_y(u.norm(), eps) * u;
}

/// @brief Hessian \f$ (f_1/y) I + f_{2}\,u u^T \f$ (f_2 = f2_term); \f$ (2/\varepsilon) I \f$ at u = 0.
/// Positive semidefinite: eigenvalues f_1/y ≥ 0 (across u) and f_1′ ≥ 0 (along u).
/// @tparam Derived fixed-size Eigen column vector
/// @param u slip vector @param eps ε > 0
/// @return k×k symmetric matrix
template <typename Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::RowsAtCompileTime> smooth_norm_hessian(
    const Eigen::MatrixBase<Derived>& u, double eps) {
  static_assert(Derived::ColsAtCompileTime == 1 && Derived::RowsAtCompileTime != Eigen::Dynamic,
                "smooth_norm_hessian: u must be a fixed-size column vector");
  constexpr int K = Derived::RowsAtCompileTime;
  using Mat = Eigen::Matrix<double, K, K>;
  const double y = u.norm();
  // u = 0 (stick): f1/y → 2/ε and f2_term·u uᵀ → 0, the limit of the inner-branch Hessian.
  if (y == 0.0) return (2.0 / eps) * Mat::Identity();
  const double f2 = f2_term(y, eps);
  // 1/(ε² y) overflows only for y < 1/(ε² DBL_MAX) (≈1e-292 at ε = 1e-8); there the Hessian is
  // (2/ε) I to machine precision, and inf·(u uᵀ = 0) would otherwise give NaN.
  if (!std::isfinite(f2)) return (2.0 / eps) * Mat::Identity();
  // Form u uᵀ first: folding f2 into one factor ((f2 u_i) u_j) would break exact symmetry.
  const Mat uuT = u * u.transpose();
  return f1_over_y(y, eps) * Mat::Identity() + f2 * uuT;
}

}  // namespace hemicontact
