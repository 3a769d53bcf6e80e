// What `hemicontact solve` does after the solve, shared by both engines (the cholmod engine in
// cli.cpp, the petsc engine's rank 0 in src/petsc/main_mpi.cpp): the result files, the summary and
// the exit code.
#include "cli.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/solve_files.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace hemicontact::cli {

std::vector<std::string> solve_plot_args(const SceneArgs& a) {
  // scripts/plot_fig2.py (3D: plot_status3d.py) DIR --title NAME [--magnification M]
  std::vector<std::string> plot_args{a.out, "--title", std::filesystem::path(a.scene).stem().string()};
  for (const auto& [key, value] : a.extra) {
    char* end = nullptr;
    const double m = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !(m > 0) || !std::isfinite(m))
      throw UsageError(key + ": expected a positive number, got '" + value + "'");
    plot_args.insert(plot_args.end(), {key, value});
  }
  return plot_args;
}

void write_solve_results(const SceneArgs& a, const std::vector<std::string>& plot_args, const nlohmann::json& scene,
                         const Model& md, const Solution& sol, const SolveOptions& opt, const nlohmann::json& extra,
                         const Vec* cell_indicators) {
  // report.json comes last: it lists every file of the set ("files") and marks it complete.
  write_solution_files(a.out, scene, md, sol, cell_indicators);
  std::fputs(summary_table(md, sol).c_str(), stdout);
  draw_solve_picture(a, plot_args, scene, md.dim());
  write_final_report(a.out, solve_report(md, sol, opt, extra));
  std::printf("results in %s\n", a.out.c_str());
}

void draw_solve_picture(const SceneArgs& a, const std::vector<std::string>& plot_args, const nlohmann::json& scene,
                        int dim) {
  if (!a.plot && !scene.at("output").at("plot").get<bool>()) return;
  const std::filesystem::path out(a.out);
  // 3D: the Γ3 status map with slip directions (scripts/plot_status3d.py, same arguments).
  const bool d3 = dim == 3;
  const char* picture = d3 ? "status3d.png" : "fig2.png";
  if (run_plot_script(d3 ? "plot_status3d.py" : "plot_fig2.py", plot_args, (out / picture).string()) != 0)
    log_warn() << "--plot: " << (out / picture).string() << " was not written (the solve's results are)";
  if (std::filesystem::exists(out / picture)) record_output_file((out / picture).string());
}

int solve_verdict(const Solution& sol, const SolveOptions& opt) {
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
  return EXIT_OK;
}

}  // namespace hemicontact::cli
