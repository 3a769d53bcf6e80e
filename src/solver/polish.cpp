#include <hemicontact/solver/polish.hpp>

#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/check/status_equations.hpp>
#include <hemicontact/problem/node_rules.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

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

// Keep the polished x_C only if the statuses stay and the certificate does not get worse.
// @p evaluated receives x's evaluation (when x is finite), which the next active-set round reads.
void accept_if_better(const Model& md, const Condensation& cond, const SolveOptions& opt, const Solution& s0,
                      const Vec& x, double load_scale, PolishResult& r, Vec& x_C, Solution* evaluated) {
  if (!x.allFinite()) {
    r.note = "singular status system";
    return;
  }
  Solution s1 = evaluate_condensed(md, cond, opt, x, load_scale);
  r.after = s1.certificate.max_residual;
  r.note = polish_rejection(md, s0, s1, 1e-7 * s0.certificate.length_scale, r.before);
  r.accepted = r.note.empty();
  if (r.accepted) x_C = x;
  if (evaluated) *evaluated = std::move(s1);
}

// 3D: on a slipping node the condition −σ_τ = λ u_τ/|u_τ| (6) is not linear in x_τ, so the status
// system R(x) = 0 is solved by Newton's method with its exact Jacobian, from the smoothed answer:
// R = S (x − y) plus the status equations of check/status_equations.hpp (contact x_ν = g; the
// layer's w p(x_ν), eq. (32); stick x_τ = 0; slip w F_b(x_ν) t, t = x_τ/|x_τ|, eq. (6)), with
// ∂t/∂x_τ = (I − t tᵀ)/|x_τ| and ∂F_b/∂x_ν the slope of F_b's branch (F_b is piecewise linear:
// a central difference over a step far below the branch width is exact up to round-off).
PolishResult polish_condensed_3d(const Model& md, const Condensation& cond, const SolveOptions& opt, const Solution& s0,
                                 Vec& x_C, double load_scale, Vec* candidate, Solution* evaluated) {
  PolishResult r;
  const int d = 3;
  const Index nc = md.contact.size(), m = cond.m();
  r.attempted = true;
  r.before = s0.certificate.max_residual;
  const Mat& S = cond.S();
  const Vec yC = load_scale * cond.y_C();
  const double delta = 1e-7 * s0.certificate.length_scale;  // difference step of F_b's slope

  // R = S (x − y) plus each node's status equations (check/status_equations.hpp, with F_b's x_ν
  // coupling: the LU solve below takes the unsymmetric Jacobian); a pinned unknown's row is the pin.
  const auto residual = [&](const Vec& x, Mat& J) {
    Vec R = S * (x - yC);
    J = S;
    for (Index k = 0; k < nc; ++k) {
      const Index iv = d * k;
      const NodeRows rows = status_rows(node_data(md, k), x.segment<3>(iv), s0.status[static_cast<size_t>(k)],
                                        frictionless_at(md, s0.state.u_nu[k], delta), roller_components(md, k),
                                        delta, true);
      if (rows.singular) return Vec(Vec::Constant(m, std::numeric_limits<double>::quiet_NaN()));
      R.segment<3>(iv) += rows.force;
      J.block<3, 3>(iv, iv) += rows.block;
      for (int c = 0; c < d; ++c)
        if (rows.is_pinned(c)) {
          R[iv + c] = x[iv + c] - rows.pin[c];
          J.row(iv + c).setZero();
          J(iv + c, iv + c) = 1;
        }
    }
    return R;
  };

  // Newton until the step reaches round-off: below 1e-14 relative, or no longer decreasing.
  Vec x = x_C;
  Mat J;
  double prev = INF;
  for (r.iterations = 1; r.iterations <= 50; ++r.iterations) {
    const Vec R = residual(x, J);
    if (!R.allFinite()) {
      r.note = "a slipping node reached u_tau = 0";
      return r;
    }
    const Vec dx = Eigen::PartialPivLU<Mat>(J).solve(-R);
    x += dx;
    const double change = dx.cwiseAbs().maxCoeff(), scale = x.cwiseAbs().maxCoeff();
    if (!(change > 1e-14 * scale) || (r.iterations > 2 && change >= prev)) break;
    prev = change;
  }
  if (candidate && x.allFinite()) *candidate = x;
  accept_if_better(md, cond, opt, s0, x, load_scale, r, x_C, evaluated);
  return r;
}

// 2D: the status system is linear for fixed λ (file comment of polish.hpp).
PolishResult polish_condensed_2d(const Model& md, const Condensation& cond, const SolveOptions& opt, const Solution& s0,
                                 Vec& x_C, double load_scale, Vec* candidate, Solution* evaluated) {
  PolishResult r;
  const int d = 2;
  const Index nc = md.contact.size(), m = cond.m();
  r.attempted = true;
  r.before = s0.certificate.max_residual;
  const Mat& S = cond.S();
  const Vec yC = load_scale * cond.y_C();
  const double delta = 1e-7 * s0.certificate.length_scale;  // branch probe of F_b

  // Rows: one per unknown, each the node's status equation (check/status_equations.hpp) at the
  // start's state: a pin, or the traction balance (S (x − y))_row + [the node's forces] = 0, with
  // p_ν linear on un's branch (exact: p is piecewise linear) and the slip force's λ = F_b(x_ν)
  // lagged (added per iteration below).
  Mat A = Mat::Zero(m, m);
  Vec b0 = Vec::Zero(m);  // λ-independent part of the right-hand side
  std::vector<char> slipping(static_cast<size_t>(nc), 0);
  const auto rows_at = [&](Index k, double x_nu, double x_tau) {
    return status_rows(node_data(md, k), Eigen::Vector3d(x_nu, x_tau, 0), s0.status[static_cast<size_t>(k)],
                       frictionless_at(md, s0.state.u_nu[k], delta), roller_components(md, k), delta, false);
  };
  for (Index k = 0; k < nc; ++k) {
    const Index iv = d * k, it = d * k + 1;
    const double un = s0.state.u_nu[k];
    const NodeRows rows = rows_at(k, un, s0.state.u_tau[k]);
    for (const Index i : {iv, it}) {
      if (rows.is_pinned(static_cast<int>(i - iv))) {
        A(i, i) = 1;
        b0[i] = rows.pin[i - iv];
      } else {
        A.row(i) = S.row(i);
        b0[i] = S.row(i).dot(yC);
      }
    }
    if (!rows.is_pinned(0)) {  // w p(x) = w p(un) + w p'(un)(x − un) on un's branch
      A(iv, iv) += rows.block(0, 0);
      b0[iv] -= rows.force[0] - rows.block(0, 0) * un;
    }
    slipping[static_cast<size_t>(k)] = !rows.is_pinned(1) && s0.status[static_cast<size_t>(k)].tangential !=
                                       TangentialStatus::STICK && !frictionless_at(md, un, delta);
  }
  const Eigen::PartialPivLU<Mat> lu(A);
  // λ's fixed point contracts like the outer loop; stop at round-off: a change below 1e-14
  // relative, or one that no longer decreases (it then only reflects the solve's round-off).
  Vec x = x_C;
  double prev = INF;
  for (r.iterations = 1; r.iterations <= 100; ++r.iterations) {
    Vec b = b0;
    for (Index k = 0; k < nc; ++k)
      if (slipping[static_cast<size_t>(k)]) b[d * k + 1] -= rows_at(k, x[d * k], x[d * k + 1]).force[1];
    const Vec xn = lu.solve(b);
    const double change = (xn - x).cwiseAbs().maxCoeff(), scale = xn.cwiseAbs().maxCoeff();
    x = xn;
    if (!(change > 1e-14 * scale) || (r.iterations > 1 && change >= prev)) break;
    prev = change;
  }
  if (candidate && x.allFinite()) *candidate = x;
  accept_if_better(md, cond, opt, s0, x, load_scale, r, x_C, evaluated);
  return r;
}

// The next status guess of an active-set round, from the rejected candidate @p c of the guess @p g
// (a primal-dual active-set step on the unsmoothed conditions, docs/model.md §4):
//  * primal: the candidate's own statuses (its u_ν picks contact / the branch of p_ν; its u_τ the slip);
//  * dual, normal: a node held at g whose rigid reaction pulls (σ_ν + ξ > 0) is released to the
//    branch of p_ν just below g;
//  * dual, tangential: a sticking node outside the cone (|σ_τ| > λ) slips along −σ_τ; a node that
//    slipped one way in the guess and came out the other way sticks.
// @p n is the candidate @p c evaluated (accept_if_better's); @p start is moved to the candidate,
// with a small tangential start on newly slipping 3D nodes (the slip direction t = x_τ/|x_τ|
// needs x_τ ≠ 0).
Solution next_guess(const Model& md, const SolveOptions& opt, const Solution& g, Solution n, const Vec& c, Vec& start) {
  start = c;
  const int d = md.dim();
  const double U = n.certificate.length_scale, delta = 1e-7 * U;
  for (Index k = 0; k < md.contact.size(); ++k) {
    NodeStatus& st = n.status[k];
    const auto& sg = g.status[k];
    if (sg.normal == NormalStatus::CONTACT && st.normal == NormalStatus::CONTACT &&
        n.state.sigma_nu[k] + n.state.xi[k] > 0) {
      st.normal = NormalStatus::COMPLIANCE;
      n.state.u_nu[k] = md.contact.g[k] - delta;  // the branch of p_ν just below g
    }
    if (frictionless_at(md, n.state.u_nu[k], delta)) continue;
    const bool slip_guess = sg.tangential != TangentialStatus::STICK;
    if (!slip_guess && n.state.sigma_tau_vec.row(k).norm() > n.state.lambda[k] * (1 + 1e-12)) {
      const Vec t = -n.state.sigma_tau_vec.row(k).transpose() / n.state.sigma_tau_vec.row(k).norm();
      if (d == 2) {
        const double s = t.dot(md.contact.tangent.row(k).transpose());
        st.tangential = s > 0 ? TangentialStatus::SLIP_PLUS : TangentialStatus::SLIP_MINUS;
      } else {
        st.tangential = TangentialStatus::SLIP;
        // local tangential unknowns (τ1, ν × τ1) of a small step along t
        const Eigen::Vector3d nu = md.contact.normal.row(k).transpose(), t1 = md.contact.tangent.row(k).transpose();
        const Eigen::Vector3d t2 = nu.cross(t1), tv = t;
        start[d * k + 1] = roller_fixed(md, k, 1) ? 0.0 : 1e-3 * U * tv.dot(t1);
        start[d * k + 2] = roller_fixed(md, k, 2) ? 0.0 : 1e-3 * U * tv.dot(t2);
      }
    } else if (slip_guess && d == 2 && st.tangential != TangentialStatus::STICK && st.tangential != sg.tangential) {
      st.tangential = TangentialStatus::STICK;
    }
  }
  return n;
}

}  // namespace

PolishResult polish_condensed(const Model& md, const Condensation& cond, const SolveOptions& opt, Vec& x_C,
                              double load_scale) {
  if (md.contact.size() == 0) {
    PolishResult r;
    r.note = "no Γ3 node";
    return r;
  }
  const auto run = [&](const SolveOptions& o, const Solution& guess, Vec& x, Vec* candidate, Solution* evaluated) {
    return md.dim() == 3 ? polish_condensed_3d(md, cond, o, guess, x, load_scale, candidate, evaluated)
                         : polish_condensed_2d(md, cond, o, guess, x, load_scale, candidate, evaluated);
  };
  // Round 0 reads the statuses off the smoothed answer. Two things can make them wrong:
  //  * the final ε exceeds check.status_tol: a sticking node has |u_τ| ~ ε_τ U, a node just short
  //    of a kink of p_ν sits ~ε_ν U from it, so it is misread. Round 0 therefore also tries the
  //    statuses read at the smoothing scale, 10 ε;
  //  * a node sits on the wrong side of a kink, of u_τ = 0 or of the cone. The rejected candidate
  //    then shows it, and the next round takes the active-set step of next_guess(), up to
  //    MAX_ROUNDS rounds.
  // Whatever the round, a candidate is kept only if its statuses are self-consistent and its
  // certificate (with the user's status_tol) beats the smoothed answer's.
  constexpr int MAX_ROUNDS = 6;
  const double coarse_tol = 10 * std::max(opt.eps_tau, opt.eps_nu);
  PolishResult first;
  double before = 0;
  Vec start = x_C, candidate;
  Solution guess = evaluate_condensed(md, cond, opt, x_C, load_scale), evaluated;
  // A round's candidate, accepted by its own guess's reading, against the smoothed answer's
  // certificate; @p after is its certificate under opt (a round's own, or evaluated here).
  const auto accept = [&](PolishResult r, const Vec& x, double after, const std::string& how) {
    if (!(after <= std::max(before, 1e-12))) return false;
    r.before = before;
    r.after = after;
    r.note = how;
    first = r;
    x_C = x;
    return true;
  };
  for (int round = 0; round < MAX_ROUNDS; ++round) {
    Vec x = start;
    PolishResult r = run(opt, guess, x, &candidate, &evaluated);
    if (round == 0) {
      first = r;
      before = r.before;
      if (r.accepted) {
        x_C = x;
        return r;
      }
      if (coarse_tol > opt.status_tol) {
        SolveOptions o = opt;
        o.status_tol = coarse_tol;
        Vec xc = start;
        const PolishResult rc = run(o, evaluate_condensed(md, cond, o, xc, load_scale), xc, nullptr, nullptr);
        // read at the coarse status_tol: its certificate under the user's is evaluated anew
        if (rc.accepted &&
            accept(rc, xc, evaluate_condensed(md, cond, opt, xc, load_scale).certificate.max_residual,
                   "statuses read at 10 eps"))
          return first;
      }
    } else if (r.accepted && accept(r, x, r.after, "after " + std::to_string(round) + " active-set round(s)")) {
      return first;
    }
    if (candidate.size() == 0) {
      first.note += "; no candidate to correct the statuses from";
      return first;
    }
    guess = next_guess(md, opt, guess, std::move(evaluated), candidate, start);
    candidate.resize(0);
  }
  first.note += "; no consistent statuses after " + std::to_string(MAX_ROUNDS) + " active-set rounds";
  return first;
}

}  // namespace hemicontact
