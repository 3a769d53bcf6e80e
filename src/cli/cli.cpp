#include "cli.hpp"

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/driver/solve.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/output/csv_writer.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/nlp/backend.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace hemicontact::cli {

std::string version() { return std::string("hemicontact ") + HEMICONTACT_VERSION; }

std::string usage() {
  return "usage:\n"
         "  hemicontact solve SCENE.json [--out DIR] [--set path=value]... [--backend NAME] [--force] [--quiet]\n"
         "                   [--plot [--magnification M]]\n"
         "      solve a scene; writes DIR/report.json, DIR/solution.vtu, DIR/gamma3.csv (DIR defaults to\n"
         "      out/<scene name>); --set overrides any scene entry (e.g. --set mesh.n=128);\n"
         "      --backend NAME is --set solver.backend=NAME; --force overwrites existing results;\n"
         "      --plot (or output.plot = true) also draws DIR/fig2.png (deformed mesh magnified M times,\n"
         "      default: largest displacement = 10% of the body; forces on Gamma3) with /usr/bin/python3 +\n"
         "      matplotlib; if that fails a warning is printed and the exit code is unchanged\n"
         "  hemicontact converge SCENE.json [--levels 4,8,...,128] [--reference 256] [--out DIR] [--set path=value]...\n"
         "                      [--backend NAME] [--force] [--quiet] [--plot]\n"
         "      mesh-convergence study: solves the reference mesh n = R, then each level n = L (every L must\n"
         "      divide R); relative energy-norm errors against the reference and observed orders go to\n"
         "      DIR/convergence.csv, DIR/convergence.json and stdout (DIR defaults to out/<scene name>-convergence);\n"
         "      --plot draws DIR/convergence.png (error vs h, log-log); exit code 3/4 if a solve did not\n"
         "      converge / certify, 2 if --plot could not draw\n"
         "  hemicontact minima SCENE.json [--starts N] [--seed S] [--backends a,b,...] [--start FILE.json]...\n"
         "                    [--group-tol T] [--load-path-steps N] [--box B] [--out DIR] [--set path=value]...\n"
         "                    [--force] [--quiet]\n"
         "      distinct solutions when (21) fails: solves from zero, all at g, all separated, N random starts\n"
         "      (default 8, seed S = 1, box +-B*U_s, B = 1), a load path up and down (N steps per unit load,\n"
         "      default 10) and each --start (a JSON array of [u_nu, u_tau] per Gamma3 node, or a report.json),\n"
         "      with each backend (default: the scene's); certified results within T (default 1e-6) of each\n"
         "      other in relative energy norm are one solution, classified local minimum or saddle; writes\n"
         "      DIR/minima.csv, DIR/minima.json, DIR/solution_<k>.vtu, DIR/minima.png (DIR defaults to\n"
         "      out/<scene name>-minima); exit code 3/4 if no run converged / certified\n"
         "  hemicontact backends        list the NLP backends compiled in\n"
         "  hemicontact --help | --version\n"
         "exit codes: 0 solved and certified, 1 usage, 2 bad input, 3 not converged, 4 certificate failed,\n"
         "            5 internal error\n";
}

SceneArgs parse_scene_args(const std::vector<std::string>& args, const std::vector<std::string>& extra_keys) {
  SceneArgs a;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& s = args[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw UsageError("option " + s + " needs a value");
      return args[++i];
    };
    if (s == "--out") a.out = value();
    else if (s == "--set") a.overrides.push_back(value());
    else if (s == "--backend") a.overrides.push_back("solver.backend=" + value());
    else if (s == "--force") a.force = true;
    else if (s == "--quiet") a.quiet = true;
    else if (s == "--plot") a.plot = true;
    else if (s.rfind("--", 0) == 0 && std::find(extra_keys.begin(), extra_keys.end(), s) != extra_keys.end())
      a.extra.emplace_back(s, value());
    else if (s.rfind("--", 0) == 0) throw UsageError("unknown option " + s);
    else if (a.scene.empty()) a.scene = s;
    else throw UsageError("unexpected argument '" + s + "'");
  }
  if (a.scene.empty()) throw UsageError("missing SCENE.json");
  if (a.out.empty()) a.out = "out/" + std::filesystem::path(a.scene).stem().string();
  return a;
}

int cmd_solve(const std::vector<std::string>& args) {
  const SceneArgs a = parse_scene_args(args, {"--magnification"});
  if (a.quiet) set_log_level(LogLevel::WARN);
  const auto t0 = std::chrono::steady_clock::now();
  // scripts/plot_fig2.py (3D: plot_status3d.py) DIR --title NAME [--magnification M]
  std::vector<std::string> plot_args{a.out, "--title", std::filesystem::path(a.scene).stem().string()};
  for (const auto& [key, value] : a.extra) {
    char* end = nullptr;
    const double m = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !(m > 0) || !std::isfinite(m))
      throw UsageError(key + ": expected a positive number, got '" + value + "'");
    plot_args.insert(plot_args.end(), {key, value});
  }
  const nlohmann::json scene = load_scene(a.scene, a.overrides);
  prepare_output_dir(a.out, a.force);
  const Model md = build_model(scene, scene_directory(a.scene));
  const SolveOptions opt = solve_options_from_scene(scene);
  Solution sol = solve(md, opt);
  sol.timings["wall_total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const std::filesystem::path out(a.out);
  const nlohmann::json report = make_report(md, sol, opt);
  write_report((out / "report.json").string(), report);
  if (scene.at("output").at("vtu").get<bool>()) write_vtu((out / "solution.vtu").string(), md, sol);
  if (scene.at("output").at("csv").get<bool>()) write_gamma3_csv((out / "gamma3.csv").string(), md, sol);
  std::fputs(summary_table(md, sol).c_str(), stdout);
  std::printf("results in %s\n", a.out.c_str());
  // 3D: the Γ3 status map with slip directions (scripts/plot_status3d.py, same arguments).
  const bool d3 = md.dim() == 3;
  if ((a.plot || scene.at("output").at("plot").get<bool>()) &&
      run_plot_script(d3 ? "plot_status3d.py" : "plot_fig2.py", plot_args) != 0)
    log_warn() << "--plot: " << (out / (d3 ? "status3d.png" : "fig2.png")).string()
               << " was not written (the solve's results are)";

  // The certificate decides: a backend that reports failure but whose (polished) answer is certified
  // is accepted with a warning; an uncertified answer fails, as "not converged" when the backend or
  // the fixed point said so, as "certificate failed" otherwise.
  if (!sol.fixed_point_converged || (!sol.backend_ok && !sol.certificate.passed)) {
    log_warn() << sol.message;
    return opt.allow_not_converged ? EXIT_OK : EXIT_NOT_CONVERGED;
  }
  if (!sol.certificate.passed) {
    log_warn() << "certificate failed: max residual " << sol.certificate.max_residual << " > "
               << sol.certificate.tol;
    return EXIT_CERTIFICATE;
  }
  if (!sol.backend_ok) log_warn() << sol.message;
  return EXIT_OK;
}

int cmd_backends(const std::vector<std::string>& args) {
  if (!args.empty()) throw UsageError("'backends' takes no arguments");
  for (const auto& [name, doc] : available_backends()) std::printf("%-20s %s\n", name.c_str(), doc.c_str());
  return EXIT_OK;
}

}  // namespace hemicontact::cli
