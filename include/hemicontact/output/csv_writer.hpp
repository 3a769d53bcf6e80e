#pragma once
/// @file csv_writer.hpp  The Γ3 quantities as CSV: one row per contact node, in the order of
/// ContactNodes (left to right on a bottom edge), for plotting against the paper's figures.
///
/// Header (2D; 3D adds z after y and appends slip_dir_x,slip_dir_y,slip_dir_z,slip_angle_deg):
/// @code
///   index,node,x,y,w,g,u_nu,u_tau,sigma_nu,sigma_tau,xi,lambda,status
/// @endcode
/// In 3D u_tau and sigma_tau are magnitudes, and the slip direction u_τ/|u_τ| and its angle
/// (SlipDirection) are NaN on sticking nodes.
/// index is the contact-node index k, node the mesh node, w the nodal weight w_k, g the gap g_k
/// (written "inf" when there is no rigid obstacle), status e.g. "compliance/slip-". Numbers are
/// written in the shortest form that reads back to the same double (full precision).

#include <hemicontact/output/gamma3_rows.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// @brief Write one CSV row per Γ3 node. Never solves.
/// @param path the .csv file to write (its directory must exist)
/// @param md   the model the solution belongs to
/// @param sol  the solution; sol.state and sol.status must be filled (evaluate_solution())
/// @throws Error (EXIT_OUTPUT) if the file cannot be written;
///         Error (EXIT_INTERNAL) if @p sol does not match @p md (sizes)
void write_gamma3_csv(const std::string& path, const Model& md, const Solution& sol);

/// @brief Write @p rows as the CSV above, row q with the contact-node index @p index[q] (a piece
/// of the Γ3 nodes, such as one rank's owned nodes in the petsc engine's distributed path).
/// @param d the mesh's dimension
/// @throws Error (EXIT_OUTPUT) if the file cannot be written; (EXIT_INTERNAL) if the sizes differ
void write_gamma3_csv(const std::string& path, int d, const std::vector<Gamma3Row>& rows,
                      const std::vector<long>& index);

}  // namespace hemicontact
