// Nonlinear P1 assembly (docs/model.md §2: ½ a(u,u) becomes ∫ W(ε(u)), F = ∂W/∂ε): one quadrature point
// per cell, exact since ε is constant on a cell. The energy term that minimizes with it is
// energy/nonlinear_elastic_energy.hpp; the model's internal force and energy (problem/model.hpp)
// read it directly.
#include <hemicontact/fem/nonlinear_assembly.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/p1.hpp>

namespace hemicontact {
namespace {

// Calls fn(c, |T|, B, dofs, ε) for every cell: B the Voigt strain matrix, dofs the cell's full dof
// indices (d·a + i), ε = B u_T.
template <int D, class Fn>
void for_each_cell(const Mesh& m, const Vec& u, Fn&& fn) {
  using E = P1<D>;
  if (u.size() != m.num_nodes() * D) throw Error("elastic energy: displacement of the wrong size", EXIT_INTERNAL);
  Eigen::Matrix<Index, E::NDOF, 1> dofs;
  Eigen::Matrix<double, E::NDOF, 1> ue;
  Vec eps(E::NVOIGT);
  for (Index c = 0; c < m.num_cells(); ++c) {
    double vol;
    const typename E::BMat B = E::strain_matrix(E::gradients(m, c, vol));
    for (int a = 0; a < E::NV; ++a)
      for (int i = 0; i < D; ++i) {
        dofs[D * a + i] = D * m.cells(c, a) + i;
        ue[D * a + i] = u[dofs[D * a + i]];
      }
    eps = B * ue;
    fn(c, vol, B, dofs, eps);
  }
}

template <int D>
double energy_d(const Mesh& m, const Material& mat, const Vec& u) {
  double s = 0;
  for_each_cell<D>(
      m, u, [&](Index, double vol, const auto&, const auto&, const Vec& eps) { s += vol * mat.energy_density(eps); });
  return s;
}

template <int D>
Vec force_d(const Mesh& m, const Material& mat, const Vec& u) {
  Vec r = Vec::Zero(u.size());
  for_each_cell<D>(m, u, [&](Index, double vol, const auto& B, const auto& dofs, const Vec& eps) {
    const Eigen::Matrix<double, P1<D>::NDOF, 1> re = vol * B.transpose() * mat.stress(eps);
    for (int k = 0; k < P1<D>::NDOF; ++k) r[dofs[k]] += re[k];
  });
  return r;
}

template <int D>
SpMat tangent_d(const Mesh& m, const Material& mat, const Vec& u) {
  constexpr int NDOF = P1<D>::NDOF;
  Triplets t;
  t.reserve(static_cast<size_t>(m.num_cells()) * NDOF * NDOF);
  for_each_cell<D>(m, u, [&](Index, double vol, const auto& B, const auto& dofs, const Vec& eps) {
    const Eigen::Matrix<double, P1<D>::NVOIGT, P1<D>::NVOIGT> C = mat.tangent(eps);
    const Eigen::Matrix<double, NDOF, NDOF> Ke = vol * B.transpose() * C * B;
    for (int a = 0; a < NDOF; ++a)
      for (int b = 0; b < NDOF; ++b) t.emplace_back(static_cast<int>(dofs[a]), static_cast<int>(dofs[b]), Ke(a, b));
  });
  SpMat K(u.size(), u.size());
  K.setFromTriplets(t.begin(), t.end());  // sums duplicates, keeps exact zeros: a fixed pattern
  return K;
}

}  // namespace

double assemble_elastic_energy(const Mesh& mesh, const Material& material, const Vec& u) {
  return mesh.dim == 2 ? energy_d<2>(mesh, material, u) : energy_d<3>(mesh, material, u);
}

Vec assemble_internal_force(const Mesh& mesh, const Material& material, const Vec& u) {
  return mesh.dim == 2 ? force_d<2>(mesh, material, u) : force_d<3>(mesh, material, u);
}

SpMat assemble_tangent_stiffness(const Mesh& mesh, const Material& material, const Vec& u) {
  return mesh.dim == 2 ? tangent_d<2>(mesh, material, u) : tangent_d<3>(mesh, material, u);
}

}  // namespace hemicontact
