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

/// Central-difference gradient of @p f at @p x with relative step @p h.
inline Vec fd_gradient(const std::function<double(const Vec&)>& f, const Vec& x, double h = 1e-6) {
  Vec g(x.size());
  for (Index i = 0; i < x.size(); ++i) {
    const double step = h * std::max(1.0, std::abs(x[i]));
    Vec xp = x, xm = x;
    xp[i] += step;
    xm[i] -= step;
    g[i] = (f(xp) - f(xm)) / (2 * step);
  }
  return g;
}

/// Central-difference Jacobian of a vector function @p g (dense; for small test problems).
inline Mat fd_jacobian(const std::function<Vec(const Vec&)>& g, const Vec& x, double h = 1e-6) {
  const Vec g0 = g(x);
  Mat J(g0.size(), x.size());
  for (Index i = 0; i < x.size(); ++i) {
    const double step = h * std::max(1.0, std::abs(x[i]));
    Vec xp = x, xm = x;
    xp[i] += step;
    xm[i] -= step;
    J.col(i) = (g(xp) - g(xm)) / (2 * step);
  }
  return J;
}

/// Assert ‖a − b‖∞ ≤ rtol·max(‖a‖∞, ‖b‖∞) + atol, printing both on failure.
inline ::testing::AssertionResult near_rel(const Mat& a, const Mat& b, double rtol, double atol) {
  const double scale = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  const double err = (a - b).cwiseAbs().maxCoeff();
  if (err <= rtol * scale + atol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "max |a-b| = " << err << " > " << rtol << "*" << scale
                                       << " + " << atol << "\n a = " << a.transpose()
                                       << "\n b = " << b.transpose();
}

}  // namespace hemicontact::test
