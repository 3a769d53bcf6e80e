#pragma once
/// @file certificate.hpp  Is u a solution of the *unsmoothed* discrete problem (22)? (docs/model.md §4)
///
/// Independent of the backend and of any smoothing: tractions come from the discrete equilibrium
/// (K u − f)_i = w_i σ_i ν-frame at Γ3 nodes; ξ, λ from the exact laws at u_ν. Residuals:
///  - feasibility      max(0, u_ν − g) / U
///  - normal           max(0, σ_ν + ξ) / S
///  - complementarity  |min((g − u_ν)/U, −(σ_ν + ξ)/S)|
///  - friction cone    max(0, |σ_τ| − λ) / S
///  - slip direction   |σ_τ + λ u_τ/|u_τ|| / S on slipping nodes (|u_τ| > status_tol·U)
///  - equilibrium      |(K u − f)_j| / F on free dofs away from Γ3
/// with scales U = displacement scale (max nodal |u|), F = max nodal |f| (a force) and
/// S = max(F / w̄, max λ_i, max |ξ_i|) (a traction; w̄ = mean Γ3 weight). Each is a max over nodes.

#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/problem/reports.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// Compute the certificate. @param status_tol relative tolerance deciding slipping nodes.
CertificateReport certify(const Model& model, const Vec& u, const ContactState& state, double tol, double status_tol);

}  // namespace hemicontact
