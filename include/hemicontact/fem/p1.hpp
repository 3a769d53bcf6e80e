#pragma once
/// @file p1.hpp  P1 (linear simplex) element kernels: barycentric gradients and the B matrix.

#include <hemicontact/mesh/mesh.hpp>

#include <Eigen/Dense>

namespace hemicontact {

/// Fixed sizes of the P1 element in dimension D.
template <int D>
struct P1 {
  static constexpr int NV = D + 1;               ///< nodes per cell
  static constexpr int NDOF = D * (D + 1);       ///< displacement dofs per cell
  static constexpr int NVOIGT = D == 2 ? 3 : 6;  ///< Voigt components
  using Grad = Eigen::Matrix<double, NV, D>;     ///< ∇φ_a, one row per node
  using BMat = Eigen::Matrix<double, NVOIGT, NDOF>;
  using KMat = Eigen::Matrix<double, NDOF, NDOF>;

  /// Gradients of the barycentric functions of cell @p c; @p measure receives its area/volume.
  static Grad gradients(const Mesh& m, Index c, double& measure) {
    Eigen::Matrix<double, D, D> J;  // columns x_a − x_0
    for (int k = 0; k < D; ++k) J.col(k) = (m.points.row(m.cells(c, k + 1)) - m.points.row(m.cells(c, 0))).transpose();
    const double det = J.determinant();
    measure = det / (D == 2 ? 2.0 : 6.0);
    // φ_a for a ≥ 1 has gradient row a−1 of J⁻¹; φ_0 = 1 − Σ φ_a.
    const Eigen::Matrix<double, D, D> Jinv = J.inverse();
    Grad G;
    G.template bottomRows<D>() = Jinv;
    G.row(0) = -Jinv.colwise().sum();
    return G;
  }

  /// Strain-displacement matrix: ε (Voigt, engineering shears) = B u_e, u_e = (u_0x, u_0y, u_1x, ...).
  static BMat strain_matrix(const Grad& G) {
    BMat B = BMat::Zero();
    for (int a = 0; a < NV; ++a) {
      for (int i = 0; i < D; ++i) B(i, D * a + i) = G(a, i);
      if constexpr (D == 2) {
        B(2, D * a + 0) = G(a, 1);
        B(2, D * a + 1) = G(a, 0);
      } else {
        // (2ε23, 2ε13, 2ε12)
        B(3, D * a + 1) = G(a, 2);
        B(3, D * a + 2) = G(a, 1);
        B(4, D * a + 0) = G(a, 2);
        B(4, D * a + 2) = G(a, 0);
        B(5, D * a + 0) = G(a, 1);
        B(5, D * a + 1) = G(a, 0);
      }
    }
    return B;
  }
};

}  // namespace hemicontact
