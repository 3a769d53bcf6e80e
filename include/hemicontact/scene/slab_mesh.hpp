#pragma once
/// @file slab_mesh.hpp  A scene's generated mesh made in slabs of cell layers, one per MPI rank
/// (the petsc engine's distributed path: no process holds the whole mesh). A box is cut along y
/// (its front/back faces carry no condition in the paper's scenes), a rectangle along x; the
/// boundary parts are those of the whole mesh (the sides of its bounding box).

#include <hemicontact/mesh/mesh.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// How a generated mesh is cut: the axis and its number of cell layers.
struct SlabCut {
  int axis = 0;    ///< 0 = x (rectangle), 1 = y (box)
  int layers = 0;  ///< cells along that axis
};

/// @return "" when the scene's mesh can be made in slabs, else why not (a Gmsh file, a perturbed
/// mesh, crossed cells), in words for the report.
std::string slab_refusal(const nlohmann::json& scene);

/// @return the cut of the scene's generated mesh (slab_refusal empty).
SlabCut slab_cut(const nlohmann::json& scene);

/// @brief The cells of layers [@p c0, @p c1) along the cut and their nodes, boundary parts assigned
/// with the sides of the whole mesh (assign_boundary_in_box) and tractions scaled by loads.scale.
/// @param counts facets each selector selected here (gamma1, gamma2, gamma3, rollers order): the
/// caller sums them over the ranks and refuses a selector that selects nothing anywhere.
Mesh build_slab_mesh(const nlohmann::json& scene, int c0, int c1, std::vector<long>& counts);

/// @return the index in the whole generated mesh (make_box / make_rectangle's numbering) of node
/// @p v of build_slab_mesh(@p scene, @p c0, @p c1, ...): the report names Γ3 nodes as the whole
/// mesh does, whichever rank's slab holds them.
long slab_global_node(const nlohmann::json& scene, int c0, int c1, Index v);

/// A block of a generated box's cell columns (the block split: every z layer, so that Γ3 on the
/// bottom face reaches each block): cells [i0, i1) × [j0, j1).
struct BlockRange {
  int i0 = 0, i1 = 0, j0 = 0, j1 = 0;
};

/// @brief The cells of the box's block @p b and their nodes (make_box_block), boundary parts
/// assigned with the sides of the whole box; @p counts as build_slab_mesh's.
Mesh build_block_mesh(const nlohmann::json& scene, const BlockRange& b, std::vector<long>& counts);

/// @return the whole box's index (make_box's numbering) of node @p v of build_block_mesh(@p scene, @p b, ...).
long block_global_node(const nlohmann::json& scene, const BlockRange& b, Index v);

/// @return the contexts of the scene's boundary selectors in the order of @p counts
/// ("boundary.gamma1[0]", ...), for the message naming one that selects nothing.
std::vector<std::string> boundary_selector_names(const nlohmann::json& scene);

}  // namespace hemicontact
