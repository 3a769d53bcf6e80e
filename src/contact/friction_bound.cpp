#include <hemicontact/contact/friction_bound.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/types.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace hemicontact {

namespace {

// F_b(r) interpolated from the table values themselves rather than from the ramp/step sum form:
// a zero value stays exactly zero (no rounding noise of a + b r + Σ …), so the (15c) equality
// test below can be exact.
double table_value(const PiecewiseLinearLaw& f, double r) {
  const auto& rk = f.breakpoints();
  const auto& left = f.values_left();
  const auto& right = f.values_right();
  const auto& s = f.slopes();
  if (r < rk.front()) return left.front() + s.front() * (r - rk.front());
  if (r >= rk.back()) return right.back() + s.back() * (r - rk.back());
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(rk.begin(), rk.end(), r) - rk.begin()) - 1;
  return right[k] + s[k + 1] * (r - rk[k]);
}

double max_abs_slope(const PiecewiseLinearLaw& f) {
  double m = 0.0;
  for (double s : f.slopes()) m = std::max(m, std::abs(s));
  return m;
}

}  // namespace

void check_friction_bound_15c(const PiecewiseLinearLaw& f, double scale, const std::string& context) {
  if (scale == 0.0) return;  // F_b ≡ 0 satisfies (15c) whatever f is.
  const std::string zero_rule = " but (15c) requires F_b(r) = 0 for r <= 0";
  const std::string sign_rule = " but (15c) requires F_b(r) >= 0 for r >= 0";
  const auto& rk = f.breakpoints();
  const auto& left = f.values_left();
  const auto& right = f.values_right();

  // r ≤ 0. With slope_left = 0 and zero values at every breakpoint ≤ 0 and at 0 itself, the
  // piecewise-linear F_b vanishes on all of (−∞, 0].
  if (f.slope_left() != 0.0)
    input_error(context + ": F_b has slope " + fmt(scale * f.slope_left(), 10) + " left of r = " + fmt(rk.front(), 10) +
                " (slope_left)" + zero_rule);
  for (std::size_t k = 0; k < rk.size() && rk[k] <= 0.0; ++k) {
    if (left[k] != 0.0)
      input_error(context + ": F_b(" + fmt(rk[k], 10) + (left[k] != right[k] ? "^-" : "") + ") = " + fmt(scale * left[k], 10) +
                  zero_rule);
    if (right[k] != 0.0) input_error(context + ": F_b(" + fmt(rk[k], 10) + ") = " + fmt(scale * right[k], 10) + zero_rule);
  }
  const double v0 = table_value(f, 0.0);
  if (v0 != 0.0) input_error(context + ": F_b(0) = " + fmt(scale * v0, 10) + zero_rule);

  // r ≥ 0. F_b(0) = 0, so nonnegative one-sided values at the positive breakpoints and a
  // nonnegative final slope make F_b ≥ 0 on [0, ∞).
  for (std::size_t k = 0; k < rk.size(); ++k) {
    if (rk[k] <= 0.0) continue;
    if (left[k] < 0.0)
      input_error(context + ": F_b(" + fmt(rk[k], 10) + (left[k] != right[k] ? "^-" : "") + ") = " + fmt(scale * left[k], 10) +
                  sign_rule);
    if (right[k] < 0.0) input_error(context + ": F_b(" + fmt(rk[k], 10) + ") = " + fmt(scale * right[k], 10) + sign_rule);
  }
  if (f.slope_right() < 0.0)
    input_error(context + ": F_b decreases with slope " + fmt(scale * f.slope_right(), 10) +
                " beyond r = " + fmt(rk.back(), 10) + " (slope_right), so it becomes negative" + sign_rule);
}

// ---------------------------------------------------------------- CoulombLayerBound

CoulombLayerBound::CoulombLayerBound(double mu, std::shared_ptr<const PiecewiseLinearLaw> p, const std::string& context)
    : m_mu(mu), m_law(std::move(p)) {
  if (!(std::isfinite(mu) && mu >= 0.0))
    input_error(context + ".mu: friction coefficient must be a finite number >= 0 (got " + fmt(mu, 10) + ")");
  if (!m_law) input_error(context + ".type: 'coulomb_layer' (F_b = mu p_nu, eq. (34)) needs a normal law");
  try {
    check_friction_bound_15c(*m_law, m_mu, context);
  } catch (const Error& e) {
    // The offending values come from contact.normal_law; say so, or the user edits the wrong key.
    input_error(std::string(e.what()) + " (F_b = mu p_nu, eq. (34); see contact.normal_law)");
  }
}

double CoulombLayerBound::F(double r) const { return m_mu * m_law->p(r); }

double CoulombLayerBound::lipschitz() const {
  if (m_mu == 0.0) return 0.0;  // avoids 0·INF
  if (!m_law->is_continuous()) return INF;
  return m_mu * max_abs_slope(*m_law);
}

bool CoulombLayerBound::depends_on_u_nu() const { return m_mu > 0.0; }

std::string CoulombLayerBound::describe() const {
  const double L = lipschitz();
  return "coulomb_layer F_b = " + fmt(m_mu, 10) +
         " p_nu(u_nu) (34), L_Fb = " + (std::isinf(L) ? std::string("inf") : fmt(L, 10));
}

// ---------------------------------------------------------------- TrescaBound

TrescaBound::TrescaBound(double bound, const std::string& context) : m_bound(bound) {
  if (!(std::isfinite(bound) && bound >= 0.0))
    input_error(context + ".bound: Tresca slip bound must be a finite number >= 0 (got " + fmt(bound, 10) + ")");
}

double TrescaBound::F(double /*r*/) const { return m_bound; }

double TrescaBound::lipschitz() const { return 0.0; }

bool TrescaBound::depends_on_u_nu() const { return false; }

std::string TrescaBound::describe() const { return "tresca F_b = " + fmt(m_bound, 10); }

// ---------------------------------------------------------------- TableBound

TableBound::TableBound(PiecewiseLinearLaw table, const std::string& context) : m_table(std::move(table)) {
  check_friction_bound_15c(m_table, 1.0, context);
}

double TableBound::F(double r) const { return m_table.p(r); }

double TableBound::lipschitz() const {
  if (!m_table.is_continuous()) return INF;
  return max_abs_slope(m_table);
}

bool TableBound::depends_on_u_nu() const {
  const auto zero = [](double v) { return v == 0.0; };
  return !(std::all_of(m_table.values_left().begin(), m_table.values_left().end(), zero) &&
           std::all_of(m_table.values_right().begin(), m_table.values_right().end(), zero) &&
           std::all_of(m_table.slopes().begin(), m_table.slopes().end(), zero));
}

std::string TableBound::describe() const {
  const double L = lipschitz();
  return "table F_b, L_Fb = " + (std::isinf(L) ? std::string("inf") : fmt(L, 10)) + ": " + m_table.describe();
}

}  // namespace hemicontact
