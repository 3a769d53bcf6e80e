#pragma once
/// @file node_rules.hpp  Readings of Γ3 nodes that every polish (solver/polish.cpp, the petsc
/// engine's) makes the same way: is a node's friction bound zero on its whole branch, is one of its
/// tangential components held by a roller, and may a polished answer replace the one it started from.

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>

#include <algorithm>
#include <cstddef>
#include <string>

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

/// The polish's acceptance rule, one for both engines: the polished answer @p s1 replaces @p s0
/// when every Γ3 node keeps its status (a tangential change only where the node is frictionless,
/// where slip±/stick carry no information) and its certificate is at most @p before, the
/// certificate the polish is judged against (PolishResult::before). Both at round-off
/// (the smoothed answer can already be exact, e.g. when no node is near a kink or stick) is a tie
/// that the polish wins: it carries no smoothing error by construction.
/// @param delta the half-width of the branch frictionless_at probes
/// @return "" when accepted, else why not (PolishResult::note)
inline std::string polish_rejection(const Model& md, const Solution& s0, const Solution& s1, double delta,
                                    double before) {
  for (Index k = 0; k < md.contact.size(); ++k) {
    const auto& a = s0.status[static_cast<std::size_t>(k)];
    const auto& b = s1.status[static_cast<std::size_t>(k)];
    if (b.normal != a.normal ||
        (b.tangential != a.tangential && !frictionless_at(md, s0.state.u_nu[k], delta)))
      return "statuses changed at node " + std::to_string(k) + " (" + a.str() + " -> " + b.str() + ")";
  }
  if (!(s1.certificate.max_residual <= std::max(before, 1e-12)))
    return "the certificate did not improve";
  return "";
}

}  // namespace hemicontact
