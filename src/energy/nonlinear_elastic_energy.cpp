#include <hemicontact/energy/nonlinear_elastic_energy.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/nonlinear_assembly.hpp>

#include <algorithm>

namespace hemicontact {
namespace {

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

NonlinearElasticEnergy::NonlinearElasticEnergy(Mesh mesh, std::shared_ptr<const Material> material, DofMap dofs)
    : m_mesh(std::move(mesh)), m_material(std::move(material)), m_dofs(std::move(dofs)) {
  if (!m_material) throw Error("NonlinearElasticEnergy: null material", EXIT_INTERNAL);
  if (m_material->dim() != m_mesh.dim)
    throw Error("NonlinearElasticEnergy: material and mesh dimensions differ", EXIT_INTERNAL);
  m_lower = lower_of(m_dofs.reduce(assemble_tangent_stiffness(m_mesh, *m_material, Vec::Zero(m_dofs.n_full()))));
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
