#pragma once
/// @file pvtu_writer.hpp  A parallel VTU (.pvtu): the index of the pieces that the ranks of the
/// petsc engine's distributed path write themselves (write_vtu, one .vtu per rank), so that no
/// process gathers the solution. ParaView opens the .pvtu and reads every piece.

#include <string>
#include <vector>

namespace hemicontact {

/// @brief Write @p path, a PUnstructuredGrid naming the arrays write_vtu writes for a mesh of
/// dimension @p dim (vtk_writer.hpp lists them) and the @p pieces (file names relative to the
/// .pvtu's folder), atomically and listed in the folder's manifest (write_text_file).
/// @throws Error (EXIT_OUTPUT) if the file cannot be written
void write_pvtu(const std::string& path, int dim, const std::vector<std::string>& pieces);

}  // namespace hemicontact
