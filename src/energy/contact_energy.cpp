#include <hemicontact/energy/contact_energy.hpp>

#include <hemicontact/contact/smooth_norm.hpp>
#include <hemicontact/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hemicontact {

// ------------------------------------------------------------------ normal compliance
NormalComplianceEnergy::NormalComplianceEnergy(std::shared_ptr<const NodalLayout> layout,
                                               std::shared_ptr<const MollifiedLaw> law)
    : NodalTerm(std::move(layout)), m_law(std::move(law)) {
  if (!m_law) throw Error("NormalComplianceEnergy: null law", EXIT_INTERNAL);
}

void NormalComplianceEnergy::set_eps(double eps_nu, const std::string& context) {
  m_law = std::make_shared<const MollifiedLaw>(m_law->exact_ptr(), eps_nu, context);
}

// e_k(x_k) = w_k j_ε(x_ν): ∇e_k = (w_k p_ε(x_ν), 0[, 0]), ∇²e_k = w_k p_ε′(x_ν) e_ν e_νᵀ (j_ε′ = p_ε).
double NormalComplianceEnergy::node_value(Index k, const NodalVector& xk) const {
  return layout().dofs().w[k] * m_law->j(xk[0]);
}

NodalVector NormalComplianceEnergy::node_gradient(Index k, const NodalVector& xk) const {
  NodalVector g = NodalVector::Zero(xk.size());
  g[0] = layout().dofs().w[k] * m_law->p(xk[0]);
  return g;
}

NodalMatrix NormalComplianceEnergy::node_hessian(Index k, const NodalVector& xk, Psd psd) const {
  NodalMatrix H = NodalMatrix::Zero(xk.size(), xk.size());
  double c = layout().dofs().w[k] * m_law->dp(xk[0]);
  if (psd == Psd::CLAMP) c = std::max(c, 0.0);  // softening branch c2 < 0 made convex
  H(0, 0) = c;
  return H;
}

// ------------------------------------------------------------------ friction
namespace {
void check_eps_tau(double eps_tau) {
  if (!(std::isfinite(eps_tau) && eps_tau > 0)) {
    std::ostringstream os;
    os << "FrictionEnergy: eps_tau must be a finite number > 0 (got " << eps_tau << ")";
    throw Error(os.str(), EXIT_INTERNAL);
  }
}
}  // namespace

FrictionEnergy::FrictionEnergy(std::shared_ptr<const NodalLayout> layout, double eps_tau, Vec lambda)
    : NodalTerm(std::move(layout)), m_eps(eps_tau) {
  check_eps_tau(eps_tau);
  set_lambda(std::move(lambda));
}

void FrictionEnergy::set_lambda(Vec lambda) {
  if (lambda.size() != layout().size())
    throw Error("FrictionEnergy: " + std::to_string(lambda.size()) + " friction bounds for " +
                    std::to_string(layout().size()) + " nodes",
                EXIT_INTERNAL);
  m_lambda = std::move(lambda);
}

void FrictionEnergy::set_eps(double eps_tau) {
  check_eps_tau(eps_tau);
  m_eps = eps_tau;
}

// A node with λ_k = 0 contributes exactly nothing (and f0 is not evaluated for it).
double FrictionEnergy::node_value(Index k, const NodalVector& xk) const {
  if (m_lambda[k] == 0) return 0.0;
  const double y = xk.tail(xk.size() - 1).norm();
  return layout().dofs().w[k] * m_lambda[k] * f0(y, m_eps);
}

NodalVector FrictionEnergy::node_gradient(Index k, const NodalVector& xk) const {
  NodalVector g = NodalVector::Zero(xk.size());
  if (m_lambda[k] == 0) return g;
  const auto ut = xk.tail(xk.size() - 1);
  // ∇_u f0(|u|) = f1(|u|) u/|u| = f1_over_y(|u|) u, finite at u = 0.
  g.tail(xk.size() - 1) = layout().dofs().w[k] * m_lambda[k] * f1_over_y(ut.norm(), m_eps) * ut;
  return g;
}

NodalMatrix FrictionEnergy::node_hessian(Index k, const NodalVector& xk, Psd) const {
  const Index nt = xk.size() - 1;
  NodalMatrix H = NodalMatrix::Zero(xk.size(), xk.size());
  if (m_lambda[k] == 0) return H;
  const double c = layout().dofs().w[k] * m_lambda[k];
  const auto ut = xk.tail(nt);
  const double y = ut.norm();
  if (nt == 1) {
    // d²/du² f0(|u|) = f1'(|u|) for scalar u (including u = 0, where f1' = 2/ε).
    H(1, 1) = c * df1(y, m_eps);
    return H;
  }
  // ∇² f0(|u|) = f1/y I + (f1' y − f1)/y³ u uᵀ; at y = 0 the second part vanishes (u uᵀ = 0).
  const double a = f1_over_y(y, m_eps);
  const double b = (y > 0) ? f2_term(y, m_eps) : 0.0;
  for (Index r = 0; r < nt; ++r)
    for (Index s = 0; s <= r; ++s) H(1 + r, 1 + s) = H(1 + s, 1 + r) = c * ((r == s ? a : 0.0) + b * ut[r] * ut[s]);
  return H;
}

}  // namespace hemicontact
