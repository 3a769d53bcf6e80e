#pragma once
/// @file estimator.hpp  A posteriori error indicators for a P1 solution of (P_V^h) in 2D and 3D
/// (one implementation over the dimension d), and Dörfler marking. The mathematics, and what is known about reliability and efficiency for
/// contact problems, is in docs/adaptivity.md.
///
/// Both estimators measure the error in the energy norm ‖v‖_E² = a(v, v) and return one
/// indicator η_T per cell, with η² = Σ_T η_T²:
///
/// - ZZ (Zienkiewicz–Zhu recovery): the cell strains ε_h|_T are averaged to the nodes with area
///   (volume) weights, ε* is their P1 interpolant, and η_T² = ∫_T (ε* − ε_h) : C_T (ε* − ε_h) (C_T
///   the material's tangent at ε_h|_T; the constant C for linear elasticity). ε* − ε_h is affine on
///   T with vertex values δ_i, so η_T² = |T| / ((d+1)(d+2)) (Σ δ_iᵀCδ_i + (Σδ_i)ᵀC(Σδ_i)), exact.
/// - ZZ_CONTACT: ZZ plus RESIDUAL's Γ3 term below, (1/m_F) Σ_{E⊂∂T∩Γ3} h_E ‖t_h − σ_h n‖²_E, on
///   the cells on Γ3 (the same function): the recovery sees σ_h only, not the contact conditions.
/// - RESIDUAL (Babuška–Miller / Verfürth, with Hild–Nicaise's contact term):
///     η_T² = (1/m_F) [ h_T² ‖f0 + div σ_h‖²_T + ½ Σ_{E⊂∂T interior} h_E ‖[σ_h n]‖²_E
///                       + Σ_{E⊂∂T∩(Γ2 ∪ free)} h_E ‖f2 − σ_h n‖²_E + Σ_{E⊂∂T∩Γ3} h_E ‖t_h − σ_h n‖²_E ]
///   (E the cell's facets, edges in 2D and faces in 3D, h_E their diameter; ‖·‖²_E integrals over
///   them) with div σ_h = 0 on P1 cells (σ_h constant per cell), f2 = 0 on traction-free facets, and on
///   Γ3 t_h the P1 interpolant of the nodal tractions t_i = (K u − f)_i / w_i (docs/model.md §4); at a
///   certified solution t_i equals the contact terms −(ξ_i + rigid reaction) ν_i − friction within
///   the certificate tolerance, so the last term is the mismatch between the computed stress and
///   the layer/foundation/friction reactions. 1/m_F (the strong-monotonicity constant (12)(b))
///   turns squared tractions into energy: a(e, e) ≥ m_F ‖ε(e)‖². The constant in front is 1 and
///   not calibrated (docs/adaptivity.md reports the measured efficiency).

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// Which indicator.
enum class EstimatorKind { ZZ, ZZ_CONTACT, RESIDUAL };

/// @return the EstimatorKind named "zz", "zz_contact" or "residual". @throws Error (EXIT_INPUT, naming adapt.estimator) otherwise.
EstimatorKind parse_estimator(const std::string& name);
/// @return "zz", "zz_contact" or "residual".
const char* to_string(EstimatorKind k);

/// The indicators of one solution.
struct ErrorEstimate {
  Vec eta;              ///< η_T per cell (energy-norm units)
  double total = 0;     ///< η = sqrt(Σ η_T²)
  double relative = 0;  ///< η / ‖u_h‖_E (the quantity adapt.target_error is compared with)
  EstimatorKind kind = EstimatorKind::ZZ;
};

/// @brief Compute the indicators of @p sol on @p md (file comment).
/// @throws Error if (RESIDUAL) the material has m_F ≤ 0.
ErrorEstimate estimate_error(const Model& md, const Solution& sol, EstimatorKind kind);

/// @brief Dörfler (bulk) marking: the fewest cells, largest indicators first, whose η_T² sum to at
/// least θ Σ η_T² (Dörfler 1996; with θ < 1 and a reliable, efficient estimator it gives a
/// contraction and optimal rates, Cascón–Kreuzer–Nochetto–Siebert 2008).
/// Ties at the threshold are all marked, so mirror-symmetric indicators give a symmetric marking.
/// @param eta indicators η_T @param theta bulk parameter in (0, 1]
/// @return a flag per cell
std::vector<char> dorfler_mark(const Vec& eta, double theta);

/// @brief The @p count cells with the largest indicators (all cells if @p count ≥ their number),
/// plus every cell tied to round-off with the last one, as in dorfler_mark (a symmetric marking for
/// symmetric indicators). Dörfler's set is such a prefix of the same order, so a smaller count
/// marks a subset of it: the adaptive loop's last step (adapt.landing).
/// @param eta indicators η_T @param count how many cells at least (0: none)
/// @return a flag per cell
std::vector<char> mark_largest(const Vec& eta, Index count);

}  // namespace hemicontact
