#pragma once
/// @file nonlinear_assembly.hpp  Assembly for a (possibly nonlinear) material: the elastic energy
/// E(u) = Σ_T |T| W(ε_T(u)) (docs/model.md §2: ½ a(u,u) becomes ∫ W(ε(u)) with F = ∂W/∂ε), the internal
/// force vector r(u) = ∫ F(ε(u)) : ε(v) and the tangent stiffness K_t(u) = ∫ ε(v) : C(ε(u)) ε(w),
/// C = ∂F/∂ε; P1 elements, one quadrature point per cell (exact: ε is constant on a cell).

#include <hemicontact/core/types.hpp>
#include <hemicontact/material/material.hpp>
#include <hemicontact/mesh/mesh.hpp>

namespace hemicontact {

/// @return Σ_T |T| W(ε_T(u)) for the full displacement @p u (N·d).
double assemble_elastic_energy(const Mesh& mesh, const Material& material, const Vec& u);

/// @return the full internal force vector r(u) = Σ_T |T| B_Tᵀ F(B_T u_T) (N·d); = K u for a linear law.
Vec assemble_internal_force(const Mesh& mesh, const Material& material, const Vec& u);

/// @return the full tangent stiffness K_t(u) = Σ_T |T| B_Tᵀ C(ε_T(u)) B_T (symmetric, full storage,
/// every adjacent node pair a full d×d block, the pattern of assemble_stiffness).
SpMat assemble_tangent_stiffness(const Mesh& mesh, const Material& material, const Vec& u);

}  // namespace hemicontact
