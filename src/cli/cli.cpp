#include "cli.hpp"

#include <hemicontact/driver/adapt.hpp>
#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/driver/solve.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/output/csv_writer.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>

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
         "  hemicontact solve SCENE.json [options]      solve a scene (report.json, solution.vtu, gamma3.csv)\n"
         "  hemicontact converge SCENE.json [options]   mesh-convergence study (the paper's Fig. 3)\n"
         "  hemicontact minima SCENE.json [options]     distinct solutions when (21) fails\n"
         "  hemicontact backends                        list the NLP backends compiled in\n"
         "  hemicontact --help | --version\n"
         "  hemicontact COMMAND --help                  the command's options, defaults and an example\n"
         "exit codes: 0 solved and certified, 1 usage, 2 bad input, 3 not converged, 4 certificate failed,\n"
         "            5 internal error, 6 the results could not be written (disk full, permissions)\n";
}

namespace {

// Options every scene command takes (parse_scene_args).
const char* const SCENE_OPTIONS =
    "  --out DIR          output folder (default shown above); created if missing\n"
    "  --set path=value   override a scene entry by its dotted path, value in JSON (repeatable),\n"
    "                     e.g. --set mesh.n=128 --set solver.tol=1e-10; every key: docs/scene-format.md\n"
    "  --backend NAME     the same as --set solver.backend=NAME (default: the scene's, ipopt);\n"
    "                     hemicontact backends lists them\n"
    "  --force            replace the results of an earlier run in DIR (only the files it wrote)\n"
    "  --quiet            warnings only on stderr (progress is on stderr by default)\n"
    "  -h, --help         this help\n";

}  // namespace

std::string command_help(const std::string& command) {
  if (command == "solve")
    return std::string(
               "usage: hemicontact solve SCENE.json [--out DIR] [--set path=value]... [--backend NAME] [--force]\n"
               "                         [--quiet] [--plot [--magnification M]]\n"
               "Solve a scene: min Pi_lambda subject to u_nu <= g, smoothed, continuation in eps, the outer fixed\n"
               "point lambda = F_b(u_nu), the exact polish and the certificate (MODEL.md section 4). Writes\n"
               "DIR/report.json, DIR/solution.vtu (ParaView), DIR/gamma3.csv; DIR defaults to out/<scene name>.\n"
               "options:\n") +
           SCENE_OPTIONS +
           "  --plot             also draw DIR/fig2.png (3D: DIR/status3d.png) with /usr/bin/python3 +\n"
           "                     matplotlib (default off; output.plot = true in the scene does the same)\n"
           "  --magnification M  deformation magnification of the picture (default: largest displacement\n"
           "                     drawn as 10% of the body)\n"
           "example:\n"
           "  hemicontact solve problems/sofonea2017-fig2.json --set mesh.n=128 --out out/fig2-128 --plot\n";
  if (command == "converge")
    return std::string(
               "usage: hemicontact converge SCENE.json [--levels L1,L2,...] [--reference R] [--out DIR]\n"
               "                            [--set path=value]... [--backend NAME] [--force] [--quiet] [--plot]\n"
               "Mesh-convergence study: solves the reference mesh n = R, then each level n = L (every L must\n"
               "divide R); relative energy-norm errors against the reference and observed orders go to\n"
               "DIR/convergence.csv, DIR/convergence.json and stdout. DIR defaults to out/<scene name>-convergence.\n"
               "Exit code 3/4 if a solve did not converge / certify, 2 if --plot could not draw.\n"
               "options:\n"
               "  --levels LIST      mesh levels, e.g. 4,8,16 or 4,8,...,128 (doubling) (default 4,8,...,128)\n"
               "  --reference R      reference level (default 256, the paper's)\n"
               "  --plot             also draw DIR/convergence.png (error vs h, log-log)\n"
               "adaptive study (--adaptive): uniform (--levels), graded (--graded-levels, mesh.grading x both,\n"
               "y high, --graded-power B, default 2) and the adaptive sequence of the scene's adapt block (target\n"
               "adapt.target_error, default 0.01) against one reference: --reference uniform:R or adaptive:T\n"
               "(default adaptive:0.002, a deeper run of the same sequence). Writes DIR/work_precision.csv,\n"
               ".json (error, estimate, efficiency index, time per mesh) and with --plot work_precision.png;\n"
               "DIR defaults to out/<scene name>-adaptive.\n"
               "  --adaptive         the work-precision study instead of the uniform one\n"
               "  --graded-levels L  n of the graded meshes (default 4,8,...,64; none: skip)\n"
               "  --graded-power B   grading exponent (default 2)\n") +
           SCENE_OPTIONS +
           "example:\n"
           "  hemicontact converge problems/sofonea2017-fig2.json --levels 4,8,...,64 --reference 128 --plot\n";
  if (command == "minima")
    return std::string(
               "usage: hemicontact minima SCENE.json [--starts N] [--seed S] [--backends a,b,...] [--start FILE]...\n"
               "                          [--group-tol T] [--load-path-steps N] [--box B] [--out DIR]\n"
               "                          [--set path=value]... [--force] [--quiet]\n"
               "Distinct solutions when the smallness condition (21) fails: solves from zero, all at g, all\n"
               "separated, N random starts, a load path up and down and each --start, with each backend;\n"
               "certified results within T of each other (relative energy norm) are one solution, classified\n"
               "local minimum or saddle. Writes DIR/minima.csv, DIR/minima.json, DIR/solution_<k>.vtu and\n"
               "DIR/minima.png; DIR defaults to out/<scene name>-minima. Exit code 3/4 if no run converged /\n"
               "certified.\n"
               "options:\n"
               "  --starts N         random starts (default 8, at most 10000)\n"
               "  --seed S           seed of the random starts (default 1; 0 to 4294967295)\n"
               "  --box B            random starts in the box +-B*U_s (default 1)\n"
               "  --backends LIST    backends to run every start with (default: the scene's)\n"
               "  --start FILE       a start: a JSON array of [u_nu, u_tau] per Gamma3 node, or a report.json\n"
               "                     (repeatable)\n"
               "  --group-tol T      relative energy-norm distance below which two results are one (default 1e-6)\n"
               "  --load-path-steps N  load path steps per unit load, up and down (default 10; 0: none)\n") +
           SCENE_OPTIONS +
           "example:\n"
           "  hemicontact minima problems/minima-softening.json --starts 16 --seed 3 --backends ipopt,newton\n";
  if (command == "backends")
    return "usage: hemicontact backends\n"
           "List the NLP backends compiled in, one per line with a description; pass one to\n"
           "hemicontact solve --backend NAME.\n"
           "options:\n"
           "  -h, --help         this help\n"
           "example:\n"
           "  hemicontact backends\n";
  return usage();
}

bool wants_help(const std::vector<std::string>& args) {
  // Options that take a value: their value is never a request for help (--set description=-h).
  static const std::vector<std::string> with_value = {
      "--out",  "--set", "--backend",  "--magnification", "--levels",          "--reference", "--starts",
      "--seed", "--box", "--backends", "--start",         "--load-path-steps", "--group-tol",
      "--graded-levels", "--graded-power"};
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "-h" || args[i] == "--help") return true;
    if (std::find(with_value.begin(), with_value.end(), args[i]) != with_value.end()) ++i;
  }
  return false;
}

SceneArgs parse_scene_args(const std::vector<std::string>& args, const std::vector<std::string>& extra_keys) {
  SceneArgs a;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& s = args[i];
    // A value that is empty where a name is expected, or that is the next option ("--out --quiet"),
    // is the user forgetting the value: never taken as a path.
    const auto value = [&]() -> std::string {
      if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0)
        throw UsageError("option " + s + " needs a value");
      return args[++i];
    };
    if (s == "--out") {
      a.out = value();
      if (a.out.empty()) throw UsageError("--out: empty folder name");
    } else if (s == "--set")
      a.overrides.push_back(value());
    else if (s == "--backend")
      a.overrides.push_back("solver.backend=" + value());
    else if (s == "--force")
      a.force = true;
    else if (s == "--quiet")
      a.quiet = true;
    else if (s == "--plot")
      a.plot = true;
    else if (s.rfind("--", 0) == 0 && std::find(extra_keys.begin(), extra_keys.end(), s) != extra_keys.end())
      a.extra.emplace_back(s, value());
    else if (s.rfind("--", 0) == 0)
      throw UsageError("unknown option " + s);
    else if (a.scene.empty())
      a.scene = s;
    else
      throw UsageError("unexpected argument '" + s + "'");
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
  const bool plot = a.plot || scene.at("output").at("plot").get<bool>();
  const char* picture = "fig2.png";  // 3D: status3d.png (known once the mesh is built)
  // Held until the program ends: no other run writes into this folder meanwhile.
  const OutputLock lock =
      prepare_output_dir(a.out, a.force, {"report.json", "solution.vtu", "gamma3.csv", "fig2.png", "status3d.png"});
  const SolveOptions opt = solve_options_from_scene(scene);
  // adapt.target_error set: the adaptive loop (driver/adapt.hpp) from the scene's mesh; the final
  // mesh's model and solution are written as a plain solve's, with the indicators in the VTU.
  const bool adaptive = adapt_requested(scene);
  AdaptResult adapted;
  AdaptOptions aopt;
  if (adaptive) {
    aopt = adapt_options_from_scene(scene);
    adapted = run_adaptive(scene, build_mesh(scene, scene_directory(a.scene)), aopt, opt);
  } else {
    adapted.model = build_model(scene, scene_directory(a.scene));
    adapted.solution = solve(adapted.model, opt);
  }
  const Model& md = adapted.model;
  Solution& sol = adapted.solution;
  sol.timings["wall_total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // report.json comes last: it lists every file of the set ("files") and marks it complete.
  const std::filesystem::path out(a.out);
  const VtuFormat vtu_format =
      scene.at("output").at("vtu_format").get<std::string>() == "ascii" ? VtuFormat::ASCII : VtuFormat::BINARY;
  if (scene.at("output").at("vtu").get<bool>()) write_vtu((out / "solution.vtu").string(), md, sol, vtu_format, adaptive ? &adapted.estimate.eta : nullptr);
  if (scene.at("output").at("csv").get<bool>()) write_gamma3_csv((out / "gamma3.csv").string(), md, sol);
  std::fputs(summary_table(md, sol).c_str(), stdout);
  // 3D: the Γ3 status map with slip directions (scripts/plot_status3d.py, same arguments).
  const bool d3 = md.dim() == 3;
  if (d3) picture = "status3d.png";
  if (plot && run_plot_script(d3 ? "plot_status3d.py" : "plot_fig2.py", plot_args) != 0)
    log_warn() << "--plot: " << (out / picture).string() << " was not written (the solve's results are)";
  if (plot && std::filesystem::exists(out / picture)) record_output_file((out / picture).string());
  nlohmann::json report = make_report(md, sol, opt);
  if (adaptive) {
    report["adapt"] = adapt_report(adapted, aopt);
    const AdaptLevel& last = adapted.history.back();
    std::printf("adapt: %zu levels, %lld dofs, estimate %.3g (target %.3g, %s), %.3g s\n", adapted.history.size(),
                static_cast<long long>(last.dofs), last.estimate, aopt.target_error, adapted.stop_reason.c_str(),
                last.cumulative_seconds);
  }
  report["files"] = output_files(a.out);
  report["files"].push_back("report.json");
  write_report((out / "report.json").string(), report);
  std::printf("results in %s\n", a.out.c_str());

  // The certificate decides: a backend that reports failure but whose (polished) answer is certified
  // is accepted with a warning; an uncertified answer fails, as "not converged" when the backend or
  // the fixed point said so, as "certificate failed" otherwise.
  if (!sol.fixed_point_converged || (!sol.backend_ok && !sol.certificate.passed)) {
    log_warn() << sol.message;
    // allow_not_converged accepts an unconverged fixed point only when its answer is certified:
    // an answer that fails the certificate never exits 0 (issue 12).
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

int cmd_backends(const std::vector<std::string>& args) {
  if (!args.empty()) throw UsageError("'backends' takes no arguments");
  for (const auto& [name, doc] : available_backends()) std::printf("%-20s %s\n", name.c_str(), doc.c_str());
  return EXIT_OK;
}

}  // namespace hemicontact::cli
