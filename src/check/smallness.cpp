#include <hemicontact/check/smallness.hpp>

#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/material/material.hpp>

#include <Eigen/Eigenvalues>

#include <Eigen/Cholesky>

#include <chrono>
#include <random>
#include <cmath>
#include <tuple>
#include <utility>

namespace hemicontact {
namespace {

// Smallest eigenvalue of A v = λ diag(m) v (A SPD, m > 0): symmetric scaling by m^{-1/2}.
double smallest_generalized(const Mat& A, const Vec& m) {
  const Vec s = m.cwiseSqrt().cwiseInverse();
  return smallest_eigenvalue_spd(s.asDiagonal() * A * s.asDiagonal());
}

// The two eigenvalues of (21) from a condensed operator S on Γ3 (node-major ν, τ...): λ_{1,ν}
// with the mass diag(w) on every component, λ_{1ν,ν} with mass on u_ν only (u_τ minimized out:
// the Schur complement onto the ν components).
std::pair<double, double> gamma3_eigenvalues(const Model& md, const Mat& S) {
  const Index nc = md.contact.size();
  const int d = md.dim();
  // λ_{1,ν}: mass diag(w_k) on every component (|u|² = u_ν² + |u_τ|² in the orthonormal frame).
  Vec mass(d * nc);
  for (Index k = 0; k < nc; ++k) mass.segment(d * k, d).setConstant(md.contact.w[k]);
  const double lambda_1 = smallest_generalized(S, mass);
  // λ_{1ν,ν}: only u_ν carries mass; minimize the quotient over u_τ first (Schur complement).
  std::vector<Index> nu, tau;
  for (Index k = 0; k < nc; ++k) {
    nu.push_back(d * k);
    for (int c = 1; c < d; ++c) tau.push_back(d * k + c);
  }
  Mat Snn(nc, nc), Snt(nc, tau.size()), Stt(tau.size(), tau.size());
  for (size_t i = 0; i < nu.size(); ++i) {
    for (size_t j = 0; j < nu.size(); ++j) Snn(i, j) = S(nu[i], nu[j]);
    for (size_t j = 0; j < tau.size(); ++j) Snt(i, j) = S(nu[i], tau[j]);
  }
  for (size_t i = 0; i < tau.size(); ++i)
    for (size_t j = 0; j < tau.size(); ++j) Stt(i, j) = S(tau[i], tau[j]);
  const Mat Sn = Snn - Snt * Stt.llt().solve(Snt.transpose());
  return {lambda_1, smallest_generalized(Sn, md.contact.w)};
}

// 0·∞ is 0 here: a term whose constant is zero contributes nothing.
double term(double c, double lam) { return c == 0 ? 0.0 : c / lam; }

SmallnessReport constants(const Model& md) {
  SmallnessReport r;
  r.m_F = md.material->m_F();
  r.L_Fb = md.friction ? md.friction->lipschitz() : 0.0;
  r.alpha_j = md.normal_law ? md.normal_law->one_sided_lipschitz() : 0.0;
  return r;
}

}  // namespace

double smallest_eigenvalue_spd(const Mat& B) {
  const Index n = B.rows();
  const auto dense = [&] {
    Eigen::SelfAdjointEigenSolver<Mat> es(B, Eigen::EigenvaluesOnly);
    return es.eigenvalues().minCoeff();
  };
  if (n <= 400) return dense();
  const Eigen::LLT<Mat> llt(B);
  if (llt.info() != Eigen::Success) return dense();  // not positive definite: the dense solver says how
  // Lanczos on B⁻¹ with full reorthogonalization: its largest eigenvalue θ is 1/λ_min(B). For a
  // Ritz pair (θ, y) of the k-step tridiagonal T_k, ‖B⁻¹y − θy‖ = β_k |s_k| (s the eigenvector of
  // T_k), and some eigenvalue of B⁻¹ lies within that residual of θ; θ never exceeds the largest,
  // and a pseudo-random start has a component along its eigenvector. So stopping at a residual
  // ≤ 1e-13·θ gives λ_min to ~1e-13 (relative).
  const Index kmax = std::min<Index>(n, 120);
  Mat Q(n, kmax + 1);
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> unif(-1.0, 1.0);
  for (Index i = 0; i < n; ++i) Q(i, 0) = unif(rng);
  Q.col(0).normalize();
  Vec alpha(kmax), beta(kmax);
  for (Index k = 0; k < kmax; ++k) {
    Vec w = llt.solve(Q.col(k));
    alpha[k] = Q.col(k).dot(w);
    for (int pass = 0; pass < 2; ++pass) w -= Q.leftCols(k + 1) * (Q.leftCols(k + 1).transpose() * w);
    beta[k] = w.norm();
    const bool exhausted = beta[k] <= 1e-300 || k + 1 == kmax;
    if ((k + 1) % 10 == 0 || exhausted) {
      Eigen::SelfAdjointEigenSolver<Mat> t;
      t.computeFromTridiagonal(alpha.head(k + 1), beta.head(k), Eigen::ComputeEigenvectors);
      const Index top = k;  // eigenvalues ascending
      const double theta = t.eigenvalues()[top];
      const double residual = beta[k] * std::abs(t.eigenvectors()(k, top));
      if (theta > 0 && (residual <= 1e-13 * theta || beta[k] <= 1e-300)) return 1.0 / theta;
      if (exhausted) break;
    }
    Q.col(k + 1) = w / beta[k];
  }
  return dense();  // not converged in kmax steps (a cluster at the bottom): the dense solver
}

SmallnessReport evaluate_smallness(const Model& md) {
  const auto t0 = std::chrono::steady_clock::now();
  SmallnessReport r = constants(md);
  const Index nc = md.contact.size();
  const int d = md.dim();
  if (nc == 0) return r;
  // Gram matrix of (u, v)_V = ∫ ε(u):ε(v): Voigt with engineering shears gives weight ½ on shears.
  Mat G = Mat::Identity(voigt_size(d), voigt_size(d));
  for (int k = d; k < voigt_size(d); ++k) G(k, k) = 0.5;
  const MovableSpMat Ke = md.dofs.reduce(assemble_stiffness(md.mesh, G));
  const Condensation cond(Ke, Vec::Zero(Ke.rows()), d * nc);
  std::tie(r.lambda_1, r.lambda_1nu) = gamma3_eigenvalues(md, cond.S());
  r.lhs = term(r.L_Fb, r.lambda_1) + term(r.alpha_j, r.lambda_1nu);
  r.lhs_lower = r.lhs_upper = r.lhs;
  r.holds = r.lhs < r.m_F;
  r.computed = true;
  r.method = "exact";
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

SmallnessReport evaluate_smallness(const Model& md, const Mat& S_K, bool allow_exact) {
  const auto t0 = std::chrono::steady_clock::now();
  SmallnessReport r = constants(md);
  const Index nc = md.contact.size();
  if (nc == 0) return r;
  const double m_F = md.material->m_F(), L_F = md.material->L_F();
  const auto [k1, k1nu] = gamma3_eigenvalues(md, S_K);
  // λ(S_G) ∈ [λ(S_K)/L_F, λ(S_K)/m_F] (header): small λ make lhs large.
  const double lo_1 = k1 / L_F, hi_1 = k1 / m_F, lo_1nu = k1nu / L_F, hi_1nu = k1nu / m_F;
  r.lhs_upper = term(r.L_Fb, lo_1) + term(r.alpha_j, lo_1nu);
  r.lhs_lower = term(r.L_Fb, hi_1) + term(r.alpha_j, hi_1nu);
  const bool holds = r.lhs_upper < r.m_F, fails = r.lhs_lower >= r.m_F;
  if (!holds && !fails && allow_exact) {
    const double lower = r.lhs_lower, upper = r.lhs_upper;
    SmallnessReport e = evaluate_smallness(md);
    e.lhs_lower = lower;
    e.lhs_upper = upper;
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return e;
  }
  r.method = "bound";
  r.holds = holds;
  r.lambda_1 = holds ? lo_1 : hi_1;
  r.lambda_1nu = holds ? lo_1nu : hi_1nu;
  r.lhs = holds ? r.lhs_upper : r.lhs_lower;
  r.computed = holds || fails;  // an undecided bracket (allow_exact = false) decides nothing
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace hemicontact
