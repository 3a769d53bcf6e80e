#pragma once
/// @file gamma3_rows.hpp  One Γ3 node's results apart from the model that holds it: what
/// report.json's "nodes" (report.hpp) and gamma3.csv (csv_writer.hpp) write per node. The petsc
/// engine's distributed path gathers these rows from the ranks' slabs to write the whole list.

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>

namespace hemicontact {

/// A Γ3 node's row.
struct Gamma3Row {
  long node = 0;            ///< the mesh node (the whole mesh's numbering)
  double p[3] = {0, 0, 0};  ///< its coordinates (the mesh's dimension of them used)
  double w = 0, g = 0, u_nu = 0, u_tau = 0, sigma_nu = 0, sigma_tau = 0, xi = 0, lambda = 0;
  NodeStatus status;
  double slip_dir[3] = {0, 0, 0};  ///< 3D only: u_τ/|u_τ| (SlipDirection)
  double slip_angle_deg = 0;       ///< 3D only
};

/// @return Γ3 node @p k's row of @p sol on @p md (sol.state and sol.status filled).
Gamma3Row gamma3_row(const Model& md, const Solution& sol, Index k);

}  // namespace hemicontact
