#pragma once
/// @file convergence_study.hpp  The result of a mesh-convergence study (studies/convergence.hpp,
/// run_convergence): one record per mesh, the study, and the reference-corrected rate fit. Plain
/// data that the study fills and the writers (output/study_writers.hpp) read, so that output/ needs
/// nothing of the study's code.

#include <hemicontact/core/types.hpp>

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace hemicontact {

/// One mesh of a convergence study (a level or the reference).
struct ConvergenceLevel {
  int n = 0;               ///< cells per side (mesh.n)
  double h = 0;            ///< the paper's h: longest side of the rectangle / n (1/n on the unit square)
  double h_max = 0;        ///< longest edge of the mesh (√2·h for the right/left splits)
  Index dofs = 0;          ///< free unknowns
  double energy_norm = 0;  ///< ‖u_L‖_E = sqrt(a(u_L, u_L)) on the level's own mesh
  double error = 0;        ///< ‖u_ref − P u_L‖_E / ‖u_ref‖_E (0 for the reference)
  double order = 0;        ///< observed order against the previous level; NaN for the first
  double seconds = 0;      ///< wall time of solve() (model assembly excluded)
  std::map<std::string, int> status_counts;  ///< Solution::status_counts()
  double certificate_residual = 0;           ///< certificate max residual
  bool converged = false;                    ///< backend and outer fixed point converged
  bool certified = false;                    ///< certificate passed
  bool ok = false;                           ///< converged && certified
  bool nested = true;                        ///< P is the exact embedding of V_L into V_ref (checked numerically)
  std::string message;                       ///< the solve's verdict
  std::string solved_by;                     ///< what produced the answer (Solution::solved_by)
  /// The solve warned that other certified solutions may exist ((21) fails and the inner problem
  /// is not known to be convex: output/report.hpp's uniqueness_warning).
  bool unique_in_doubt = false;
  /// Non-empty: why this level is taken to lie on another branch than the others
  /// (flag_other_branches); it is left out of the rate fit.
  std::string other_branch;
};

/// The result of run_convergence().
struct ConvergenceStudy {
  ConvergenceLevel reference;            ///< the reference mesh (error 0, order NaN)
  std::vector<ConvergenceLevel> levels;  ///< the levels, coarse to fine
  /// What solved the levels and the reference: the distinct Solution::solved_by labels, joined by
  /// ", " (e.g. "exact" when the backend's stage was skipped on every level: strongly convex).
  std::string backend;
  nlohmann::json scene;                  ///< the effective scene of the reference solve

  /// @return true when the reference and every level converged and were certified.
  bool ok() const;
  /// @return the n of every mesh (reference included) that failed, e.g. {8, 128}.
  std::vector<int> failed() const;
};

/// The observed orders against a finite reference are biased upwards near the reference: for nested
/// spaces and a linear problem, Galerkin orthogonality in the energy norm gives
///   ‖u − u_L‖²_E = ‖u − u_R‖²_E + ‖u_R − u_L‖²_E,
/// so if ‖u − u_L‖_E ≈ C h_L^α then the measured e_L ≈ C sqrt(h_L^{2α} − h_R^{2α}) (relative
/// errors: C absorbs ‖u_R‖_E). fit_rate() fits C and α to that model, which removes the bias
/// and turns the errors into an estimate of the asymptotic rate (for the paper's scenes α ≈ 0.72,
/// the corner exponent where the clamped side meets the free sides; docs/convergence.md).
/// With contact the identity is approximate (the solution set is not a linear space); the
/// reported max_rel_residual says how well the model fits.
struct RateFit {
  double alpha = 0;             ///< fitted rate α
  double C = 0;                 ///< fitted constant (relative error at h = 1)
  int levels_used = 0;          ///< number of (finest) levels in the fit
  double max_rel_residual = 0;  ///< max_L |model_L / e_L − 1| over the fitted levels
  bool valid = false;           ///< false when fewer than 2 usable levels (error > 0, h > h_R)
};

/// @brief Fit e_L = C sqrt(h_L^{2α} − h_R^{2α}) (least squares in log e) to the @p max_levels
/// finest levels of @p study with error > 0, h > h_R and no other_branch flag; α is searched in
/// [0.05, 4].
/// @param study a finished study @param max_levels how many of the finest levels to use (≥ 2)
/// @return the fit; valid = false if fewer than 2 levels qualify
RateFit fit_rate(const ConvergenceStudy& study, int max_levels = 4);

/// When a level lies on another branch of a nonconvex law than the others.
struct BranchCheck {
  /// A level whose error is off the fit of the other levels (leave one out) by more than this
  /// factor, either way. On one branch the errors of nested meshes follow the fitted curve to
  /// tens of percent (the paper's scenes: fit residuals ≤ 20 %); a level on another branch misses
  /// it by the distance between two solutions, O(1) against errors of a few percent.
  double error_factor = 3.0;
};

/// @brief Flag (ConvergenceLevel::other_branch) the levels that lie on another branch, where the
/// study's solves warned that other certified solutions may exist (unique_in_doubt, on a level or
/// on the reference): such a level's error is off the fit of the other levels by more than
/// BranchCheck::error_factor. Nothing is flagged where uniqueness is not in doubt.
/// @return the n of the flagged levels
std::vector<int> flag_other_branches(ConvergenceStudy& study, const BranchCheck& check = {});

}  // namespace hemicontact
