// The cholmod engine's side of studies/scene_solve.hpp: solve_scene, with the adaptive loop.
#include <hemicontact/studies/scene_solve.hpp>

#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/studies/minima.hpp>
#include <hemicontact/studies/petsc_process.hpp>

#include <chrono>

namespace hemicontact {

namespace {

// The adaptive loop from the scene's own mesh: the final mesh's model and solution, the loop's
// record in the report ("adapt") and in adapt_levels.json, each certified level handed to
// @p level_done as it ends.
SceneSolve solve_adaptive(const nlohmann::json& scene, const std::string& scene_dir,
                          const std::function<void(const std::vector<AdaptLevel>&)>& level_done) {
  SceneSolve r;
  r.scene = scene;
  r.opt = solve_options_from_scene(scene);
  const AdaptOptions aopt = adapt_options_from_scene(scene);
  std::vector<AdaptLevel> so_far;
  const auto keep = [&](const AdaptLevel& L, const Model&, const Solution&, const ErrorEstimate&) {
    so_far.push_back(L);
    if (level_done) level_done(so_far);
  };
  AdaptResult adapted =
      run_adaptive(scene, build_mesh(scene, scene_dir), aopt, r.opt, keep, petsc_level_engine(scene, scene_dir));
  r.extra = adapt_solve_extra(adapted, aopt, r.missed);
  r.indicators = adapted.estimate.eta;
  r.adapt = aopt;
  r.adapt_levels = std::move(adapted.history);
  r.adapt_levels_file = adapt_levels_json(r.adapt_levels, aopt, /*partial=*/false);
  r.stop_reason = adapted.stop_reason;
  r.model = std::make_shared<const Model>(std::move(adapted.model));
  r.solution = std::move(adapted.solution);
  return r;
}

// The cholmod engine's solve; where other certified solutions may exist (uniqueness_warning), the
// second-order check of `minima` says which kind the one found is.
Solution solve_and_classify(const Model& md, const SolveOptions& o) {
  ContactSolver solver(md, o);
  Solution sol = solver.solve();
  if (sol.certificate.passed && !uniqueness_warning(sol).empty())
    sol.second_order = second_order_check(solver, md, o, sol, MinimaOptions{});
  return sol;
}

}  // namespace

SceneSolve solve_scene(const nlohmann::json& scene, const std::string& scene_dir,
                       const std::function<void(const std::vector<AdaptLevel>&)>& level_done) {
  if (!adapt_requested(scene)) return solve_scene_with(scene, scene_dir, solve_and_classify);
  const auto t0 = std::chrono::steady_clock::now();
  SceneSolve r = solve_adaptive(scene, scene_dir, level_done);
  r.solution.timings["wall_total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace hemicontact
