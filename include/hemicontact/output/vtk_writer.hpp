#pragma once
/// @file vtk_writer.hpp  The solution as a VTK XML UnstructuredGrid (.vtu) for ParaView.
///
/// Binary by default: the arrays go raw into one appended block, zlib-compressed (VTK's
/// vtkZLibDataCompressor layout, header_type UInt64) when the build has zlib — about 5x smaller
/// than ASCII and written in a fraction of the time. ASCII (output.vtu_format = "ascii") writes
/// every number in the shortest form that reads back to the same double, for diffs. No VTK
/// library is needed either way. Points always have 3 components (z = 0 in 2D); cells are VTK_TRIANGLE (5) in 2D
/// and VTK_TETRA (10) in 3D.
///
/// PointData
///  - "displacement" (3 components)
///  - "gamma3" (Int32 0/1): the node is a (non-clamped) Γ3 node
///  - on Γ3 nodes, 0 elsewhere: "u_nu", "u_tau", "sigma_nu", "sigma_tau", "xi", "lambda"
///    (2D: u_tau, sigma_tau signed along τ; 3D: magnitudes — see ContactState), and
///    "u_tau_vec", "sigma_tau_vec" (3 components, the tangential vectors)
///  - "status_normal" (Int32): −1 not on Γ3, 0 separated, 1 compliance, 2 contact
///  - "status_tangential" (Int32): −1 not on Γ3, 0 stick, 1 slip+, 2 slip−, 3 slip (3D)
///  - by name, UInt8 0/1: "separated", "compliance", "contact", "stick", and "slip_plus",
///    "slip_minus" (2D) or "slip" (3D): colour by any of them in ParaView
///
/// FieldData: "status_legend", the legend of the two integer codes as text (UInt8 characters;
/// also an XML comment in the file).
///  - 3D only: "slip_dir" (3 components, u_τ/|u_τ| on slipping Γ3 nodes, 0 elsewhere) and
///    "slip_angle_deg" (its angle in the tangent plane, SlipDirection; 0 elsewhere)
///
/// CellData
///  - "strain" (Voigt: ε11, ε22, 2ε12 in 2D; ε11, ε22, ε33, 2ε23, 2ε13, 2ε12 in 3D)
///  - "stress" (Voigt, md.material->stress(strain)), "von_mises"
///  - "error_indicator" (adaptive solves only: η_T of check/estimator.hpp, energy-norm units)

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <string>
#include <utility>
#include <vector>

namespace hemicontact {

/// The VTU's cell fields of a solution (constant per cell on P1 elements), one row per cell.
struct CellFields {
  RowMat strain;  ///< Voigt: ε11, ε22, 2ε12 in 2D; ε11, ε22, ε33, 2ε23, 2ε13, 2ε12 in 3D
  RowMat stress;  ///< Voigt, md.material->stress(strain)
  Vec von_mises;  ///< the von Mises stress of each row of stress
};

/// @return the strain, stress and von Mises stress per cell that write_vtu writes (the Python
/// module's Result.strain and Result.stress are these arrays too).
CellFields cell_fields(const Model& md, const Solution& sol);

/// How the arrays are stored.
enum class VtuFormat { BINARY, ASCII };

/// @brief Write the solution as a VTK XML UnstructuredGrid. Never solves.
/// @param path the .vtu file to write (its directory must exist)
/// @param md   the model the solution belongs to
/// @param sol  the solution; sol.u, sol.state and sol.status must be filled (evaluate_solution())
/// @throws Error (EXIT_OUTPUT) if the file cannot be written;
///         Error (EXIT_INTERNAL) if @p sol does not match @p md (sizes)
/// @param format binary (appended, compressed with zlib when available; the default) or ASCII
/// @param error_indicator per-cell η_T written as CellData "error_indicator" (null or empty: none)
/// @param cells the cells written (a distributed piece's own; its points are all written), null: all
void write_vtu(const std::string& path, const Model& md, const Solution& sol, VtuFormat format = VtuFormat::BINARY,
               const Vec* error_indicator = nullptr, const std::vector<Index>* cells = nullptr);

/// @brief Write a ParaView collection (.pvd) of VTU files: one DataSet per entry, its "timestep"
/// the entry's number (the mesh level of a convergence study, the index of a distinct solution),
/// its file relative to the .pvd's folder. ParaView steps through them with the time controls.
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& entries);

/// @brief Integer code of a normal status as written to "status_normal".
/// @param s the status @return 0 separated, 1 compliance, 2 contact
int status_code(NormalStatus s);

/// @brief Integer code of a tangential status as written to "status_tangential".
/// @param s the status @return 0 stick, 1 slip+, 2 slip−, 3 slip
int status_code(TangentialStatus s);

}  // namespace hemicontact
