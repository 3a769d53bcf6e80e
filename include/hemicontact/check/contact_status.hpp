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
/// The same from a residual @p residual = K u − f already at hand (full components; the petsc
/// engine's pieces, whose rows of K live on their owners). Statuses: check/judge.hpp.
ContactState contact_state(const Model& model, const Vec& u, Vec residual);

/// @return the slip direction of contact node @p k (3D only; @p k's u_τ from @p s).
SlipDirection slip_direction(const Model& model, const ContactState& s, Index k);

}  // namespace hemicontact
