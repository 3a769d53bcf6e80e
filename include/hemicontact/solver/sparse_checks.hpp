#pragma once
/// @file sparse_checks.hpp  The smallness condition (21) and the inner-convexity test without a
/// dense matrix of Γ3 size: the extreme eigenvalues they need come from Lanczos on S⁻¹, applied
/// through the factor the solve already has (never an extra factorization).
///
/// Both tests read the condensed stiffness S_K = K_CC − K_CI K_II⁻¹ K_IC on the m = d·n_Γ3 Γ3
/// unknowns (node-major ν, τ...), and only through its smallest generalized eigenvalues
///   k_1   = λ_min(S_K, diag(w) on every component)   (λ_{1,ν} of (21) up to the bracket)
///   k_1ν  = λ_min(S_ν, diag(w)),  S_ν = the Schur complement of S_K onto the normal unknowns,
/// (check/smallness.hpp: λ(S_K)/L_F ≤ λ(S_G) ≤ λ(S_K)/m_F brackets (21)'s eigenvalues). S_K⁻¹ is
/// (K⁻¹)_CC and S_ν⁻¹ = (K⁻¹)_νν, so each is the largest eigenvalue θ of an operator applied by one
/// solve: with the condensation's factor, two triangular solves with L_CC (S = L_CC L_CCᵀ, m² flops);
/// in the full formulation, one solve with the elastic factor. The inner problem Φ_λ is strongly
/// convex iff S_K − α W_ν ≻ 0 iff (Schur complement onto ν) S_ν − α W ≻ 0 iff k_1ν > α.

#include <hemicontact/contact/piecewise_linear_law.hpp>
#include <hemicontact/core/types.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/reports.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <functional>
#include <string>

namespace hemicontact {

/// The largest eigenvalue of a symmetric positive semidefinite operator, by Lanczos.
struct LanczosResult {
  double theta = 0;     ///< the largest Ritz value (never above the largest eigenvalue)
  double residual = 0;  ///< its Ritz residual: some eigenvalue lies in [θ − r, θ + r]
  int iterations = 0;   ///< operator applications
  bool converged = false;  ///< residual ≤ tol·θ (or the Krylov space exhausted)
};

/// Lanczos steps between two readings of the Ritz pair (a reading is an eigensolve of T_k).
inline constexpr int LANCZOS_READ_EVERY = 5;

/// Lanczos with full reorthogonalization from a fixed pseudo-random start (the result does not
/// depend on the run), run in portions (advance) so that a caller can stop it once the bracket
/// [θ, θ + r] answers its question.
class LanczosRun {
 public:
  /// @param apply v ↦ A v @param n size @param max_iter operator applications at most
  LanczosRun(std::function<Vec(const Vec&)> apply, Index n, int max_iter);
  /// Up to @p steps more steps; then the Ritz pair, converged at relative residual @p tol.
  void advance(int steps, double tol);
  /// Converged, the Krylov space exhausted, or max_iter reached.
  bool done() const { return done_; }
  const LanczosResult& result() const { return R_; }

 private:
  std::function<Vec(const Vec&)> apply_;
  Index kmax_ = 0, k_ = 0;
  Mat Q_;
  Vec alpha_, beta_;
  LanczosResult R_;
  bool done_ = false;
};

/// LanczosRun to @p tol. @param apply v ↦ A v @param n size @param tol relative Ritz residual
/// @param max_iter operator applications at most.
LanczosResult lanczos_largest(const std::function<Vec(const Vec&)>& apply, Index n, double tol, int max_iter);

/// k_1 and k_1ν of S_K (file comment), each with the lower bound 1/(θ + r) the Ritz residual allows.
struct Gamma3Spectrum {
  double k1 = 0, k1_low = 0;      ///< λ_min(S_K, diag(w)) and a lower bound of it
  double k1nu = 0, k1nu_low = 0;  ///< λ_min(S_ν, diag(w)) and a lower bound of it
  bool has_k1 = true;             ///< k_1 was asked for (only k_1ν decides the inner convexity)
  bool converged = false;         ///< both Lanczos runs converged (the k_1ν run, without k_1)
  bool decided = false;           ///< stopped before that: the caller's question was decided
  int iterations = 0;             ///< S⁻¹ applications, both runs
  double seconds = 0;             ///< wall time
  std::string how;                ///< "Lanczos on <what applied S^-1>: N steps, residual r"
};

/// @param apply_Sinv b ↦ S_K⁻¹ b on the Γ3 unknowns @param w Γ3 weights @param d dimension
/// @param what how S⁻¹ is applied, for the report.
/// @param decided where given, the runs stop once both are within check.lanczos_decide_tol and it
/// is true of the brackets so far, else at check.lanczos_tol.
/// @param with_k1 false: the k_1ν run alone (half the S⁻¹ applications), for a caller that asks
/// the inner convexity only; the result's has_k1 says so and (21) is not decided from it.
Gamma3Spectrum gamma3_spectrum(const std::function<Vec(const Vec&)>& apply_Sinv, const Vec& w, int d,
                               const SolveOptions& opt, const std::string& what,
                               const std::function<bool(const Gamma3Spectrum&)>& decided = {},
                               bool with_k1 = true);

/// (21) decided by the bracket of check/smallness.hpp from the spectrum: method "bound", computed
/// only when the bracket (widened by the Lanczos residuals) decides; the note says how, or why not.
SmallnessReport smallness_from_spectrum(const Model& md, const Gamma3Spectrum& s);

/// The inner-convexity test from k_1ν: strongly convex iff k_1ν > α (file comment); checked only
/// when the Lanczos bounds decide. min_eigenvalue is k_1ν − α (reports.hpp: the same sign).
InnerConvexity convexity_from_spectrum(const Gamma3Spectrum& s, const PiecewiseLinearLaw* law);

}  // namespace hemicontact
