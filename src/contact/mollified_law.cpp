#include <hemicontact/contact/mollified_law.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/types.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

namespace hemicontact {

namespace mollifier {

// All six functions use t = (x + ε)/(2ε) ∈ (0, 1) inside the window. The branches at |x| = ε
// agree in value and first derivative, which is what makes p_ε C¹ and j_ε C².

double smooth_ramp(double x, double eps) {
  if (x <= -eps) return 0.0;
  if (x >= eps) return x;
  const double y = x + eps;
  return y * y / (4.0 * eps);
}

double smooth_ramp_d1(double x, double eps) {
  if (x <= -eps) return 0.0;
  if (x >= eps) return 1.0;
  return (x + eps) / (2.0 * eps);
}

double smooth_ramp_integral(double x, double eps) {
  if (x <= -eps) return 0.0;
  // ∫_{-ε}^{ε} (y+ε)²/(4ε) dy = (2ε)³/(12ε) = 2ε²/3 = ε²/2 + ε²/6: the ramp's own ½x² plus the
  // constant excess ε²/6 of the mollified ramp over (x)_+.
  if (x >= eps) return 0.5 * x * x + eps * eps / 6.0;
  const double y = x + eps;
  return y * y * y / (12.0 * eps);
}

double smooth_step(double x, double eps) {
  if (x <= -eps) return 0.0;
  if (x >= eps) return 1.0;
  const double t = (x + eps) / (2.0 * eps);
  return t * t * (3.0 - 2.0 * t);
}

double smooth_step_d1(double x, double eps) {
  if (x <= -eps || x >= eps) return 0.0;
  const double t = (x + eps) / (2.0 * eps);
  // d/dx t²(3 − 2t) = 6t(1 − t) · dt/dx, dt/dx = 1/(2ε).
  return 3.0 * t * (1.0 - t) / eps;
}

double smooth_step_integral(double x, double eps) {
  if (x <= -eps) return 0.0;
  // S_ε − H is odd about 0, so its integral over the window vanishes: beyond it, exactly (x)_+.
  if (x >= eps) return x;
  const double t = (x + eps) / (2.0 * eps);
  // ∫ t²(3 − 2t) dx = 2ε ∫ (3t² − 2t³) dt = 2ε (t³ − t⁴/2) = ε t³ (2 − t).
  return eps * t * t * t * (2.0 - t);
}

}  // namespace mollifier

MollifiedLaw::MollifiedLaw(std::shared_ptr<const PiecewiseLinearLaw> law, double eps_nu, const std::string& context)
    : m_law(std::move(law)), m_eps(eps_nu) {
  if (!m_law) throw Error(context + ": MollifiedLaw needs a normal law (got null)", EXIT_INTERNAL);
  if (!(std::isfinite(eps_nu) && eps_nu > 0.0)) {
    std::ostringstream os;
    os << context << ": eps_nu must be a finite number > 0 (got " << eps_nu << ")";
    input_error(os.str());
  }
  m_P0 = antiderivative(0.0);
}

MollifiedLaw::MollifiedLaw(const PiecewiseLinearLaw& law, double eps_nu, const std::string& context)
    : MollifiedLaw(std::make_shared<const PiecewiseLinearLaw>(law), eps_nu, context) {}

double MollifiedLaw::antiderivative(double r) const {
  const auto& rk = m_law->breakpoints();
  const auto& ds = m_law->slope_changes();
  const auto& jk = m_law->jumps();
  double v = m_law->affine_intercept() * r + 0.5 * m_law->slope_left() * r * r;
  for (std::size_t k = 0; k < rk.size(); ++k) {
    const double x = r - rk[k];
    v += ds[k] * mollifier::smooth_ramp_integral(x, m_eps) + jk[k] * mollifier::smooth_step_integral(x, m_eps);
  }
  return v;
}

double MollifiedLaw::j(double r) const { return antiderivative(r) - m_P0; }

double MollifiedLaw::p(double r) const {
  const auto& rk = m_law->breakpoints();
  const auto& ds = m_law->slope_changes();
  const auto& jk = m_law->jumps();
  double v = m_law->affine_intercept() + m_law->slope_left() * r;
  for (std::size_t k = 0; k < rk.size(); ++k) {
    const double x = r - rk[k];
    v += ds[k] * mollifier::smooth_ramp(x, m_eps) + jk[k] * mollifier::smooth_step(x, m_eps);
  }
  return v;
}

double MollifiedLaw::dp(double r) const {
  const auto& rk = m_law->breakpoints();
  const auto& ds = m_law->slope_changes();
  const auto& jk = m_law->jumps();
  double v = m_law->slope_left();
  for (std::size_t k = 0; k < rk.size(); ++k) {
    const double x = r - rk[k];
    v += ds[k] * mollifier::smooth_ramp_d1(x, m_eps) + jk[k] * mollifier::smooth_step_d1(x, m_eps);
  }
  return v;
}

Interval MollifiedLaw::subdifferential(double r) const {
  const double v = p(r);
  return {v, v};
}

double MollifiedLaw::one_sided_lipschitz() const {
  // p_ε′ is constant outside all windows (the exact slopes) and, between two consecutive window
  // edges, a sum of constants, linear q_ε′ pieces and quadratic S_ε′ pieces: a quadratic. Its
  // minimum on each such interval is at an end or at the vertex, found from three samples.
  std::vector<double> edges;
  for (double rk : m_law->breakpoints()) {
    edges.push_back(rk - m_eps);
    edges.push_back(rk + m_eps);
  }
  std::sort(edges.begin(), edges.end());
  double dp_min = std::min(m_law->slope_left(), m_law->slope_right());
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    const double a = edges[i], b = edges[i + 1], len = b - a;
    if (!(len > 0.0)) continue;
    const double f0 = dp(a), fm = dp(a + 0.5 * len), f1 = dp(b);
    dp_min = std::min({dp_min, f0, f1});
    // f(s) = f0 + B s + A s², s ∈ [0, 1], interpolating f0, fm, f1.
    const double A = 2.0 * (f0 + f1 - 2.0 * fm);
    const double B = f1 - f0 - A;
    if (A > 0.0) {
      const double s = -B / (2.0 * A);
      if (s > 0.0 && s < 1.0) dp_min = std::min(dp_min, dp(a + s * len));
    }
  }
  return std::max(0.0, -dp_min);
}

bool MollifiedLaw::windows_overlap() const {
  const auto& rk = m_law->breakpoints();
  for (std::size_t k = 0; k + 1 < rk.size(); ++k)
    if (rk[k + 1] - rk[k] < 2.0 * m_eps) return true;
  return false;
}

double MollifiedLaw::p_error_bound() const {
  const auto& ds = m_law->slope_changes();
  const auto& jk = m_law->jumps();
  double max_term = 0.0, sum = 0.0;
  for (std::size_t k = 0; k < ds.size(); ++k) {
    const double term = std::abs(ds[k]) * m_eps / 4.0 + std::abs(jk[k]) / 2.0;
    max_term = std::max(max_term, term);
    sum += term;
  }
  // Disjoint windows: at most one term is inexact at any r. Overlapping: triangle inequality.
  return windows_overlap() ? sum : max_term;
}

double MollifiedLaw::j_error_bound() const {
  // Per term, the integrated error E_k(r) = ∫_{-∞}^r (mollified − exact) lies in [0, M_k] with
  // M_k = ε²/6 (ramp) or 3ε/16 (step, peak at x = 0); j_ε − j_ν = Σ_k [E_k(r) − E_k(0)].
  const auto& ds = m_law->slope_changes();
  const auto& jk = m_law->jumps();
  double sum = 0.0;
  for (std::size_t k = 0; k < ds.size(); ++k)
    sum += std::abs(ds[k]) * m_eps * m_eps / 6.0 + std::abs(jk[k]) * 3.0 * m_eps / 16.0;
  return sum;
}

std::string MollifiedLaw::describe() const {
  std::ostringstream os;
  os << "mollified (eps_nu = " << m_eps << ", alpha_jnu = " << one_sided_lipschitz() << ") of " << m_law->describe();
  return os.str();
}

}  // namespace hemicontact
