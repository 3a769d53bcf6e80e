#pragma once
/// @file bisection.hpp  Newest-vertex bisection of triangles (2D) and of tagged tetrahedra (3D)
/// with the conforming closure.
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

/// 3D: tagged tetrahedra (Maubach 1995; Kossaczký 1994; Traxler 1997). A cell is an ordered list
/// (x0, x1, x2, x3) with a tag k ∈ {1, 2, 3}; its refinement edge is (x0, xk). Bisecting it at the
/// midpoint z of (x0, xk) gives the children (x0, …, x_{k−1}, z, x_{k+1}, …, x3) and
/// (x1, …, xk, z, x_{k+1}, …, x3), both tagged k − 1 (3 after 1). Three generations split all six
/// edges of a cell into eight children; on Kuhn (and reflected Kuhn) meshes every descendant is
/// similar to one of finitely many tetrahedra, so the shape stays regular at any depth, and two
/// cells sharing a face split it the same way, so the closure below is conforming. The closure is
/// the 2D one over edges: while a cell has an edge with a midpoint, it is bisected (its refinement
/// edge gets a midpoint if it had none). The boundary facets of the children are the halves of the
/// parent's boundary faces and keep their part, traction and groups.

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

/// The tagged tetrahedra of a 3D mesh (file comment), one entry per cell of the mesh they label.
struct TetLabels {
  std::vector<std::array<int, 4>> order;  ///< per cell (x0, x1, x2, x3): refinement edge (x0, x_tag)
  std::vector<unsigned char> tag;         ///< per cell k ∈ {1, 2, 3}
  /// @return the number of labelled cells.
  Index size() const { return static_cast<Index>(order.size()); }
};

/// A refined mesh and how it derives from the coarse one.
struct Bisection {
  Mesh mesh;  ///< the conforming refined mesh (boundary parts, tractions, groups, rollers inherited)
  /// For each new node N_coarse + k: the two nodes whose midpoint it is (indices in the fine mesh,
  /// always smaller than N_coarse + k, so a field can be filled in order).
  std::vector<std::array<int, 2>> new_node_parents;
  std::vector<int> cell_parent;  ///< per fine cell, the coarse cell it lies in
  TetLabels labels;              ///< 3D: the fine cells' tagged tetrahedra (empty in 2D)
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

/// @brief Label every tetrahedron of a 3D mesh for Maubach bisection: x0 and x3 the ends of its
/// longest edge (x0 the smaller node index), x1 the remaining vertex nearer to x0, tag 3. On a box
/// mesh (Kuhn or symmetric pattern: Kuhn cubes, mirrored at the mid planes) each cell is the path
/// x0 → x1 → x2 → x3 along the three cube axes and the refinement edge the cube's main diagonal,
/// which every cell of that cube shares: Maubach's compatible labelling of a Kuhn mesh. On other
/// meshes the labelling is the same rule, and bisect() checks the result is conforming.
/// @throws Error if the mesh is not 3D.
TetLabels label_tetrahedra(const Mesh& mesh);

/// @brief 3D: refine the cells flagged in @p marked (size num_cells) of @p coarse, labelled by
/// @p labels, by Maubach bisection with the conforming closure (file comment). NEWEST_VERTEX marks
/// a cell's refinement edge, BISEC3 all six edges (at least eight children). New nodes, parents,
/// boundary facets and rollers as in 2D; Bisection::labels labels the fine mesh.
/// @throws Error (EXIT_INPUT, naming the kind of mesh needed) if the closure does not end or leaves a
/// face shared by more than two cells or a mismatched boundary (a labelling that is not compatible:
/// a perturbed box, an imported mesh whose cells are not Kuhn paths).
Bisection bisect(const Mesh& coarse, const TetLabels& labels, const std::vector<char>& marked,
                 BisectionRule rule = BisectionRule::BISEC3);

/// A 3D mesh with its tagged tetrahedra.
struct LabelledMesh {
  Mesh mesh;
  TetLabels labels;
};

/// @brief Stevenson's 12-split (2008, §4) of any conforming tetrahedral mesh: every cell T is cut
/// through its barycentre b_T and its faces' barycentres b_F into twelve cells (b_T, b_F and an
/// edge of F), each labelled so that the refinement edge is that coarse edge. The labelling is
/// compatible (the closure of bisect() is conforming and the shapes stay in finitely many
/// similarity classes) whatever the coarse mesh, which label_tetrahedra's is on Kuhn meshes only.
/// Boundary facets split in three through b_F and keep their part, traction and groups; a face
/// node is held by the rollers its facet's three corners share.
/// @throws Error if the mesh is not 3D.
LabelledMesh split_for_bisection(const Mesh& coarse);

/// @return whether every edge that is one cell's refinement edge is the refinement edge of every
/// cell that contains it. label_tetrahedra's labelling of a Kuhn mesh has it (the cube diagonals,
/// shared by the six cells of their cube); a longest-edge labelling of a perturbed or unstructured
/// mesh in general has not, and its closure is then not conforming.
bool refinement_edges_agree(const Mesh& mesh, const TetLabels& labels);

/// @brief The labelled mesh 3D refinement starts from: @p mesh with label_tetrahedra's labels when
/// refinement_edges_agree (Kuhn meshes: box meshes, imported meshes of Kuhn cubes), else
/// split_for_bisection(mesh) (12 times the cells; any conforming mesh).
/// @param lattice optional: the same cells on other node positions (a generated box before
/// mesh.perturb moved its nodes), labelled instead of @p mesh; ignored unless its cells are
/// @p mesh's. Compatibility depends on the cells alone, so a perturbed Kuhn box needs no split.
/// @throws Error if the mesh is not 3D.
LabelledMesh label_for_bisection(Mesh mesh, const Mesh* lattice = nullptr);

/// @return the cells' shape measure: the smallest dihedral angle (radians) over all cells of a 3D
/// mesh, the smallest interior angle in 2D.
double min_simplex_angle(const Mesh& mesh);

/// @return the P1 field @p u_coarse (d components per node, node-major) carried to the fine mesh of
/// @p b: old nodes keep their values, each new node gets the mean of its two parents (exact on nested
/// P1 spaces).
Vec prolongate_bisection(const Bisection& b, const Vec& u_coarse, int components);

}  // namespace hemicontact
