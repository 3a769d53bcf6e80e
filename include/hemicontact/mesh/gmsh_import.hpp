#pragma once
/// @file gmsh_import.hpp  Reading Gmsh .msh files (through the Gmsh C++ API) into a Mesh.
///
/// Only available when hemicontact was built with the Gmsh API (<hemicontact/config.hpp> defines
/// HEMICONTACT_HAS_GMSH 1); otherwise read_gmsh() throws an Error saying so. Gmsh stays a private
/// dependency: this header does not include <gmsh.h>.
///
/// What is read:
/// - 2D (no tetrahedra in the file): the 3-node triangles (MSH type 2) are the cells, the node
///   coordinates must lie in the plane z = 0, and the physical groups of dimension 1 (2-node lines,
///   type 1) become named facet groups;
/// - 3D: the 4-node tetrahedra (type 4) are the cells and the physical groups of dimension 2
///   (3-node triangles, type 2) the facet groups.
///
/// A facet group is named by its physical name, or by its tag as a decimal string if it has no
/// name (Gmsh allows unnamed groups), so that a scene can select it with {"physical": "contact"}.
/// Every element of a facet group must be a boundary facet of the cell mesh: a group that contains
/// an interior facet (e.g. a "contact" line drawn through the body) is rejected, because Γ1, Γ2
/// and Γ3 are parts of ∂Ω (paper §2).

#include <hemicontact/mesh/mesh.hpp>

#include <string>

namespace hemicontact {

/// @brief Read a Gmsh mesh file (any format Gmsh reads; tested with MSH 4.1 ASCII).
///
/// Nodes used by the cells are renumbered 0..N−1 in increasing Gmsh tag order (nodes no cell uses
/// are dropped); cells are oriented positively (two nodes swapped when the measure is negative);
/// the boundary facets are extracted (extract_boundary_facets) with parts NONE, and
/// Mesh::facet_groups maps each physical group of dimension d−1 to indices into Mesh::facets.
///
/// Gmsh is initialized (without reading user configuration files, terminal output off) and
/// finalized inside this call, also when it throws; so it must not be called while the caller
/// holds a Gmsh session of its own, nor from two threads at once.
///
/// @param path the .msh file.
/// @param allow_scripts false (the default): the file must start as an MSH file does
///   ("$MeshFormat", version 2.x or 4.x, ASCII or binary) before Gmsh sees it, since Gmsh runs
///   anything else as a script (SystemCall, Printf > "file"); true (scene key mesh.allow_scripts):
///   any file Gmsh reads, .geo scripts included, which run code.
/// @return the mesh, Mesh::origin = "gmsh <path>".
/// @throws Error (EXIT_INPUT) naming the file when it is missing or unreadable, not an MSH file
///   (without @p allow_scripts), when Gmsh cannot
///   parse it, when it has no triangles (2D) / tetrahedra (3D), contains other cell types
///   (quadrangles, second-order elements...), has a degenerate cell, a 2D mesh off the plane
///   z = 0, two facet groups with the same name, or a physical group holding a facet that is not
///   on the boundary ("physical group 'contact' contains facet (a, b) which is not on the
///   boundary", a and b being Gmsh node tags); and when Gmsh import was not compiled in.
Mesh read_gmsh(const std::string& path, bool allow_scripts = false);

}  // namespace hemicontact
