#pragma once
/// @file node_rules.hpp  Two readings of one Γ3 node that every polish (driver/polish.cpp, the petsc
/// engine's) makes the same way: is its friction bound zero on its whole branch, and is one of its
/// tangential components held by a roller.

#include <hemicontact/problem/model.hpp>

#include <cstddef>

namespace hemicontact {

/// True when the friction bound vanishes on u_ν's whole branch (no friction, or F_b = 0 around u_ν,
/// e.g. a separated node, (15c)): then σ_τ = 0 is the node's tangential equation whatever u_τ is,
/// and the sign or size of u_τ (slip±/stick) carries no information.
/// @param md the model @param u_nu the node's u_ν @param delta the half-width of the branch probed
inline bool frictionless_at(const Model& md, double u_nu, double delta) {
  if (!md.friction) return true;
  return md.friction->F(u_nu) == 0 && md.friction->F(u_nu - delta) == 0 && md.friction->F(u_nu + delta) == 0;
}

/// Is local component @p c (1 = τ1, 2 = τ2) of contact node @p k held at zero by a roller?
inline bool roller_fixed(const Model& md, Index k, int c) {
  return !md.contact.fixed_local.empty() && (md.contact.fixed_local[static_cast<std::size_t>(k)] & (1u << c));
}

}  // namespace hemicontact
