#pragma once
/// @file symmetric_matrix.hpp  A symmetric sparse matrix kept as its lower triangle.

#include <hemicontact/core/types.hpp>

namespace hemicontact {

/// A symmetric sparse matrix stored as its lower triangle, diagonal included (compressed, rows
/// sorted): half the memory of both triangles (the model's K_x: 45 instead of 90 MB at fig2
/// n = 512), and what CHOLMOD (stype −1) and Ipopt's Hessian take as they are. It is not a SpMat,
/// so that no product can read the triangle as the whole matrix: K x goes through operator*, and
/// the triangle itself through lower(). Moves without a copy (MovableSpMat).
class SymmetricSpMat {
 public:
  SymmetricSpMat() = default;
  /// The lower triangle of @p A (both triangles stored, or only the lower one; the upper is not read).
  explicit SymmetricSpMat(const SpMat& A);
  /// @return K x.
  Vec operator*(const Vec& x) const;
  /// @return the stored lower triangle.
  const SpMat& lower() const { return m_lower; }
  /// @return both triangles (dense checks, small matrices).
  SpMat full() const;
  /// @return the diagonal.
  Vec diagonal() const { return m_lower.diagonal(); }
  Index rows() const { return m_lower.rows(); }
  Index cols() const { return m_lower.cols(); }
  /// @return whether it holds no matrix (a model built for the petsc engine).
  bool empty() const { return m_lower.size() == 0; }

 private:
  MovableSpMat m_lower;
};

}  // namespace hemicontact
