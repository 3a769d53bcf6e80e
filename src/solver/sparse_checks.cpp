#include <hemicontact/solver/sparse_checks.hpp>

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <utility>

namespace hemicontact {
namespace {

// The largest eigenvalue of the k-step tridiagonal T_k and its Ritz residual β_k |s_k|.
std::pair<double, double> ritz_top(const Vec& alpha, const Vec& beta, Index k) {
  Eigen::SelfAdjointEigenSolver<Mat> t;
  t.computeFromTridiagonal(alpha.head(k + 1), beta.head(k), Eigen::ComputeEigenvectors);
  return {t.eigenvalues()[k], beta[k] * std::abs(t.eigenvectors()(k, k))};  // ascending: the top is k
}

// k_1, k_1ν and their lower bounds 1/(θ + r) from the two runs' Ritz pairs (k_1 NaN where its run
// was not asked for).
Gamma3Spectrum spectrum_of(const LanczosResult& r1, const LanczosResult& rn, bool with_k1) {
  Gamma3Spectrum S;
  S.has_k1 = with_k1;
  S.k1 = with_k1 ? 1 / r1.theta : NAN;
  S.k1_low = with_k1 ? 1 / (r1.theta + r1.residual) : NAN;
  S.k1nu = 1 / rn.theta;
  S.k1nu_low = 1 / (rn.theta + rn.residual);
  S.converged = (r1.converged || !with_k1) && rn.converged;
  S.iterations = r1.iterations + rn.iterations;
  return S;
}

// 0·∞ is 0 here: a term whose constant is zero contributes nothing (as in check/smallness.cpp).
double term(double c, double lam) { return c == 0 ? 0.0 : c / lam; }

}  // namespace

LanczosRun::LanczosRun(std::function<Vec(const Vec&)> apply, Index n, int max_iter)
    : apply_(std::move(apply)), kmax_(std::min<Index>(n, std::max(1, max_iter))) {
  if (n == 0) {
    done_ = true;
    return;
  }
  Q_.resize(n, kmax_ + 1);
  alpha_.resize(kmax_);
  beta_.resize(kmax_);
  std::mt19937 rng(12345);  // a fixed start: the same answer on every run
  std::uniform_real_distribution<double> unif(-1.0, 1.0);
  for (Index i = 0; i < n; ++i) Q_(i, 0) = unif(rng);
  Q_.col(0).normalize();
}

// Up to @p steps more steps (the Ritz pair read after the last); stops where the Krylov space is
// exhausted or max_iter is reached (done()).
void LanczosRun::advance(int steps, double tol) {
  for (int s = 0; s < steps && !done_; ++s) {
    const Index k = k_;
    Vec w = apply_(Q_.col(k));
    R_.iterations = static_cast<int>(k + 1);
    alpha_[k] = Q_.col(k).dot(w);
    // Full reorthogonalization, twice: the Ritz residual bound below holds only for an orthonormal Q.
    for (int pass = 0; pass < 2; ++pass) w -= Q_.leftCols(k + 1) * (Q_.leftCols(k + 1).transpose() * w);
    beta_[k] = w.norm();
    const bool invariant = beta_[k] <= 1e-300;
    done_ = invariant || k + 1 == kmax_;
    if (s + 1 == steps || done_) {
      std::tie(R_.theta, R_.residual) = ritz_top(alpha_, beta_, k);
      if (invariant) R_.residual = 0;  // an invariant subspace: θ is an eigenvalue
    }
    if (!done_) Q_.col(k + 1) = w / beta_[k];
    ++k_;
  }
  R_.converged = R_.theta > 0 && R_.residual <= tol * R_.theta;
  done_ = done_ || R_.converged;
}

LanczosResult lanczos_largest(const std::function<Vec(const Vec&)>& apply, Index n, double tol, int max_iter) {
  LanczosRun run(apply, n, max_iter);
  while (!run.done()) run.advance(LANCZOS_READ_EVERY, tol);
  return run.result();
}

Gamma3Spectrum gamma3_spectrum(const std::function<Vec(const Vec&)>& apply_Sinv, const Vec& w, int d,
                               const SolveOptions& opt, const std::string& what,
                               const std::function<bool(const Gamma3Spectrum&)>& decided, bool with_k1) {
  const auto t0 = clk::now();
  const Index nc = w.size(), m = d * nc;
  // (W^-1/2 S W^-1/2)⁻¹ = W^1/2 S⁻¹ W^1/2: the scaling of the inverse operator is by diag(w)^1/2.
  const Vec s = w.cwiseSqrt();
  // k_1: W^1/2 S⁻¹ W^1/2, W = diag(w) on every component.
  const auto op1 = [&](const Vec& v) {
    Vec b(m);
    for (Index k = 0; k < nc; ++k) b.segment(d * k, d) = s[k] * v.segment(d * k, d);
    Vec x = apply_Sinv(b);
    for (Index k = 0; k < nc; ++k) x.segment(d * k, d) *= s[k];
    return x;
  };
  // k_1ν: (S⁻¹)_νν = S_ν⁻¹, scaled by diag(w)^1/2 on the normal unknowns.
  const auto opn = [&](const Vec& v) {
    Vec b = Vec::Zero(m);
    for (Index k = 0; k < nc; ++k) b[d * k] = s[k] * v[k];
    const Vec x = apply_Sinv(b);
    Vec y(nc);
    for (Index k = 0; k < nc; ++k) y[k] = s[k] * x[d * k];
    return y;
  };
  // Both runs side by side, read every LANCZOS_READ_EVERY steps: they stop at check.lanczos_tol, or
  // once both are within check.lanczos_decide_tol and their brackets decide what the caller asks
  // (@p decided): a bracket that decides needs no more digits.
  // Without k_1 its run is empty (size 0: done before it starts).
  LanczosRun r1(op1, with_k1 ? m : 0, opt.lanczos_max_iter), rn(opn, nc, opt.lanczos_max_iter);
  Gamma3Spectrum S;
  do {
    r1.advance(LANCZOS_READ_EVERY, opt.lanczos_tol);
    rn.advance(LANCZOS_READ_EVERY, opt.lanczos_tol);
    S = spectrum_of(r1.result(), rn.result(), with_k1);
    Gamma3Spectrum final_now = S;  // what the caller would read were the runs to stop here
    final_now.decided = true;
    const auto close = [&](const LanczosResult& r) {
      return r.theta > 0 && r.residual <= opt.lanczos_decide_tol * r.theta;
    };
    S.decided = decided && (close(r1.result()) || !with_k1) && close(rn.result()) && decided(final_now);
  } while (!(r1.done() && rn.done()) && !S.decided);
  const LanczosResult &a = r1.result(), &b = rn.result();
  S.how = "Lanczos on " + what + ": " +
          (with_k1 ? std::to_string(a.iterations) + " + " + std::to_string(b.iterations) +
                         " steps, relative Ritz residuals " + fmt(a.residual / a.theta, 2) + ", " +
                         fmt(b.residual / b.theta, 2)
                   : "k_1nu alone (the inner convexity's), " + std::to_string(b.iterations) +
                         " steps, relative Ritz residual " + fmt(b.residual / b.theta, 2)) +
          (S.decided && !S.converged ? " (stopped once the brackets decided)"
           : S.converged             ? ""
                                     : " (not converged in check.lanczos_max_iter steps)");
  S.seconds = since(t0);
  return S;
}

SmallnessReport smallness_from_spectrum(const Model& md, const Gamma3Spectrum& s) {
  SmallnessReport r;
  r.m_F = md.material->m_F();
  r.L_Fb = md.friction ? md.friction->lipschitz() : 0.0;
  r.alpha_j = md.normal_law ? md.normal_law->one_sided_lipschitz() : 0.0;
  r.seconds = s.seconds;
  r.method = "bound";
  r.note = s.how;
  if (!s.has_k1) throw Error("smallness (21) from a spectrum without k_1", EXIT_INTERNAL);
  if (!s.converged && !s.decided) return r;
  const double m_F = md.material->m_F(), L_F = md.material->L_F();
  // λ(S_G) ∈ [λ(S_K)/L_F, λ(S_K)/m_F] (check/smallness.hpp), λ(S_K) ∈ [k_low, k] (Lanczos).
  const double lo_1 = s.k1_low / L_F, hi_1 = s.k1 / m_F, lo_1nu = s.k1nu_low / L_F, hi_1nu = s.k1nu / m_F;
  r.lhs_upper = term(r.L_Fb, lo_1) + term(r.alpha_j, lo_1nu);
  r.lhs_lower = term(r.L_Fb, hi_1) + term(r.alpha_j, hi_1nu);
  const bool holds = r.lhs_upper < r.m_F, fails = r.lhs_lower >= r.m_F;
  r.holds = holds;
  r.lambda_1 = holds ? lo_1 : hi_1;
  r.lambda_1nu = holds ? lo_1nu : hi_1nu;
  r.lhs = holds ? r.lhs_upper : r.lhs_lower;
  r.computed = holds || fails;
  if (!r.computed)
    r.note += "; not decided: the bracket [" + fmt(r.lhs_lower, 4) + ", " + fmt(r.lhs_upper, 4) + "] contains m_F = " +
              fmt(r.m_F, 4) + ", and the exact eigenvalues need a factorization of the eps:eps Gram matrix, " +
              "made only when asked (check.smallness_method = exact)";
  return r;
}

InnerConvexity convexity_from_spectrum(const Gamma3Spectrum& s, const PiecewiseLinearLaw* law) {
  InnerConvexity c;
  c.softening = law ? law->one_sided_lipschitz() : 0.0;
  if (!std::isfinite(c.softening)) {
    c.checked = true;
    c.min_eigenvalue = -INF;
    c.note = "p_nu jumps downward: j_nu is not semiconvex";
    return c;
  }
  // S − αW_ν ≻ 0 ⟺ k_1ν > α (sparse_checks.hpp); k_1ν ∈ [k1nu_low, k1nu].
  c.min_eigenvalue = s.k1nu - c.softening;
  const bool convex = s.k1nu_low > c.softening, not_convex = s.k1nu <= c.softening;
  c.checked = (s.converged || s.decided) && (convex || not_convex);
  c.strongly_convex = c.checked && convex;
  c.note = s.how + "; k_1nu - alpha = lambda_min(W^-1/2 S_nu W^-1/2) - alpha, the sign of lambda_min(S - alpha W_nu)" +
           (c.checked ? "" : "; not decided within the Lanczos residual");
  return c;
}

}  // namespace hemicontact
