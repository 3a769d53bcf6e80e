#include <hemicontact/contact/piecewise_linear_law.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/types.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <utility>

namespace hemicontact {

namespace {

std::string list(const std::vector<double>& v, const char* sep) {
  std::ostringstream os;
  for (std::size_t i = 0; i < v.size(); ++i) os << (i ? sep : "") << fmt(v[i], 10);
  return os.str();
}

double ramp(double x) { return x > 0.0 ? x : 0.0; }

}  // namespace

PiecewiseLinearLaw::PiecewiseLinearLaw(std::vector<Point> points, std::optional<double> slope_left,
                                       std::optional<double> slope_right, const std::string& context)
    : m_points(std::move(points)) {
  const std::string key = context + ".points";
  if (m_points.empty()) input_error(key + ": at least one point [r, p] is required");

  for (std::size_t i = 0; i < m_points.size(); ++i) {
    const auto [r, p] = m_points[i];
    const std::string at = key + "[" + std::to_string(i) + "]";
    if (!std::isfinite(r) || !std::isfinite(p))
      input_error(at + ": values must be finite (r = " + fmt(r, 10) + ", p = " + fmt(p, 10) + ")");
    if (i == 0) {
      m_r.push_back(r);
      m_p_left.push_back(p);
      m_p_right.push_back(p);
      continue;
    }
    const double r_prev = m_points[i - 1][0];
    if (r < r_prev)
      input_error(at + ": r decreases (" + fmt(r, 10) + " after " + fmt(r_prev, 10) + "): p_nu must be a function of r");
    if (r == r_prev) {
      // A second point at the same r is the right limit of a jump; a third one would leave
      // the value of p between the two limits undefined, so it is rejected.
      if (i >= 2 && m_points[i - 2][0] == r)
        input_error(at + ": r = " + fmt(r, 10) + " appears three times; a jump is exactly two points with the same r");
      m_p_right.back() = p;
      continue;
    }
    m_r.push_back(r);
    m_p_left.push_back(p);
    m_p_right.push_back(p);
  }

  const std::size_t nb = m_r.size();
  std::vector<double> segment;
  for (std::size_t k = 0; k + 1 < nb; ++k) {
    const double s = (m_p_left[k + 1] - m_p_right[k]) / (m_r[k + 1] - m_r[k]);
    // Two distinct but nearly equal r with different p give an overflowing slope: a jump
    // must be written as two equal r, not as a steep segment.
    if (!std::isfinite(s))
      input_error(key + "[" + std::to_string(k + 1) + "]: slope of the segment from r = " + fmt(m_r[k], 10) +
                  " to r = " + fmt(m_r[k + 1], 10) + " is not finite (write a jump as two points with equal r)");
    segment.push_back(s);
  }
  // null slopes continue the neighbouring segment; a table with one distinct r has none,
  // and then p is constant on each side of it.
  const double sl = slope_left.value_or(segment.empty() ? 0.0 : segment.front());
  const double sr = slope_right.value_or(segment.empty() ? 0.0 : segment.back());
  if (!std::isfinite(sl)) input_error(context + ".slope_left: must be finite (got " + fmt(sl, 10) + ")");
  if (!std::isfinite(sr)) input_error(context + ".slope_right: must be finite (got " + fmt(sr, 10) + ")");

  m_slopes.reserve(nb + 1);
  m_slopes.push_back(sl);
  m_slopes.insert(m_slopes.end(), segment.begin(), segment.end());
  m_slopes.push_back(sr);
  for (std::size_t k = 0; k < nb; ++k) {
    m_dslope.push_back(m_slopes[k + 1] - m_slopes[k]);
    m_jump.push_back(m_p_right[k] - m_p_left[k]);
  }
  m_a = m_p_left[0] - sl * m_r[0];
  m_P0 = antiderivative(0.0);
}

PiecewiseLinearLaw PiecewiseLinearLaw::paper(double c1, double c2, double c3, double r1, double r2,
                                             const std::string& context) {
  const std::pair<const char*, double> values[] = {{"c1", c1}, {"c2", c2}, {"c3", c3}, {"r1", r1}, {"r2", r2}};
  for (const auto& [name, v] : values)
    if (!std::isfinite(v)) input_error(context + "." + name + ": must be finite (got " + fmt(v, 10) + ")");
  if (!(r1 > 0.0)) input_error(context + ".r1: (32) requires 0 < r1 < r2 (got r1 = " + fmt(r1, 10) + ")");
  if (!(r2 > r1))
    input_error(context + ".r2: (32) requires 0 < r1 < r2 (got r1 = " + fmt(r1, 10) + ", r2 = " + fmt(r2, 10) + ")");
  PiecewiseLinearLaw law({{0.0, 0.0}, {r1, c1 * r1}, {r2, c1 * r1 + c2 * (r2 - r1)}}, 0.0, c3, context);
  law.m_origin = "paper (32) c1=" + fmt(c1, 10) + " c2=" + fmt(c2, 10) + " c3=" + fmt(c3, 10) + " r1=" + fmt(r1, 10) + " r2=" + fmt(r2, 10);
  return law;
}

double PiecewiseLinearLaw::evaluate(double r, double h_at_zero) const {
  double v = m_a + m_slopes.front() * r;
  for (std::size_t k = 0; k < m_r.size(); ++k) {
    const double x = r - m_r[k];
    v += m_dslope[k] * ramp(x);
    if (x > 0.0 || (x == 0.0 && h_at_zero > 0.0)) v += m_jump[k];
  }
  return v;
}

double PiecewiseLinearLaw::antiderivative(double r) const {
  // ∫ (x)_+ = ½ (x)_+²  and  ∫ H(x) = (x)_+ : exact, no quadrature.
  double v = m_a * r + 0.5 * m_slopes.front() * r * r;
  for (std::size_t k = 0; k < m_r.size(); ++k) {
    const double x = ramp(r - m_r[k]);
    v += 0.5 * m_dslope[k] * x * x + m_jump[k] * x;
  }
  return v;
}

double PiecewiseLinearLaw::j(double r) const { return antiderivative(r) - m_P0; }

double PiecewiseLinearLaw::p(double r) const { return evaluate(r, 1.0); }

double PiecewiseLinearLaw::p_plus(double r) const { return evaluate(r, 1.0); }

double PiecewiseLinearLaw::p_minus(double r) const { return evaluate(r, 0.0); }

double PiecewiseLinearLaw::dp(double r) const {
  // The slope of the piece containing r; at r = r_k the right piece (matches p's right limit).
  const auto it = std::upper_bound(m_r.begin(), m_r.end(), r);
  return m_slopes[static_cast<std::size_t>(it - m_r.begin())];
}

Interval PiecewiseLinearLaw::subdifferential(double r) const {
  const double lo = p_minus(r), hi = p_plus(r);
  return {std::min(lo, hi), std::max(lo, hi)};
}

double PiecewiseLinearLaw::one_sided_lipschitz() const {
  // A downward jump J < 0 at r_k: with r1 < r_k < r2 close to it, (ξ1 − ξ2)(r2 − r1) ≈ |J| |r2 − r1|,
  // which no α |r2 − r1|² bounds as r2 − r1 → 0. Upward jumps only help (monotone part).
  for (double jump : m_jump)
    if (jump < 0.0) return INF;
  const double s_min = *std::min_element(m_slopes.begin(), m_slopes.end());
  return std::max(0.0, -s_min);
}

bool PiecewiseLinearLaw::is_continuous() const {
  return std::all_of(m_jump.begin(), m_jump.end(), [](double jump) { return jump == 0.0; });
}

std::string PiecewiseLinearLaw::describe() const {
  std::ostringstream os;
  os << "piecewise-linear p_nu";
  if (!m_origin.empty()) os << " [" << m_origin << "]";
  os << ": breakpoints [" << list(m_r, ", ") << "], slopes " << list(m_slopes, " | ");
  if (is_continuous()) {
    os << ", no jumps";
  } else {
    os << ", jumps [" << list(m_jump, ", ") << "]";
  }
  const double alpha = one_sided_lipschitz();
  os << ", alpha_jnu = " << (std::isinf(alpha) ? std::string("inf") : fmt(alpha, 10));
  return os.str();
}

}  // namespace hemicontact
