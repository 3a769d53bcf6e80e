// Finite-difference tests of the energy terms (docs/model.md §2; every term, because every backend
// trusts the derivatives it is given): value → gradient and gradient → Hessian for ElasticEnergy,
// LoadEnergy, NormalComplianceEnergy, FrictionEnergy, the composite TotalEnergy and
// ScaledObjective, at 10 random points plus points on every branch of the paper's law (32)
// (c = (100, −100, 400), r = (0.1, 0.15)) and of the smoothed norm, for ε = ε_ν = ε_τ ∈ {1e-8, …, 1}
// and d = 2, 3 (3D friction: τ-blocks of a NodalDofs with dim = 3).
//
// ---------------------------------------------------------------- how the tolerances are derived
// Central differences with step h_i in coordinate i:
//   |FD − exact| ≤ h²/6·sup|f‴|  (truncation)  +  δf/h  (round-off, δf = error of one evaluation).
// Steps (per coordinate, chosen per ε):
//   interior dofs  h = 1e-6            (the elastic/load energy is quadratic: truncation-free);
//   ν dofs         h = 1e-6, but 1e-3 ε inside a window (≪ ε_ν: the step stays in the window) and
//                  ≤ ¼ of the distance to the nearest window edge r_k ± ε (never crosses one);
//   τ dofs         h = 1e-3 ε          (≪ ε_τ: the step never crosses |u_τ| = ε).
// Points are never within 2h of a non-smooth point (window edges r_k ± ε, |u_τ| = ε, u_τ = 0 except
// the dedicated u_τ = 0 point), so every difference stays on one polynomial/smooth piece. The
// small steps inside windows cost accuracy (round-off ∝ 1/h), which is why the gradient and
// Hessian are also compared with the law's p_ε, p_ε′ directly (identity checks below):
//   value → gradient: j_ε‴ = p_ε″ ≤ Σ|Δs_k|/(2ε) inside windows, f0‴ = −2/ε² inside |u_τ| < ε, so
//     the truncation is ≤ (h/ε)²/3 · (gradient scale) ≤ 3.3e-7 relative;
//   gradient → Hessian: p_ε is piecewise quadratic and (2D) f1 is quadratic on each side of 0,
//     so central differences are exact up to round-off; in 3D ∇f0(|u|) = (2/ε − |u|/ε²)u has third
//     derivatives ≲ 3/(ε²|u|), i.e. truncation ≲ (h/ε)²·ε/(2|u|) ≤ 5e-6 relative for |u| ≥ 0.1ε.
//   ⇒ relative part kRtol = 1e-5 (of the per-component gradient scale G_i / per-row Hessian scale).
// Round-off: one evaluation of a sum of m products errs by ≤ γ_m·(sum of |summands|), m ≲ 20
//   (a 17-dof dot product plus a few terms) ⇒ δf ≤ kRound·F with kRound = 64·DBL_EPSILON = 128u
//   and F a bound on the magnitudes of the summands (magnitudes() below), likewise for ∇.
//   ⇒ gradient tol_i = kRtol·G_i + kRound·F/h_i, Hessian tol_ij = kRtol·Hrow_i + kRound·G_i/h_j.
// Exactly at u_τ = 0, ∇f0(|u|) = (2/ε − |u|/ε²)u is only C¹ (u|u| term): the central difference of
//   the gradient is (2/ε − h/ε²)·wλ, an error of exactly wλ·h/ε² on the τ-diagonal, which is
//   added to that point's Hessian tolerance (and the analytic values are checked exactly).
// Identity checks (gradient = w p_ν on a branch, Hessian = w·c_branch, friction force wλ u/|u|…)
// compare two evaluations of a handful of roundings: 1e-12 relative.

#include <hemicontact/contact/mollified_law.hpp>
#include <hemicontact/contact/piecewise_linear_law.hpp>
#include <hemicontact/contact/smooth_norm.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/energy/contact_energy.hpp>
#include <hemicontact/energy/elastic_energy.hpp>
#include <hemicontact/energy/total_energy.hpp>

#include <Eigen/Eigenvalues>
#include "support/fd_check.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace hemicontact {
namespace {

// The paper's law (32).
constexpr double LAW_C1 = 100, LAW_C2 = -100, LAW_C3 = 400, LAW_R1 = 0.1, LAW_R2 = 0.15;
constexpr double KINKS[] = {0.0, LAW_R1, LAW_R2};

constexpr double kRtol = 1e-5;               // truncation part (file comment)
constexpr double kRound = 64 * DBL_EPSILON;  // round-off part (file comment)
constexpr double kIdentity = 1e-12;          // two evaluations of the same formula

// ---------------------------------------------------------------- the hand-built problem

/// n_int interior dofs then nc contact nodes of dim components (ν, τ[, τ2]), as DofMap orders them.
struct Problem {
  int dim = 2;
  double eps = 1e-2;  ///< ε_ν = ε_τ (absolute)
  Index n_int = 5, nc = 4, n = 0;
  SpMat K;       ///< symmetric, diagonally dominant (SPD), full storage
  SpMat blocks;  ///< lower pattern of the nodal d×d blocks only (values 0)
  Vec f;
  NodalDofs nodes;
  Vec lambda;  ///< frozen friction bounds; the last node has λ = 0
  std::shared_ptr<const PiecewiseLinearLaw> exact;
  std::shared_ptr<const MollifiedLaw> law;
  double h_int = 1e-6, h_nu = 0, h_tau = 0;  ///< h_nu: the step inside windows

  Index nu(Index k) const { return nodes.first[k]; }
  /// The nodes laid out in @p pattern (the nodal terms' shared Hessian positions).
  std::shared_ptr<const NodalLayout> layout(const SpMat& pattern) const {
    return std::make_shared<const NodalLayout>(nodes, pattern);
  }
  /// FD step of a ν component at r (file comment): 1e-6, but ≤ 1e-3 ε inside a window and never
  /// more than a quarter of the distance to the nearest window edge r_k ± ε.
  double law_step(double r) const {
    double h = 1e-6;
    for (double rk : KINKS) {
      const double d = std::abs(r - rk);
      if (d < eps) h = std::min(h, 1e-3 * eps);
      h = std::min(h, 0.25 * std::abs(d - eps));
    }
    return h;
  }
  /// FD step of every coordinate at x (file comment).
  Vec steps(const Vec& x) const {
    Vec h = Vec::Constant(n, h_int);
    for (Index k = 0; k < nc; ++k) {
      h[nu(k)] = law_step(x[nu(k)]);
      for (int a = 1; a < dim; ++a) h[nu(k) + a] = h_tau;
    }
    return h;
  }
};

Problem make_problem(int dim, double eps, unsigned seed = 7, Index n_int = 5) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Problem p;
  p.dim = dim;
  p.eps = eps;
  p.n_int = n_int;
  p.n = p.n_int + p.nc * dim;
  p.h_nu = std::min(1e-3 * eps, 1e-6);
  p.h_tau = 1e-3 * eps;
  p.nodes.dim = dim;
  p.nodes.w.resize(p.nc);
  for (Index k = 0; k < p.nc; ++k) {
    p.nodes.first.push_back(p.n_int + dim * k);
    p.nodes.w[k] = 0.2 + 0.8 * u01(rng);
  }
  // K: diagonal 4..5, tridiagonal couplings in [−1, 1] and full nodal blocks with entries in
  // [−½, ½]: off-diagonal row sums ≤ 2 + (d−1)/2 < 4, so K is SPD (Gershgorin).
  Triplets t, tb;
  for (Index i = 0; i < p.n; ++i) t.emplace_back(i, i, 4.0 + u01(rng));
  for (Index i = 0; i + 1 < p.n; ++i) {
    const double v = 2 * u01(rng) - 1;
    t.emplace_back(i + 1, i, v);
    t.emplace_back(i, i + 1, v);
  }
  for (Index k = 0; k < p.nc; ++k)
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b <= a; ++b) {
        const Index r = p.nu(k) + a, c = p.nu(k) + b;
        tb.emplace_back(r, c, 0.0);
        if (a == b) continue;
        const double v = u01(rng) - 0.5;
        t.emplace_back(r, c, v);
        t.emplace_back(c, r, v);
      }
  p.K.resize(p.n, p.n);
  p.K.setFromTriplets(t.begin(), t.end());
  p.K.makeCompressed();
  p.blocks.resize(p.n, p.n);
  p.blocks.setFromTriplets(tb.begin(), tb.end());  // explicit zeros are kept
  p.blocks.makeCompressed();
  p.f.resize(p.n);
  for (Index i = 0; i < p.n; ++i) p.f[i] = 2 * u01(rng) - 1;
  p.lambda.resize(p.nc);
  for (Index k = 0; k < p.nc; ++k) p.lambda[k] = 0.5 + u01(rng);
  p.lambda[p.nc - 1] = 0.0;  // a node without friction (the term skips it)
  p.exact = std::make_shared<const PiecewiseLinearLaw>(PiecewiseLinearLaw::paper(LAW_C1, LAW_C2, LAW_C3, LAW_R1, LAW_R2));
  p.law = std::make_shared<const MollifiedLaw>(p.exact, eps);
  return p;
}

/// Dense symmetric matrix from a lower-triangular one (fails on upper entries).
Mat symmetric_from_lower(const SpMat& L) {
  Mat D = Mat::Zero(L.rows(), L.cols());
  for (int c = 0; c < L.outerSize(); ++c)
    for (SpMat::InnerIterator it(L, c); it; ++it) {
      EXPECT_GE(it.row(), it.col()) << "Hessian entry above the diagonal";
      D(it.row(), it.col()) += it.value();
      if (it.row() != it.col()) D(it.col(), it.row()) += it.value();
    }
  return D;
}

/// Same outer/inner index arrays (the fixed pattern).
::testing::AssertionResult same_pattern(const SpMat& a, const SpMat& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros())
    return ::testing::AssertionFailure() << "size/nnz differ: " << a.nonZeros() << " vs " << b.nonZeros();
  if (!a.isCompressed() || !b.isCompressed()) return ::testing::AssertionFailure() << "not compressed";
  if (!std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1, b.outerIndexPtr()))
    return ::testing::AssertionFailure() << "outer index arrays differ";
  if (!std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr()))
    return ::testing::AssertionFailure() << "inner index arrays differ";
  return ::testing::AssertionSuccess();
}

// ---------------------------------------------------------------- evaluables

struct Fn {
  std::function<double(const Vec&)> value;
  std::function<Vec(const Vec&)> gradient;
  std::function<SpMat(const Vec&, Psd)> hessian;
};

Fn of_term(const EnergyTerm& t, const SpMat& pattern) {
  Fn fn;
  fn.value = [&t](const Vec& x) { return t.value(x); };
  fn.gradient = [&t](const Vec& x) {
    Vec g = Vec::Zero(x.size());
    t.add_gradient(x, g);
    return g;
  };
  fn.hessian = [&t, pattern](const Vec& x, Psd psd) {
    SpMat H = pattern;
    std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
    t.add_hessian(x, H, psd);
    EXPECT_TRUE(same_pattern(H, pattern)) << t.name() << " changed the pattern";
    return H;
  };
  return fn;
}

Fn of_objective(const NlpObjective& o) {
  Fn fn;
  fn.value = [&o](const Vec& x) { return o.value(x); };
  fn.gradient = [&o](const Vec& x) {
    Vec g;
    o.gradient(x, g);
    return g;
  };
  fn.hessian = [&o](const Vec& x, Psd psd) {
    SpMat H;
    o.hessian(x, H, psd);
    EXPECT_TRUE(same_pattern(H, o.hessian_pattern()));
    return H;
  };
  return fn;
}

// ---------------------------------------------------------------- magnitudes for round-off

struct Terms {
  bool elastic = false, load = false, normal = false, friction = false;
};
struct Scales {
  double F = 0;  ///< bound on the summands of the value
  Vec G;         ///< per component: bound on the summands of the gradient
};

/// Σ_k |Δs_k| ((|r−r_k|+ε)² + (|r_k|+ε)²) ≥ the summands of j_ε(r) = P_ε(r) − P_ε(0).
double j_magnitude(const Problem& p, double r) {
  double s = 0;
  for (size_t k = 0; k < p.exact->breakpoints().size(); ++k) {
    const double rk = p.exact->breakpoints()[k], ds = std::abs(p.exact->slope_changes()[k]);
    s += ds * (std::pow(std::abs(r - rk) + p.eps, 2) + std::pow(std::abs(rk) + p.eps, 2));
  }
  return s;
}
/// Σ_k |Δs_k| (|r−r_k| + ε) ≥ the summands of p_ε(r).
double p_magnitude(const Problem& p, double r) {
  double s = 0;
  for (size_t k = 0; k < p.exact->breakpoints().size(); ++k)
    s += std::abs(p.exact->slope_changes()[k]) * (std::abs(r - p.exact->breakpoints()[k]) + p.eps);
  return s;
}

Scales magnitudes(const Problem& p, const Terms& on, const Vec& x) {
  Scales s;
  s.G = Vec::Zero(p.n);
  const SpMat Kabs = p.K.cwiseAbs();
  const Vec xa = x.cwiseAbs();
  if (on.elastic) {
    s.F += 0.5 * xa.dot(Kabs * xa);
    s.G += Kabs * xa;
  }
  if (on.load) {
    s.F += p.f.cwiseAbs().dot(xa);
    s.G += p.f.cwiseAbs();
  }
  for (Index k = 0; k < p.nc; ++k) {
    const double w = p.nodes.w[k], r = x[p.nu(k)];
    if (on.normal) {
      s.F += w * j_magnitude(p, r);
      s.G[p.nu(k)] += w * p_magnitude(p, r);
    }
    if (on.friction) {
      const double y = x.segment(p.nu(k) + 1, p.dim - 1).norm();
      s.F += w * p.lambda[k] * (y + p.eps);
      for (int a = 1; a < p.dim; ++a) s.G[p.nu(k) + a] += w * p.lambda[k];
    }
  }
  return s;
}

// ---------------------------------------------------------------- the FD check

/// Value → gradient and gradient → Hessian (Psd::NONE, the true Hessian) at x with per-coordinate
/// steps h; @p extra is added to the Hessian tolerance (the u_τ = 0 point), empty = none.
void check_fd(const Fn& fn, const Vec& x, const Vec& h, const Scales& s, const Mat& extra = Mat()) {
  const Index n = x.size();
  const Vec g = fn.gradient(x);
  ASSERT_EQ(g.size(), n);
  const Mat H = symmetric_from_lower(fn.hessian(x, Psd::NONE));
  const Vec g_fd = test::fd_gradient(fn.value, x, h);
  const Mat H_fd = test::fd_jacobian(fn.gradient, x, h);
  double worst_g = 0, worst_h = 0;
  std::string where_g, where_h;
  const auto take = [](double err, double tol, double& worst, std::string& where, const std::string& w) {
    const double r = err / tol;
    if (!(r <= worst)) {
      worst = r;
      std::ostringstream os;
      os << w << ": |FD − exact| = " << err << ", tol = " << tol;
      where = os.str();
    }
  };
  for (Index i = 0; i < n; ++i) {
    const double Gi = std::max({s.G[i], std::abs(g[i]), std::abs(g_fd[i])});
    const double tol = kRtol * Gi + kRound * s.F / h[i] + DBL_MIN;
    take(std::abs(g_fd[i] - g[i]), tol, worst_g, where_g,
         "g[" + std::to_string(i) + "] = " + std::to_string(g[i]) + " vs FD " + std::to_string(g_fd[i]));
  }
  for (Index i = 0; i < n; ++i) {
    const double Hrow = std::max(H.row(i).cwiseAbs().maxCoeff(), H_fd.row(i).cwiseAbs().maxCoeff());
    const double Gi = std::max({s.G[i], std::abs(g[i])});
    for (Index j = 0; j < n; ++j) {
      double tol = kRtol * Hrow + kRound * Gi / h[j] + DBL_MIN;
      if (extra.size()) tol += extra(i, j);
      take(std::abs(H_fd(i, j) - H(i, j)), tol, worst_h, where_h,
           "H(" + std::to_string(i) + "," + std::to_string(j) + ") = " + std::to_string(H(i, j)) + " vs FD " +
               std::to_string(H_fd(i, j)));
    }
  }
  EXPECT_LE(worst_g, 1.0) << "gradient: worst " << where_g;
  EXPECT_LE(worst_h, 1.0) << "Hessian: worst " << where_h;
}

// ---------------------------------------------------------------- sample points

/// Outside every window (by more than the step inside windows)?
bool outside_windows(const Problem& p, double r) {
  for (double rk : KINKS)
    if (std::abs(r - rk) <= p.eps + 2 * p.h_nu) return false;
  return true;
}
/// Slope of the exact law at r (off the kinks).
double branch_slope(double r) { return r < 0 ? 0.0 : r < LAW_R1 ? LAW_C1 : r < LAW_R2 ? LAW_C2 : LAW_C3; }

/// A random unit vector of d−1 components.
Vec random_direction(int nt, std::mt19937& rng) {
  std::normal_distribution<double> nd;
  Vec v(nt);
  do {
    for (int a = 0; a < nt; ++a) v[a] = nd(rng);
  } while (v.norm() < 1e-3);
  return v.normalized();
}

/// Random point: interior in [−0.2, 0.2], r in [−0.05, 0.3] (all four branches of (32)),
/// |u_τ| log-uniform in [0.1ε, 30ε] — each redrawn while within 2h of a non-smooth point.
Vec random_point(const Problem& p, std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Vec x(p.n);
  for (Index i = 0; i < p.n_int; ++i) x[i] = 0.4 * u01(rng) - 0.2;
  for (Index k = 0; k < p.nc; ++k) {
    double r;
    do r = -0.05 + 0.35 * u01(rng);
    while (p.law_step(r) < 0.5 * p.h_nu);  // not (nearly) on a window edge
    x[p.nu(k)] = r;
    double y;
    do y = p.eps * std::pow(10.0, -1.0 + std::log10(300.0) * u01(rng));
    while (std::abs(y - p.eps) <= 2 * p.h_tau || y <= 2 * p.h_tau);
    x.segment(p.nu(k) + 1, p.dim - 1) = y * random_direction(p.dim - 1, rng);
  }
  return x;
}

struct LawPoint {
  double r;
  bool in_window;
  std::string what;
};

/// Points on each branch of (32) at kink ± δ with δ = 100ε or 10ε (≫ ε_ν), the branch middles
/// and far points — kept only if outside every window — and points inside each window,
/// |r − r_k| < ε/2.
std::vector<LawPoint> law_points(const Problem& p) {
  std::vector<LawPoint> pts;
  const double lo[] = {-INF, 0.0, LAW_R1, LAW_R2}, hi[] = {0.0, LAW_R1, LAW_R2, INF};
  for (int b = 0; b < 4; ++b) {
    std::vector<double> cand;
    for (double delta : {100 * p.eps, 10 * p.eps}) {
      if (std::isfinite(lo[b])) cand.push_back(lo[b] + delta);
      if (std::isfinite(hi[b])) cand.push_back(hi[b] - delta);
    }
    if (std::isfinite(lo[b]) && std::isfinite(hi[b])) cand.push_back(0.5 * (lo[b] + hi[b]));
    if (!std::isfinite(lo[b])) cand.push_back(-0.05);
    if (!std::isfinite(hi[b])) cand.push_back(0.3);
    for (double r : cand)
      if (r > lo[b] && r < hi[b] && outside_windows(p, r))
        pts.push_back({r, false, "branch " + std::to_string(b) + " r = " + std::to_string(r)});
  }
  for (double rk : KINKS)
    for (double s : {-0.4, -0.1, 0.25, 0.45})
      pts.push_back({rk + s * p.eps, true, "window r_k = " + std::to_string(rk) + " + " + std::to_string(s) + "ε"});
  return pts;
}

/// |u_τ|/ε on both sides of ε (never on it), including 0 (exact stick).
const double FRICTION_Y[] = {0.0, 0.1, 0.5, 0.9, 1.1, 2.0, 100.0};

/// Extra Hessian tolerance at u_τ = 0 of node k: wλh/ε² on its τ-diagonal (file comment).
Mat zero_slip_extra(const Problem& p, Index k) {
  Mat e = Mat::Zero(p.n, p.n);
  for (int a = 1; a < p.dim; ++a)
    e(p.nu(k) + a, p.nu(k) + a) = p.nodes.w[k] * p.lambda[k] * p.h_tau / (p.eps * p.eps) * (1 + 1e-6);
  return e;
}

// ---------------------------------------------------------------- the parameterized suite

using Param = std::tuple<int, double>;  // (dim, ε)

class EnergyFd : public ::testing::TestWithParam<Param> {
 protected:
  void SetUp() override {
    dim_ = std::get<0>(GetParam());
    eps_ = std::get<1>(GetParam());
    p_ = make_problem(dim_, eps_);
  }
  int dim_ = 2;
  double eps_ = 1;
  Problem p_;
};

TEST_P(EnergyFd, Elastic) {
  ElasticEnergy el{SymmetricSpMat(p_.K)};
  const Fn fn = of_term(el, el.lower());
  std::mt19937 rng(11);
  for (int i = 0; i < 10; ++i) {
    SCOPED_TRACE("random point " + std::to_string(i));
    const Vec x = random_point(p_, rng);
    check_fd(fn, x, p_.steps(x), magnitudes(p_, {true, false, false, false}, x));
    // The Hessian is K itself (its lower triangle), independent of x.
    const Mat H = symmetric_from_lower(fn.hessian(x, Psd::CLAMP));
    EXPECT_EQ((H - Mat(p_.K)).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_NEAR(el.value(x), 0.5 * x.dot(Mat(p_.K) * x), kIdentity * magnitudes(p_, {true}, x).F);
  }
}

TEST_P(EnergyFd, Load) {
  LoadEnergy load(p_.f);
  const Fn fn = of_term(load, p_.blocks);
  std::mt19937 rng(12);
  for (int i = 0; i < 10; ++i) {
    SCOPED_TRACE("random point " + std::to_string(i));
    const Vec x = random_point(p_, rng);
    check_fd(fn, x, p_.steps(x), magnitudes(p_, {false, true, false, false}, x));
    EXPECT_EQ(fn.gradient(x), Vec(-p_.f));
    const SpMat H = fn.hessian(x, Psd::NONE);
    EXPECT_EQ(Eigen::Map<const Vec>(H.valuePtr(), H.nonZeros()).cwiseAbs().maxCoeff(), 0.0);  // linear
  }
}

TEST_P(EnergyFd, NormalCompliance) {
  NormalComplianceEnergy term(p_.layout(p_.blocks), p_.law);
  const Fn fn = of_term(term, p_.blocks);
  const Terms on{false, false, true, false};
  std::mt19937 rng(13);
  for (int i = 0; i < 10; ++i) {
    SCOPED_TRACE("random point " + std::to_string(i));
    const Vec x = random_point(p_, rng);
    check_fd(fn, x, p_.steps(x), magnitudes(p_, on, x));
  }
  const double w0 = p_.nodes.w[0];
  for (const LawPoint& lp : law_points(p_)) {
    SCOPED_TRACE(lp.what);
    Vec x = random_point(p_, rng);
    x[p_.nu(0)] = lp.r;
    check_fd(fn, x, p_.steps(x), magnitudes(p_, on, x));
    const Vec g = fn.gradient(x);
    const Mat H = symmetric_from_lower(fn.hessian(x, Psd::NONE));
    // Only ν entries: the τ components of the gradient and Hessian are zero.
    for (int a = 1; a < dim_; ++a) EXPECT_EQ(g[p_.nu(0) + a], 0.0);
    EXPECT_EQ(H.row(p_.nu(0)).cwiseAbs().sum(), std::abs(H(p_.nu(0), p_.nu(0))));
    // Against the law: ∂/∂x_ν = w p_ε(r), ∂² = w p_ε′(r).
    EXPECT_NEAR(g[p_.nu(0)], w0 * p_.law->p(lp.r), kIdentity * w0 * p_magnitude(p_, lp.r));
    EXPECT_NEAR(H(p_.nu(0), p_.nu(0)), w0 * p_.law->dp(lp.r), kIdentity * w0 * 600);
    if (!lp.in_window) {
      // Outside the windows the mollified law is the exact one, branch by branch.
      EXPECT_NEAR(g[p_.nu(0)], w0 * p_.exact->p(lp.r), kIdentity * w0 * p_magnitude(p_, lp.r));
      EXPECT_NEAR(H(p_.nu(0), p_.nu(0)), w0 * branch_slope(lp.r), kIdentity * w0 * 600);
    }
  }
}

TEST_P(EnergyFd, Friction) {
  FrictionEnergy term(p_.layout(p_.blocks), eps_, p_.lambda);
  EXPECT_EQ(term.eps(), eps_);
  const Fn fn = of_term(term, p_.blocks);
  const Terms on{false, false, false, true};
  const int nt = dim_ - 1;
  std::mt19937 rng(14);
  for (int i = 0; i < 10; ++i) {
    SCOPED_TRACE("random point " + std::to_string(i));
    const Vec x = random_point(p_, rng);
    check_fd(fn, x, p_.steps(x), magnitudes(p_, on, x));
    // The λ = 0 node contributes nothing; no friction term touches ν components.
    const Index last = p_.nc - 1;
    const Vec g = fn.gradient(x);
    EXPECT_EQ(g.segment(p_.nu(last), dim_).cwiseAbs().maxCoeff(), 0.0);
    for (Index k = 0; k < p_.nc; ++k) EXPECT_EQ(g[p_.nu(k)], 0.0);
  }
  const Index k = 1;  // node with λ > 0
  const double wl = p_.nodes.w[k] * p_.lambda[k];
  for (double s : FRICTION_Y)
    for (int sign : {1, -1}) {
      if (s == 0 && sign < 0) continue;
      const double y = s * eps_;
      SCOPED_TRACE("|u_tau|/eps = " + std::to_string(s) + ", sign " + std::to_string(sign));
      Vec x = random_point(p_, rng);
      const Vec dir = sign * random_direction(nt, rng);
      x.segment(p_.nu(k) + 1, nt) = y * dir;
      check_fd(fn, x, p_.steps(x), magnitudes(p_, on, x), s == 0 ? zero_slip_extra(p_, k) : Mat());
      const Vec g = fn.gradient(x).segment(p_.nu(k) + 1, nt);
      const Mat Hb = symmetric_from_lower(fn.hessian(x, Psd::NONE)).block(p_.nu(k) + 1, p_.nu(k) + 1, nt, nt);
      if (s == 0) {
        // Exact stick: gradient exactly 0, Hessian exactly (2/ε) wλ I.
        EXPECT_EQ(g.cwiseAbs().maxCoeff(), 0.0);
        EXPECT_NEAR((Hb - 2.0 / eps_ * wl * Mat::Identity(nt, nt)).cwiseAbs().maxCoeff(), 0.0,
                    kIdentity * 2.0 / eps_ * wl);
        continue;
      }
      // The smoothed friction force wλ f1(y) u/|u|: the exact force wλ u/|u| for y ≥ ε.
      const double t = s;
      const double f1v = s >= 1 ? 1.0 : t * (2 - t);
      EXPECT_NEAR((g - wl * f1v * dir).norm(), 0.0, kIdentity * wl);
      // Hessian eigen-structure: wλ f1′(y) along u, wλ f1(y)/y across it (3D).
      const double df1v = s >= 1 ? 0.0 : 2 * (1 - t) / eps_;
      const double f1y = s >= 1 ? 1.0 / y : (2 - t) / eps_;
      EXPECT_NEAR((Hb * dir - wl * df1v * dir).norm(), 0.0, kIdentity * wl * 2 / eps_);
      if (nt == 2) {
        const Vec perp = (Vec(2) << -dir[1], dir[0]).finished();
        EXPECT_NEAR((Hb * perp - wl * f1y * perp).norm(), 0.0, kIdentity * wl * 2 / eps_);
      }
    }
}

/// Elastic + load + normal compliance + friction on K's lower pattern, as solve() assembles it.
struct Composite {
  std::shared_ptr<ElasticEnergy> el;
  std::shared_ptr<LoadEnergy> load;
  std::shared_ptr<NormalComplianceEnergy> normal;
  std::shared_ptr<FrictionEnergy> friction;
  std::unique_ptr<TotalEnergy> total;
  explicit Composite(const Problem& p) {
    el = std::make_shared<ElasticEnergy>(SymmetricSpMat(p.K));
    load = std::make_shared<LoadEnergy>(p.f);
    total = std::make_unique<TotalEnergy>(p.n, el->lower());
    const auto layout = p.layout(total->hessian_pattern());  // one layout for both nodal terms
    normal = std::make_shared<NormalComplianceEnergy>(layout, p.law);
    friction = std::make_shared<FrictionEnergy>(layout, p.eps, p.lambda);
    total->add(el);
    total->add(load);
    total->add(normal);
    total->add(friction);
  }
};

/// All sample points of the composite: random, law branches/windows on node 0, friction on node 1.
struct Sample {
  Vec x;
  Mat extra;
  std::string what;
};
std::vector<Sample> composite_points(const Problem& p) {
  std::vector<Sample> out;
  std::mt19937 rng(15);
  for (int i = 0; i < 10; ++i) out.push_back({random_point(p, rng), Mat(), "random " + std::to_string(i)});
  for (const LawPoint& lp : law_points(p)) {
    Vec x = random_point(p, rng);
    x[p.nu(0)] = lp.r;
    out.push_back({x, Mat(), lp.what});
  }
  for (double s : FRICTION_Y) {
    Vec x = random_point(p, rng);
    x.segment(p.nu(1) + 1, p.dim - 1) = s * p.eps * random_direction(p.dim - 1, rng);
    out.push_back({x, s == 0 ? zero_slip_extra(p, 1) : Mat(), "|u_tau|/eps = " + std::to_string(s)});
  }
  return out;
}

TEST_P(EnergyFd, Total) {
  Composite c(p_);
  const TotalEnergy& total = *c.total;
  EXPECT_EQ(total.size(), p_.n);
  EXPECT_TRUE(same_pattern(total.hessian_pattern(), c.el->lower()));
  const Fn fn = of_objective(total);
  const Fn parts[] = {of_term(*c.el, c.el->lower()), of_term(*c.load, c.el->lower()), of_term(*c.normal, c.el->lower()),
                      of_term(*c.friction, c.el->lower())};
  for (const Sample& s : composite_points(p_)) {
    SCOPED_TRACE(s.what);
    const Scales sc = magnitudes(p_, {true, true, true, true}, s.x);
    check_fd(fn, s.x, p_.steps(s.x), sc, s.extra);
    // The composite is the sum of its terms (same pattern, values added).
    double v = 0;
    Vec g = Vec::Zero(p_.n);
    Mat H = Mat::Zero(p_.n, p_.n);
    for (const Fn& part : parts) {
      v += part.value(s.x);
      g += part.gradient(s.x);
      H += symmetric_from_lower(part.hessian(s.x, Psd::NONE));
    }
    EXPECT_NEAR(fn.value(s.x), v, kIdentity * sc.F);
    EXPECT_LE((fn.gradient(s.x) - g).cwiseAbs().maxCoeff(), kIdentity * sc.G.maxCoeff());
    const Mat Ht = symmetric_from_lower(fn.hessian(s.x, Psd::NONE));
    EXPECT_LE((Ht - H).cwiseAbs().maxCoeff(), kIdentity * H.cwiseAbs().maxCoeff());
  }
}

TEST_P(EnergyFd, Scaled) {
  Composite c(p_);
  // s_x, s_f far from 1 and from each other so that a swapped or missing factor shows.
  const double sx = 0.05, sf = 3.0;
  const ScaledObjective scaled(*c.total, sx, sf);
  EXPECT_EQ(scaled.x_scale(), sx);
  EXPECT_EQ(scaled.f_scale(), sf);
  EXPECT_EQ(scaled.size(), p_.n);
  EXPECT_TRUE(same_pattern(scaled.hessian_pattern(), c.total->hessian_pattern()));
  const Fn fn = of_objective(scaled), base = of_objective(*c.total);
  for (const Sample& s : composite_points(p_)) {
    SCOPED_TRACE(s.what);
    const Vec xt = s.x / sx;
    Scales sc = magnitudes(p_, {true, true, true, true}, s.x);
    sc.F /= sf;
    sc.G *= sx / sf;
    check_fd(fn, xt, p_.steps(s.x) / sx, sc, s.extra.size() ? Mat(s.extra * (sx * sx / sf)) : Mat());
    // f̃(x̃) = f(s_x x̃)/s_f, ∇̃ = (s_x/s_f) ∇f, ∇̃² = (s_x²/s_f) ∇²f.
    const Vec xb = sx * xt;
    EXPECT_NEAR(fn.value(xt), base.value(xb) / sf, kIdentity * sc.F);
    EXPECT_LE((fn.gradient(xt) - sx / sf * base.gradient(xb)).cwiseAbs().maxCoeff(), kIdentity * sc.G.maxCoeff());
    const Mat Hb = symmetric_from_lower(base.hessian(xb, Psd::NONE)) * (sx * sx / sf);
    EXPECT_LE((symmetric_from_lower(fn.hessian(xt, Psd::NONE)) - Hb).cwiseAbs().maxCoeff(),
              kIdentity * Hb.cwiseAbs().maxCoeff());
  }
}

// The condensed formulation (solve()'s default for a linear material): Γ3 unknowns only, the
// condensed elastic energy ½(x − y)ᵀS(x − y) + c with a dense SPD S on dense_lower_pattern, plus
// the contact terms at nd.first[k] = d·k — exactly how make_formulation assembles it.
TEST_P(EnergyFd, CondensedTotal) {
  const Problem p = make_problem(dim_, eps_, 7, 0);
  ASSERT_EQ(p.n, p.nc * dim_);
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Vec v(p.n), y(p.n);
  for (Index i = 0; i < p.n; ++i) {
    v[i] = 2 * u01(rng) - 1;
    y[i] = 0.2 * u01(rng) - 0.1;
  }
  const Mat S = Mat(p.K) + 0.5 * v * v.transpose();  // dense (Schur complements are), SPD
  const double c0 = -0.7;
  const SpMat pattern = dense_lower_pattern(p.n);
  EXPECT_EQ(pattern.nonZeros(), p.n * (p.n + 1) / 2);
  auto el = std::make_shared<CondensedElasticEnergy>(std::make_shared<const Mat>(S), y, c0);
  const auto layout = p.layout(pattern);
  auto normal = std::make_shared<NormalComplianceEnergy>(layout, p.law);
  auto friction = std::make_shared<FrictionEnergy>(layout, eps_, p.lambda);
  TotalEnergy total(p.n, pattern);
  total.add(el);
  total.add(normal);
  total.add(friction);
  const Fn fe = of_term(*el, pattern), ft = of_objective(total);
  const Mat Sabs = S.cwiseAbs();
  for (const Sample& smp : composite_points(p)) {
    SCOPED_TRACE(smp.what);
    const Vec& x = smp.x;
    const Vec da = (x - y).cwiseAbs();
    Scales se;  // ½|d|ᵀ|S||d| + |c| (d = x − y), ∇: |S||d| — plus the magnitudes of x − y itself
    se.F = 0.5 * da.dot(Sabs * da) + std::abs(c0);
    se.G = Sabs * (x.cwiseAbs() + y.cwiseAbs());
    check_fd(fe, x, p.steps(x), se);
    EXPECT_NEAR(el->value(x), 0.5 * (x - y).dot(S * (x - y)) + c0, kIdentity * se.F);
    EXPECT_LE((symmetric_from_lower(fe.hessian(x, Psd::NONE)) - S).cwiseAbs().maxCoeff(), kIdentity * Sabs.maxCoeff());
    Scales st = magnitudes(p, {false, false, true, true}, x);
    st.F += se.F;
    st.G += se.G;
    check_fd(ft, x, p.steps(x), st, smp.extra);
  }
}

// Psd::CLAMP on the softening branch (c2 < 0): the normal term's curvature is clamped to 0 and
// the composite (K SPD + clamped nodal terms + convex friction) is PSD; Psd::NONE keeps w c2.
TEST_P(EnergyFd, ClampOnSofteningBranch) {
  const double r = 0.5 * (LAW_R1 + LAW_R2);  // middle of (r1, r2)
  std::mt19937 rng(16);
  Vec x = random_point(p_, rng);
  x[p_.nu(0)] = r;
  if (!outside_windows(p_, r)) {
    // ε = 1: the windows overlap so much that p_ε′ = Σ Δs_k q_ε′(r − r_k) ≥ 0 everywhere (the −200
    // ramp is always outweighed), i.e. the mollified law has no softening left: CLAMP == NONE.
    EXPECT_EQ(p_.law->one_sided_lipschitz(), 0.0);
    NormalComplianceEnergy term(p_.layout(p_.blocks), p_.law);
    const Fn fn = of_term(term, p_.blocks);
    EXPECT_EQ(symmetric_from_lower(fn.hessian(x, Psd::NONE)), symmetric_from_lower(fn.hessian(x, Psd::CLAMP)));
    return;
  }
  const double w0 = p_.nodes.w[0];
  const double scale = p_.K.cwiseAbs().sum() + w0 * 600 + 2.0 / eps_ * (p_.nodes.w.cwiseProduct(p_.lambda)).maxCoeff();

  NormalComplianceEnergy term(p_.layout(p_.blocks), p_.law);
  const Fn fn = of_term(term, p_.blocks);
  const Mat Hn = symmetric_from_lower(fn.hessian(x, Psd::NONE));
  const Mat Hc = symmetric_from_lower(fn.hessian(x, Psd::CLAMP));
  EXPECT_NEAR(Hn(p_.nu(0), p_.nu(0)), w0 * LAW_C2, kIdentity * w0 * 600);  // negative curvature w c2
  EXPECT_EQ(Hc(p_.nu(0), p_.nu(0)), 0.0);
  Eigen::SelfAdjointEigenSolver<Mat> ec(Hc), en(Hn);
  EXPECT_GE(ec.eigenvalues().minCoeff(), -1e-12 * scale);
  EXPECT_LE(en.eigenvalues().minCoeff(), w0 * LAW_C2 * (1 - 1e-12));
  // CLAMP differs from NONE only where the curvature is negative.
  for (Index k = 0; k < p_.nc; ++k) {
    const double dp = p_.nodes.w[k] * p_.law->dp(x[p_.nu(k)]);
    EXPECT_EQ(Hc(p_.nu(k), p_.nu(k)), std::max(dp, 0.0));
  }

  Composite c(p_);
  const Fn tf = of_objective(*c.total);
  const Mat Tn = symmetric_from_lower(tf.hessian(x, Psd::NONE));
  const Mat Tc = symmetric_from_lower(tf.hessian(x, Psd::CLAMP));
  Eigen::SelfAdjointEigenSolver<Mat> tc(Tc), tn(Tn);
  EXPECT_GE(tc.eigenvalues().minCoeff(), -1e-12 * scale);
  // Rayleigh quotient at e_ν0: K_νν + w c2 ≤ 5 − 0.2·100 < 0, so NONE is indefinite.
  const double rq = p_.K.coeff(p_.nu(0), p_.nu(0)) + w0 * LAW_C2;
  ASSERT_LT(rq, 0.0);
  EXPECT_LE(tn.eigenvalues().minCoeff(), rq + 1e-12 * scale);
  EXPECT_NEAR((Tn - Tc).cwiseAbs().sum(), (Hn - Hc).cwiseAbs().sum(), 1e-12 * scale);
}

// The Hessian pattern is fixed: repeated calls on the same H keep nnz, index arrays and storage.
TEST_P(EnergyFd, PatternFixedAcrossCalls) {
  Composite c(p_);
  const ScaledObjective scaled(*c.total, 0.05, 3.0);
  std::mt19937 rng(17);
  for (const NlpObjective* o :
       {static_cast<const NlpObjective*>(c.total.get()), static_cast<const NlpObjective*>(&scaled)}) {
    const SpMat& P = o->hessian_pattern();
    EXPECT_TRUE(P.isCompressed());
    for (int c2 = 0; c2 < P.outerSize(); ++c2)
      for (SpMat::InnerIterator it(P, c2); it; ++it) EXPECT_GE(it.row(), it.col());
    SpMat H;
    o->hessian(random_point(p_, rng), H, Psd::NONE);
    ASSERT_TRUE(same_pattern(H, P));
    const int* inner = H.innerIndexPtr();
    const double* values = H.valuePtr();
    for (int i = 0; i < 6; ++i) {
      const Vec x = random_point(p_, rng);
      o->hessian(x, H, i % 2 ? Psd::CLAMP : Psd::NONE);
      EXPECT_TRUE(same_pattern(H, P));
      EXPECT_EQ(H.innerIndexPtr(), inner);  // no reallocation: the backend may hold these pointers
      EXPECT_EQ(H.valuePtr(), values);
      // Values are recomputed, not accumulated: a fresh H gives the same numbers.
      SpMat H2;
      o->hessian(x, H2, i % 2 ? Psd::CLAMP : Psd::NONE);
      EXPECT_EQ(Eigen::Map<const Vec>(H.valuePtr(), H.nonZeros()), Eigen::Map<const Vec>(H2.valuePtr(), H2.nonZeros()));
    }
  }
}

// ---------------------------------------------------------------- the check can fail

/// A term with a deliberately wrong derivative, to show check_fd flags it.
enum class Bug { GRADIENT_1E4, HESSIAN_1E3, EXACT_LAW_GRADIENT, EXACT_LAW_HESSIAN };
class BuggyTerm : public EnergyTerm {
 public:
  BuggyTerm(std::shared_ptr<EnergyTerm> t, Bug bug, const Problem& p) : m_t(std::move(t)), m_bug(bug), m_p(p) {}
  std::string name() const override { return "buggy " + m_t->name(); }
  double value(const Vec& x) const override { return m_t->value(x); }
  void add_gradient(const Vec& x, Vec& g) const override {
    Vec h = Vec::Zero(x.size());
    m_t->add_gradient(x, h);
    if (m_bug == Bug::GRADIENT_1E4) h *= 1 + 1e-4;  // a 1e-4 relative error
    if (m_bug == Bug::EXACT_LAW_GRADIENT)           // w p_ν instead of w p_ε: wrong inside windows only
      for (Index k = 0; k < m_p.nc; ++k) h[m_p.nu(k)] = m_p.nodes.w[k] * m_p.exact->p(x[m_p.nu(k)]);
    g += h;
  }
  void add_hessian(const Vec& x, SpMat& H, Psd psd) const override {
    SpMat L = H;
    std::fill(L.valuePtr(), L.valuePtr() + L.nonZeros(), 0.0);
    m_t->add_hessian(x, L, psd);
    if (m_bug == Bug::HESSIAN_1E3) Eigen::Map<Vec>(L.valuePtr(), L.nonZeros()) *= 1 + 1e-3;
    if (m_bug == Bug::EXACT_LAW_HESSIAN)
      for (Index k = 0; k < m_p.nc; ++k)
        L.coeffRef(m_p.nu(k), m_p.nu(k)) = m_p.nodes.w[k] * m_p.exact->dp(x[m_p.nu(k)]);
    Eigen::Map<Vec>(H.valuePtr(), H.nonZeros()) += Eigen::Map<const Vec>(L.valuePtr(), L.nonZeros());
  }

 private:
  std::shared_ptr<EnergyTerm> m_t;
  Bug m_bug;
  const Problem& m_p;
};

/// Does check_fd report a failure at x (failures intercepted, not recorded)?
bool flags(const Fn& fn, const Problem& p, const Terms& on, const Vec& x) {
  ::testing::TestPartResultArray results;
  {
    ::testing::ScopedFakeTestPartResultReporter intercept(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
    check_fd(fn, x, p.steps(x), magnitudes(p, on, x));
  }
  return results.size() > 0;
}

TEST_P(EnergyFd, CheckFlagsWrongDerivatives) {
  const auto layout = p_.layout(p_.blocks);
  auto normal = std::make_shared<NormalComplianceEnergy>(layout, p_.law);
  auto friction = std::make_shared<FrictionEnergy>(layout, eps_, p_.lambda);
  const Terms on_n{false, false, true, false}, on_f{false, false, false, true};
  std::mt19937 rng(18);
  std::vector<Vec> xs;
  for (int i = 0; i < 10; ++i) xs.push_back(random_point(p_, rng));
  std::vector<Vec> windows;  // node 0 inside a window of p_ε
  for (const LawPoint& lp : law_points(p_)) {
    Vec x = random_point(p_, rng);
    x[p_.nu(0)] = lp.r;
    (lp.in_window ? windows : xs).push_back(x);
  }
  for (Bug bug : {Bug::GRADIENT_1E4, Bug::HESSIAN_1E3}) {
    SCOPED_TRACE("bug " + std::to_string(static_cast<int>(bug)));
    const BuggyTerm bn(normal, bug, p_), bf(friction, bug, p_);
    const Fn fn = of_term(bn, p_.blocks), ff = of_term(bf, p_.blocks);
    int flagged_f = 0;
    for (const Vec& x : xs) {
      EXPECT_TRUE(flags(fn, p_, on_n, x));  // every point has some node with p_ε, p_ε′ ≠ 0
      flagged_f += flags(ff, p_, on_f, x);
    }
    // A 1e-4 gradient error shows everywhere; the 2D friction Hessian vanishes when every node
    // slides with |u_τ| ≥ ε, so a scaled Hessian shows only at points with some |u_τ| < ε.
    if (bug == Bug::GRADIENT_1E4)
      EXPECT_EQ(flagged_f, static_cast<int>(xs.size()));
    else
      EXPECT_GT(flagged_f, 0);
  }
  // Using the exact law's p_ν, p_ν′ instead of the mollified ones is caught inside the windows.
  for (Bug bug : {Bug::EXACT_LAW_GRADIENT, Bug::EXACT_LAW_HESSIAN}) {
    SCOPED_TRACE("bug " + std::to_string(static_cast<int>(bug)));
    const BuggyTerm bn(normal, bug, p_);
    const Fn fn = of_term(bn, p_.blocks);
    for (const Vec& x : windows) EXPECT_TRUE(flags(fn, p_, on_n, x));
  }
}

INSTANTIATE_TEST_SUITE_P(DimEps, EnergyFd,
                         ::testing::Combine(::testing::Values(2, 3), ::testing::Values(1e-8, 1e-6, 1e-4, 1e-2, 1.0)),
                         [](const ::testing::TestParamInfo<Param>& info) {
                           std::ostringstream os;
                           os << "d" << std::get<0>(info.param) << "_eps1em"
                              << static_cast<int>(std::lround(-std::log10(std::get<1>(info.param))));
                           return os.str();
                         });

// ---------------------------------------------------------------- small direct checks

// pattern_position finds lower entries (either argument order) and refuses absent ones.
TEST(PatternPosition, FindsAndRejects) {
  const Problem p = make_problem(3, 1e-2);
  const SpMat& B = p.blocks;
  const Index a = p.nu(1);
  const Index pos = pattern_position(B, a + 2, a + 1);
  EXPECT_EQ(B.innerIndexPtr()[pos], a + 2);
  EXPECT_EQ(pattern_position(B, a + 1, a + 2), pos);
  EXPECT_THROW(pattern_position(B, p.nu(2), p.nu(1)), Error);  // different nodes: not in the blocks
}

// ---------------------------------------------------------------- owning

// The condensed elastic term shares S: the caller's handle can go.
TEST(CondensedElasticEnergy, OwnsItsSchurComplement) {
  const Problem p = make_problem(3, 1e-2);
  std::mt19937 rng(32);
  const Vec x = random_point(p, rng);
  const Mat S = Mat(p.K);
  const Vec y = Vec::Constant(p.n, 0.1);
  const SpMat pattern = dense_lower_pattern(p.n);
  std::unique_ptr<CondensedElasticEnergy> condensed;
  {
    auto owner = std::make_shared<const Mat>(S);
    condensed = std::make_unique<CondensedElasticEnergy>(owner, y, 0.5);
  }
  const Fn fn = of_term(*condensed, pattern);
  EXPECT_EQ(fn.value(x), 0.5 * (x - y).dot(S * (x - y)) + 0.5);
  EXPECT_EQ(fn.gradient(x), Vec(S * (x - y)));
  EXPECT_EQ(symmetric_from_lower(fn.hessian(x, Psd::NONE)), S);
  EXPECT_THROW((void)CondensedElasticEnergy(nullptr, y, 0.0), Error);
  EXPECT_THROW((void)CondensedElasticEnergy(std::make_shared<const Mat>(Mat::Identity(2, 2)), y, 0.0), Error);
}

// ---------------------------------------------------------------- complete from construction

/// Value, gradient and Hessian (on @p pattern) of a term at x, for exact comparisons.
struct Eval {
  double v;
  Vec g;
  Mat H;
};
Eval eval(const EnergyTerm& t, const SpMat& pattern, const Vec& x, Psd psd = Psd::NONE) {
  const Fn fn = of_term(t, pattern);
  return {fn.value(x), fn.gradient(x), symmetric_from_lower(fn.hessian(x, psd))};
}
void expect_same(const Eval& a, const Eval& b) {
  EXPECT_EQ(a.v, b.v);
  EXPECT_EQ(a.g, b.g);
  EXPECT_EQ(a.H, b.H);
}

// set_eps (ε-continuation) gives exactly the term built with that width: the normal term
// re-mollifies the same exact law, friction changes ε_τ only.
TEST(ContactEnergy, SetEpsEqualsConstructionWithThatWidth) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE("d = " + std::to_string(dim));
    const Problem p = make_problem(dim, 1e-2);
    const auto layout = p.layout(p.blocks);
    const double eps2 = 3e-3;
    NormalComplianceEnergy normal(layout, p.law);
    normal.set_eps(eps2);
    EXPECT_EQ(normal.law().eps_nu(), eps2);
    EXPECT_EQ(&normal.law().exact(), p.exact.get());  // the same exact law, not a copy
    const NormalComplianceEnergy normal2(layout, std::make_shared<const MollifiedLaw>(p.exact, eps2));
    FrictionEnergy friction(layout, p.eps, p.lambda);
    friction.set_eps(eps2);
    EXPECT_EQ(friction.eps(), eps2);
    const FrictionEnergy friction2(layout, eps2, p.lambda);
    std::mt19937 rng(31);
    for (int i = 0; i < 5; ++i) {
      const Vec x = random_point(p, rng);
      expect_same(eval(normal, p.blocks, x), eval(normal2, p.blocks, x));
      expect_same(eval(normal, p.blocks, x, Psd::CLAMP), eval(normal2, p.blocks, x, Psd::CLAMP));
      expect_same(eval(friction, p.blocks, x), eval(friction2, p.blocks, x));
    }
    // Re-lagging replaces λ whole.
    const Vec lam = 2 * p.lambda;
    friction.set_lambda(lam);
    EXPECT_EQ(friction.lambda(), lam);
  }
}

// A term cannot be built without its law or with an unusable width or bounds.
TEST(ContactEnergy, RejectsIncompleteConstruction) {
  const Problem p = make_problem(2, 1e-2);
  const auto layout = p.layout(p.blocks);
  EXPECT_THROW((void)NormalComplianceEnergy(layout, nullptr), Error);
  EXPECT_THROW((void)FrictionEnergy(layout, 0.0, p.lambda), Error);
  EXPECT_THROW((void)FrictionEnergy(layout, INF, p.lambda), Error);
  EXPECT_THROW((void)FrictionEnergy(layout, 1e-2, Vec::Zero(p.nc + 1)), Error);
  FrictionEnergy friction(layout, 1e-2, p.lambda);
  EXPECT_THROW(friction.set_eps(-1e-2), Error);
  EXPECT_THROW(friction.set_lambda(Vec::Zero(p.nc - 1)), Error);
  EXPECT_EQ(friction.eps(), 1e-2);  // unchanged by the refused calls
  EXPECT_EQ(friction.lambda(), p.lambda);
  NormalComplianceEnergy normal(layout, p.law);
  EXPECT_THROW(normal.set_eps(0.0), Error);
  EXPECT_EQ(normal.law().eps_nu(), 1e-2);
}

// The normal term keeps its law and layout alive: the caller's handles can go.
TEST(ContactEnergy, OwnsItsLawAndLayout) {
  const Problem p = make_problem(3, 1e-2);
  std::mt19937 rng(32);
  const Vec x = random_point(p, rng);
  const Eval ref_n = eval(NormalComplianceEnergy(p.layout(p.blocks), p.law), p.blocks, x);
  std::unique_ptr<NormalComplianceEnergy> normal;
  {
    auto exact = std::make_shared<const PiecewiseLinearLaw>(PiecewiseLinearLaw::paper(LAW_C1, LAW_C2, LAW_C3, LAW_R1, LAW_R2));
    normal = std::make_unique<NormalComplianceEnergy>(p.layout(p.blocks),
                                                      std::make_shared<const MollifiedLaw>(exact, p.eps));
  }  // the law and the layout now live in the term only
  expect_same(eval(*normal, p.blocks, x), ref_n);
}

}  // namespace
}  // namespace hemicontact
