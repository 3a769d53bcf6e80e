#pragma once
/// @file scene_solve.hpp  One solve of a scene, from the effective scene to the files, as every front
/// end that holds the whole model runs it: `hemicontact solve` (cholmod engine) and the Python
/// module's solve() and Result.write() (an engine passed in: solve_scene_with). The scene's
/// adapt block picks the adaptive loop (solver/adapt.hpp) or one solve; the result keeps what the
/// report and the files need. Two sources: scene_solve.cpp (solve_scene, the cholmod engine and
/// the adaptive loop) and scene_files.cpp (the rest), which hemicontact-mpi links without the NLP
/// backends.
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>
#include <hemicontact/solver/adapt.hpp>

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hemicontact {

/// A solved scene: the model (adaptive: the final mesh's), its solution and what the report adds.
struct SceneSolve {
  nlohmann::json scene;                             ///< the effective scene solved
  SolveOptions opt;                                 ///< its options (solve_options_from_scene)
  std::shared_ptr<const Model> model;               ///< never changed after it is built
  Solution solution;                                ///< timings["wall_total"] from the start of the call
  nlohmann::json extra = nlohmann::json::object();  ///< report keys beside solve_report's ("adapt", ...)
  std::optional<Vec> indicators;                    ///< adaptive: the final mesh's η_T (the VTU's)
  std::optional<AdaptOptions> adapt;                ///< adaptive: its options
  std::vector<AdaptLevel> adapt_levels;             ///< adaptive: every level, coarse to fine
  nlohmann::json adapt_levels_file;                 ///< adaptive: adapt_levels.json's content (else null)
  std::string stop_reason;                          ///< adaptive: why the loop stopped (AdaptResult's)
  std::string missed;  ///< why a requested adaptive target was not met ("" if met or not asked)
};

/// The engine that solves a built model (the cholmod engine: solver/solve.hpp's solve).
using SceneEngine = std::function<Solution(const Model&, const SolveOptions&)>;

/// @brief One solve of the effective @p scene (config.hpp's load_scene; relative paths from
/// @p scene_dir) by @p engine, with no adaptive refinement: build_model, then the engine.
/// @throws Error as build_model and the engine do; EXIT_INPUT if the scene asks for adaptivity
SceneSolve solve_scene_with(const nlohmann::json& scene, const std::string& scene_dir, const SceneEngine& engine);

/// @throws Error (EXIT_INPUT) where @p scene asks for adaptive refinement (adapt.target_error), which
/// only the cholmod engine runs: the petsc engine refuses the key rather than drop it.
void refuse_adaptive_outside_cholmod(const nlohmann::json& scene);

/// @brief The cholmod engine's solve of @p scene: the adaptive loop from the scene's own mesh where
/// adapt.target_error is set (@p level_done then gets every certified level so far, as each ends),
/// else solve_scene_with(scene, scene_dir, solve).
SceneSolve solve_scene(const nlohmann::json& scene, const std::string& scene_dir,
                       const std::function<void(const std::vector<AdaptLevel>&)>& level_done = {});

/// @return report.json's content for @p r (solve_report with r.extra).
nlohmann::json scene_solve_report(const SceneSolve& r);

/// @brief Write @p r's files into the prepared folder @p dir (output_dir.hpp): adapt_levels.json of
/// an adaptive solve, solution.vtu and gamma3.csv as the scene asks, then @p before_report (the
/// picture), then @p report as report.json, last (it marks the set complete).
void write_scene_solve(const std::string& dir, const SceneSolve& r, const nlohmann::json& report,
                       const std::function<void()>& before_report = {});

/// @return the exit code of a solve (core/error.hpp's codes): 0 for a certified answer, 3 where the
/// backend or the fixed point did not converge (0 with solver.fixed_point.allow_not_converged on a
/// certified answer), 4 where the certificate failed; 3 where an adaptive target was missed. The
/// reason is logged as a warning.
int solve_exit_code(const SceneSolve& r);
/// The same for a solution of @p opt; @p missed: an adaptive target's miss ("" if none).
int solve_exit_code(const Solution& sol, const SolveOptions& opt, const std::string& missed = "");

}  // namespace hemicontact
