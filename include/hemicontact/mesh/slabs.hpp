#pragma once
/// @file slabs.hpp  Pieces of the generated meshes, made by each MPI rank for itself: the petsc
/// engine's distributed path builds only its own slab of cell layers (plus one ghost layer), so
/// that no process holds the whole mesh (docs/petsc-engine.md, "Distributed mesh").

#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/generators.hpp>

#include <vector>

namespace hemicontact {

/// @brief The cells of make_box(@p s) whose y-layer j lies in [j0, j1), and their nodes: the same
/// coordinates and the same split as in the whole box. Node (i, j, k) has index
/// (k·(j1 − j0 + 1) + j − j0)·(nx + 1) + i (make_box's numbering when j0 = 0, j1 = ny).
/// @throws Error as make_box, and for a perturbed box (its draws run over the whole box).
Mesh make_box_slab(const BoxSpec& s, int j0, int j1);

/// @brief The cells of make_box(@p s) in the columns i0 <= i < i1, j0 <= j < j1 (every z layer),
/// and their nodes: the same coordinates and split as in the whole box (the petsc engine's block
/// split, for more ranks than a slab cut allows; Γ3 on the bottom face z = z0 reaches every block).
/// Node (i, j, k) has index (k·(j1 − j0 + 1) + j − j0)·(i1 − i0 + 1) + i − i0.
/// @throws Error as make_box_slab.
Mesh make_box_block(const BoxSpec& s, int i0, int i1, int j0, int j1);

/// @brief The cells of make_rectangle(@p s) in the columns i0 <= i < i1, and their nodes. Grid node
/// (i, j) has index j·(i1 − i0 + 1) + i − i0 (make_rectangle's numbering when i0 = 0, i1 = nx).
/// @throws Error as make_rectangle, and for a perturbed rectangle or crossed cells (their centre
/// nodes are not numbered on a grid).
Mesh make_rectangle_slab(const RectangleSpec& s, int i0, int i1);

/// @brief assign_boundary on a piece of a mesh: the sides are those of the whole mesh's bounding
/// box [@p lo, @p hi] (1 × d each), a selector may select nothing on the piece, and Γ1 may be
/// absent from it (the caller checks both over all pieces).
/// @return the number of facets each selector selected, in the order gamma1, gamma2, gamma3, rollers.
std::vector<long> assign_boundary_in_box(Mesh& mesh, const BoundarySpec& spec, const RowMat& lo, const RowMat& hi);

}  // namespace hemicontact
