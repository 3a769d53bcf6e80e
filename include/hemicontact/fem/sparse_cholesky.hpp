#pragma once
/// @file sparse_cholesky.hpp  Sparse SPD factorization (CHOLMOD supernodal LLᵀ), kept behind a
/// pimpl so CHOLMOD stays a private dependency.

#include <hemicontact/core/types.hpp>

#include <memory>

namespace hemicontact {

/// Sparse Cholesky factorization of an SPD matrix. Analyse once per pattern, factor per values.
class SparseCholesky {
 public:
  SparseCholesky();
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
