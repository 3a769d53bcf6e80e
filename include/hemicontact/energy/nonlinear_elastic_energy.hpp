#pragma once
/// @file nonlinear_elastic_energy.hpp  The elastic energy of a (possibly nonlinear) material,
/// E(u) = Σ_T |T| W(ε_T(u)) (docs/model.md §2: ½ a(u,u) becomes ∫ W(ε(u)) with F = ∂W/∂ε), its gradient
/// (the internal force vector r(u) = ∫ F(ε(u)) : ε(v)) and Hessian (the tangent stiffness
/// K_t(u) = ∫ ε(v) : C(ε(u)) ε(w), C = ∂F/∂ε), P1 elements, one quadrature point per cell (exact:
/// ε is constant on a cell).

#include <hemicontact/energy/energy_term.hpp>
#include <hemicontact/fem/dof_map.hpp>
#include <hemicontact/fem/nonlinear_assembly.hpp>
#include <hemicontact/material/material.hpp>
#include <hemicontact/mesh/mesh.hpp>

#include <memory>

namespace hemicontact {

/// E(x) = Σ_T |T| W(ε_T(T x)) in the reduced unknowns x (u = T x, DofMap), with gradient Tᵀ r(T x)
/// and Hessian Tᵀ K_t(T x) T. For a linear material ElasticEnergy (constant K) is the cheaper
/// choice; this term is the full-space path for nonlinear ones (static condensation is not exact).
class NonlinearElasticEnergy : public EnergyTerm {
 public:
  /// @param mesh the mesh (copied: the term owns what it evaluates on; a mesh is small next to K)
  /// @param material the law F (shared)
  /// @param dofs the full ↔ reduced map (copied, as the mesh)
  /// @throws Error (internal) if the material is null or its dimension is not the mesh's
  NonlinearElasticEnergy(Mesh mesh, std::shared_ptr<const Material> material, DofMap dofs);
  std::string name() const override { return "elastic"; }
  double value(const Vec& x) const override;
  void add_gradient(const Vec& x, Vec& g) const override;
  /// Adds the lower triangle of Tᵀ K_t T; @p H must have lower()'s pattern. @p psd is ignored: the
  /// law is strongly monotone, so K_t is positive definite on the free dofs.
  void add_hessian(const Vec& x, SpMat& H, Psd psd) const override;
  /// @return the lower-triangular Hessian pattern (that of Tᵀ K_t(0) T).
  const SpMat& lower() const { return m_lower; }

 private:
  Mesh m_mesh;
  std::shared_ptr<const Material> m_material;
  DofMap m_dofs;
  SpMat m_lower;
};

}  // namespace hemicontact
