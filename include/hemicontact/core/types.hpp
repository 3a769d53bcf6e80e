#pragma once
/// @file types.hpp  Basic linear-algebra aliases used throughout hemicontact.

#include <Eigen/Core>
#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <limits>
#include <vector>

namespace hemicontact {

/// Signed index type (Eigen's).
using Index = Eigen::Index;
/// Dense column vector of doubles.
using Vec = Eigen::VectorXd;
/// Dense matrix of doubles.
using Mat = Eigen::MatrixXd;
/// Dense integer matrix (connectivity tables).
using IMat = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
/// Dense matrix of doubles stored row by row (node coordinates: one row per node).
using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
/// Sparse matrix, column-major, int indices (what CHOLMOD and Ipopt take).
using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
/// A SpMat that moves. Eigen 3.4's SparseMatrix has neither a move constructor nor a move
/// assignment, so a struct holding one (the model's stiffness, the largest array of a run) is
/// copied whenever it is moved: `model = build_model(...)` cost a full copy of K_x. This holder
/// moves by swap; everything else is SpMat's (it binds to `const SpMat&`).
class MovableSpMat : public SpMat {
 public:
  using SpMat::SpMat;
  using SpMat::operator=;
  MovableSpMat() = default;
  MovableSpMat(const MovableSpMat&) = default;
  MovableSpMat& operator=(const MovableSpMat&) = default;
  MovableSpMat(MovableSpMat&& o) noexcept { swap(o); }
  MovableSpMat& operator=(MovableSpMat&& o) noexcept {
    swap(o);
    return *this;
  }
  MovableSpMat(const SpMat& o) : SpMat(o) {}  // NOLINT(google-explicit-constructor): a SpMat value
  MovableSpMat(SpMat&& o) noexcept { swap(o); }  // NOLINT(google-explicit-constructor)
  MovableSpMat& operator=(const SpMat& o) {
    SpMat::operator=(o);
    return *this;
  }
  MovableSpMat& operator=(SpMat&& o) noexcept {
    swap(o);
    return *this;
  }
};
/// One sparse entry.
using Triplet = Eigen::Triplet<double, int>;
/// A list of sparse entries, summed on assembly.
using Triplets = std::vector<Triplet>;

/// +infinity, used for absent bounds (no rigid obstacle: g = +inf).
constexpr double INF = std::numeric_limits<double>::infinity();
/// Not a number: a value that was not computed (CSV and JSON write it as empty / null).
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace hemicontact
