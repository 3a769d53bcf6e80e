#pragma once
/// @file adapt.hpp  The adaptive loop SOLVE → ESTIMATE → MARK → REFINE (docs/adaptivity.md).
///
///   mesh ← the scene's mesh, cells labelled for newest-vertex bisection (2D: longest edge; 3D:
///          tagged tetrahedra on Kuhn meshes, marked tetrahedra (AMP) on any other,
///          label_for_bisection) — the same loop in 2D and 3D
///   loop:
///     model ← build_model(scene, mesh)        Γ3 nodes, weights, frames, K, f: rebuilt from the mesh
///     u     ← ContactSolver(model).solve(z0)   factorization and condensation redone on each mesh;
///                                              z0 = the previous level's u carried to this mesh
///     η     ← estimate_error(model, u)         per cell; relative η / ‖u‖_E
///     stop when η/‖u‖_E ≤ target_error, the level cap is reached, or the next mesh would exceed max_dofs
///     mesh  ← bisect(mesh, dorfler_mark(η, θ))  conforming, no hanging nodes; the marking cut to the
///                                              largest η_T when it overshoots the predicted need (landing);
///                                              up to `lookahead` steps on predicted η_T when they reach it
///
/// The smallness diagnostic (21) is not evaluated on the intermediate levels (it says nothing about
/// the adaptive choice and costs an extra eigenvalue computation): only on the final mesh when the
/// scene asks for it, from that mesh's condensation as a plain solve does (ContactSolver::smallness).

#include <hemicontact/check/adapt_options.hpp>
#include <hemicontact/check/estimator.hpp>
#include <hemicontact/mesh/bisection.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hemicontact {

/// @return true when the scene asks for adaptation (adapt.target_error is set).
/// (Inline: hemicontact-mpi, which links no adaptive loop, asks it too to refuse the key.)
inline bool adapt_requested(const nlohmann::json& scene) {
  return scene.contains("adapt") && !scene.at("adapt").at("target_error").is_null();
}
/// @return the options of the scene's `adapt` block. @throws Error naming the key for a bad value.
AdaptOptions adapt_options_from_scene(const nlohmann::json& scene);

/// One mesh of the adaptive sequence.
struct AdaptLevel {
  int level = 0;
  Index nodes = 0, cells = 0, dofs = 0, contact_nodes = 0;
  double estimate = 0;           ///< η/‖u_h‖_E
  double estimate_abs = 0;       ///< η
  double energy_norm = 0;        ///< ‖u_h‖_E
  double energy = 0;             ///< Π(u_h) (Solution::energy)
  /// The formulation this level's solve chose ("condensed", "full"; solver/method_choice.hpp): each
  /// level chooses from its own model, as a plain solve of that mesh would.
  std::string method;
  /// sqrt(2 (Π(u_h) − Π(u))) / ‖u_h‖_E against AdaptOptions::reference_energy (NaN without one)
  double reference_error = std::numeric_limits<double>::quiet_NaN();
  double seconds = 0;            ///< this level: model build + solve + estimate (+ refinement after it)
  double cumulative_seconds = 0; ///< from the start of run_adaptive (mesh generation included)
  double solve_seconds = 0;      ///< the solve alone (factorization and condensation included)
  /// The level's phases (wall seconds; they add up to `seconds` but for bookkeeping): the model
  /// (Γ3 nodes, weights, K, f), the solver's set-up (fill-reducing ordering, factorization, Schur
  /// complement onto Γ3), the solve from the carried start (exact solver, polish, certificate), the
  /// estimator, and the refinement (Dörfler marking, bisection, prolongation of u; 0 on the last level).
  double build_seconds = 0, setup_seconds = 0, contact_seconds = 0, estimate_seconds = 0, refine_seconds = 0;
  double certificate = 0;        ///< certificate max residual
  bool ok = false;               ///< converged and certified
  Index marked = 0;              ///< cells marked by Dörfler, over all steps (0 on the last level)
  int steps = 0;                 ///< refinement steps to the next level (> 1: AdaptOptions::lookahead)
  bool landed = false;           ///< the marking was cut to the predicted need (AdaptOptions::landing) or to max_dofs
};

/// The result of run_adaptive.
struct AdaptResult {
  Model model;                      ///< the final mesh's model
  Solution solution;                ///< its solution (smallness evaluated if the scene asks)
  ErrorEstimate estimate;           ///< its indicators
  std::vector<AdaptLevel> history;  ///< every level, coarse to fine
  bool reached = false;             ///< the target was met
  std::string stop_reason;          ///< "target reached", "max_levels", "max_dofs", "not certified"
};

/// Called after each level is solved and estimated.
using AdaptLevelSolved =
    std::function<void(const AdaptLevel&, const Model&, const Solution&, const ErrorEstimate&)>;

/// @brief Run the adaptive loop (file comment) from @p initial (boundary parts assigned).
/// A level whose solve is not certified ends the loop (stop_reason "not certified"): refining on a
/// wrong answer would chase its error.
/// A level's solve by another engine, where it takes it (studies/petsc_process.hpp's
/// petsc_level_engine: solver/engine_choice.hpp's choose_level_engine); nullopt: the level is solved
/// here (ContactSolver, from the previous level's u). @p previous: the previous level's solution
/// (null on the first), whose method_choice numbers say what its factorization took; @p u_start:
/// its u carried to this level's mesh (empty on the first), the start either engine takes.
using AdaptLevelEngine = std::function<std::optional<Solution>(const Model&, const SolveOptions&,
                                                               const Solution* previous, const Vec& u_start)>;
/// @param level_engine each level's other engine (null: every level here)
AdaptResult run_adaptive(const nlohmann::json& scene, Mesh initial, const AdaptOptions& aopt,
                         const SolveOptions& sopt, const AdaptLevelSolved& on_level = nullptr,
                         const AdaptLevelEngine& level_engine = nullptr);

/// @return the report.json "adapt" object: options, history, final estimate, stop reason.
nlohmann::json adapt_report(const AdaptResult& r, const AdaptOptions& aopt);

/// @return the content of adapt_levels.json: the certified levels of @p levels (adapt_report's
/// keys without reached and stop_reason), with "partial" and a note on what the file is.
nlohmann::json adapt_levels_json(const std::vector<AdaptLevel>& levels, const AdaptOptions& aopt, bool partial);

/// @brief The report.json keys of an adaptive solve beside make_report's: "adapt" (adapt_report),
/// and, when the loop stopped above the target on a certified answer, "ok": false and a
/// "message" saying which cap stopped it.
/// @param missed set to that reason ("" when the target was met or the answer is not certified)
nlohmann::json adapt_solve_extra(const AdaptResult& adapted, const AdaptOptions& aopt, std::string& missed);

}  // namespace hemicontact
