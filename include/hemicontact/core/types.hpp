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
/// One sparse entry.
using Triplet = Eigen::Triplet<double, int>;
/// A list of sparse entries, summed on assembly.
using Triplets = std::vector<Triplet>;

/// +infinity, used for absent bounds (no rigid obstacle: g = +inf).
constexpr double INF = std::numeric_limits<double>::infinity();

}  // namespace hemicontact
