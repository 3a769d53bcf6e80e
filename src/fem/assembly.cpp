#include <hemicontact/fem/assembly.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/p1.hpp>

#include <cmath>

namespace hemicontact {
namespace {

template <int D>
SpMat stiffness(const Mesh& m, const Mat& Ddyn) {
  using E = P1<D>;
  const Eigen::Matrix<double, E::NVOIGT, E::NVOIGT> Dm = Ddyn;
  Triplets t;
  t.reserve(static_cast<size_t>(m.num_cells()) * E::NDOF * E::NDOF);
  for (Index c = 0; c < m.num_cells(); ++c) {
    double vol;
    const auto G = E::gradients(m, c, vol);
    const auto B = E::strain_matrix(G);
    const typename E::KMat Ke = vol * B.transpose() * Dm * B;
    for (int a = 0; a < E::NV; ++a)
      for (int i = 0; i < D; ++i)
        for (int b = 0; b < E::NV; ++b)
          for (int j = 0; j < D; ++j)
            t.emplace_back(D * m.cells(c, a) + i, D * m.cells(c, b) + j, Ke(D * a + i, D * b + j));
  }
  const Index n = m.num_nodes() * D;
  SpMat K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  return K;
}

template <int D>
RowMat strains(const Mesh& m, const Vec& u) {
  using E = P1<D>;
  RowMat eps(m.num_cells(), E::NVOIGT);
  for (Index c = 0; c < m.num_cells(); ++c) {
    double vol;
    const auto B = E::strain_matrix(E::gradients(m, c, vol));
    Eigen::Matrix<double, E::NDOF, 1> ue;
    for (int a = 0; a < E::NV; ++a)
      for (int i = 0; i < D; ++i) ue[D * a + i] = u[D * m.cells(c, a) + i];
    eps.row(c) = (B * ue).transpose();
  }
  return eps;
}

}  // namespace

SpMat assemble_stiffness(const Mesh& mesh, const Material& material) {
  if (!material.is_linear()) throw Error("assemble_stiffness: material is nonlinear", EXIT_INTERNAL);
  const Vec zero = Vec::Zero(voigt_size(mesh.dim));
  return mesh.dim == 2 ? stiffness<2>(mesh, material.tangent(zero)) : stiffness<3>(mesh, material.tangent(zero));
}

Vec assemble_body_force(const Mesh& mesh, const Vec& f0) {
  const int d = mesh.dim;
  Vec f = Vec::Zero(mesh.num_nodes() * d);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    const double share = mesh.cell_measure(c) / (d + 1);
    for (int a = 0; a <= d; ++a) f.segment(d * mesh.cells(c, a), d) += share * f0;
  }
  return f;
}

Vec assemble_tractions(const Mesh& mesh) {
  const int d = mesh.dim;
  Vec f = Vec::Zero(mesh.num_nodes() * d);
  for (Index k = 0; k < mesh.num_facets(); ++k) {
    if (mesh.facet_part[k] != Part::GAMMA2) continue;
    const Vec& f2 = mesh.tractions.at(mesh.facet_load[k]);
    const double share = mesh.facet_measure(k) / d;
    for (int a = 0; a < d; ++a) f.segment(d * mesh.facets(k, a), d) += share * f2;
  }
  return f;
}

RowMat cell_strains(const Mesh& mesh, const Vec& u) {
  return mesh.dim == 2 ? strains<2>(mesh, u) : strains<3>(mesh, u);
}

double von_mises(const Eigen::Ref<const Eigen::RowVectorXd>& s, int dim) {
  if (dim == 2) return std::sqrt(s[0] * s[0] - s[0] * s[1] + s[1] * s[1] + 3 * s[2] * s[2]);
  const double a = s[0] - s[1], b = s[1] - s[2], c = s[2] - s[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

}  // namespace hemicontact
