#include <hemicontact/check/smallness.hpp>

#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/material/material.hpp>

#include <Eigen/Eigenvalues>

#include <chrono>
#include <cmath>

namespace hemicontact {
namespace {

// Smallest eigenvalue of A v = λ diag(m) v (A SPD, m > 0): symmetric scaling by m^{-1/2}.
double smallest_generalized(const Mat& A, const Vec& m) {
  const Vec s = m.cwiseSqrt().cwiseInverse();
  const Mat B = s.asDiagonal() * A * s.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Mat> es(B, Eigen::EigenvaluesOnly);
  return es.eigenvalues().minCoeff();
}

}  // namespace

SmallnessReport evaluate_smallness(const Model& md) {
  const auto t0 = std::chrono::steady_clock::now();
  SmallnessReport r;
  r.m_F = md.material->m_F();
  r.L_Fb = md.friction ? md.friction->lipschitz() : 0.0;
  r.alpha_j = md.normal_law ? md.normal_law->one_sided_lipschitz() : 0.0;
  const Index nc = md.contact.size();
  const int d = md.dim();
  if (nc == 0) return r;
  // Gram matrix of (u, v)_V = ∫ ε(u):ε(v): Voigt with engineering shears gives weight ½ on shears.
  Mat G = Mat::Identity(voigt_size(d), voigt_size(d));
  for (int k = d; k < voigt_size(d); ++k) G(k, k) = 0.5;
  const SpMat Ke = md.dofs.reduce(assemble_stiffness(md.mesh, G));
  const Condensation cond(Ke, Vec::Zero(Ke.rows()), d * nc);
  const Mat& S = cond.S();  // local (ν, τ...) components per node, node-major
  // λ_{1,ν}: mass diag(w_k) on every component (|u|² = u_ν² + |u_τ|² in the orthonormal frame).
  Vec mass(d * nc);
  for (Index k = 0; k < nc; ++k) mass.segment(d * k, d).setConstant(md.contact.w[k]);
  r.lambda_1 = smallest_generalized(S, mass);
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
  r.lambda_1nu = smallest_generalized(Sn, md.contact.w);
  // 0·∞ is 0 here: a term whose constant is zero contributes nothing.
  const auto term = [](double c, double lam) { return c == 0 ? 0.0 : c / lam; };
  r.lhs = term(r.L_Fb, r.lambda_1) + term(r.alpha_j, r.lambda_1nu);
  r.holds = r.lhs < r.m_F;
  r.computed = true;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace hemicontact
