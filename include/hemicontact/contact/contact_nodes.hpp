#pragma once
/// @file contact_nodes.hpp  Γ3 nodes with nodal-quadrature weights w_i, normals ν_i, frames and gaps g_i.
///
/// docs/model.md §2: the contact integrals ∫Γ3 j_ν(u_ν), ∫Γ3 F_b|u_τ| are evaluated by nodal quadrature:
/// node i carries w_i = Σ |F|/d over the Γ3 facets F touching it (half the adjacent lengths in 2D).
/// Its normal ν_i is the facet normal; at a kink of Γ3 it is the measure-weighted average of the
/// adjacent facet normals, normalized (this makes Σ_i w_i ν_i equal ∫Γ3 ν, the consistent choice for
/// the normal force balance). In 2D the tangent is ν turned 90° counter-clockwise, τ = (−ν_y, ν_x),
/// so on a bottom edge (ν = (0, −1)) τ = (1, 0) and "slip+" means moving in +x.

#include <hemicontact/mesh/mesh.hpp>

#include <string>
#include <utility>
#include <vector>

namespace hemicontact {

/// The thickness g of the soft layer (eq. (7)): a constant, +∞ (no rigid obstacle), or piecewise
/// linear along one coordinate (constant beyond the end points).
struct Gap {
  double constant = INF;                          ///< used when points is empty
  int axis = 0;                                   ///< coordinate of the table (0 = x, 1 = y, 2 = z)
  std::vector<std::pair<double, double>> points;  ///< (coordinate, g), increasing coordinate
  /// @return g at the point @p x.
  double at(const Eigen::Ref<const Eigen::RowVectorXd>& x) const;
  /// @return true if g = +∞ everywhere (no bound constraint at all).
  bool is_infinite() const { return points.empty() && constant == INF; }
  /// @return a one-line description.
  std::string describe() const;
};

/// The Γ3 nodes, in a fixed order (sorted by coordinates: left to right on a bottom edge).
struct ContactNodes {
  std::vector<int> node;  ///< mesh node index of each contact node
  Vec w;                  ///< nodal quadrature weights w_i
  RowMat normal;          ///< ν_i, one row each (unit, outward)
  RowMat tangent;         ///< τ_i (2D: one tangent; 3D: first tangent, the second is ν × τ1)
  Vec g;                  ///< g_i = g(x_i) (may be +∞)
  /// Per node, a bit mask of the *local* tangential components (bit 1: τ1, bit 2: τ2) held at zero
  /// by a roller (Mesh::node_fixed): the frame is chosen so that each fixed global axis is one
  /// local tangent. Empty when no Γ3 node has a roller.
  std::vector<unsigned char> fixed_local;
  /// @return the number of contact nodes.
  Index size() const { return static_cast<Index>(node.size()); }
};

/// @return whether a Γ3 node at @p a (mesh node @p ia) comes before one at @p b (node @p ib) in
/// ContactNodes' order: lexicographic by the @p dim coordinates, then by node index.
bool gamma3_precedes(const double* a, long ia, const double* b, long ib, int dim);

/// Per mesh node, its Γ3 facets' sums: the weight w = Σ |f|/d (eq. (24)'s quadrature) and the
/// normal sum Σ (|f|/d) n_f, whose direction is the node's ν.
struct Gamma3Sums {
  Vec w;          ///< one per mesh node (0: on no Γ3 facet)
  RowMat normal;  ///< one row per mesh node
};
/// @return the sums over the Γ3 facets of @p mesh.
Gamma3Sums gamma3_sums(const Mesh& mesh);

/// The boundary data of nodes whose facets a mesh holds only in part: a distributed piece's ghost
/// nodes, each with what its owner computed from all of its facets (otherwise the piece would give
/// a ghost another Γ3 weight, frame, membership or clamping than its owner does, and so other
/// unknowns).
struct GivenBoundary {
  std::vector<Index> node;           ///< mesh nodes
  Vec w;                             ///< their Γ3 weights (Gamma3Sums)
  RowMat normal;                     ///< their Γ3 normal sums
  std::vector<char> clamped;         ///< on Γ1
  std::vector<unsigned char> held;   ///< roller mask (Mesh::held)
};

/// Collect the Γ3 nodes of @p mesh that are not clamped (a node on Γ1 ∩ Γ3 is clamped); the Γ3
/// sums of the nodes in @p given (if any) are the given ones.
/// @throws Error if a Γ3 gap value is negative (thickness g ≥ 0, eq. (14)), or if a roller holds a
/// Γ3 node along a direction that is not tangent to Γ3 (it would fight the contact law).
ContactNodes make_contact_nodes(const Mesh& mesh, const std::vector<bool>& clamped, const Gap& gap,
                                const GivenBoundary* given = nullptr);

}  // namespace hemicontact
