// SymmetricSpMat (core/symmetric_matrix.hpp): the lower triangle of a symmetric matrix, built from
// either storage, whose product and full() are the matrix's own.
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/symmetric_matrix.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace hemicontact {
namespace {

// A symmetric 6 × 6 matrix with a zero pattern off the diagonal (both triangles stored).
SpMat symmetric_example() {
  Mat A = Mat::Zero(6, 6);
  for (int i = 0; i < 6; ++i) A(i, i) = 4.0 + i;
  const int pairs[][2] = {{1, 0}, {3, 0}, {2, 1}, {5, 2}, {4, 3}, {5, 4}};
  for (const auto& p : pairs) A(p[0], p[1]) = A(p[1], p[0]) = std::sin(1.0 + p[0] + 7.0 * p[1]);
  return A.sparseView();
}

TEST(SymmetricSpMat, KeepsTheLowerTriangleAndActsAsTheMatrix) {
  const SpMat A = symmetric_example();
  const SpMat lower_only = A.triangularView<Eigen::Lower>();
  for (const SpMat& from : {A, lower_only}) {
    const SymmetricSpMat K(from);
    EXPECT_EQ(K.lower().nonZeros(), 12);  // 6 diagonal + 6 below it
    EXPECT_TRUE(K.lower().isCompressed());
    for (Index j = 0; j < K.cols(); ++j)
      for (SpMat::InnerIterator it(K.lower(), j); it; ++it) EXPECT_GE(it.row(), j);
    EXPECT_EQ(Mat(K.full()), Mat(A));
    const Vec x = Vec::LinSpaced(6, -1.0, 2.0);
    EXPECT_LE((K * x - A * x).cwiseAbs().maxCoeff(), 1e-15 * (A.cwiseAbs() * x.cwiseAbs()).maxCoeff());
    EXPECT_EQ(K.diagonal(), Vec(A.diagonal()));
  }
  EXPECT_TRUE(SymmetricSpMat().empty());
  EXPECT_THROW((void)(SymmetricSpMat(A) * Vec::Ones(5)), Error);
  EXPECT_THROW(SymmetricSpMat(SpMat(3, 4)), Error);
}

}  // namespace
}  // namespace hemicontact
