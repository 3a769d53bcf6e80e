#pragma once
/// @file condensation.hpp  Static condensation of a linear elastic problem onto its trailing
/// (Γ3) unknowns: the nonlinearity lives only on Γ3, so after one sparse factorization the contact
/// problem is a small dense one.
///
/// With K = [K_II K_IC; K_CI K_CC] (the last m unknowns are C) and y = K⁻¹ f,
///   min_{x_I} ½ xᵀK x − fᵀx  =  ½ (x_C − y_C)ᵀ S (x_C − y_C) − ½ fᵀy,
///   S = K_CC − K_CI K_II⁻¹ K_IC = ((K⁻¹)_CC)⁻¹,
/// and the minimizing interior is x = y + K⁻¹ E_C S (x_C − y_C) (one solve). S is taken from the
/// factor itself: with the C unknowns ordered last, L = [L_II 0; L_CI L_CC] and S = L_CC L_CCᵀ,
/// i.e. the trailing block of the supernodal factor — no m right-hand sides are solved.
/// S (x_C − y_C) is also the nodal force (K x − f)_C of the recovered x.

#include <hemicontact/core/types.hpp>

#include <memory>
#include <string>

namespace hemicontact {

/// Factor once, condense onto the last m unknowns, recover the interior on demand.
class Condensation {
 public:
  /// @param K SPD matrix whose last @p m unknowns are condensed, its lower triangle read (both
  /// triangles stored or the lower one: the model's K_x.lower());
  /// @param f right-hand side;
  /// @param ordering fill-reducing ordering of the interior, on its node graph: "amd" (constrained
  /// AMD on the whole graph, the condensed unknowns last), "metis", "nesdis" (on the interior's
  /// graph) or "auto" (amd for 2D up to 200 000 nodes, metis for larger 2D, nesdis for 3D).
  /// @throws Error if K is not positive definite.
  Condensation(const SpMat& K, const Vec& f, Index m, const std::string& ordering = "auto");
  /// The analysis alone (ordering + symbolic factorization, no numbers): predicted_flops() and
  /// factor_nnz() are then known, and factorize() finishes the condensation with the same analysis.
  /// The method choice (solver/method_choice.hpp) reads the prediction before any numeric work.
  Condensation(const SpMat& K, Index m, const std::string& ordering = "auto");
  /// Numeric factorization of @p K (the matrix analysed), S, y = K⁻¹f: after the analysis-only
  /// constructor, once. @throws Error if K is not positive definite.
  void factorize(const SpMat& K, const Vec& f);
  ~Condensation();
  Condensation(const Condensation&) = delete;
  Condensation& operator=(const Condensation&) = delete;
  /// @return the number of condensed unknowns m.
  Index m() const { return m_m; }
  /// @return the ordering used ("amd", "metis" or "nesdis"; "none" without interior unknowns).
  const std::string& ordering() const { return m_ordering; }
  /// @return the Schur complement S (dense, symmetric positive definite).
  const Mat& S() const { return m_S; }
  /// @return y = K⁻¹ f, the unconstrained solution.
  const Vec& y() const { return m_y; }
  /// @return the trailing part y_C.
  Vec y_C() const { return m_y.tail(m()); }
  /// @return the constant −½ fᵀ y of the condensed energy.
  double constant() const { return m_const; }
  /// @return the full vector whose trailing part is @p x_C and whose interior minimizes the energy
  /// for the loads @p load_scale × f (y scales linearly with the loads).
  Vec recover(const Vec& x_C, double load_scale = 1.0) const;
  /// @return K⁻¹ b with the stored factor.
  Vec solve(const Vec& b) const;
  /// @return S⁻¹ b for @p b on the m condensed unknowns: two dense triangular solves with L_CC
  /// (S = L_CC L_CCᵀ), m² flops and no m × m temporary (the checks' Lanczos, solver/sparse_checks.hpp).
  Vec solve_schur(const Vec& b) const;
  /// @return seconds spent in: ordering+symbolic analysis, numeric factorization, extracting S.
  double analyze_seconds() const { return m_t_analyze; }
  /// @copydoc analyze_seconds
  double factorize_seconds() const { return m_t_factor; }
  /// @copydoc analyze_seconds
  double schur_seconds() const { return m_t_schur; }
  /// @return nonzeros of the factor L (known after the analysis).
  double factor_nnz() const { return m_nnz; }
  /// @return CHOLMOD's flop count of the numeric factorization, predicted by the analysis.
  double predicted_flops() const { return m_flops; }

 private:
  void extract_schur(Index nI, Index m);
  struct Impl;
  std::unique_ptr<Impl> m_impl;
  Mat m_S;
  Vec m_y;
  Index m_m = 0;
  double m_const = 0, m_t_analyze = 0, m_t_factor = 0, m_t_schur = 0, m_nnz = 0, m_flops = 0;
  std::string m_ordering = "none";
};

}  // namespace hemicontact
