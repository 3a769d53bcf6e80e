#pragma once
/// @file model.hpp  Everything a scene defines, assembled once: mesh and parts, material, loads,
/// Γ3 data, laws, the reduced stiffness and load. Solvers, checks and writers read it; none mutate it.

#include <hemicontact/contact/contact_nodes.hpp>
#include <hemicontact/contact/friction_bound.hpp>
#include <hemicontact/contact/piecewise_linear_law.hpp>
#include <hemicontact/fem/dof_map.hpp>
#include <hemicontact/material/material.hpp>
#include <hemicontact/mesh/mesh.hpp>

#include <nlohmann/json.hpp>

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
  SpMat K;                                               ///< full stiffness (N·d); nonlinear F: tangent at u = 0
  Vec f;                                                 ///< full load vector, eq. (17)
  SpMat Kx;                                              ///< reduced stiffness Tᵀ K T
  Vec fx;                                                ///< reduced load Tᵀ f
  std::shared_ptr<const PiecewiseLinearLaw> normal_law;  ///< exact p_ν; null: no soft layer
  std::shared_ptr<const FrictionBound> friction;         ///< F_b; null: frictionless
  std::map<std::string, double> timings;                 ///< seconds: mesh, assembly, ...

  /// @return the spatial dimension d.
  int dim() const { return mesh.dim; }
  /// @return full displacement u_ν of contact node k.
  double u_nu(const Vec& u, Index k) const;
  /// @return the full internal force vector r(u) = ∫ F(ε(u)) : ε(φ) (MODEL.md §4: the equilibrium
  /// residual is r(u) − f); K u for a linear material (the same floating-point operation as before).
  Vec internal_force(const Vec& u) const;
  /// @return the stored elastic energy ∫ W(ε(u)); ½ uᵀ K u for a linear material.
  double elastic_energy(const Vec& u) const;
};

}  // namespace hemicontact
