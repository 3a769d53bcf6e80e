// Energy barriers between local minima: the string method on the condensed Γ3 unknowns with λ
// frozen, the highest image refined to an exact saddle on its branch signature, and verified
// (barriers.hpp).

#include <hemicontact/studies/barriers.hpp>

#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/solver/exact_inner.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <memory>

namespace hemicontact {
namespace {

// The condensed energy of the model at load factor 1 with a frozen λ (barriers.hpp).
struct Landscape {
  const Model& md;
  std::shared_ptr<Condensation> C;
  ExactInnerProblem P;
  double L = 0;  // upper bound of the smooth part's curvature: λ_max(S) + max_k w_k max|p_ν'|

  Landscape(const Model& m, const Vec& lambda) : md(m) {
    const Index nc = md.contact.size();
    C = std::make_shared<Condensation>(md.Kx.lower(), md.fx, md.dim() * nc);
    P.S = &C->S();
    P.y = C->y_C();
    P.d = md.dim();
    P.w = md.contact.w;
    P.g = md.contact.g;
    P.lambda = lambda;
    P.law = md.normal_law.get();
    P.fixed.assign(md.contact.fixed_local.begin(), md.contact.fixed_local.end());
    double smax = 0;
    if (P.law)
      for (double s : P.law->slopes()) smax = std::max(smax, std::abs(s));
    L = Eigen::SelfAdjointEigenSolver<Mat>(C->S(), Eigen::EigenvaluesOnly).eigenvalues().maxCoeff() +
        (nc ? P.w.maxCoeff() : 0.0) * smax;
    double fs = md.fx.size() ? md.fx.cwiseAbs().maxCoeff() : 0.0;
    P.traction_scale = std::max(fs / (nc ? P.w.mean() : 1.0), nc ? lambda.cwiseAbs().maxCoeff() : 0.0);
    if (!(P.traction_scale > 0)) P.traction_scale = 1;
  }
  double energy(const Vec& x) const { return exact_inner_energy(P, x) + C->constant(); }
  // x with x_ν ≤ g and the roller-held unknowns at 0 (an interpolation may pass g by an ulp).
  Vec feasible(Vec x) const {
    for (Index k = 0; k < P.w.size(); ++k) {
      x[P.d * k] = std::min(x[P.d * k], P.g[k]);
      for (int c = 0; c < P.d; ++c)
        if (!P.fixed.empty() && (P.fixed[static_cast<size_t>(k)] & (1u << c))) x[P.d * k + c] = 0;
    }
    return x;
  }
  // One proximal-gradient step of Φ_λ with step 1/L (barriers.hpp).
  Vec step(const Vec& x) const {
    Vec g = (*P.S) * (x - P.y);
    const Index nc = P.w.size();
    for (Index k = 0; k < nc; ++k)
      if (P.law) g[P.d * k] += P.w[k] * P.law->p(x[P.d * k]);
    Vec z = x - g / L;
    for (Index k = 0; k < nc; ++k) {
      z[P.d * k] = std::min(z[P.d * k], P.g[k]);
      for (int c = 1; c < P.d; ++c) {
        const double v = z[P.d * k + c], kap = P.w[k] * P.lambda[k] / L;
        z[P.d * k + c] = v > kap ? v - kap : v < -kap ? v + kap : 0.0;
      }
      for (int c = 0; c < P.d; ++c)
        if (!P.fixed.empty() && (P.fixed[static_cast<size_t>(k)] & (1u << c))) z[P.d * k + c] = 0;
    }
    return z;
  }
};

// Images equally spaced in arc length again, by linear interpolation along the polygon.
void reparametrize(std::vector<Vec>& X) {
  const size_t M = X.size() - 1;
  std::vector<double> s(M + 1, 0.0);
  for (size_t i = 1; i <= M; ++i) s[i] = s[i - 1] + (X[i] - X[i - 1]).norm();
  if (!(s[M] > 0)) return;
  std::vector<Vec> Y(X);
  size_t j = 0;
  for (size_t i = 1; i < M; ++i) {
    const double t = s[M] * static_cast<double>(i) / static_cast<double>(M);
    while (j + 1 < M && s[j + 1] < t) ++j;
    const double h = s[j + 1] - s[j], a = h > 0 ? (t - s[j]) / h : 0.0;
    Y[i] = (1 - a) * X[j] + a * X[j + 1];
  }
  X.swap(Y);
}

// The converged string from xa to xb (barriers.hpp); @p steps returns the steps taken.
std::vector<Vec> string_path(const Landscape& E, const Vec& xa, const Vec& xb, const BarrierOptions& bo, int& steps) {
  const int M = bo.images - 1;
  std::vector<Vec> X(static_cast<size_t>(M + 1));
  for (int i = 0; i <= M; ++i) X[static_cast<size_t>(i)] = xa + (xb - xa) * (static_cast<double>(i) / M);
  const double scale = std::max({xa.cwiseAbs().maxCoeff(), xb.cwiseAbs().maxCoeff(), 1e-300});
  for (steps = 1; steps <= bo.max_steps; ++steps) {
    const std::vector<Vec> old = X;
    for (int i = 1; i < M; ++i) X[static_cast<size_t>(i)] = E.step(X[static_cast<size_t>(i)]);
    reparametrize(X);
    for (int i = 1; i < M; ++i) X[static_cast<size_t>(i)] = E.feasible(X[static_cast<size_t>(i)]);
    double moved = 0;
    for (int i = 1; i < M; ++i) moved = std::max(moved, (X[static_cast<size_t>(i)] - old[static_cast<size_t>(i)]).cwiseAbs().maxCoeff());
    if (moved <= bo.string_tol * scale) break;
  }
  return X;
}

// The piece of p_ν that r lies on (the count of breakpoints ≤ r).
int piece_index(const PiecewiseLinearLaw& law, double r) {
  const auto& b = law.breakpoints();
  return static_cast<int>(std::upper_bound(b.begin(), b.end(), r) - b.begin());
}

// p_ν = A + s r on piece i.
std::pair<double, double> piece_line(const PiecewiseLinearLaw& law, int i) {
  const auto& b = law.breakpoints();
  const double s = law.slopes()[static_cast<size_t>(i)];
  const double A = i == 0 ? law.values_left()[0] - s * b[0] : law.values_right()[static_cast<size_t>(i - 1)] - s * b[static_cast<size_t>(i - 1)];
  return {A, s};
}

// The stationary point of Φ_λ on the branch signature of @p x (2D; barriers.hpp), with its
// checks filled into @p side. False when the point is off its signature.
bool saddle_on_signature(const Landscape& E, const Vec& x, const BarrierOptions& bo, BarrierSide& side) {
  const ExactInnerProblem& P = E.P;
  const Mat& S = *P.S;
  const Index m = x.size(), nc = P.w.size();
  Mat A = S, H = S;
  Vec rhs = S * P.y;
  std::vector<bool> keep(static_cast<size_t>(m), true);
  std::vector<int> piece(static_cast<size_t>(nc), -1);
  for (Index k = 0; k < nc; ++k) {
    const Index iv = 2 * k, it = 2 * k + 1;
    const auto pin = [&](Index i, double v) { A.row(i).setZero(), A(i, i) = 1, rhs[i] = v, keep[static_cast<size_t>(i)] = false; };
    if (x[iv] >= P.g[k]) {
      pin(iv, P.g[k]);
    } else if (P.law) {
      piece[static_cast<size_t>(k)] = piece_index(*P.law, x[iv]);
      const auto [a0, s] = piece_line(*P.law, piece[static_cast<size_t>(k)]);
      A(iv, iv) += P.w[k] * s, H(iv, iv) += P.w[k] * s, rhs[iv] -= P.w[k] * a0;
    }
    if (P.lambda[k] > 0 && x[it] == 0)
      pin(it, 0.0);
    else
      rhs[it] -= P.w[k] * P.lambda[k] * (x[it] > 0 ? 1.0 : -1.0);
  }
  const Vec z = A.fullPivLu().solve(rhs);
  for (Index k = 0; k < nc; ++k) {
    const int i = piece[static_cast<size_t>(k)];
    if (i >= 0 && (z[2 * k] >= P.g[k] || piece_index(*P.law, z[2 * k]) != i)) return false;
    if (keep[static_cast<size_t>(2 * k + 1)] && P.lambda[k] > 0 && z[2 * k + 1] * x[2 * k + 1] <= 0) return false;
  }
  std::vector<Index> idx;
  for (Index i = 0; i < m; ++i)
    if (keep[static_cast<size_t>(i)]) idx.push_back(i);
  Mat Hr(static_cast<Index>(idx.size()), static_cast<Index>(idx.size()));
  for (size_t a = 0; a < idx.size(); ++a)
    for (size_t b = 0; b < idx.size(); ++b) Hr(Index(a), Index(b)) = H(idx[a], idx[b]);
  const Vec ev = Eigen::SelfAdjointEigenSolver<Mat>(Hr, Eigen::EigenvaluesOnly).eigenvalues();
  const double tiny = bo.round_off * std::max(ev.cwiseAbs().maxCoeff(), 1e-300);
  side.negative = static_cast<int>((ev.array() < -tiny).count());
  side.residual = exact_inner_residual(P, z);
  side.saddle = z;
  side.energy_saddle = E.energy(z);
  side.verified = side.residual <= bo.saddle_tol && side.negative == 1;
  if (!side.verified)
    side.note = "stationary point on the highest image's signature: residual " + fmt(side.residual, 3) + ", " +
                std::to_string(side.negative) + " negative eigenvalue(s)";
  return true;
}

// One side of a barrier: the string on @p E from xa to xb, its saddle refined and verified.
// The saddle of one segment of the path (images X, its profile): the exact stationary point on the
// signature of the highest image or of one of its neighbours, the first verified one (or the last
// found). False when the highest point is an end (no barrier on this segment).
bool segment_saddle(const Landscape& E, const std::vector<Vec>& X, const std::vector<double>& prof,
                    const BarrierOptions& bo, BarrierSide& seg) {
  const int top = static_cast<int>(std::max_element(prof.begin(), prof.end()) - prof.begin());
  if (top == 0 || top == static_cast<int>(X.size()) - 1) return false;
  seg.note = "no stationary point on the signatures of the highest image and its neighbours";
  for (int off : {0, -1, 1, -2, 2}) {
    const int i = top + off;
    if (i <= 0 || i >= static_cast<int>(X.size()) - 1) continue;
    BarrierSide trial = seg;
    if (!saddle_on_signature(E, X[static_cast<size_t>(i)], bo, trial)) continue;
    seg = trial;
    if (seg.verified) {
      seg.note.clear();
      break;
    }
  }
  return true;
}

// The minimum-energy path from xa to xb on E, segment by segment (barriers.hpp): the string, split
// at each interior local minimum of its profile (relaxed to a minimum of Φ_λ by the local
// descent), each piece a string of its own; every segment's saddle refined. The side keeps the
// highest saddle; it is verified when every segment's is.
void chain(const Landscape& E, const Vec& xa, const Vec& xb, const BarrierOptions& bo, int depth, BarrierSide& side) {
  int steps = 0;
  const std::vector<Vec> X = string_path(E, xa, xb, bo, steps);
  side.steps += steps;
  std::vector<double> prof;
  for (const Vec& x : X) prof.push_back(E.energy(x));
  const double noise = bo.round_off * std::max(std::abs(prof.front()), std::abs(prof.back()));
  std::vector<Vec> stops{xa};
  for (size_t i = 1; i + 1 < prof.size() && depth < bo.max_depth; ++i)
    if (prof[i] < prof[i - 1] - noise && prof[i] < prof[i + 1] - noise) {
      Vec c = X[i];
      ExactInnerOptions lo;
      lo.local_descent = true;
      exact_inner_solve(E.P, c, lo);
      stops.push_back(E.feasible(c));
    }
  stops.push_back(xb);
  if (stops.size() > 2) {
    side.intermediate += static_cast<int>(stops.size()) - 2;
    for (size_t q = 0; q + 1 < stops.size(); ++q) chain(E, stops[q], stops[q + 1], bo, depth + 1, side);
    return;
  }
  side.profile.insert(side.profile.end(), prof.begin(), prof.end());
  BarrierSide seg;
  if (!segment_saddle(E, X, prof, bo, seg)) return;
  side.all_verified = side.all_verified && seg.verified;
  if (!seg.verified && side.note.empty()) side.note = seg.note;
  if (side.saddle.size() == 0 || seg.energy_saddle > side.energy_saddle) {
    side.saddle = seg.saddle;
    side.energy_saddle = seg.energy_saddle;
    side.residual = seg.residual;
    side.negative = seg.negative;
  }
  side.saddles.push_back(seg.energy_saddle);
}

void run_side(const Landscape& E, const Vec& xa, const Vec& xb, const BarrierOptions& bo, BarrierSide& side) {
  // The minima as the solver left them may sit an ulp beyond g: on the bound.
  chain(E, E.feasible(xa), E.feasible(xb), bo, 0, side);
  side.energy_min = E.energy(E.feasible(xa));
  side.neighbours = side.intermediate == 0;
  side.verified = side.all_verified && side.saddle.size() > 0;
  if (side.saddle.size() == 0) side.note = "the path rises from one end to the other: no saddle between these two";
  side.barrier = side.energy_saddle - side.energy_min;
}

Vec gamma3_of(const Model& md, const Solution& s) { return s.x.tail(md.dim() * md.contact.size()); }

// The barrier between minima a and b of @p R (barriers.hpp: λ frozen per side where it depends on u).
Barrier barrier_between(const Model& md, const MinimaReport& R, int a, int b, const BarrierOptions& bo) {
  Barrier B;
  B.a = a, B.b = b;
  B.from_a.minimum = a, B.from_b.minimum = b;
  const Solution &sa = R.solutions[static_cast<size_t>(a)].solution, &sb = R.solutions[static_cast<size_t>(b)].solution;
  const Vec xa = gamma3_of(md, sa), xb = gamma3_of(md, sb);
  const bool lagged = md.friction && md.friction->depends_on_u_nu();
  if (!lagged) {
    const Landscape E(md, md.friction ? sa.state.lambda : Vec(Vec::Zero(md.contact.size())));
    run_side(E, xa, xb, bo, B.from_a);
    B.from_b = B.from_a;
    B.from_b.minimum = b;
    B.from_b.energy_min = B.from_a.profile.back();
    B.from_b.barrier = B.from_b.energy_saddle - B.from_b.energy_min;
    std::reverse(B.from_b.profile.begin(), B.from_b.profile.end());
    B.from_a.lambda = B.from_b.lambda = md.friction ? "Tresca (independent of u)" : "none (frictionless)";
    return B;
  }
  for (BarrierSide* side : {&B.from_a, &B.from_b}) {
    const bool at_a = side == &B.from_a;
    const Landscape E(md, (at_a ? sa : sb).state.lambda);
    Vec far = E.feasible(at_a ? xb : xa);  // relaxed on this side's Φ_λ by the local descent
    ExactInnerOptions lo;
    lo.local_descent = true;
    exact_inner_solve(E.P, far, lo);
    side->lambda = "frozen at minimum " + std::to_string(at_a ? a : b) + "'s own lambda = F_b(u_nu)";
    run_side(E, at_a ? xa : xb, far, bo, *side);
  }
  return B;
}

}  // namespace

void require_barrier_scene(const Model& md) {
  if (md.dim() != 2) input_error("minima --barriers: 2D scenes only (3D slip directions make the saddle conditions nonlinear)");
  if (md.normal_law && md.normal_law->one_sided_lipschitz() == INF)
    input_error("minima --barriers: p_nu jumps downward, so j_nu has no gradient there and the string method does not apply");
}

std::vector<Barrier> find_barriers(const Model& md, const SolveOptions& opt, const MinimaReport& R,
                                   const BarrierOptions& bo) {
  (void)opt;
  require_barrier_scene(md);
  if (bo.minima < 2 || bo.images < 3 || !(bo.string_tol > 0) || bo.max_steps < 1 || !(bo.saddle_tol > 0) ||
      !(bo.round_off > 0) || bo.max_depth < 0)
    input_error("minima --barriers: bad options (at least 2 minima, 3 images, positive tolerances)");
  std::vector<int> minima;
  for (size_t k = 0; k < R.solutions.size() && static_cast<int>(minima.size()) < bo.minima; ++k)
    if (R.solutions[k].second_order.verdict == "local minimum") minima.push_back(static_cast<int>(k));
  std::vector<Barrier> out;
  for (size_t i = 0; i < minima.size(); ++i)
    for (size_t j = i + 1; j < minima.size(); ++j) {
      out.push_back(barrier_between(md, R, minima[i], minima[j], bo));
      const Barrier& B = out.back();
      log_info() << "barrier " << B.a << " - " << B.b << ": saddle " << fmt(B.from_a.energy_saddle, 10) << " ("
                 << (B.from_a.verified ? "verified" : "NOT verified") << "), barrier " << fmt(B.from_a.barrier, 6)
                 << " from " << B.a << ", " << fmt(B.from_b.barrier, 6) << " from " << B.b << "; "
                 << B.from_a.steps << " string steps";
    }
  return out;
}

Solution state_of_gamma3(const Model& md, const SolveOptions& opt, const Vec& x) {
  const Condensation C(md.Kx.lower(), md.fx, x.size());
  Solution s;
  s.x = C.recover(x);
  s.u = md.dofs.to_full(s.x);
  evaluate_solution(md, opt, s);
  return s;
}

}  // namespace hemicontact
