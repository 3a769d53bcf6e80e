#pragma once
/// @file contact_status.hpp  Γ3 tractions from the discrete equilibrium and the contact status of
/// each node (docs/model.md §3-§4; deal.II step-41: the contact force is the residual of the
/// unconstrained system divided by the nodal weight).

#include <hemicontact/problem/contact_state.hpp>
#include <hemicontact/problem/model.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// @return the contact state of the full displacement @p u (no smoothing anywhere; in 3D with the
/// slip directions of every node whose u_τ ≠ 0).
ContactState contact_state(const Model& model, const Vec& u);

/// Decide statuses with the tolerance tol·U (U: displacement scale, a length):
/// separated if u_ν ≤ tol·U; contact if u_ν ≥ g − tol·U; compliance otherwise;
/// stick if |u_τ| ≤ tol·U, else slip by the sign of u_τ (2D).
std::vector<NodeStatus> classify(const Model& model, const ContactState& s, double U, double tol);

/// @return the slip direction of contact node @p k (3D only; @p k's u_τ from @p s).
SlipDirection slip_direction(const Model& model, const ContactState& s, Index k);

/// @return the displacement scale U = max nodal |u| (or the mesh size when u = 0).
double displacement_scale(const Model& model, const Vec& u);

}  // namespace hemicontact
