#pragma once
/// @file fem_problem.hpp  Test-only FEM helpers: a degree-4 triangle quadrature, load assembly for
/// a smooth body force, L2 / energy-norm errors against an exact field, and a clamped linear solve.
///
/// These live in the tests, not the library: the library's loads are piecewise constant (exact
/// with nodal shares), while a manufactured solution needs the quadrature of a smooth f0.

#include <hemicontact/contact/contact_nodes.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/fem/dof_map.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/material/material.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/mesh.hpp>

#include <array>
#include <cmath>
#include <functional>

namespace hemicontact::test {

/// A 2D vector field x ↦ v(x, y).
using Field2 = std::function<Eigen::Vector2d(double, double)>;
/// A 2D strain field in Voigt form (ε11, ε22, 2ε12).
using StrainField2 = std::function<Eigen::Vector3d(double, double)>;

/// Symmetric 6-point rule on triangles, exact for polynomials of degree ≤ 4 (Dunavant 1985,
/// "High degree efficient symmetrical Gaussian quadrature rules for the triangle", rule 4).
/// Points in barycentric coordinates; weights sum to 1 (multiply by |T|).
struct TriangleRule {
  std::array<std::array<double, 3>, 6> bary;  ///< barycentric coordinates of the points
  std::array<double, 6> w;                    ///< weights, Σ w = 1
};

/// @return Dunavant's degree-4 rule.
inline const TriangleRule& dunavant4() {
  static const TriangleRule rule = [] {
    const double a = 0.44594849091596488632, wa = 0.22338158967801146570;
    const double b = 0.09157621350977074346, wb = 0.10995174365532186764;
    TriangleRule r;
    r.bary = {{{1 - 2 * a, a, a},
               {a, 1 - 2 * a, a},
               {a, a, 1 - 2 * a},
               {1 - 2 * b, b, b},
               {b, 1 - 2 * b, b},
               {b, b, 1 - 2 * b}}};
    r.w = {wa, wa, wa, wb, wb, wb};
    return r;
  }();
  return rule;
}

/// Calls @p fn(x, y, weight·|T|, bary) at every quadrature point of every cell (2D meshes).
template <class Fn>
void for_each_quadrature_point(const Mesh& m, Fn&& fn) {
  const TriangleRule& q = dunavant4();
  for (Index c = 0; c < m.num_cells(); ++c) {
    const double area = m.cell_measure(c);
    for (int k = 0; k < 6; ++k) {
      double x = 0, y = 0;
      for (int a = 0; a < 3; ++a) {
        x += q.bary[k][a] * m.points(m.cells(c, a), 0);
        y += q.bary[k][a] * m.points(m.cells(c, a), 1);
      }
      fn(c, x, y, q.w[k] * area, q.bary[k]);
    }
  }
}

/// @return the full load vector ∫Ω f·φ_a (component i at dof 2a+i), by the degree-4 rule.
inline Vec assemble_smooth_load(const Mesh& m, const Field2& f) {
  Vec F = Vec::Zero(2 * m.num_nodes());
  for_each_quadrature_point(m, [&](Index c, double x, double y, double w, const std::array<double, 3>& l) {
    const Eigen::Vector2d fv = f(x, y);
    for (int a = 0; a < 3; ++a) F.segment<2>(2 * m.cells(c, a)) += w * l[a] * fv;
  });
  return F;
}

/// @return ‖u − u_h‖_{L2(Ω)} by the degree-4 rule (u_h interpolated with the barycentric weights).
inline double l2_error(const Mesh& m, const Vec& uh, const Field2& u) {
  double s = 0;
  for_each_quadrature_point(m, [&](Index c, double x, double y, double w, const std::array<double, 3>& l) {
    Eigen::Vector2d v = u(x, y);
    for (int a = 0; a < 3; ++a) v -= l[a] * uh.segment<2>(2 * m.cells(c, a));
    s += w * v.squaredNorm();
  });
  return std::sqrt(s);
}

/// @return the energy-norm error sqrt(∫ (ε(u) − ε(u_h)) : F (ε(u) − ε(u_h))) by the degree-4 rule,
/// F given by its Voigt matrix @p D (engineering shears, so eᵀ D e = e : F e).
inline double energy_error(const Mesh& m, const Vec& uh, const StrainField2& eps, const Mat& D) {
  const RowMat eh = cell_strains(m, uh);
  const Eigen::Matrix3d D3 = D;
  double s = 0;
  for_each_quadrature_point(m, [&](Index c, double x, double y, double w, const std::array<double, 3>&) {
    const Eigen::Vector3d e = eps(x, y) - eh.row(c).transpose();
    s += w * e.dot(D3 * e);
  });
  return std::sqrt(s);
}

/// @return the full displacement u = T x, K_x x = Tᵀ f, for the Γ1 tags already on @p m and no
/// contact (DofMap with an empty ContactNodes). @throws Error if K_x is not positive definite.
inline Vec solve_clamped(const Mesh& m, const Material& material, const Vec& f_full) {
  const DofMap dofs(m, clamped_nodes(m), ContactNodes{});
  SparseCholesky chol;
  chol.compute(dofs.reduce(assemble_stiffness(m, material)));
  return dofs.to_full(chol.solve(dofs.to_reduced(f_full)));
}

}  // namespace hemicontact::test
