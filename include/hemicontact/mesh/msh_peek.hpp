#pragma once
/// @file msh_peek.hpp  An MSH file's size from its header alone (no Gmsh, no node read): what
/// solver.engine = auto needs to choose an engine before any mesh is made (solver/engine_choice).

#include <optional>
#include <string>

namespace hemicontact {

/// The dimension of the mesh (the highest of its entities, or of its physical groups where the
/// file has no $Entities: MSH 2) and its node count ($Nodes' header).
struct MshSize {
  int dim = 0;
  double nodes = 0;
};

/// Reads the sections before $Nodes of an MSH 2.x or 4.1 file, ASCII or binary, and $Nodes' count.
/// @return nothing where the file is not a regular file, not MSH 2/4.1, states no dimension before
///         its nodes, or has no $Nodes within the first 64 MiB: the caller then cannot size it.
std::optional<MshSize> peek_msh_size(const std::string& path);

}  // namespace hemicontact
