#include <hemicontact/driver/polish.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace hemicontact {
namespace {

// Statuses, certificate and energies of condensed unknowns x_C.
Solution evaluate_condensed(const Model& md, const Condensation& cond, const SolveOptions& opt, const Vec& x_C,
                            double load_scale) {
  Solution s;
  s.x = cond.recover(x_C, load_scale);
  s.u = md.dofs.to_full(s.x);
  evaluate_solution(md, opt, s);
  return s;
}

}  // namespace

PolishResult polish_condensed(const Model& md, const Condensation& cond, const SolveOptions& opt, Vec& x_C,
                              double load_scale) {
  PolishResult r;
  const int d = md.dim();
  const Index nc = md.contact.size(), m = cond.m();
  if (d != 2 || nc == 0) {
    r.note = d != 2 ? "3D slip directions are not linear: not polished" : "no Γ3 node";
    return r;
  }
  r.attempted = true;
  const Solution s0 = evaluate_condensed(md, cond, opt, x_C, load_scale);
  r.before = s0.certificate.max_residual;
  const Mat& S = cond.S();
  const Vec yC = load_scale * cond.y_C();

  // Rows: one per unknown. Row ν_k / τ_k either pins the unknown or states the traction balance
  // (S (x − y))_row / w + [branch terms] = 0, multiplied by w to keep S's scale.
  Mat A = Mat::Zero(m, m);
  Vec b0 = Vec::Zero(m);  // λ-independent part of the right-hand side
  std::vector<int> slip_sign(nc, 0);
  for (Index k = 0; k < nc; ++k) {
    const Index iv = d * k, it = d * k + 1;
    const double w = md.contact.w[k], un = s0.state.u_nu[k];
    const NodeStatus st = s0.status[k];
    if (st.normal == NormalStatus::CONTACT) {
      A(iv, iv) = 1;
      b0[iv] = md.contact.g[k];
    } else {
      // p(x) = p(un) + p'(un)(x − un) on un's branch (exact: p is piecewise linear).
      const double p0 = md.normal_law ? md.normal_law->p(un) : 0.0;
      const double dp0 = md.normal_law ? md.normal_law->dp(un) : 0.0;
      A.row(iv) = S.row(iv);
      A(iv, iv) += w * dp0;
      b0[iv] = S.row(iv).dot(yC) - w * (p0 - dp0 * un);
    }
    if (st.tangential == TangentialStatus::STICK || !md.friction) {
      if (st.tangential == TangentialStatus::STICK) {
        A(it, it) = 1;  // x_τ = 0
      } else {
        A.row(it) = S.row(it);  // frictionless: σ_τ = 0
        b0[it] = S.row(it).dot(yC);
      }
    } else {
      slip_sign[k] = st.tangential == TangentialStatus::SLIP_PLUS ? 1 : -1;
      A.row(it) = S.row(it);
      b0[it] = S.row(it).dot(yC);  // − w s λ added per iteration
    }
  }
  const Eigen::PartialPivLU<Mat> lu(A);
  // λ's fixed point contracts like the outer loop; stop at round-off: a change below 1e-14
  // relative, or one that no longer decreases (it then only reflects the solve's round-off).
  Vec x = x_C;
  double prev = INF;
  for (r.iterations = 1; r.iterations <= 100; ++r.iterations) {
    Vec b = b0;
    for (Index k = 0; k < nc; ++k)
      if (slip_sign[k]) b[d * k + 1] -= md.contact.w[k] * slip_sign[k] * md.friction->F(x[d * k]);
    const Vec xn = lu.solve(b);
    const double change = (xn - x).cwiseAbs().maxCoeff(), scale = xn.cwiseAbs().maxCoeff();
    x = xn;
    if (!(change > 1e-14 * scale) || (r.iterations > 1 && change >= prev)) break;
    prev = change;
  }
  if (!x.allFinite()) {
    r.note = "singular status system";
    return r;
  }
  const Solution s1 = evaluate_condensed(md, cond, opt, x, load_scale);
  r.after = s1.certificate.max_residual;
  for (Index k = 0; k < nc; ++k)
    if (s1.status[k].str() != s0.status[k].str()) {
      r.note = "statuses changed at node " + std::to_string(k) + " (" + s0.status[k].str() + " -> " +
               s1.status[k].str() + ")";
      return r;
    }
  // Both at round-off (the smoothed answer can already be exact, e.g. when no node is near a kink
  // or stick) is a tie that the polish wins: it carries no smoothing error by construction.
  if (!(r.after <= std::max(r.before, 1e-12))) {
    r.note = "the certificate did not improve";
    return r;
  }
  r.accepted = true;
  x_C = x;
  return r;
}

}  // namespace hemicontact
