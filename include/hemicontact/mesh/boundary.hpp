#pragma once
/// @file boundary.hpp  Assigning boundary facets to Γ1 (clamped), Γ2 (traction), Γ3 (contact).

#include <hemicontact/mesh/mesh.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// Selects boundary facets: by a side of the bounding box or by a named (Gmsh physical) group,
/// optionally restricted to facets whose midpoint coordinate along the side lies in [from, to).
/// That coordinate is, in 2D, y on left/right and x on bottom/top; in 3D, z (the vertical) on the
/// lateral sides left/right/front/back and x on bottom/top.
struct BoundarySelector {
  /// "left", "right" (x = min/max), "bottom", "top" (2D: y, 3D: z = min/max), "front", "back"
  /// (3D only: y = min/max); or empty
  std::string side;
  std::string physical;         ///< name of a group in Mesh::facet_groups; or empty
  double from = -INF;           ///< lower end of the half-open interval along the side
  double to = INF;              ///< upper end (excluded)
  Vec traction;                 ///< Γ2 only: the constant traction f2 on the selected facets
  std::string context;          ///< where it came from, for messages (e.g. "boundary.gamma2[1]")
  std::vector<int> components;  ///< rollers only: the displacement components held at zero (0 = x, ...)
};

/// The selectors of the three parts.
struct BoundarySpec {
  std::vector<BoundarySelector> gamma1;  ///< clamped
  std::vector<BoundarySelector> gamma2;  ///< tractions
  std::vector<BoundarySelector> gamma3;  ///< contact
  /// Roller (symmetry-plane) conditions: u_c = 0 for the listed components c on the selected
  /// facets' nodes, the other components free (a roller facet may also be on Γ2 or be free).
  std::vector<BoundarySelector> rollers;
};

/// Tag mesh.facets with their parts and tractions.
/// @throws Error naming the selector when one selects nothing, names an unknown side or group,
/// or when two selectors claim the same facet; and when no Γ1 facet results (the problem would
/// not be coercive: the paper requires meas(Γ1) > 0).
/// Rollers set Mesh::node_fixed; a roller selector without components, or with a component
/// ≥ dim, is an error naming it.
void assign_boundary(Mesh& mesh, const BoundarySpec& spec);

/// @return a flag per node: true if the node lies on a Γ1 facet (its displacement is zero).
std::vector<bool> clamped_nodes(const Mesh& mesh);

}  // namespace hemicontact
