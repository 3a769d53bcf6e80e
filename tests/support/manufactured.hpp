#pragma once
/// @file manufactured.hpp  The smooth displacement field of the manufactured-solution tests, zero on
/// the boundary of the unit square:  u1 = sin πx sin πy,  u2 = C2 p(x) p(y),  p(t) = t(1 − t).

#include <Eigen/Dense>

#include <cmath>

namespace hemicontact::test::manufactured {

constexpr double PI = 3.14159265358979323846;
constexpr double C2 = 8;  ///< amplitude of u2, so that both components are O(1)

/// p(t) = t(1 − t).
inline double p(double t) { return t * (1 - t); }
/// p'(t).
inline double dp(double t) { return 1 - 2 * t; }

/// The exact displacement.
inline Eigen::Vector2d u_exact(double x, double y) { return {std::sin(PI * x) * std::sin(PI * y), C2 * p(x) * p(y)}; }

/// ε(u) in Voigt form: (∂x u1, ∂y u2, ∂y u1 + ∂x u2).
inline Eigen::Vector3d eps_exact(double x, double y) {
  const double sx = std::sin(PI * x), sy = std::sin(PI * y), cx = std::cos(PI * x), cy = std::cos(PI * y);
  return {PI * cx * sy, C2 * p(x) * dp(y), PI * sx * cy + C2 * dp(x) * p(y)};
}

}  // namespace hemicontact::test::manufactured
