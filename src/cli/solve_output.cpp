// What `hemicontact solve` does after the solve, shared by both engines (the cholmod engine in
// cli.cpp, the petsc engine's rank 0 in src/petsc/main_mpi.cpp): the result files (write_scene_solve),
// the summary on stdout and the picture.
#include "cli.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/studies/scene_solve.hpp>

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

void write_solve_results(const SceneArgs& a, const std::vector<std::string>& plot_args, const SceneSolve& r,
                         const nlohmann::json& report) {
  write_scene_solve(a.out, r, report, [&] {
    std::fputs(summary_table(*r.model, r.solution).c_str(), stdout);
    draw_solve_picture(a, plot_args, r.scene, r.model->dim());
  });
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

}  // namespace hemicontact::cli
