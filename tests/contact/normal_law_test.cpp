// Tests of the normal laws (paper (32)-(33), (13)(d)): PiecewiseLinearLaw and MollifiedLaw.
//
// Tolerances are derived, not tuned:
//  - values are sums of a handful of terms of size ≲ 10², so evaluation round-off is
//    ≲ 10 ulp · 10² ≈ 1e-13; we allow 1e-12 absolute on O(1..100) values;
//  - central differences with step h: truncation ≤ h²/6 · sup|f'''| (bounded from the law's
//    slope changes and jumps, see fd_tolerance) plus round-off ≤ C·u·|f|/h;
//  - composite Simpson is exact for cubics, and on every piece between breakpoints / window
//    edges p is a polynomial of degree ≤ 3, so the quadrature error is round-off only.

#include <hemicontact/contact/mollified_law.hpp>
#include <hemicontact/contact/piecewise_linear_law.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/types.hpp>

#include "support/fd_check.hpp"

#include "support/expect_error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace hemicontact {
namespace {

constexpr double U = DBL_EPSILON;

// ---------------------------------------------------------------- test laws (plain builders)

/// The paper's example (32): c = (100, -100, 400), r = (0.1, 0.15).
PiecewiseLinearLaw paper_law() { return PiecewiseLinearLaw::paper(100, -100, 400, 0.1, 0.15); }

/// Layer that gives way: p rises with slope 100 to 10 at r = 0.1, drops to 4 (J = -6), then
/// slope 20 to (0.2, 6) and slope 50 beyond. Satisfies (15c), α = +INF (downward jump).
PiecewiseLinearLaw dropping_law() {
  return PiecewiseLinearLaw({{-0.05, 0.0}, {0.0, 0.0}, {0.1, 10.0}, {0.1, 4.0}, {0.2, 6.0}}, 0.0, 50.0);
}

/// Monotone law with an upward jump at 0 (a pre-stressed layer): α = 0.
PiecewiseLinearLaw monotone_law() {
  return PiecewiseLinearLaw({{0.0, 0.0}, {0.0, 1.0}, {0.1, 2.0}, {0.2, 6.0}}, 0.0, 40.0);
}

enum class LawKind { Paper, Dropping, Monotone };

PiecewiseLinearLaw make_law(LawKind kind) {
  switch (kind) {
    case LawKind::Paper: return paper_law();
    case LawKind::Dropping: return dropping_law();
    case LawKind::Monotone: return monotone_law();
  }
  return paper_law();
}

std::string kind_name(LawKind kind) {
  switch (kind) {
    case LawKind::Paper: return "paper";
    case LawKind::Dropping: return "dropping";
    case LawKind::Monotone: return "monotone";
  }
  return "?";
}

/// Expect fn() to throw an input Error whose message contains every string in @p parts.
using hemicontact::test::expect_input_error;

// ---------------------------------------------------------------- paper law, exact values

TEST(LawPaper, ValuesAtKnownPoints) {
  const auto law = paper_law();
  // p from (32) by hand: c1 r on (0, r1]; 10 + c2 (r − 0.1) on (r1, r2); 5 + c3 (r − 0.15) after.
  EXPECT_NEAR(law.p(-1.0), 0.0, 1e-12);
  EXPECT_NEAR(law.p(0.0), 0.0, 1e-12);
  EXPECT_NEAR(law.p(0.05), 5.0, 1e-12);
  EXPECT_NEAR(law.p(0.1), 10.0, 1e-12);
  EXPECT_NEAR(law.p(0.12), 8.0, 1e-12);
  EXPECT_NEAR(law.p(0.15), 5.0, 1e-12);
  EXPECT_NEAR(law.p(0.2), 5.0 + 400 * 0.05, 1e-12);
  // j (33) by hand: ∫0^0.1 100 r = 0.5; + ∫ over (0.1, 0.15) of 10 − 100 s = 0.5 − 0.125;
  // + ∫ over (0.15, 0.2) of 5 + 400 s = 0.25 + 0.5.
  EXPECT_NEAR(law.j(-1.0), 0.0, 1e-12);
  EXPECT_EQ(law.j(0.0), 0.0);
  EXPECT_NEAR(law.j(0.1), 0.5, 1e-12);
  EXPECT_NEAR(law.j(0.15), 0.875, 1e-12);
  EXPECT_NEAR(law.j(0.2), 1.625, 1e-12);
  // Slopes; at a kink dp is the right slope.
  EXPECT_EQ(law.dp(-1.0), 0.0);
  EXPECT_EQ(law.dp(0.05), 100.0);
  EXPECT_EQ(law.dp(0.1), -100.0);
  EXPECT_EQ(law.dp(0.12), -100.0);
  EXPECT_EQ(law.dp(0.2), 400.0);
  // Continuous p: ∂j is a point, also at the kinks.
  for (double r : {0.0, 0.1, 0.15, 0.07}) {
    SCOPED_TRACE("r = " + std::to_string(r));
    const Interval s = law.subdifferential(r);
    EXPECT_NEAR(s.lo, law.p(r), 1e-12);
    EXPECT_NEAR(s.hi, law.p(r), 1e-12);
  }
  EXPECT_TRUE(law.is_continuous());
  // α of (13)(d): the most negative slope is c2 = −100.
  EXPECT_EQ(law.one_sided_lipschitz(), 100.0);
  EXPECT_NE(law.describe().find("paper (32)"), std::string::npos);
}

TEST(LawPaper, Representation) {
  const auto law = paper_law();
  EXPECT_EQ(law.breakpoints(), (std::vector<double>{0.0, 0.1, 0.15}));
  EXPECT_EQ(law.slopes(), (std::vector<double>{0.0, 100.0, -100.0, 400.0}));
  EXPECT_EQ(law.slope_changes(), (std::vector<double>{100.0, -200.0, 500.0}));
  EXPECT_EQ(law.jumps(), (std::vector<double>{0.0, 0.0, 0.0}));
  EXPECT_EQ(law.affine_intercept(), 0.0);
}

TEST(LawPaper, RejectsBadKinks) {
  expect_input_error([] { PiecewiseLinearLaw::paper(100, -100, 400, 0.0, 0.15); },
                     {"contact.normal_law.r1", "0 < r1 < r2"});
  expect_input_error([] { PiecewiseLinearLaw::paper(100, -100, 400, 0.2, 0.15); },
                     {"contact.normal_law.r2", "0 < r1 < r2"});
  expect_input_error([] { PiecewiseLinearLaw::paper(100, NAN, 400, 0.1, 0.15); }, {"contact.normal_law.c2"});
}

// ---------------------------------------------------------------- tables: jumps, α, defaults

TEST(LawTable, DownwardJumpSubdifferentialAndAlpha) {
  const auto law = dropping_law();
  EXPECT_FALSE(law.is_continuous());
  EXPECT_NEAR(law.p_minus(0.1), 10.0, 1e-12);
  EXPECT_NEAR(law.p_plus(0.1), 4.0, 1e-12);
  EXPECT_NEAR(law.p(0.1), 4.0, 1e-12);  // right-continuous
  const Interval s = law.subdifferential(0.1);
  EXPECT_NEAR(s.lo, 4.0, 1e-12);
  EXPECT_NEAR(s.hi, 10.0, 1e-12);
  const Interval t = law.subdifferential(0.15);  // off the jump: a point
  EXPECT_EQ(t.lo, t.hi);
  EXPECT_NEAR(t.lo, 5.0, 1e-12);
  EXPECT_EQ(law.one_sided_lipschitz(), INF);
  EXPECT_EQ(law.jumps()[2], -6.0);
  // (ξ1 − ξ2)(r2 − r1) / |r1 − r2|² across the jump grows like |J|/δ: no finite α exists.
  const double d = 1e-6;
  const double ratio = (law.p(0.1 - d) - law.p(0.1 + d)) * (2 * d) / (4 * d * d);
  EXPECT_GT(ratio, 1e6);
}

TEST(LawTable, MonotoneLawsHaveAlphaZero) {
  const auto law = monotone_law();
  EXPECT_EQ(law.one_sided_lipschitz(), 0.0);
  const Interval s = law.subdifferential(0.0);  // upward jump at 0
  EXPECT_EQ(s.lo, 0.0);
  EXPECT_EQ(s.hi, 1.0);
  const PiecewiseLinearLaw smooth({{0.0, 0.0}, {0.1, 1.0}, {0.2, 5.0}}, 0.0, 40.0);
  EXPECT_EQ(smooth.one_sided_lipschitz(), 0.0);
}

TEST(LawTable, NullSlopesContinueTheEndSegments) {
  const PiecewiseLinearLaw law({{0.0, 0.0}, {0.1, 1.0}, {0.2, 3.0}}, std::nullopt, std::nullopt);
  EXPECT_NEAR(law.slope_left(), 10.0, 1e-12);
  EXPECT_NEAR(law.slope_right(), 20.0, 1e-12);
  EXPECT_NEAR(law.p(-0.1), -1.0, 1e-12);
  EXPECT_NEAR(law.p(0.3), 5.0, 1e-12);
  // A single point: constant p on both sides, j linear.
  const PiecewiseLinearLaw single({{0.3, 2.0}}, std::nullopt, std::nullopt);
  EXPECT_EQ(single.slope_left(), 0.0);
  EXPECT_EQ(single.slope_right(), 0.0);
  EXPECT_NEAR(single.p(-5.0), 2.0, 1e-12);
  EXPECT_NEAR(single.j(0.7), 1.4, 1e-12);
  EXPECT_NEAR(single.j(-0.5), -1.0, 1e-12);
  // A single jump (two points, one r): slopes default to 0.
  const PiecewiseLinearLaw step({{0.1, 0.0}, {0.1, 3.0}}, std::nullopt, std::nullopt);
  EXPECT_EQ(step.slope_left(), 0.0);
  EXPECT_NEAR(step.j(0.3), 0.6, 1e-12);
}

struct BadTable {
  std::string name;
  std::vector<PiecewiseLinearLaw::Point> points;
  std::optional<double> slope_left, slope_right;
  std::vector<std::string> message_parts;
};

class LawTableValidation : public ::testing::TestWithParam<BadTable> {};

TEST_P(LawTableValidation, RejectsWithKeyInMessage) {
  const BadTable& bad = GetParam();
  SCOPED_TRACE(bad.name);
  expect_input_error([&] { PiecewiseLinearLaw(bad.points, bad.slope_left, bad.slope_right, "contact.normal_law"); },
                     bad.message_parts);
}

INSTANTIATE_TEST_SUITE_P(
    LawTables, LawTableValidation,
    ::testing::Values(
        BadTable{"empty", {}, 0.0, 0.0, {"contact.normal_law.points", "at least one point"}},
        BadTable{"nan_p", {{0.0, 0.0}, {0.1, NAN}}, 0.0, 0.0, {"contact.normal_law.points[1]", "finite"}},
        BadTable{"inf_r", {{-INF, 0.0}, {0.1, 1.0}}, 0.0, 0.0, {"contact.normal_law.points[0]", "finite"}},
        BadTable{"decreasing",
                 {{0.0, 0.0}, {0.1, 1.0}, {0.2, 2.0}, {0.1, 3.0}},
                 0.0,
                 0.0,
                 {"contact.normal_law.points[3]: r decreases (0.1 after 0.2): p_nu must be a "
                  "function of r"}},
        BadTable{"triple",
                 {{0.0, 0.0}, {0.1, 1.0}, {0.1, 2.0}, {0.1, 3.0}},
                 0.0,
                 0.0,
                 {"contact.normal_law.points[3]", "three times"}},
        BadTable{"slope_left_inf", {{0.0, 0.0}, {0.1, 1.0}}, INF, 0.0, {"contact.normal_law.slope_left"}},
        BadTable{"slope_right_nan", {{0.0, 0.0}, {0.1, 1.0}}, 0.0, NAN, {"contact.normal_law.slope_right"}},
        BadTable{"overflowing_segment",
                 {{0.0, 0.0}, {1e-320, 1e300}},
                 0.0,
                 0.0,
                 {"contact.normal_law.points[1]", "not finite"}}),
    [](const ::testing::TestParamInfo<BadTable>& info) { return info.param.name; });

// ---------------------------------------------------------------- helpers for both laws

/// Exact law (eps = 0) or its mollification.
std::shared_ptr<const NormalLaw> law_for(const PiecewiseLinearLaw& exact, double eps) {
  if (eps == 0.0) return std::make_shared<PiecewiseLinearLaw>(exact);
  return std::make_shared<MollifiedLaw>(exact, eps);
}

/// Points where the law's smoothness class drops: breakpoints (exact) or window edges (mollified).
std::vector<double> singular_points(const PiecewiseLinearLaw& exact, double eps) {
  std::vector<double> s;
  for (double r : exact.breakpoints()) {
    if (eps == 0.0) {
      s.push_back(r);
    } else {
      s.push_back(r - eps);
      s.push_back(r + eps);
    }
  }
  std::sort(s.begin(), s.end());
  return s;
}

double distance_to(const std::vector<double>& set, double r) {
  double d = INF;
  for (double s : set) d = std::min(d, std::abs(r - s));
  return d;
}

/// sup|p′|, sup|p″| and sup|p‴| bounds (p″ = p‴ = 0 on the pieces of the exact law):
/// q′ ≤ 1, q″ = 1/(2ε), S′ ≤ 3/(4ε), |S″| ≤ 3/(2ε²), |S‴| = 3/(2ε³).
struct DerivativeBounds {
  double d2p = 0.0, d3p = 0.0, dp = 0.0;
};
DerivativeBounds bounds(const PiecewiseLinearLaw& exact, double eps) {
  DerivativeBounds b;
  for (double s : exact.slopes()) b.dp += std::abs(s);
  if (eps == 0.0) return b;
  for (std::size_t k = 0; k < exact.breakpoints().size(); ++k) {
    const double ds = std::abs(exact.slope_changes()[k]), jk = std::abs(exact.jumps()[k]);
    b.d2p += ds / (2 * eps) + 1.5 * jk / (eps * eps);
    b.d3p += 1.5 * jk / (eps * eps * eps);
    b.dp += 0.75 * jk / eps;
  }
  return b;
}

/// Bound on Σ|summands| in the sum form of p (a + b r + Σ Δs_k q(r − r_k) + Σ J_k S(r − r_k)),
/// using q(x) ≤ |x| + ε and S ≤ 1: the scale of the round-off of one evaluation of p.
double p_summands(const PiecewiseLinearLaw& exact, double eps, double r) {
  double s = std::abs(exact.affine_intercept()) + std::abs(exact.slope_left() * r);
  for (std::size_t k = 0; k < exact.breakpoints().size(); ++k)
    s += std::abs(exact.slope_changes()[k]) * (std::abs(r - exact.breakpoints()[k]) + eps) + std::abs(exact.jumps()[k]);
  return s;
}

/// Same for j = P(r) − P(0) (antiderivatives ≤ (|x| + ε)²/2 and ≤ |x| + ε), both evaluations.
double j_summands(const PiecewiseLinearLaw& exact, double eps, double r) {
  const auto one = [&](double x) {
    double s = std::abs(exact.affine_intercept() * x) + std::abs(exact.slope_left()) * x * x / 2;
    for (std::size_t k = 0; k < exact.breakpoints().size(); ++k) {
      const double d = std::abs(x - exact.breakpoints()[k]) + eps;
      s += std::abs(exact.slope_changes()[k]) * d * d / 2 + std::abs(exact.jumps()[k]) * d;
    }
    return s;
  };
  return one(r) + one(0.0);
}

/// Composite Simpson of p over [a, b] split at @p cuts; each piece gets left value
/// p_plus(a_i) and right value p_minus(b_i), so jumps at the cuts are integrated correctly.
double simpson(const std::function<double(double)>& p_right, const std::function<double(double)>& p_left, double a,
               double b, std::vector<double> cuts, int n = 8) {
  if (a == b) return 0.0;
  const double sign = a < b ? 1.0 : -1.0;
  const double lo = std::min(a, b), hi = std::max(a, b);
  std::vector<double> nodes{lo};
  std::sort(cuts.begin(), cuts.end());
  for (double c : cuts)
    if (c > lo && c < hi) nodes.push_back(c);
  nodes.push_back(hi);
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
    const double x0 = nodes[i], x1 = nodes[i + 1], h = (x1 - x0) / n;
    double s = p_right(x0) + p_left(x1);
    for (int m = 1; m < n; ++m) s += (m % 2 ? 4.0 : 2.0) * p_right(x0 + m * h);
    total += s * h / 3.0;
  }
  return sign * total;
}

using LawParam = std::tuple<LawKind, double>;

std::string law_param_name(const ::testing::TestParamInfo<LawParam>& info) {
  const double eps = std::get<1>(info.param);
  std::ostringstream os;
  os << kind_name(std::get<0>(info.param)) << "_";
  if (eps == 0.0) {
    os << "exact";
  } else {
    os << "eps1em" << static_cast<int>(std::lround(-std::log10(eps)));
  }
  return os.str();
}

class LawQuadratureAndFd : public ::testing::TestWithParam<LawParam> {};

// j(r) = ∫0^r p, against Simpson per smooth piece, for r on every branch.
TEST_P(LawQuadratureAndFd, PotentialMatchesQuadrature) {
  const auto [kind, eps] = GetParam();
  const PiecewiseLinearLaw exact = make_law(kind);
  const auto law = law_for(exact, eps);
  std::function<double(double)> p_right = [&](double r) { return law->p(r); };
  std::function<double(double)> p_left = p_right;
  if (eps == 0.0) {
    p_right = [&](double r) { return exact.p_plus(r); };
    p_left = [&](double r) { return exact.p_minus(r); };
  }
  std::vector<double> cuts = singular_points(exact, eps);
  cuts.insert(cuts.end(), exact.breakpoints().begin(), exact.breakpoints().end());
  EXPECT_EQ(law->j(0.0), 0.0);
  for (double r : {-0.3, -0.05, -1e-3, 0.02, 0.1, 0.1 + 3e-7, 0.125, 0.15, 0.17, 0.4}) {
    SCOPED_TRACE("r = " + std::to_string(r));
    const double q = simpson(p_right, p_left, 0.0, r, cuts);
    // Round-off only (Simpson is exact on the cubic pieces): ≲ 1e-13 per evaluation × |r|.
    EXPECT_NEAR(law->j(r), q, 1e-11 * (1.0 + std::abs(q)));
  }
}

// FD of j → p and p → dp beside every kink (exact) or inside/around every window (mollified).
TEST_P(LawQuadratureAndFd, DerivativesMatchFiniteDifferences) {
  const auto [kind, eps] = GetParam();
  const PiecewiseLinearLaw exact = make_law(kind);
  const auto law = law_for(exact, eps);
  const std::vector<double> sing = singular_points(exact, eps);
  const DerivativeBounds b = bounds(exact, eps);

  std::vector<double> points{-0.2, 0.03, 0.125, 0.3};
  const std::vector<double> offsets =
      eps == 0.0 ? std::vector<double>{-1e-3, -1e-6, 1e-6, 1e-3}
                 : std::vector<double>{-2.0 * eps, -1.05 * eps, -0.95 * eps, -0.5 * eps, -0.1 * eps,
                                       0.3 * eps,  0.95 * eps,  1.05 * eps,  2.0 * eps};
  for (double rk : exact.breakpoints())
    for (double d : offsets) points.push_back(rk + d);

  int checked = 0;
  for (double r : points) {
    const double dist = distance_to(sing, r);
    // Points that land on another window's edge (overlapping windows at eps = 0.1) are skipped:
    // the FD stencil must not straddle a point where p″ (or p′) jumps.
    if (dist < 1e-6 * std::max(eps, 1e-6)) continue;
    // Step: 1e-3 of the distance to the nearest singular point (so the stencil stays on one
    // smooth piece) and of ε (so h²·p‴ ≪ p′ inside a window).
    const double h = 1e-3 * std::min({dist, eps == 0.0 ? 1.0 : eps, 1.0});
    SCOPED_TRACE("r = " + std::to_string(r) + ", h = " + std::to_string(h));
    Vec x(1);
    x << r;
    const Vec dj = test::fd_gradient([&](const Vec& v) { return law->j(v[0]); }, x, h);
    const Vec ddj = test::fd_gradient([&](const Vec& v) { return law->p(v[0]); }, x, h);
    // Truncation h²/6·sup|f‴| plus round-off: each evaluation errs by ≲ n·u·Σ|summands|
    // (n ≤ 2·#breakpoints + 3 additions), and the difference quotient divides 2 of them by 2h;
    // r ± h is itself rounded (≤ u|r|/2 each), which perturbs the quotient by |f′|·u|r|/h.
    const double n_add = 2.0 * exact.breakpoints().size() + 3.0;
    const double tol_p =
        h * h / 6 * b.d2p + n_add * U * j_summands(exact, eps, r) / h + std::abs(law->p(r)) * U * std::abs(r) / h;
    const double tol_dp =
        h * h / 6 * b.d3p + n_add * U * p_summands(exact, eps, r) / h + std::abs(law->dp(r)) * U * std::abs(r) / h;
    EXPECT_NEAR(dj[0], law->p(r), tol_p);
    EXPECT_NEAR(ddj[0], law->dp(r), tol_dp);
    ++checked;
  }
  // The skip rule must not empty the test (it only drops points on another window's edge).
  EXPECT_GE(checked, static_cast<int>(points.size() * 3 / 4));
}

INSTANTIATE_TEST_SUITE_P(LawKinds, LawQuadratureAndFd,
                         ::testing::Combine(::testing::Values(LawKind::Paper, LawKind::Dropping, LawKind::Monotone),
                                            ::testing::Values(0.0, 1e-8, 1e-6, 1e-3, 1e-1)),
                         law_param_name);

// ---------------------------------------------------------------- mollified law

class LawMollified : public ::testing::TestWithParam<LawParam> {};

// p_ε = p and dp_ε = dp outside the windows, j_ε − j constant there; the documented error
// bounds hold everywhere (up to round-off 1e-12).
TEST_P(LawMollified, ExactOutsideWindowsAndWithinBounds) {
  const auto [kind, eps] = GetParam();
  const PiecewiseLinearLaw exact = make_law(kind);
  const MollifiedLaw law(exact, eps);
  const double p_bound = law.p_error_bound(), j_bound = law.j_error_bound();
  int outside = 0;
  for (int i = 0; i <= 2000; ++i) {
    const double r = -0.4 + 0.8 * i / 2000.0 + 1e-9;  // offset: avoid landing on breakpoints
    SCOPED_TRACE("r = " + std::to_string(r));
    EXPECT_LE(std::abs(law.p(r) - exact.p(r)), p_bound + 1e-12);
    EXPECT_LE(std::abs(law.j(r) - exact.j(r)), j_bound + 1e-12);
    bool in_window = false;
    for (double rk : exact.breakpoints()) in_window |= std::abs(r - rk) < eps;
    if (in_window) continue;
    ++outside;
    EXPECT_NEAR(law.p(r), exact.p(r), 1e-12);
    EXPECT_NEAR(law.dp(r), exact.dp(r), 1e-12);
  }
  EXPECT_GT(outside, 100);
  // Right of every window j_ε − j is the constant Σ_k Δs_k ε²/6 − (j_ε − j)(0)…: check constancy.
  const double rmax = exact.breakpoints().back() + eps;
  const double d1 = law.j(rmax + 0.01) - exact.j(rmax + 0.01);
  const double d2 = law.j(rmax + 0.3) - exact.j(rmax + 0.3);
  EXPECT_NEAR(d1, d2, 1e-11);
  const Interval s = law.subdifferential(exact.breakpoints().back());
  EXPECT_EQ(s.lo, s.hi);
}

// C¹ p_ε and C⁰ dp_ε across window edges: the difference over a gap 2τ is O(τ).
TEST_P(LawMollified, ContinuousAtWindowEdges) {
  const auto [kind, eps] = GetParam();
  const PiecewiseLinearLaw exact = make_law(kind);
  const MollifiedLaw law(exact, eps);
  const DerivativeBounds b = bounds(exact, eps);
  for (double e : singular_points(exact, eps)) {
    SCOPED_TRACE("edge = " + std::to_string(e));
    const double tau = 1e-6 * eps;
    // |Δp| ≤ 2τ sup|p′|, |Δdp| ≤ 2τ sup|p″|, plus round-off of the sums (~1e-13 · scale).
    EXPECT_NEAR(law.p(e - tau), law.p(e + tau), 2 * tau * b.dp + 1e-12);
    EXPECT_NEAR(law.dp(e - tau), law.dp(e + tau), 2 * tau * b.d2p + 1e-12 * (1.0 + b.dp));
    EXPECT_NEAR(law.j(e - tau), law.j(e + tau), 2 * tau * (1.0 + std::abs(law.p(e))) + 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(LawKinds, LawMollified,
                         ::testing::Combine(::testing::Values(LawKind::Paper, LawKind::Dropping, LawKind::Monotone),
                                            ::testing::Values(1e-8, 1e-6, 1e-3, 1e-1)),
                         law_param_name);

TEST(LawMollifiedBounds, ErrorBoundsAreAttained) {
  const double eps = 1e-3;
  const auto exact = paper_law();
  const MollifiedLaw law(exact, eps);
  EXPECT_FALSE(law.windows_overlap());
  // At the centre of the kink window the ramp error is exactly Δs ε/4 (Δs = −200 at r1).
  EXPECT_NEAR(law.p(0.1) - exact.p(0.1), -200 * eps / 4, 1e-12);
  EXPECT_NEAR(law.p_error_bound(), 500 * eps / 4, 1e-15);
  // Right of all windows, j_ε − j = Σ Δs_k ε²/6 − (j_ε − j)(0); at 0 the first window is half
  // passed: ∫_{-ε}^{0} (x+ε)²/(4ε) = ε²/12.
  const double expected = (100 - 200 + 500) * eps * eps / 6 - 100 * eps * eps / 12;
  EXPECT_NEAR(law.j(0.3) - exact.j(0.3), expected, 1e-13);
  // Jump: |S_ε − H| reaches 1/2 at the jump (from either side).
  const auto drop = dropping_law();
  const MollifiedLaw mdrop(drop, eps);
  EXPECT_NEAR(mdrop.p(0.1) - drop.p_minus(0.1), -3.0 - 80 * eps / 4, 1e-12);
  EXPECT_NEAR(mdrop.p(0.1) - drop.p_plus(0.1), 3.0 - 80 * eps / 4, 1e-12);
}

TEST(LawMollifiedBounds, OneSidedLipschitz) {
  // Disjoint windows, continuous p: p_ε′ interpolates between the slopes, α unchanged.
  EXPECT_NEAR(MollifiedLaw(paper_law(), 1e-3).one_sided_lipschitz(), 100.0, 1e-9);
  EXPECT_NEAR(MollifiedLaw(monotone_law(), 1e-3).one_sided_lipschitz(), 0.0, 1e-12);
  // Downward jump J = −6 at 0.1 with Δs = −80 (slope 100 → 20): inside the window
  // p_ε′(t) = 100 − 80 t − (6·3/ε) t (1 − t), minimised at t* = 1/2 + 80ε/36.
  for (double eps : {1e-3, 1e-6}) {
    SCOPED_TRACE("eps = " + std::to_string(eps));
    const double t = 0.5 + 80 * eps / 36;
    const double dp_min = 100 - 80 * t - 18 / eps * t * (1 - t);
    const double alpha = MollifiedLaw(dropping_law(), eps).one_sided_lipschitz();
    EXPECT_NEAR(alpha, -dp_min, 1e-9 * std::abs(dp_min));
  }
  // Overlapping windows: compare with a dense scan (spacing δ: error ≤ δ²/8 sup|p‴|·… ≪ 1e-6).
  const MollifiedLaw wide(paper_law(), 0.1);
  EXPECT_TRUE(wide.windows_overlap());
  double scan = 0.0;
  for (int i = 0; i <= 200000; ++i) scan = std::max(scan, -wide.dp(-0.3 + 0.7 * i / 200000.0));
  EXPECT_NEAR(wide.one_sided_lipschitz(), scan, 1e-6 * (1.0 + scan));
}

TEST(LawMollifiedBounds, RejectsBadEps) {
  for (double eps : {0.0, -1e-3, double(NAN), INF}) {
    SCOPED_TRACE("eps = " + std::to_string(eps));
    expect_input_error([&] { MollifiedLaw(paper_law(), eps, "solver.eps_nu"); }, {"solver.eps_nu", "eps_nu must be"});
  }
}

TEST(LawMollifiedBounds, MollifierPrimitivesMatchExactOutsideWindow) {
  using namespace mollifier;
  const double eps = 0.01;
  for (double x : {-0.5, -0.011, 0.011, 0.5}) {
    SCOPED_TRACE("x = " + std::to_string(x));
    EXPECT_EQ(smooth_ramp(x, eps), std::max(0.0, x));
    EXPECT_EQ(smooth_step(x, eps), x > 0 ? 1.0 : 0.0);
    EXPECT_EQ(smooth_step_integral(x, eps), std::max(0.0, x));
    // The ramp's antiderivative carries the documented excess ε²/6 beyond the window.
    EXPECT_NEAR(smooth_ramp_integral(x, eps), 0.5 * std::max(0.0, x) * std::max(0.0, x) + (x > 0 ? eps * eps / 6 : 0.0),
                1e-16);
  }
  EXPECT_DOUBLE_EQ(smooth_ramp(0.0, eps), eps / 4);
  EXPECT_DOUBLE_EQ(smooth_step(0.0, eps), 0.5);
  EXPECT_DOUBLE_EQ(smooth_step_d1(0.0, eps), 0.75 / eps);
  EXPECT_DOUBLE_EQ(smooth_step_integral(0.0, eps), 3 * eps / 16);
}

}  // namespace
}  // namespace hemicontact
