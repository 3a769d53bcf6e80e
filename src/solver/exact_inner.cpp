#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/solver/exact_inner.hpp>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace hemicontact {
namespace {

bool held(const ExactInnerProblem& P, Index k, int c) {
  return !P.fixed.empty() && (P.fixed[static_cast<size_t>(k)] & (1u << c));
}

// p_ν on piece i (0: left of the first breakpoint, i: between breakpoints i−1 and i, K: right of
// the last) is affine, p(t) = A + s t; its ends lo < hi. Exact from the table (eq. (32)).
struct Piece {
  double lo, hi, A, s;
};

Piece piece(const PiecewiseLinearLaw& law, size_t i) {
  const auto& b = law.breakpoints();
  const auto& s = law.slopes();
  const size_t K = b.size();
  Piece q;
  q.s = s[i];
  q.lo = i == 0 ? -INF : b[i - 1];
  q.hi = i == K ? INF : b[i];
  if (i == 0)
    q.A = law.values_left()[0] - q.s * b[0];
  else
    q.A = law.values_right()[i - 1] - q.s * b[i - 1];
  return q;
}

// The piece of t: the i with lo < t < hi; −1 when t is a breakpoint (p_ν has a kink or a jump
// there: the node is pinned at it in the Newton step).
int piece_of(const PiecewiseLinearLaw& law, double t) {
  const auto& b = law.breakpoints();
  for (size_t i = 0; i < b.size(); ++i) {
    if (t == b[i]) return -1;
    if (t < b[i]) return static_cast<int>(i);
  }
  return static_cast<int>(b.size());
}

// The exact proximal map of the normal unknown: the global minimizer over t ≤ g of
//   φ(t) = ½ a (t − x0)² + r0 (t − x0) + w j_ν(t),
// the restriction of Φ_λ to one normal unknown (a = S_ii > 0, r0 = its gradient at x0). On each
// piece φ is quadratic with curvature a + w s: its stationary point clipped to the piece, or the
// piece's ends when the curvature is not positive, are the candidates; breakpoints are ends.
// x0 itself is a candidate, so φ never increases. NaN if φ is unbounded below (an outer slope of
// p_ν below −a/w: no minimizer exists).
double normal_prox(double a, double x0, double r0, double w, double g, const PiecewiseLinearLaw* law) {
  if (!law) return std::min(x0 - r0 / a, g);
  const auto phi = [&](double t) { return 0.5 * a * (t - x0) * (t - x0) + r0 * (t - x0) + w * law->j(t); };
  double best = std::min(x0, g), fbest = phi(best);
  const auto consider = [&](double t) {
    if (!(t <= g) || !std::isfinite(t)) return;
    const double f = phi(t);
    if (f < fbest) best = t, fbest = f;
  };
  const size_t K = law->breakpoints().size();
  for (size_t i = 0; i <= K; ++i) {
    const Piece q = piece(*law, i);
    const double hi = std::min(q.hi, g);
    if (!(q.lo <= hi)) continue;
    const double c = a + w * q.s;
    if (c > 0) {
      // φ'(t) = a (t − x0) + r0 + w (A + s t) = 0
      consider(std::clamp((a * x0 - r0 - w * q.A) / c, q.lo, hi));
    } else if (!std::isfinite(q.lo)) {
      return NaN;  // concave (or linear and decreasing) towards −∞ on an unbounded piece
    } else if (!std::isfinite(hi)) {
      return NaN;  // towards +∞ with no obstacle
    }
    consider(q.lo);
    consider(hi);
  }
  return best;
}

// The local counterpart of normal_prox (ExactInnerOptions::local_descent): from x0 downhill along
// the same φ, piece by piece, to the first point where φ stops decreasing: a stationary point inside
// a piece (curvature a + w s > 0 there), a breakpoint where φ' changes sign, or g. Pieces are
// numbered as in piece(): the one right of t is the count of breakpoints ≤ t, the one left of t the
// count of breakpoints < t. NaN where φ decreases without end (an unbounded piece).
double normal_descent(double a, double x0, double r0, double w, double g, const PiecewiseLinearLaw* law) {
  if (!law) return std::min(x0 - r0 / a, g);
  const auto& b = law->breakpoints();
  const int K = static_cast<int>(b.size());
  const int right = static_cast<int>(std::upper_bound(b.begin(), b.end(), x0) - b.begin());
  const int left = static_cast<int>(std::lower_bound(b.begin(), b.end(), x0) - b.begin());
  const auto dphi = [&](int i, double t) {  // φ' on piece i at t
    const Piece q = piece(*law, static_cast<size_t>(i));
    return a * (t - x0) + r0 + w * (q.A + q.s * t);
  };
  const auto stationary = [&](int i) {  // φ' = 0 on piece i, or NaN where φ is not convex there
    const Piece q = piece(*law, static_cast<size_t>(i));
    const double c = a + w * q.s;
    return c > 0 ? (a * x0 - r0 - w * q.A) / c : NaN;
  };
  const auto up = [&]() -> double {  // φ' < 0 right of x0: walk right
    for (int i = right; i <= K; ++i) {
      const double hi = std::min(piece(*law, static_cast<size_t>(i)).hi, g), ts = stationary(i);
      if (ts < hi) return ts;  // inside the piece (ts > the walk's point: φ' < 0 there and c > 0)
      if (!std::isfinite(hi)) return NaN;
      if (hi == g || dphi(i + 1, hi) >= 0) return hi;
    }
    return g;
  };
  const auto down = [&]() -> double {  // φ' > 0 left of x0: walk left
    for (int i = left; i >= 0; --i) {
      const double lo = piece(*law, static_cast<size_t>(i)).lo, ts = stationary(i);
      if (ts > lo) return ts;
      if (!std::isfinite(lo)) return NaN;
      if (dphi(i - 1, lo) <= 0) return lo;
    }
    return NaN;
  };
  const bool go_up = x0 < g && dphi(right, x0) < 0, go_down = dphi(left, x0) > 0;
  if (go_up && go_down) {  // a concave kink at x0: the lower of the two descents
    const double tu = up(), td = down();
    const auto phi = [&](double t) { return 0.5 * a * (t - x0) * (t - x0) + r0 * (t - x0) + w * law->j(t); };
    return std::isnan(tu) || std::isnan(td) ? NaN : (phi(tu) <= phi(td) ? tu : td);
  }
  return go_up ? up() : go_down ? down() : x0;
}

// Soft threshold, the exact proximal map of τ ↦ κ|τ|.
double soft(double v, double kappa) { return v > kappa ? v - kappa : v < -kappa ? v + kappa : 0.0; }

}  // namespace

double exact_inner_energy(const ExactInnerProblem& P, const Vec& x) {
  const Vec e = x - P.y;
  double E = 0.5 * e.dot(*P.S * e);
  const Index nc = P.w.size();
  for (Index k = 0; k < nc; ++k) {
    const double xn = x[P.d * k];
    if (xn > P.g[k]) return INF;
    if (P.law) E += P.w[k] * P.law->j(xn);
    E += P.w[k] * P.lambda[k] * x.segment(P.d * k + 1, P.d - 1).norm();
  }
  return E;
}

double exact_inner_residual(const ExactInnerProblem& P, const Vec& x) {
  const Vec r = *P.S * (x - P.y);  // w σ in the nodes' (ν, τ) frames
  const Index nc = P.w.size();
  const int d = P.d;
  double res = 0;
  for (Index k = 0; k < nc; ++k) {
    const double w = P.w[k], xn = x[d * k], sn = r[d * k] / w;
    const Interval I = P.law ? P.law->subdifferential(xn) : Interval{0, 0};
    double rn;
    if (xn > P.g[k])
      rn = INF;
    else if (xn == P.g[k])
      rn = std::max(0.0, sn + I.lo);  // the rigid part may push (σ_ν + ξ ≤ 0), eq. (5)
    else
      rn = std::max({0.0, -sn - I.hi, sn + I.lo});  // distance of −σ_ν to ∂j_ν(x_ν)
    if (held(P, k, 0)) rn = 0;
    Vec st = Vec::Zero(d - 1), ut = Vec::Zero(d - 1);
    for (int c = 1; c < d; ++c)
      if (!held(P, k, c)) st[c - 1] = r[d * k + c] / w, ut[c - 1] = x[d * k + c];
    const double y = ut.norm(), lam = P.lambda[k];
    const double rt = y > 0 ? (st + lam * ut / y).norm() : std::max(0.0, st.norm() - lam);
    res = std::max({res, rn, rt});
  }
  return res / P.traction_scale;
}

namespace {

// The Newton step's statuses: which unknowns are held and the piece of each free normal unknown.
struct ActiveSet {
  std::vector<Index> free;  // free unknowns, increasing
  std::vector<int> code;    // per unknown: −1 held, else the piece (normal) or 0 (tangential)
  bool operator==(const ActiveSet& o) const { return code == o.code; }
};

ActiveSet active_set(const ExactInnerProblem& P, const Vec& x) {
  const Index nc = P.w.size();
  const int d = P.d;
  ActiveSet A;
  A.code.assign(static_cast<size_t>(d * nc), 0);
  for (Index k = 0; k < nc; ++k) {
    const double xn = x[d * k];
    int& cn = A.code[static_cast<size_t>(d * k)];
    if (held(P, k, 0) || xn >= P.g[k])
      cn = -1;  // contact: x_ν = g
    else if (P.law)
      cn = piece_of(*P.law, xn);  // −1 on a breakpoint
    const bool stick = P.lambda[k] > 0 && x.segment(d * k + 1, d - 1).squaredNorm() == 0;
    for (int c = 1; c < d; ++c)
      if (held(P, k, c) || stick) A.code[static_cast<size_t>(d * k + c)] = -1;
  }
  for (Index i = 0; i < d * nc; ++i)
    if (A.code[static_cast<size_t>(i)] >= 0) A.free.push_back(i);
  return A;
}

}  // namespace

// The reduced Hessian's factor of the active set `cached` (ExactInnerFactor).
struct ExactInnerFactor::Impl {
  ActiveSet cached;
  Eigen::LLT<Mat> llt;
  Eigen::LDLT<Mat> ldlt;
  bool factored = false, use_llt = false;
};
ExactInnerFactor::ExactInnerFactor() : m(std::make_unique<Impl>()) {}
ExactInnerFactor::~ExactInnerFactor() = default;

namespace {

// The state of one exact_inner_solve: x and r = S (x − y) (kept together), Φ_λ(x), and the
// reduced Hessian's factor kept across Newton steps (and, given one, across solves).
class InnerSolver {
 public:
  InnerSolver(const ExactInnerProblem& P, Vec& x, const ExactInnerOptions& opt, ExactInnerResult& R,
              ExactInnerFactor::Impl& F)
      : P(P), S(*P.S), d(P.d), nc(P.w.size()), m(d * nc), x(x), opt(opt), R(R), F(F) {}
  void start();
  bool sweep();
  bool newton();
  double& energy() { return E; }
  void refresh_r() { r = S * (x - P.y); }

 private:
  void move(Index i, double t);
  Vec piece_gradient(const ActiveSet& A, std::vector<std::pair<Index, Eigen::Matrix2d>>& slip_blocks) const;
  bool factor(const ActiveSet& A, const std::vector<std::pair<Index, Eigen::Matrix2d>>& slip_blocks);
  bool line_search(const ActiveSet& A, const Vec& dF);
  double step_cap(const ActiveSet& A, const Vec& dF) const;

  const ExactInnerProblem& P;
  const Mat& S;
  const int d;
  const Index nc, m;
  Vec& x;
  const ExactInnerOptions& opt;
  ExactInnerResult& R;
  ExactInnerFactor::Impl& F;  // a factor of the reduced Hessian of F.cached
  Vec r;
  double E = 0;
};

void InnerSolver::start() {
  for (Index k = 0; k < nc; ++k) {
    x[d * k] = std::min(x[d * k], P.g[k]);
    for (int c = 0; c < d; ++c)
      if (held(P, k, c)) x[d * k + c] = 0;
  }
  r = S * (x - P.y);
  E = exact_inner_energy(P, x);
}

void InnerSolver::move(Index i, double t) {
  const double dt = t - x[i];
  if (dt == 0) return;
  x[i] = t;
  r += dt * S.col(i);
}

// One sweep of exact proximal coordinate steps (file comment); r follows x by rank-one updates.
// False if Φ_λ is unbounded below along a normal unknown.
bool InnerSolver::sweep() {
  for (Index k = 0; k < nc; ++k) {
    const Index iv = d * k;
    const double w = P.w[k], lam = P.lambda[k];
    if (!held(P, k, 0)) {
      const double t = opt.local_descent ? normal_descent(S(iv, iv), x[iv], r[iv], w, P.g[k], P.law)
                                         : normal_prox(S(iv, iv), x[iv], r[iv], w, P.g[k], P.law);
      if (std::isnan(t)) return false;
      move(iv, t);
    }
    if (d == 2 || held(P, k, 1) || held(P, k, 2)) {
      for (int c = 1; c < d; ++c)
        if (!held(P, k, c)) {
          const Index i = iv + c;
          const double a = S(i, i);
          move(i, soft(x[i] - r[i] / a, w * lam / a));
        }
    } else {
      // 3D: proximal-gradient step on the tangential block, majorized by L = λ_max(S_ττ);
      // the proximal map of w λ |·| is the disk shrink.
      const Index i = iv + 1;
      const double a = S(i, i), b = S(i, i + 1), c = S(i + 1, i + 1);
      const double L = 0.5 * (a + c) + std::sqrt(0.25 * (a - c) * (a - c) + b * b);
      Eigen::Vector2d z = x.segment<2>(i) - r.segment<2>(i) / L;
      const double nz = z.norm(), kappa = w * lam / L;
      z *= nz > kappa ? 1 - kappa / nz : 0.0;
      move(i, z[0]);
      move(i + 1, z[1]);
    }
  }
  return true;
}

// The gradient of Φ_λ on the current pieces; 3D: the slip nodes' curvature blocks of w λ |u_τ|.
Vec InnerSolver::piece_gradient(const ActiveSet& A,
                                std::vector<std::pair<Index, Eigen::Matrix2d>>& slip_blocks) const {
  Vec G = r;
  for (Index k = 0; k < nc; ++k) {
    const Index iv = d * k;
    const double w = P.w[k], lam = P.lambda[k];
    const int cn = A.code[static_cast<size_t>(iv)];
    if (cn >= 0 && P.law) {
      const Piece q = piece(*P.law, static_cast<size_t>(cn));
      G[iv] += w * (q.A + q.s * x[iv]);
    }
    const Vec ut = x.segment(iv + 1, d - 1);
    const double y = ut.norm();
    if (lam > 0 && y > 0) {
      G.segment(iv + 1, d - 1) += w * lam * ut / y;
      if (d == 3) {
        const Eigen::Vector2d t = ut / y;
        slip_blocks.emplace_back(iv + 1, w * lam / y * (Eigen::Matrix2d::Identity() - t * t.transpose()));
      }
    }
  }
  return G;
}

// The reduced Hessian's factor: blocked Cholesky when it is positive definite (the convex case;
// m³/3 flops), else LDLᵀ, whose direction is used only if it is a descent direction. 2D: the
// reduced Hessian depends only on the active set, so its factorization is kept while the set
// stays the same. False if neither factors.
bool InnerSolver::factor(const ActiveSet& A, const std::vector<std::pair<Index, Eigen::Matrix2d>>& slip_blocks) {
  const bool reuse = d == 2 && F.factored && A == F.cached;
  if (reuse) return true;
  const Index nf = static_cast<Index>(A.free.size());
  Mat H(nf, nf);
  for (Index a = 0; a < nf; ++a)
    for (Index b = 0; b < nf; ++b) H(a, b) = S(A.free[a], A.free[b]);
  std::vector<Index> pos(static_cast<size_t>(m), -1);
  for (Index a = 0; a < nf; ++a) pos[static_cast<size_t>(A.free[a])] = a;
  for (Index k = 0; k < nc; ++k) {
    const Index iv = d * k;
    const int cn = A.code[static_cast<size_t>(iv)];
    if (cn >= 0 && P.law) H(pos[iv], pos[iv]) += P.w[k] * P.law->slopes()[static_cast<size_t>(cn)];
  }
  for (const auto& [i, B] : slip_blocks)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        if (pos[i + a] >= 0 && pos[i + b] >= 0) H(pos[i + a], pos[i + b]) += B(a, b);
  ++R.factorizations;
  F.cached = A;
  F.llt.compute(H);
  F.use_llt = F.llt.info() == Eigen::Success;
  if (!F.use_llt) F.ldlt.compute(H);
  F.factored = F.use_llt || F.ldlt.info() == Eigen::Success;
  return F.factored;
}

// Backtracking on Φ_λ along the free unknowns' direction dF; true if a step was taken.
bool InnerSolver::line_search(const ActiveSet& A, const Vec& dF) {
  const Index nf = static_cast<Index>(A.free.size());
  Vec xt = x;
  // Near a solution the decrease of Φ_λ (~ residual²) falls below Φ_λ's round-off and cannot be
  // seen: there the full step is also taken when Φ_λ stays within round-off (1e-14 of its
  // terms' size) and the stationarity residual drops (3D: Newton's quadratic convergence).
  const double res0 = exact_inner_residual(P, x);
  const double E_noise = 1e-14 * (std::abs(E) + std::abs((x - P.y).dot(r)));
  for (double alpha = step_cap(A, dF); alpha >= std::ldexp(1.0, -opt.max_halvings); alpha *= 0.5) {
    for (Index a = 0; a < nf; ++a) xt[A.free[a]] = x[A.free[a]] + alpha * dF[a];
    for (Index k = 0; k < nc; ++k) xt[d * k] = std::min(xt[d * k], P.g[k]);
    const double Et = exact_inner_energy(P, xt);
    if (Et < E || (alpha == 1 && Et <= E + E_noise && exact_inner_residual(P, xt) < 0.5 * res0)) {
      x = xt;
      E = Et;
      r = S * (x - P.y);
      ++R.newton_steps;
      return true;
    }
  }
  return false;
}

// The longest step along dF, at most 1: with ExactInnerOptions::local_descent, no free normal
// unknown leaves its piece of p_ν (or passes g), so the step crosses no barrier; the next sweep
// goes on from the breakpoint. On one piece Φ_λ is quadratic and dF a Newton descent direction, so
// Φ_λ decreases all the way to the cap.
double InnerSolver::step_cap(const ActiveSet& A, const Vec& dF) const {
  double cap = 1;
  if (!opt.local_descent || !P.law) return cap;
  for (size_t a = 0; a < A.free.size(); ++a) {
    const Index i = A.free[a];
    if (i % d != 0) continue;
    const Piece q = piece(*P.law, static_cast<size_t>(A.code[static_cast<size_t>(i)]));
    const double hi = std::min(q.hi, P.g[i / d]), step = dF[static_cast<Index>(a)];
    if (step > 0 && std::isfinite(hi)) cap = std::min(cap, (hi - x[i]) / step);
    if (step < 0 && std::isfinite(q.lo)) cap = std::min(cap, (q.lo - x[i]) / step);
  }
  return cap;
}

// One active-set Newton step with backtracking on Φ_λ (file comment).
bool InnerSolver::newton() {
  const ActiveSet A = active_set(P, x);
  const Index nf = static_cast<Index>(A.free.size());
  if (nf == 0) return false;
  std::vector<std::pair<Index, Eigen::Matrix2d>> slip_blocks;
  const Vec G = piece_gradient(A, slip_blocks);
  if (!factor(A, slip_blocks)) return false;
  Vec gF(nf);
  for (Index a = 0; a < nf; ++a) gF[a] = G[A.free[a]];
  const Vec dF = F.use_llt ? Vec(F.llt.solve(-gF)) : Vec(F.ldlt.solve(-gF));
  if (!dF.allFinite() || !(dF.dot(gF) < 0)) return false;  // not a descent direction (softening)
  return line_search(A, dF);
}

}  // namespace

ExactInnerResult exact_inner_solve(const ExactInnerProblem& P, Vec& x, const ExactInnerOptions& opt,
                                   ExactInnerFactor* keep) {
  ExactInnerResult R;
  ExactInnerFactor own;
  InnerSolver solver(P, x, opt, R, keep ? *keep->m : *own.m);
  solver.start();
  double& E = solver.energy();
  for (R.rounds = 1; R.rounds <= opt.max_rounds; ++R.rounds) {
    check_interrupt();
    const double E0 = E;
    if (!solver.sweep()) {
      R.note = "Phi_lambda is unbounded below along a normal unknown (an outer slope of p_nu below -S_ii/w)";
      break;
    }
    E = exact_inner_energy(P, x);
    R.residual = exact_inner_residual(P, x);
    if (R.residual <= opt.tol) break;
    const bool stepped = solver.newton();
    solver.refresh_r();  // drop the rank-one updates' accumulated round-off
    R.residual = exact_inner_residual(P, x);
    if (R.residual <= opt.tol) break;
    if (!stepped && !(E < E0)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.3g", R.residual);
      R.note = std::string("no decrease of Phi_lambda in a round (residual ") + buf + ")";
      break;
    }
  }
  R.rounds = std::min(R.rounds, opt.max_rounds);
  R.energy = E;
  R.converged = R.residual <= opt.tol;
  if (!R.converged && R.note.empty()) R.note = "max_rounds reached";
  return R;
}

InnerConvexity inner_convexity(const Mat& S, const Vec& w, int d, const PiecewiseLinearLaw* law, Index max_unknowns) {
  InnerConvexity c;
  c.softening = law ? law->one_sided_lipschitz() : 0.0;
  const Index m = S.rows();
  if (!std::isfinite(c.softening)) {
    c.checked = true;
    c.min_eigenvalue = -INF;
    c.note = "p_nu jumps downward: j_nu is not semiconvex";
    return c;
  }
  if (m > max_unknowns) {
    c.note = "not checked: " + std::to_string(m) + " condensed unknowns > solver.exact.convexity_max_unknowns";
    return c;
  }
  c.checked = true;
  Mat M = S;
  for (Index k = 0; k < w.size(); ++k) M(d * k, d * k) -= c.softening * w[k];
  // Positive definite or not: one Cholesky decides. For the eigenvalue, inverse iteration on a
  // positive definite shift M + σI (σ = α max w makes it ⪰ S ≻ 0 when M is indefinite).
  Eigen::LLT<Mat> llt(M);
  c.strongly_convex = llt.info() == Eigen::Success;
  double shift = 0;
  if (!c.strongly_convex) {
    shift = c.softening * w.maxCoeff() + 1e-12 * S.diagonal().maxCoeff();
    llt.compute(M + shift * Mat::Identity(m, m));
    if (llt.info() != Eigen::Success) {
      c.min_eigenvalue = NaN;
      c.note = "S - alpha W_nu is not positive definite (Cholesky); eigenvalue not estimated";
      return c;
    }
  }
  Vec v = Vec::LinSpaced(m, 1.0, 2.0);
  v.normalize();
  double rq = NaN;
  for (int it = 0; it < 200; ++it) {
    Vec z = llt.solve(v);
    z.normalize();
    const double q = z.dot(M * z) + shift;  // Rayleigh quotient of M + σI
    v = z;
    if (std::abs(q - rq) <= 1e-10 * std::abs(q)) {
      rq = q;
      break;
    }
    rq = q;
  }
  c.min_eigenvalue = rq - shift;
  c.note = std::string(c.strongly_convex ? "Cholesky of S - alpha W_nu succeeded" : "Cholesky of S - alpha W_nu failed") +
           "; smallest eigenvalue by inverse iteration";
  return c;
}

Vec Anderson::next(const Vec& lambda, const Vec& G) {
  const Vec f = G - lambda;
  if (m_has_prev) {
    m_dF.push_back(f - m_prev_f);
    m_dG.push_back(G - m_prev_G);
    if (static_cast<int>(m_dF.size()) > m_memory) m_dF.erase(m_dF.begin()), m_dG.erase(m_dG.begin());
  }
  m_prev_f = f;
  m_prev_G = G;
  m_has_prev = true;
  const Vec relaxed = G - (1 - m_theta) * f;  // (1 − θ) λ + θ G
  if (m_memory == 0 || m_dF.empty()) return relaxed.cwiseMax(0.0);
  const Index n = f.size(), mk = static_cast<Index>(m_dF.size());
  Mat DF(n, mk), DG(n, mk);
  for (Index j = 0; j < mk; ++j) DF.col(j) = m_dF[static_cast<size_t>(j)], DG.col(j) = m_dG[static_cast<size_t>(j)];
  const Vec gamma = DF.colPivHouseholderQr().solve(f);
  if (!gamma.allFinite()) return relaxed.cwiseMax(0.0);
  return (G - DG * gamma - (1 - m_theta) * (f - DF * gamma)).cwiseMax(0.0);
}

}  // namespace hemicontact
