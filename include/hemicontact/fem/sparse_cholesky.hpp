#pragma once
/// @file sparse_cholesky.hpp  Sparse SPD factorization (CHOLMOD LLᵀ, supernodal or simplicial as
/// CHOLMOD's own flop rule chooses), kept behind a pimpl so CHOLMOD stays a private dependency.

#include <hemicontact/core/types.hpp>

#include <memory>
#include <string>

namespace hemicontact {

/// Sparse Cholesky factorization of an SPD matrix. Analyse once per pattern, factor per values.
class SparseCholesky {
 public:
  /// solver.ordering = auto's rule for a whole-mesh factorization (the full formulation's, ssn's,
  /// the linear solve's): AMD up to this many unknowns, nested dissection above. Measured (ssn,
  /// CHOLMOD's flop rule choosing supernodal or simplicial; whole solve): the fig2 strip 1000 × 1
  /// (8k unknowns) 17.7 → 12.4 ms with AMD, fig2 n = 64 (8k) 67 → 61 ms; fig2 n = 128 (33k) and the 3D
  /// box n = 12 (6k) even; 3D n = 16 (15k) 0.65 → 0.95 s and fig2 n = 256 (132k) 2.1 → 2.6 s
  /// with AMD (nested dissection's smaller fill pays for its ordering once a factorization
  /// costs more than the ordering).
  static constexpr Index AMD_UP_TO = 20000;
  /// @param ordering "auto" (AMD_UP_TO), "amd", "metis" or "nesdis" (solver.ordering)
  explicit SparseCholesky(const std::string& ordering = "auto");
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;
  /// Symbolic analysis (fill-reducing ordering) of @p A's pattern (full or lower storage).
  void analyze(const SpMat& A);
  /// Numeric factorization. @throws Error (EXIT_NOT_CONVERGED) if A is not positive definite.
  void factorize(const SpMat& A);
  /// analyze() followed by factorize().
  void compute(const SpMat& A);
  /// @return A⁻¹ b.
  Vec solve(const Vec& b) const;
  /// @return wall seconds of the last analyze() and factorize().
  double analyze_seconds() const;
  /// @copydoc analyze_seconds
  double factorize_seconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

}  // namespace hemicontact
