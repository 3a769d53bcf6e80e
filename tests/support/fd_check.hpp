#pragma once
/// @file fd_check.hpp  Finite-difference checks of value -> gradient -> Hessian (polyfem test_form).
///
/// Central differences with step h have truncation error O(h² f''') and round-off O(ε_mach |f|/h);
/// h = 1e-6 · max(1, |x|) balances them for O(1)-scaled data, so relative agreement to ~1e-6 is
/// expected for the gradient and ~1e-5 for the Hessian (looser, as in ipc-toolkit's 1e-3 practice,
/// because the Hessian check differentiates the already-approximate gradient once more).

#include <hemicontact/core/types.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace hemicontact::test {

/// Central-difference gradient of @p f at @p x with the step @p steps[i] in coordinate i (for
/// functions with branches, whose steps must stay on one piece: tests/energy/energy_terms_test.cpp).
inline Vec fd_gradient(const std::function<double(const Vec&)>& f, const Vec& x, const Vec& steps) {
  Vec g(x.size());
  for (Index i = 0; i < x.size(); ++i) {
    Vec xp = x, xm = x;
    xp[i] += steps[i];
    xm[i] -= steps[i];
    g[i] = (f(xp) - f(xm)) / (2 * steps[i]);
  }
  return g;
}

/// Central-difference Jacobian of a vector function @p g (dense; for small test problems) with the
/// step @p steps[j] in coordinate j.
inline Mat fd_jacobian(const std::function<Vec(const Vec&)>& g, const Vec& x, const Vec& steps) {
  Mat J;
  for (Index j = 0; j < x.size(); ++j) {
    Vec xp = x, xm = x;
    xp[j] += steps[j];
    xm[j] -= steps[j];
    const Vec col = (g(xp) - g(xm)) / (2 * steps[j]);
    if (j == 0) J.resize(col.size(), x.size());
    J.col(j) = col;
  }
  return J;
}

/// The relative steps h·max(1, |x_i|) of fd_gradient / fd_jacobian with a scalar @p h.
inline Vec relative_steps(const Vec& x, double h) { return (h * x.cwiseAbs().cwiseMax(1.0)).eval(); }

/// Central-difference gradient of @p f at @p x with relative step @p h.
inline Vec fd_gradient(const std::function<double(const Vec&)>& f, const Vec& x, double h = 1e-6) {
  return fd_gradient(f, x, relative_steps(x, h));
}

/// Central-difference Jacobian of a vector function @p g (dense; for small test problems).
inline Mat fd_jacobian(const std::function<Vec(const Vec&)>& g, const Vec& x, double h = 1e-6) {
  return fd_jacobian(g, x, relative_steps(x, h));
}

/// Assert ‖a − b‖∞ ≤ rtol·max(‖a‖∞, ‖b‖∞) + atol, printing both on failure.
inline ::testing::AssertionResult near_rel(const Mat& a, const Mat& b, double rtol, double atol) {
  const double scale = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  const double err = (a - b).cwiseAbs().maxCoeff();
  if (err <= rtol * scale + atol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "max |a-b| = " << err << " > " << rtol << "*" << scale << " + " << atol
                                       << "\n a = " << a.transpose() << "\n b = " << b.transpose();
}

}  // namespace hemicontact::test
