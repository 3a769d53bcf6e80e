#pragma once
/// @file model.hpp  Everything a scene defines, assembled once: mesh and parts, material, loads,
/// Γ3 data, laws, the reduced stiffness and load. Solvers, checks and writers read it; none mutate it.

#include <hemicontact/contact/contact_nodes.hpp>
#include <hemicontact/contact/friction_bound.hpp>
#include <hemicontact/contact/piecewise_linear_law.hpp>
#include <hemicontact/core/symmetric_matrix.hpp>
#include <hemicontact/fem/dof_map.hpp>
#include <hemicontact/material/material.hpp>
#include <hemicontact/mesh/mesh.hpp>

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <memory>
#include <string>

namespace hemicontact {

/// The assembled discrete problem (P_V^h), eq. (22).
struct Model {
  nlohmann::json scene;                                  ///< effective scene (defaults injected)
  Mesh mesh;                                             ///< mesh with tagged boundary parts
  std::shared_ptr<const Material> material;              ///< elasticity operator F
  std::vector<bool> clamped;                             ///< Γ1 flag per node
  Gap gap;                                               ///< layer thickness g
  ContactNodes contact;                                  ///< Γ3 nodes, weights, frames, g_i
  DofMap dofs;                                           ///< full ↔ reduced unknowns
  Vec f;                                                 ///< full load vector, eq. (17)
  /// reduced stiffness Tᵀ K T (nonlinear F: tangent at u = 0); the only copy of K, its lower
  /// triangle (half the memory; K_x x through operator*). Empty in the petsc engine's models
  /// (build_model(..., stiffness = false)): each rank assembles its rows into PETSc, and
  /// internal_force, a and elastic_energy of a linear material refuse (EXIT_INTERNAL).
  SymmetricSpMat Kx;
  Vec fx;                                                ///< reduced load Tᵀ f
  std::shared_ptr<const PiecewiseLinearLaw> normal_law;  ///< exact p_ν; null: no soft layer
  std::shared_ptr<const FrictionBound> friction;         ///< F_b; null: frictionless
  std::map<std::string, double> timings;                 ///< seconds: mesh, assembly, ...

  /// @return the spatial dimension d.
  int dim() const { return mesh.dim; }
  /// @return full displacement u_ν of contact node k.
  double u_nu(const Vec& u, Index k) const;
  /// @return the full internal force vector r(u) = ∫ F(ε(u)) : ε(φ) (docs/model.md §4: the equilibrium
  /// residual is r(u) − f) on the free dofs and the Γ3 nodes; 0 on Γ1 and on roller-held components
  /// of other nodes (their reactions, which the certificate does not use). For a linear material
  /// T K_x Tᵀ u, which equals K u there for every u that vanishes on Γ1 and the held components.
  Vec internal_force(const Vec& u) const;
  /// @return the stored elastic energy ∫ W(ε(u)); ½ a(u, u) for a linear material.
  double elastic_energy(const Vec& u) const;
  /// @return the bilinear form a(u, v) = uᵀ K v of eq. (17) (K(0) for a nonlinear law) of two full
  /// displacements that vanish on Γ1 and on roller-held components (solutions and their
  /// interpolants on nested meshes): (Tᵀu)ᵀ K_x (Tᵀv), since u = T Tᵀ u for such u. The model keeps
  /// one stiffness (the largest array of a run); the full K is reduced in place and dropped after
  /// assembly.
  double a(const Vec& u, const Vec& v) const;
};

}  // namespace hemicontact
