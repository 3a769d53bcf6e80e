#pragma once
/// @file bisection.hpp  Newest-vertex bisection of triangles (2D) with the conforming closure.
///
/// Convention: a cell (c0, c1, c2) has its *refinement edge* (c1, c2), opposite its *newest vertex*
/// c0. Bisecting it inserts the midpoint m of (c1, c2) and creates the children (m, c0, c1) and
/// (m, c2, c0): both keep the positive orientation, m is their newest vertex, and the parent's two
/// other edges become the children's refinement edges (Mitchell 1991; Binev, Dahmen, DeVore 2004).
/// Every triangle produced this way is similar to one of at most four triangles per initial cell
/// (Sewell), so the minimum angle never degenerates however deep the refinement goes.
///
/// Conforming closure: the edges to split are marked (the refinement edge of every marked cell,
/// or all three edges), then, until nothing changes, every cell that has a marked edge gets its
/// refinement edge marked too. Each cell is then bisected recursively along marked refinement
/// edges; because a marked edge of a cell is either its refinement edge or becomes a child's, every
/// marked edge is split on both sides and no unmarked edge is split: the result has no hanging
/// node. The loop only adds marks, so it ends after at most (number of edges) passes.
///
/// Boundary facets split with their edge: the two halves keep the part, the Γ2 traction index and
/// the facet groups of their parent, and the orientation (outward normal) of the parent. Old nodes
/// keep their indices; new nodes are appended, each the midpoint of two old (or new) nodes, so a P1
/// field is carried to the fine mesh exactly (nested spaces) by averaging its two parents.

#include <hemicontact/mesh/mesh.hpp>

#include <array>
#include <vector>

namespace hemicontact {

/// What a marked cell asks for.
enum class BisectionRule {
  NEWEST_VERTEX,  ///< one bisection of its refinement edge (area halves)
  BISEC3          ///< all three edges split: four children, diameter halves (fewer levels)
};

/// @return the BisectionRule named "newest_vertex" or "bisec3". @throws Error otherwise.
BisectionRule parse_bisection_rule(const std::string& name);
/// @return the scene's name of @p rule ("newest_vertex" or "bisec3"), the inverse of parse_bisection_rule.
const char* to_string(BisectionRule rule);

/// A refined mesh and how it derives from the coarse one.
struct Bisection {
  Mesh mesh;  ///< the conforming refined mesh (boundary parts, tractions, groups, rollers inherited)
  /// For each new node N_coarse + k: the two nodes whose midpoint it is (indices in the fine mesh,
  /// always smaller than N_coarse + k, so a field can be filled in order).
  std::vector<std::array<int, 2>> new_node_parents;
  std::vector<int> cell_parent;  ///< per fine cell, the coarse cell it lies in
};

/// Rotate every cell cyclically (orientation unchanged) so that its longest edge is the refinement
/// edge (c1, c2). On the structured meshes (right/left/symmetric: the diagonal of each square; crossed:
/// the square's side) the two cells that share a refinement edge then both have it as their
/// refinement edge, which keeps the closure local (Binev–Dahmen–DeVore's compatible labelling).
/// Ties (equal lengths up to 1e-12 relative) go to the first edge in the order (c1,c2), (c2,c0), (c0,c1).
/// @throws Error if the mesh is not 2D.
void label_longest_edges(Mesh& mesh);

/// Refine the cells flagged in @p marked (size num_cells) by newest-vertex bisection with the
/// conforming closure (file comment).
/// @throws Error if the mesh is not 2D or @p marked has the wrong size.
Bisection bisect(const Mesh& coarse, const std::vector<char>& marked, BisectionRule rule = BisectionRule::BISEC3);

/// @return the P1 field @p u_coarse (d components per node, node-major) carried to the fine mesh of
/// @p b: old nodes keep their values, each new node gets the mean of its two parents (exact on nested
/// P1 spaces).
Vec prolongate_bisection(const Bisection& b, const Vec& u_coarse, int components);

}  // namespace hemicontact
