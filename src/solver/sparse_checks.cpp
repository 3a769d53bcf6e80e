#include <hemicontact/solver/sparse_checks.hpp>

#include <hemicontact/core/clock.hpp>
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

// 0·∞ is 0 here: a term whose constant is zero contributes nothing (as in check/smallness.cpp).
double term(double c, double lam) { return c == 0 ? 0.0 : c / lam; }

}  // namespace

LanczosResult lanczos_largest(const std::function<Vec(const Vec&)>& apply, Index n, double tol, int max_iter) {
  LanczosResult R;
  if (n == 0) return R;
  const Index kmax = std::min<Index>(n, std::max(1, max_iter));
  Mat Q(n, kmax + 1);
  std::mt19937 rng(12345);  // a fixed start: the same answer on every run
  std::uniform_real_distribution<double> unif(-1.0, 1.0);
  for (Index i = 0; i < n; ++i) Q(i, 0) = unif(rng);
  Q.col(0).normalize();
  Vec alpha(kmax), beta(kmax);
  for (Index k = 0; k < kmax; ++k) {
    Vec w = apply(Q.col(k));
    R.iterations = static_cast<int>(k + 1);
    alpha[k] = Q.col(k).dot(w);
    // Full reorthogonalization, twice: the Ritz residual bound below holds only for an orthonormal Q.
    for (int pass = 0; pass < 2; ++pass) w -= Q.leftCols(k + 1) * (Q.leftCols(k + 1).transpose() * w);
    beta[k] = w.norm();
    const bool exhausted = beta[k] <= 1e-300 || k + 1 == kmax;
    if ((k + 1) % 5 == 0 || exhausted) {
      std::tie(R.theta, R.residual) = ritz_top(alpha, beta, k);
      if (beta[k] <= 1e-300) R.residual = 0;  // an invariant subspace: θ is an eigenvalue
      R.converged = R.theta > 0 && R.residual <= tol * R.theta;
      if (R.converged || exhausted) return R;
    }
    Q.col(k + 1) = w / beta[k];
  }
  return R;
}

Gamma3Spectrum gamma3_spectrum(const std::function<Vec(const Vec&)>& apply_Sinv, const Vec& w, int d,
                               const SolveOptions& opt, const std::string& what) {
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
  const LanczosResult r1 = lanczos_largest(op1, m, opt.lanczos_tol, opt.lanczos_max_iter);
  const LanczosResult rn = lanczos_largest(opn, nc, opt.lanczos_tol, opt.lanczos_max_iter);
  Gamma3Spectrum S;
  S.k1 = 1 / r1.theta;
  S.k1_low = 1 / (r1.theta + r1.residual);
  S.k1nu = 1 / rn.theta;
  S.k1nu_low = 1 / (rn.theta + rn.residual);
  S.converged = r1.converged && rn.converged;
  S.iterations = r1.iterations + rn.iterations;
  S.how = "Lanczos on " + what + ": " + std::to_string(r1.iterations) + " + " + std::to_string(rn.iterations) +
          " steps, relative Ritz residuals " + fmt(r1.residual / r1.theta, 2) + ", " + fmt(rn.residual / rn.theta, 2) +
          (S.converged ? "" : " (not converged in check.lanczos_max_iter steps)");
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
  if (!s.converged) return r;
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
  c.checked = s.converged && (convex || not_convex);
  c.strongly_convex = c.checked && convex;
  c.note = s.how + "; k_1nu - alpha = lambda_min(W^-1/2 S_nu W^-1/2) - alpha, the sign of lambda_min(S - alpha W_nu)" +
           (c.checked ? "" : "; not decided within the Lanczos residual");
  return c;
}

}  // namespace hemicontact
