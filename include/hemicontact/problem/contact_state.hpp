#pragma once
/// @file contact_state.hpp  What a displacement means on Γ3: the unsmoothed nodal quantities and
/// the contact status of each node (docs/model.md §3-§4). Computed by check/contact_status.hpp; read by
/// the polish, the certificate and every writer.

#include <hemicontact/core/types.hpp>

#include <Eigen/Core>

#include <array>
#include <map>
#include <string>

namespace hemicontact {

/// Normal status (paper Fig. 2).
enum class NormalStatus { SEPARATED, COMPLIANCE, CONTACT };
/// Tangential status; in 2D slip± along τ (on a bottom edge slip+ moves in +x); 3D: SLIP.
enum class TangentialStatus { STICK, SLIP_PLUS, SLIP_MINUS, SLIP };

/// Status of one Γ3 node.
struct NodeStatus {
  NormalStatus normal = NormalStatus::SEPARATED;          ///< separated / compliance / contact
  TangentialStatus tangential = TangentialStatus::STICK;  ///< stick / slip
  /// @return e.g. "compliance/slip-", "contact/stick".
  std::string str() const;
};

/// @return "separated", "compliance" or "contact".
const char* to_string(NormalStatus s);
/// @return "stick", "slip+", "slip-" or "slip".
const char* to_string(TangentialStatus s);

/// Slip direction of a 3D Γ3 node, as reported in report.json, gamma3.csv and the VTU.
struct SlipDirection {
  Eigen::Vector3d dir = Eigen::Vector3d::Zero();  ///< u_τ/|u_τ| (zero when u_τ = 0)
  /// Angle of dir in the tangent plane, in degrees in (−180, 180]: measured from the global x axis
  /// projected onto the plane (the y axis when x is normal to it), counter-clockwise about the
  /// inward normal −ν. On a bottom face (ν = −e_z) this is atan2(d_y, d_x) of the top view.
  double angle_deg = 0;
};

/// Unsmoothed Γ3 quantities of a displacement u, one entry per contact node.
struct ContactState {
  Vec u_nu;       ///< u_ν,i = u_i·ν_i
  Vec u_tau;      ///< 2D: u_i·τ_i (signed); 3D: |u_τ,i|
  Vec sigma_nu;   ///< σ_ν,i = ((K u − f)_i / w_i)·ν_i
  Vec sigma_tau;  ///< 2D: σ·τ (signed); 3D: |σ_τ|
  Vec xi;         ///< ξ_i: the point of ∂j_ν(u_ν,i) nearest to −σ_ν,i (= p_ν(u_ν,i) where p is continuous)
  Vec lambda;     ///< F_b(u_ν,i) (0 when frictionless)
  RowMat u_tau_vec;      ///< u_τ,i as a vector (d components)
  RowMat sigma_tau_vec;  ///< σ_τ,i as a vector (d components)
  Vec residual;          ///< the full residual K u − f (nodal forces)
  /// 3D: u_τ,i/|u_τ,i| (zero where u_τ = 0), computed once here so that every writer reports the
  /// same direction (SlipDirection); empty in 2D, where the sign of u_τ is the direction (slip±).
  RowMat slip_dir;
  Vec slip_angle_deg;  ///< 3D: the angle of slip_dir in the tangent plane (SlipDirection::angle_deg)
};

/// Status counts in the order separated, compliance, contact, stick, slip+, slip-, slip: summed
/// over the nodes a process owns, then over processes (check/judge.hpp).
using StatusCounts = std::array<long, 7>;
/// @return the names of StatusCounts' entries.
const std::array<const char*, 7>& status_count_names();
/// Add @p s to @p c.
void count_status(StatusCounts& c, const NodeStatus& s);
/// @return @p c keyed by name, as report.json's status_counts: "slip" only where a node slips in 3D.
std::map<std::string, int> count_map(const StatusCounts& c);

}  // namespace hemicontact
