#pragma once
/// @file mesh_bytes.hpp  A whole Mesh as bytes and back, for the petsc engine run as a process of
/// its own on a mesh its caller made (studies/petsc_process.hpp: an adaptive level, which no scene
/// key describes). Every field of Mesh is carried, so that build_model on the copy gives the
/// caller's model: nodes, cells, facets and their parts, Γ2 loads and tractions, named groups,
/// roller masks, origin. Native byte order (both ends are one machine's processes).

#include <hemicontact/mesh/mesh.hpp>

#include <string>
#include <string_view>

namespace hemicontact {

/// @return @p mesh as bytes (mesh_from_bytes reads them).
std::string mesh_to_bytes(const Mesh& mesh);

/// @return the mesh that mesh_to_bytes wrote into @p bytes.
/// @throws Error (EXIT_INPUT) naming what is wrong where the bytes are not such a mesh (too short
///         or long, a count or a node index out of range, an unknown part): never a crash
Mesh mesh_from_bytes(std::string_view bytes);

}  // namespace hemicontact
