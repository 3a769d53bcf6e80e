#include <hemicontact/energy/nonlinear_elastic_energy.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/p1.hpp>

#include <algorithm>

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
  for_each_cell<D>(m, u, [&](Index, double vol, const auto&, const auto&, const Vec& eps) {
    s += vol * mat.energy_density(eps);
  });
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

bool same_pattern(const SpMat& A, const SpMat& B) {
  return A.rows() == B.rows() && A.cols() == B.cols() && A.isCompressed() && B.isCompressed() &&
         A.nonZeros() == B.nonZeros() &&
         std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1, B.outerIndexPtr()) &&
         std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), B.innerIndexPtr());
}

SpMat lower_of(const SpMat& A) {
  SpMat L = A.triangularView<Eigen::Lower>();
  L.makeCompressed();
  return L;
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

NonlinearElasticEnergy::NonlinearElasticEnergy(const Mesh& mesh, std::shared_ptr<const Material> material,
                                               const DofMap& dofs)
    : m_mesh(mesh), m_material(std::move(material)), m_dofs(dofs) {
  if (m_material->dim() != mesh.dim)
    throw Error("NonlinearElasticEnergy: material and mesh dimensions differ", EXIT_INTERNAL);
  m_lower = lower_of(m_dofs.reduce(assemble_tangent_stiffness(mesh, *m_material, Vec::Zero(dofs.n_full()))));
}

double NonlinearElasticEnergy::value(const Vec& x) const {
  return assemble_elastic_energy(m_mesh, *m_material, m_dofs.to_full(x));
}

// ∂/∂x Σ|T| W(B_T (T x)_T) = Tᵀ Σ|T| B_Tᵀ F(ε_T) = Tᵀ r(u).
void NonlinearElasticEnergy::add_gradient(const Vec& x, Vec& g) const {
  g += m_dofs.to_reduced(assemble_internal_force(m_mesh, *m_material, m_dofs.to_full(x)));
}

// ∂²/∂x² = Tᵀ (Σ|T| B_Tᵀ C(ε_T) B_T) T. Assembly with the same triplet structure at every u gives
// the same pattern as at u = 0 (m_lower), so the values add position by position; a differing
// pattern (never expected) falls back to a lookup per entry.
void NonlinearElasticEnergy::add_hessian(const Vec& x, SpMat& H, Psd) const {
  const SpMat L = lower_of(m_dofs.reduce(assemble_tangent_stiffness(m_mesh, *m_material, m_dofs.to_full(x))));
  if (same_pattern(L, H)) {
    Eigen::Map<Vec>(H.valuePtr(), H.nonZeros()) += Eigen::Map<const Vec>(L.valuePtr(), L.nonZeros());
    return;
  }
  for (Index j = 0; j < L.outerSize(); ++j)
    for (SpMat::InnerIterator it(L, j); it; ++it) H.valuePtr()[pattern_position(H, it.row(), j)] += it.value();
}

}  // namespace hemicontact
