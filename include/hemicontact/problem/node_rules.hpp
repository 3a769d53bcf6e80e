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

/// The polish's rule for one Γ3 node: does it keep its status from @p a (before) to @p b (after)?
/// A tangential change counts only where the node is frictionless (@p u_nu0, its u_ν before), where
/// slip±/stick carry no information. Read node by node, so that the distributed engine applies it
/// on each rank's owned nodes and reduces the verdict.
/// @param delta the half-width of the branch frictionless_at probes
inline bool polish_status_kept(const Model& md, const NodeStatus& a, const NodeStatus& b, double u_nu0, double delta) {
  return b.normal == a.normal && (b.tangential == a.tangential || frictionless_at(md, u_nu0, delta));
}

/// The polish's rule for the certificate: the polished answer's @p after is at most @p before, or
/// both are at round-off (1e-12: the smoothed answer can already be exact, e.g. when no node is
/// near a kink or stick; a tie that the polish wins, as it carries no smoothing error by
/// construction). @return "" when not worse, else the note.
inline std::string polish_certificate_rejection(double after, double before) {
  if (!(after <= std::max(before, 1e-12))) return "the certificate did not improve";
  return "";
}

/// The polish's acceptance rule, one for both engines: the polished answer @p s1 replaces @p s0
/// when every Γ3 node keeps its status (polish_status_kept) and its certificate is at most
/// @p before, the certificate the polish is judged against (PolishResult::before;
/// polish_certificate_rejection).
/// @param delta the half-width of the branch frictionless_at probes
/// @return "" when accepted, else why not (PolishResult::note)
inline std::string polish_rejection(const Model& md, const Solution& s0, const Solution& s1, double delta,
                                    double before) {
  for (Index k = 0; k < md.contact.size(); ++k) {
    const auto& a = s0.status[static_cast<std::size_t>(k)];
    const auto& b = s1.status[static_cast<std::size_t>(k)];
    if (!polish_status_kept(md, a, b, s0.state.u_nu[k], delta))
      return "statuses changed at node " + std::to_string(k) + " (" + a.str() + " -> " + b.str() + ")";
  }
  return polish_certificate_rejection(s1.certificate.max_residual, before);
}

}  // namespace hemicontact
