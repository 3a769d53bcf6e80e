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
///
/// Other meshes: Arnold–Mukherjee–Pouly's marked tetrahedra (2000; AmpMarks), which need no
/// particular mesh: the same closure ends with a conforming mesh, and the shapes stay in finitely
/// many similarity classes, from the longest-edge marking of the mesh as it is (mark_tetrahedra).

#include <hemicontact/mesh/mesh.hpp>

#include <array>
#include <limits>
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

/// Arnold, Mukherjee and Pouly's marked tetrahedron (2000), relative to the positions 0..3 of the
/// cell's vertices in TetLabels::order: the refinement edge (edge[0], edge[1]); the marked edge of
/// the face opposite position k, the edge of that face opposite its vertex at position face[k];
/// and the flag of the planar type (P_f). Bisecting at the midpoint z of the refinement edge, the
/// child without vertex a (z in its place) keeps the parent's face opposite a, with its mark, and
/// takes that mark as its refinement edge; the halves of the two faces through the refinement edge
/// are marked opposite z; the new face through z is marked opposite z too, except in a flagged
/// planar parent, where it takes the mark of the kept face's vertex. Children of a planar parent
/// (all four marked edges in one face) are flagged when it is not. The marks of a shared face
/// depend on that face alone, so its two sides split it alike, and every descendant is similar to
/// one of finitely many tetrahedra (AMP 2000, §3–4).
struct AmpMarks {
  std::array<unsigned char, 2> edge{};
  std::array<unsigned char, 4> face{};
  unsigned char flagged = 0;
};

/// The labels of a 3D mesh's tetrahedra for bisection (file comment), one entry per cell of the
/// mesh they label: Maubach's tagged tetrahedra, or AMP's marked tetrahedra (tag 0, marks in amp).
struct TetLabels {
  std::vector<std::array<int, 4>> order;  ///< per cell (x0, x1, x2, x3): refinement edge (x0, x_tag)
  std::vector<unsigned char> tag;         ///< per cell k ∈ {1, 2, 3}; 0: marked tetrahedron amp[c]
  std::vector<AmpMarks> amp;              ///< per cell if any tag is 0, else empty
  /// @return the number of labelled cells.
  Index size() const { return static_cast<Index>(order.size()); }
};

/// @return the ends of a cell's refinement edge: (x0, x_tag) of Maubach's order @p x and tag, or
/// the marked edge of AMP's marks @p m (tag 0).
inline std::array<int, 2> refinement_edge(const std::array<int, 4>& x, int tag, const AmpMarks& m) {
  if (tag) return {x[0], x[static_cast<size_t>(tag)]};
  return {x[m.edge[0]], x[m.edge[1]]};
}

/// A refined mesh and how it derives from the coarse one.
struct Bisection {
  Mesh mesh;  ///< the conforming refined mesh (boundary parts, tractions, groups, rollers inherited)
  /// For each new node N_coarse + k: the two nodes whose midpoint it is (indices in the fine mesh,
  /// always smaller than N_coarse + k, so a field can be filled in order).
  std::vector<std::array<int, 2>> new_node_parents;
  std::vector<int> cell_parent;  ///< per fine cell, the coarse cell it lies in
  TetLabels labels;              ///< 3D: the fine cells' tagged tetrahedra (empty in 2D)
  /// The refined mesh's node count, known once the closure has ended. Above the @p max_nodes given
  /// to bisect() it is all there is: the mesh and the rest are not built (`built` false), as the
  /// adaptive loop refuses such a mesh by its size alone (AdaptOptions::max_dofs).
  Index nodes = 0;
  bool built = false;
};

/// No limit on the refined mesh's node count (bisect()'s default max_nodes).
inline constexpr Index NO_NODE_LIMIT = std::numeric_limits<Index>::max();

/// Rotate every cell cyclically (orientation unchanged) so that its longest edge is the refinement
/// edge (c1, c2). On the structured meshes (right/left/symmetric: the diagonal of each square; crossed:
/// the square's side) the two cells that share a refinement edge then both have it as their
/// refinement edge, which keeps the closure local (Binev–Dahmen–DeVore's compatible labelling).
/// Ties (equal lengths up to 1e-12 relative) go to the first edge in the order (c1,c2), (c2,c0), (c0,c1).
/// @throws Error if the mesh is not 2D.
void label_longest_edges(Mesh& mesh);

/// Refine the cells flagged in @p marked (size num_cells) by newest-vertex bisection with the
/// conforming closure (file comment); a refinement of more than @p max_nodes nodes is counted, not
/// built (Bisection::nodes).
/// @throws Error if the mesh is not 2D or @p marked has the wrong size.
Bisection bisect(const Mesh& coarse, const std::vector<char>& marked, BisectionRule rule = BisectionRule::BISEC3,
                 Index max_nodes = NO_NODE_LIMIT);

/// @brief Label every tetrahedron of a 3D mesh for Maubach bisection: x0 and x3 the ends of its
/// longest edge (x0 the smaller node index), x1 the remaining vertex nearer to x0, tag 3. On a box
/// mesh (Kuhn or symmetric pattern: Kuhn cubes, mirrored at the mid planes) each cell is the path
/// x0 → x1 → x2 → x3 along the three cube axes and the refinement edge the cube's main diagonal,
/// which every cell of that cube shares: Maubach's compatible labelling of a Kuhn mesh. On other
/// meshes the labelling is the same rule, and bisect() checks the result is conforming.
/// @throws Error if the mesh is not 3D.
TetLabels label_tetrahedra(const Mesh& mesh);

/// @brief 3D: refine the cells flagged in @p marked (size num_cells) of @p coarse, labelled by
/// @p labels, by Maubach's (or AMP's) bisection with the conforming closure (file comment). NEWEST_VERTEX marks
/// a cell's refinement edge, BISEC3 all six edges (at least eight children). New nodes, parents,
/// boundary facets and rollers as in 2D; Bisection::labels labels the fine mesh. Above @p max_nodes
/// nodes after the closure, only Bisection::nodes is filled (the closure is a third of the work; the
/// fine cells, facets and the conformity check are the rest).
/// @throws Error (EXIT_INPUT, naming the kind of mesh needed) if the closure does not end or leaves a
/// face shared by more than two cells or a mismatched boundary (a labelling that is not compatible:
/// a perturbed box, an imported mesh whose cells are not Kuhn paths).
Bisection bisect(const Mesh& coarse, const TetLabels& labels, const std::vector<char>& marked,
                 BisectionRule rule = BisectionRule::BISEC3, Index max_nodes = NO_NODE_LIMIT);

/// A 3D mesh with its tagged tetrahedra.
struct LabelledMesh {
  Mesh mesh;
  TetLabels labels;
};

/// @return whether every edge that is one cell's refinement edge is the refinement edge of every
/// cell that contains it. label_tetrahedra's labelling of a Kuhn mesh has it (the cube diagonals,
/// shared by the six cells of their cube); a longest-edge labelling of a perturbed or unstructured
/// mesh in general has not, and its closure is then not conforming.
bool refinement_edges_agree(const Mesh& mesh, const TetLabels& labels);

/// @brief AMP's initial marking of any conforming tetrahedral mesh (Arnold, Mukherjee, Pouly 2000,
/// §4): a strict order of the edges, longest first (ties by node indices); each cell's refinement
/// edge and each face's marked edge are the first of theirs in it, no cell flagged. A face's mark
/// depends on the face alone, which is what conformity needs; the cells are not split.
/// @throws Error if the mesh is not 3D.
TetLabels mark_tetrahedra(const Mesh& mesh);

/// @brief The labelled mesh 3D refinement starts from: @p mesh with label_tetrahedra's labels when
/// refinement_edges_agree (Kuhn meshes: box meshes, imported meshes of Kuhn cubes), else with
/// mark_tetrahedra's (any conforming mesh, as it is: no split).
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
