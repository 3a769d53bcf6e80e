#pragma once
/// @file node_kernels.hpp  The rules of docs/model.md §3-§4 for one Γ3 node, stated once.
///
/// Pure functions of one node's data (frame, weight, gap, laws), its displacement u_i and its row of
/// the discrete residual R = K u − f (a nodal force, docs/model.md §4): its Γ3 state (σ, ξ, λ), its
/// status, its certificate terms and its energy terms. Every engine and layout reads a node through
/// these (check/judge.hpp reduces them over the nodes a process owns), so that the certificate, the
/// statuses and the energies have one definition each.

#include <hemicontact/problem/contact_state.hpp>
#include <hemicontact/problem/model.hpp>

#include <Eigen/Core>

#include <array>

namespace hemicontact {

/// What the rules read of one Γ3 node k of a model (docs/model.md §2: nodal quadrature on Γ3).
struct NodeData {
  int d = 2;                                     ///< dimension
  Eigen::Vector3d nu = Eigen::Vector3d::Zero();  ///< outward normal ν_i (d components used)
  Eigen::Vector3d tau = Eigen::Vector3d::Zero(); ///< 2D: the tangent τ_i (its sign gives slip±)
  double w = 0;                                  ///< quadrature weight w_i
  double g = 0;                                  ///< layer thickness g_i (the bound u_ν ≤ g)
  unsigned held = 0;                             ///< global components held by a roller (bit c)
  const PiecewiseLinearLaw* normal_law = nullptr;  ///< p_ν, ∂j_ν; null: no soft layer
  const FrictionBound* friction = nullptr;         ///< F_b; null: frictionless
};

/// @return node @p k's data (md.contact's row k).
NodeData node_data(const Model& md, Index k);

/// One Γ3 node's unsmoothed quantities (ContactState holds them for every node).
struct NodeState {
  double u_nu = 0, u_tau = 0;          ///< u_ν; 2D: u·τ (signed), 3D: |u_τ|
  double sigma_nu = 0, sigma_tau = 0;  ///< σ_ν; 2D: σ·τ (signed), 3D: |σ_τ|
  double xi = 0;                       ///< ξ ∈ ∂j_ν(u_ν), nearest to −σ_ν
  double lambda = 0;                   ///< F_b(u_ν)
  Eigen::Vector3d u_tau_vec = Eigen::Vector3d::Zero();      ///< u_τ (d components)
  Eigen::Vector3d sigma_tau_vec = Eigen::Vector3d::Zero();  ///< σ_τ (d components)
};

/// The state of a node from its displacement @p u_k and its residual row @p r_k = (K u − f)_i
/// (d entries each, global components): σ_i = r_k / w_i (deal.II step-41), a roller's held
/// components dropped (their reaction is not a contact traction).
NodeState node_state(const NodeData& n, const double* u_k, const double* r_k);

/// The scales every judgement is relative to (docs/model.md §4): a length U (max nodal |u|, the
/// mesh size when u = 0), a force F (max nodal |f|) and a traction S = max(F/w̄, max λ, max |ξ|).
struct JudgeScales {
  double U = 1, F = 1, S = 1;
};

/// The node's status (docs/model.md §3) with the tolerances t = tol·U (a length) and s = tol·S (a
/// traction): contact where u_ν ≥ g − t; compliance where the layer is compressed (u_ν > t) or carries
/// a load (ξ > s, the case of a stiff layer whose u_ν is below t); separated otherwise. Tangential:
/// stick where |u_τ| ≤ t, else slip (2D: slip± by the sign of u·τ).
NodeStatus node_status(const NodeData& n, const NodeState& s, const JudgeScales& sc, double tol);

/// The node's certificate terms, normalized (docs/model.md §4), in CertificateReport's order.
enum NodeTerm { FEASIBILITY, NORMAL, COMPLEMENTARITY, FRICTION_CONE, SLIP_DIRECTION, NODE_TERMS };
/// @return the terms; SLIP_DIRECTION is 0 on a node that does not slip (|u_τ| ≤ tol·U). NaN stays
/// NaN (a non-finite state is a failed certificate, never a pass).
std::array<double, NODE_TERMS> node_terms(const NodeData& n, const NodeState& s, const JudgeScales& sc, double tol);

/// The node's energy terms of Π (docs/model.md §2): w_i j_ν(u_ν,i) and w_i F_b(u_ν,i) |u_τ,i|.
struct NodeEnergy {
  double j = 0, friction = 0;
};
NodeEnergy node_energy(const NodeData& n, const NodeState& s);

/// @return row @p k of @p cs as a NodeState; store_node writes one back.
NodeState load_node(const ContactState& cs, Index k);
void store_node(ContactState& cs, Index k, const NodeState& s);

}  // namespace hemicontact
