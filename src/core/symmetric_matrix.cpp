#include <hemicontact/core/symmetric_matrix.hpp>

#include <hemicontact/core/error.hpp>

namespace hemicontact {

SymmetricSpMat::SymmetricSpMat(const SpMat& A) {
  if (A.rows() != A.cols()) throw Error("SymmetricSpMat: a non-square matrix", EXIT_INTERNAL);
  // Sized exactly, column by column (no triplets, no second full copy).
  const Index n = A.cols();
  Eigen::VectorXi per_col(n);
  for (Index j = 0; j < n; ++j) {
    int k = 0;
    for (SpMat::InnerIterator it(A, j); it; ++it) k += it.row() >= j;
    per_col[j] = k;
  }
  SpMat L(n, n);
  L.reserve(per_col);
  for (Index j = 0; j < n; ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it)
      if (it.row() >= j) L.insert(it.row(), j) = it.value();
  L.makeCompressed();
  m_lower = std::move(L);
}

Vec SymmetricSpMat::operator*(const Vec& x) const {
  if (x.size() != cols()) throw Error("SymmetricSpMat: a vector of the wrong size", EXIT_INTERNAL);
  return m_lower.selfadjointView<Eigen::Lower>() * x;
}

SpMat SymmetricSpMat::full() const { return m_lower.selfadjointView<Eigen::Lower>(); }

}  // namespace hemicontact
