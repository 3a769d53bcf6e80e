// Tests of the C² slip-norm mollifier (smooth_norm.hpp): 1-D law identities, exactness for
// |u| ≥ ε, |∇| ≤ 1 (friction cone), and FD of value → gradient → Hessian for k = 1 and k = 2.
//
// FD tolerances: the step is h = 1e-3·min(ε, |y − ε|, y) so the stencil never crosses the branch
// at |u| = ε (sampled at ε(1 ± 0.05), never on it). Truncation is ≤ h²/6·sup|f‴| with
// |f‴| ≲ 2/ε² + 6/y² for f0 and one more 1/min(ε,y) for the gradient; round-off is ≲ 8u·|f|/h
// plus the rounding of u ± h (≤ u|u_i| per side).

#include <hemicontact/contact/smooth_norm.hpp>
#include <hemicontact/core/types.hpp>

#include "support/fd_check.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cfloat>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <tuple>

namespace hemicontact {
namespace {

constexpr double ULP = DBL_EPSILON;
const double EPSILONS[] = {1e-8, 1e-4, 1e-2, 1.0};

// ---------------------------------------------------------------- scalar law

class SmoothNormScalar : public ::testing::TestWithParam<double> {};

TEST_P(SmoothNormScalar, ExactOutsideAndOffsetInside) {
  const double eps = GetParam();
  // Exact (bitwise) for y ≥ ε: slipping nodes feel the true |u_τ|.
  for (double s : {1.0, 1.05, 2.0, 1e3}) {
    const double y = s * eps;
    SCOPED_TRACE("y/eps = " + std::to_string(s));
    EXPECT_EQ(f0(y, eps), y);
    EXPECT_EQ(f1(y, eps), 1.0);
    EXPECT_EQ(df1(y, eps), 0.0);
    EXPECT_EQ(f1_over_y(y, eps), 1.0 / y);
  }
  // Offset: f0(0) = ε/3 and 0 ≤ f0(y) − y ≤ ε/3 (= ε(1 − y/ε)³/3).
  EXPECT_DOUBLE_EQ(f0(0.0, eps), eps / 3);
  for (double s : {0.0, 0.01, 0.3, 0.5, 0.95, 0.999}) {
    const double y = s * eps;
    SCOPED_TRACE("y/eps = " + std::to_string(s));
    EXPECT_GE(f0(y, eps) - y, 0.0);
    EXPECT_LE(f0(y, eps) - y, eps / 3 * (1 + 4 * ULP));
    // The polynomial form of the header, evaluated independently (≲ 4 ulp of ε).
    const double poly = -y * y * y / (3 * eps * eps) + y * y / eps + eps / 3;
    EXPECT_NEAR(f0(y, eps), poly, 8 * ULP * eps);
  }
  // f1_over_y is finite at 0 with the limit 2/ε; f2_term's y = 0 branch is 0.
  EXPECT_EQ(f1_over_y(0.0, eps), 2.0 / eps);
  EXPECT_EQ(f1(0.0, eps), 0.0);
  EXPECT_EQ(df1(0.0, eps), 2.0 / eps);
  EXPECT_EQ(f2_term(0.0, eps), 0.0);
}

TEST_P(SmoothNormScalar, IdentitiesAndBounds) {
  const double eps = GetParam();
  for (int i = 1; i <= 400; ++i) {
    const double y = eps * 2.0 * i / 400.0 * (1 - 1e-7);  // never exactly on ε
    SCOPED_TRACE("y/eps = " + std::to_string(y / eps));
    // f1/y · y = f1: both sides are 2–3 roundings of the same quantity → ≤ 8 ulp apart.
    EXPECT_NEAR(f1_over_y(y, eps) * y, f1(y, eps), 8 * ULP * f1(y, eps));
    // f2_term = (f1′ y − f1)/y³, evaluated directly (cancellation-free check: compare y³·f2).
    const double direct = df1(y, eps) * y - f1(y, eps);
    EXPECT_NEAR(f2_term(y, eps) * y * y * y, direct, 16 * ULP * (1.0 + std::abs(direct)));
    // 0 ≤ f1 ≤ 1 (exactly in floating point: fl(t(2 − t)) ≤ 1, see f1) and f1′ ≥ 0 (convexity).
    EXPECT_GE(f1(y, eps), 0.0);
    EXPECT_LE(f1(y, eps), 1.0);
    EXPECT_GE(df1(y, eps), 0.0);
  }
}

TEST_P(SmoothNormScalar, DerivativesMatchFiniteDifferences) {
  const double eps = GetParam();
  for (double s : {0.01, 0.3, 0.7, 0.95, 1.05, 2.0, 10.0}) {
    const double y = s * eps;
    const double h = 1e-3 * std::min({eps, std::abs(y - eps), y});
    SCOPED_TRACE("y/eps = " + std::to_string(s));
    Vec x(1);
    x << y;
    // fd_gradient's step is h·max(1, |y|): recompute it for the error bounds.
    const double step = h * std::max(1.0, y);
    const double g = test::fd_gradient([&](const Vec& v) { return f0(v[0], eps); }, x, h)[0];
    const double d = test::fd_gradient([&](const Vec& v) { return f1(v[0], eps); }, x, h)[0];
    // f0‴ = −2/ε² inside, 0 outside; f1‴ = 0 inside (f1 is quadratic) and outside.
    EXPECT_NEAR(g, f1(y, eps), step * step / 3 / (eps * eps) + 8 * ULP * (y + eps) / step + ULP * y / step);
    EXPECT_NEAR(d, df1(y, eps), 8 * ULP * 2.0 / step + df1(y, eps) * ULP * y / step);
  }
}

INSTANTIATE_TEST_SUITE_P(SmoothNormEps, SmoothNormScalar, ::testing::ValuesIn(EPSILONS));

// ---------------------------------------------------------------- vector helpers, k = 1, 2

using VecParam = std::tuple<int, double>;

template <int K>
void check_vector_case(double eps) {
  using V = Eigen::Matrix<double, K, 1>;
  std::mt19937 rng(1234 + K);
  std::normal_distribution<double> normal;
  int checked = 0;
  for (double s : {0.01, 0.5, 0.95, 1.05, 2.0, 10.0}) {
    for (int rep = 0; rep < 3; ++rep) {
      V dir;
      for (int i = 0; i < K; ++i) dir[i] = normal(rng);
      const V u = s * eps * dir.normalized();
      const double y = u.norm();
      SCOPED_TRACE("k = " + std::to_string(K) + ", |u|/eps = " + std::to_string(y / eps));

      // Exactness for |u| ≥ ε (value and gradient = the true norm's).
      if (s > 1.0) {
        EXPECT_NEAR(smooth_norm(u, eps), y, 2 * ULP * y);
        EXPECT_TRUE(test::near_rel(smooth_norm_gradient(u, eps), u / y, 4 * ULP, 0.0));
      }
      // |∇| = f1(|u|) ≤ 1: the smoothed friction force stays in the cone. The product
      // (f1/y)·u can exceed f1 by a few roundings, hence the 4u slack.
      EXPECT_LE(smooth_norm_gradient(u, eps).norm(), 1.0 + 4 * ULP);

      const double h = 1e-3 * std::min({eps, std::abs(y - eps), y});
      const double step = h * std::max(1.0, u.cwiseAbs().maxCoeff());
      const Vec x = u;
      const auto value = [&](const Vec& v) { return smooth_norm(V(v), eps); };
      const auto grad = [&](const Vec& v) { return Vec(smooth_norm_gradient(V(v), eps)); };
      const Vec g_fd = test::fd_gradient(value, x, h);
      const Mat H_fd = test::fd_jacobian(grad, x, h);
      const Vec g = smooth_norm_gradient(u, eps);
      const Mat H = smooth_norm_hessian(u, eps);
      // Truncation: h²/6 · |f‴| with |f‴| ≲ 2/ε² + 6/y² (norm curvature) for the value, and one
      // more derivative (÷ min(ε, y)) for the gradient; round-off as in the file comment.
      const double m = std::min(eps, y);
      const double f3 = 2 / (eps * eps) + 6 / (y * y);
      EXPECT_TRUE(test::near_rel(g_fd, g, 0.0, step * step / 6 * f3 + 8 * ULP * (y + eps) / step + ULP * y / step));
      EXPECT_TRUE(
          test::near_rel(H_fd, H, 0.0, step * step / 6 * f3 * 6 / m + 8 * ULP * 2.0 / step + (2 / eps) * ULP * y / step));
      // Symmetric, positive semidefinite (eigenvalues f1/y and f1′, both ≥ 0).
      EXPECT_TRUE(test::near_rel(H, H.transpose(), 0.0, 0.0));
      const Eigen::SelfAdjointEigenSolver<Mat> es(H);
      EXPECT_GE(es.eigenvalues().minCoeff(), -4 * ULP * (2 / eps));
      ++checked;
    }
  }
  EXPECT_EQ(checked, 18);

  // u = 0 (stick): value ε/3, zero gradient, Hessian (2/ε) I; and no NaN for tiny |u|.
  const V zero = V::Zero();
  EXPECT_DOUBLE_EQ(smooth_norm(zero, eps), eps / 3);
  EXPECT_EQ(smooth_norm_gradient(zero, eps), zero);
  EXPECT_TRUE(test::near_rel(smooth_norm_hessian(zero, eps), (2 / eps) * Mat::Identity(K, K), 0.0, 0.0));
  const V tiny = V::Constant(1e-300);
  const Mat Ht = smooth_norm_hessian(tiny, eps);
  EXPECT_TRUE(Ht.allFinite());
  EXPECT_TRUE(test::near_rel(Ht, (2 / eps) * Mat::Identity(K, K), 4 * ULP, 0.0));
}

class SmoothNormVector : public ::testing::TestWithParam<VecParam> {};

TEST_P(SmoothNormVector, FiniteDifferencesExactnessAndCone) {
  const auto [k, eps] = GetParam();
  if (k == 1) check_vector_case<1>(eps);
  if (k == 2) check_vector_case<2>(eps);
}

INSTANTIATE_TEST_SUITE_P(SmoothNormDims, SmoothNormVector,
                         ::testing::Combine(::testing::Values(1, 2), ::testing::ValuesIn(EPSILONS)),
                         [](const ::testing::TestParamInfo<VecParam>& info) {
                           std::ostringstream os;
                           os << "k" << std::get<0>(info.param) << "_eps1em"
                              << std::lround(-std::log10(std::get<1>(info.param)));
                           return os.str();
                         });

TEST(SmoothNormHessian, OneDimensionalReducesToDf1) {
  // For k = 1: f1/y + f2_term·y² = f1′ (the 1-D second derivative) on both branches.
  for (double eps : EPSILONS) {
    for (double s : {0.2, 0.9, 1.5}) {
      SCOPED_TRACE("eps = " + std::to_string(eps) + ", y/eps = " + std::to_string(s));
      const Eigen::Matrix<double, 1, 1> u = Eigen::Matrix<double, 1, 1>::Constant(-s * eps);
      EXPECT_NEAR(smooth_norm_hessian(u, eps)(0, 0), df1(s * eps, eps), 8 * ULP * 2 / eps);
      EXPECT_NEAR(smooth_norm_gradient(u, eps)(0), -f1(s * eps, eps), 4 * ULP);
    }
  }
}

}  // namespace
}  // namespace hemicontact
