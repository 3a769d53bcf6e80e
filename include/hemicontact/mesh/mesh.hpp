#pragma once
/// @file mesh.hpp  Simplicial mesh (triangles in 2D, tetrahedra in 3D) with tagged boundary facets.

#include <hemicontact/core/types.hpp>

#include <map>
#include <string>
#include <vector>

namespace hemicontact {

/// Boundary part a facet belongs to (paper §2: Γ = Γ1 ∪ Γ2 ∪ Γ3).
enum class Part : int {
  NONE = 0,    ///< boundary facet that carries no condition (traction-free)
  GAMMA1 = 1,  ///< clamped, u = 0, eq. (3)
  GAMMA2 = 2,  ///< traction f2, eq. (4)
  GAMMA3 = 3   ///< contact with the soft-layer foundation, eqs. (5)-(6)
};

/// @return "none", "gamma1", "gamma2" or "gamma3".
const char* to_string(Part p);

/// A P1 mesh: nodes, cells and the boundary facets with their part tags.
struct Mesh {
  int dim = 2;                   ///< spatial dimension d (2 or 3)
  RowMat points;                 ///< N × d node coordinates, one row per node
  IMat cells;                    ///< M × (d+1) node indices, positively oriented
  IMat facets;                   ///< F × d node indices of every boundary facet
  std::vector<Part> facet_part;  ///< part of each facet (NONE until assigned)
  std::vector<int> facet_load;   ///< for Γ2 facets: index of its traction in Mesh::tractions, else -1
  std::vector<Vec> tractions;    ///< the piecewise-constant tractions f2 (one per Γ2 selector)
  /// Named facet groups (Gmsh physical groups): name → indices into facets.
  std::map<std::string, std::vector<Index>> facet_groups;
  /// Per node, a bit mask of the displacement components held at zero by roller conditions
  /// (bit c: component c; boundary.rollers); empty when there are none. Γ1 nodes are not listed
  /// here (they are fully clamped: clamped_nodes()).
  std::vector<unsigned char> node_fixed;
  /// @return node @p v's roller mask (0 when it has none).
  unsigned char held(Index v) const { return node_fixed.empty() ? 0 : node_fixed[static_cast<size_t>(v)]; }
  /// Human-readable origin ("rectangle 64x64 right", "gmsh file.msh"), for the report.
  std::string origin;

  /// @return number of nodes N.
  Index num_nodes() const { return points.rows(); }
  /// @return number of cells M.
  Index num_cells() const { return cells.rows(); }
  /// @return number of boundary facets F.
  Index num_facets() const { return facets.rows(); }
  /// @return the signed measure (area/volume) of cell @p c; > 0 when positively oriented.
  double cell_measure(Index c) const;
  /// @return the measure (length/area) of facet @p f.
  double facet_measure(Index f) const;
  /// @return the unit outward normal of boundary facet @p f (outward w.r.t. its cell).
  Vec facet_normal(Index f) const;
  /// @return the smallest edge length of the mesh (a length scale h_min).
  double min_edge_length() const;
  /// @return the largest edge length of the mesh (h).
  double max_edge_length() const;
};

/// Find every facet that belongs to exactly one cell and store them in mesh.facets (parts NONE).
/// Facets are oriented so that facet_normal() points out of the body.
/// @throws Error if a facet is shared by more than two cells (non-manifold mesh), or if two cells
/// lie on the same side of their common facet (a folded mesh: one cell was inverted, and a reader
/// such as read_gmsh that reorients cells to positive measure hid the inversion itself).
void extract_boundary_facets(Mesh& mesh);

/// Check cell orientation and measures.
/// @throws Error naming the first cell with zero or negative measure (inverted or degenerate).
void check_cells(const Mesh& mesh);

}  // namespace hemicontact
