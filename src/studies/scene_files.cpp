// The part of studies/scene_solve.hpp that every engine links (hemicontact-mpi too, which has no NLP
// backend registry): one solve by a given engine, the report, the files and the exit code.
#include <hemicontact/studies/scene_solve.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/solve_files.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>

#include <chrono>
#include <filesystem>

namespace hemicontact {

void refuse_adaptive_outside_cholmod(const nlohmann::json& scene) {
  if (adapt_requested(scene))
    input_error("adapt.target_error: adaptive refinement runs its loop in the process that holds the model "
                "(solver.engine = auto or cholmod: a level whose factorization would not fit goes to the petsc "
                "engine there), not in hemicontact-mpi (solver.engine = petsc)");
}

SceneSolve solve_scene_with(const nlohmann::json& scene, const std::string& scene_dir, const SceneEngine& engine) {
  refuse_adaptive_outside_cholmod(scene);
  const auto t0 = std::chrono::steady_clock::now();
  SceneSolve r;
  r.scene = scene;
  r.opt = solve_options_from_scene(scene);
  r.model = std::make_shared<const Model>(build_model(scene, scene_dir));
  r.solution = engine(*r.model, r.opt);
  r.solution.timings["wall_total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

nlohmann::json scene_solve_report(const SceneSolve& r) { return solve_report(*r.model, r.solution, r.opt, r.extra); }

void write_scene_solve(const std::string& dir, const SceneSolve& r, const nlohmann::json& report,
                       const std::function<void()>& before_report) {
  if (!r.adapt_levels_file.is_null())
    write_text_file((std::filesystem::path(dir) / ADAPT_LEVELS_FILE).string(), r.adapt_levels_file.dump(2) + "\n");
  write_solution_files(dir, r.scene, *r.model, r.solution, r.indicators ? &*r.indicators : nullptr);
  if (before_report) before_report();
  write_final_report(dir, report);
}

int solve_exit_code(const SceneSolve& r) { return solve_exit_code(r.solution, r.opt, r.missed); }

int solve_exit_code(const Solution& sol, const SolveOptions& opt, const std::string& missed) {
  // The certificate decides: a backend that reports failure but whose (polished) answer is certified
  // is accepted with a warning; an uncertified answer fails, as "not converged" when the backend or
  // the fixed point said so, as "certificate failed" otherwise.
  if (!sol.fixed_point_converged || (!sol.backend_ok && !sol.certificate.passed)) {
    log_warn() << sol.message;
    // allow_not_converged accepts an unconverged fixed point only when its answer is certified:
    // an answer that fails the certificate never exits 0, since exit 0 promises a solution.
    if (opt.allow_not_converged && sol.certificate.passed) {
      log_warn() << "solver.fixed_point.allow_not_converged: accepted, the certificate passed";
      return EXIT_OK;
    }
    return EXIT_NOT_CONVERGED;
  }
  if (!sol.certificate.passed) {
    log_warn() << "certificate failed: max residual " << sol.certificate.max_residual << " > " << sol.certificate.tol;
    return EXIT_CERTIFICATE;
  }
  if (!sol.backend_ok) log_warn() << sol.message;
  // A cap that stops the adaptive loop above the target is not success (it once exited 0).
  if (!missed.empty()) {
    log_warn() << missed;
    return EXIT_NOT_CONVERGED;
  }
  return EXIT_OK;
}

}  // namespace hemicontact
