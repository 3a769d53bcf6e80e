#include "cli.hpp"

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/output/csv_writer.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/adapt.hpp>
#include <hemicontact/solver/engine_choice.hpp>
#include <hemicontact/studies/scene_solve.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/studies/adapt_study.hpp>
#include <hemicontact/studies/barriers.hpp>
#include <hemicontact/studies/minima.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <unistd.h>

namespace hemicontact::cli {

std::string version() { return std::string("hemicontact ") + HEMICONTACT_VERSION; }

std::string usage() {
  return "usage:\n"
         "  hemicontact solve SCENE.json [options]      solve a scene (report.json, solution.vtu, gamma3.csv)\n"
         "  hemicontact converge SCENE.json [options]   mesh-convergence study (the paper's Fig. 3)\n"
         "  hemicontact minima SCENE.json [options]     distinct solutions when (21) fails\n"
         "  hemicontact path SCENE.json [options]       a quasi-static load history: jumps, hysteresis\n"
         "  hemicontact backends                        list the NLP backends compiled in\n"
         "  hemicontact --help | --version\n"
         "  hemicontact COMMAND --help                  the command's options, defaults and an example\n"
         "exit codes: 0 solved and certified, 1 usage, 2 bad input (or too big for the memory), 3 not converged\n"
         "            (or adapt.target_error not met), 4 certificate failed, 5 internal error, 6 the results could\n"
         "            not be written (disk full, permissions)\n";
}

namespace {
// A default as the help text writes it: the shortest round-trip text without the exponent's
// leading zero ("1e-6", as a user types it, not "1e-06").
std::string help_number(double v) {
  std::string t = round_trip(v);
  const auto e = t.find("e-0");
  if (e != std::string::npos) t.erase(e + 2, 1);
  return t;
}
}  // namespace

std::string command_help(const std::string& command) {
  if (command == "solve")
    return std::string(
               "usage: hemicontact solve SCENE.json [--out DIR] [--set path=value]... [--backend NAME] [--force]\n"
               "                         [--quiet] [--plot [--magnification M]]\n"
               "Solve a scene: min Pi_lambda subject to u_nu <= g with the nonsmooth terms smoothed, handed to\n"
               "the NLP backend (solver.backend; auto: ipopt where built) inside the outer fixed point\n"
               "lambda = F_b(u_nu); the exact solver (no smoothing) takes over from the backend's first\n"
               "eps-stage, and the certificate judges the unsmoothed answer. Under solver.backend = auto (the\n"
               "default) the backend's stage is skipped where the inner problem is strongly convex (its\n"
               "minimizer is unique), and the summary says so with the eigenvalue; --backend NAME always runs\n"
               "NAME's first stage. stdout and report.json (backend, phases, solved_by) say what ran. Writes\n"
               "DIR/report.json, DIR/solution.vtu (ParaView), DIR/gamma3.csv; DIR defaults to out/<scene name>.\n"
               "options:\n") +
           scene_options_help() +
           "  --plot             also draw DIR/fig2.png (3D: DIR/status3d.png) with /usr/bin/python3 +\n"
           "                     matplotlib (default off; output.plot = true in the scene does the same)\n"
           "  --magnification M  deformation magnification of the picture (default: largest displacement\n"
           "                     drawn as 10% of the body)\n"
           "example:\n"
           "  hemicontact solve problems/sofonea2017-fig2.json --set mesh.n=128 --out out/fig2-128 --plot\n";
  if (command == "converge") {
    const WorkPrecisionRequest wp;
    return std::string(
               "usage: hemicontact converge SCENE.json [--levels L1,L2,...] [--reference R] [--out DIR]\n"
               "                            [--set path=value]... [--backend NAME] [--force] [--quiet] [--plot]\n"
               "Mesh-convergence study: solves the reference mesh n = R, then each level n = L (every L must\n"
               "divide R); relative energy-norm errors against the reference and observed orders go to\n"
               "DIR/convergence.csv, DIR/convergence.json and stdout. DIR defaults to out/<scene name>-convergence.\n"
               "Exit code 3/4 if a solve did not converge / certify, 2 if --plot could not draw.\n"
               "options:\n"
               "  --levels LIST      mesh levels, e.g. 4,8,16 or 4,8,...,128 (doubling) (default ") +
           CONVERGE_LEVELS + ")\n  --reference R      reference level (default " + CONVERGE_REFERENCE +
           ", the paper's)\n"
           "  --plot             also draw DIR/convergence.png (error vs h, log-log)\n"
           "adaptive study (--adaptive): uniform (--levels), graded (--graded-levels, mesh.grading x both,\n"
           "y high, --graded-power B, default " + help_number(wp.graded_power) +
           ") and the adaptive sequence of the scene's adapt block\n"
           "(target adapt.target_error, default " + help_number(AdaptOptions{}.target_error) +
           ") against one reference: --reference uniform:R or adaptive:T\n"
           "(default " + wp.reference + ", a deeper run of the same sequence). Writes DIR/work_precision.csv,\n"
           ".json (error, estimate, efficiency index, time per mesh) and with --plot work_precision.png;\n"
           "DIR defaults to out/<scene name>-adaptive.\n"
           "  --adaptive         the work-precision study instead of the uniform one\n"
           "  --graded-levels L  n of the graded meshes (default " + ADAPTIVE_LEVELS + "; none: skip)\n"
           "  --graded-power B   grading exponent (default " + help_number(wp.graded_power) + ")\n" +
           scene_options_help() +
           "example:\n"
           "  hemicontact converge problems/sofonea2017-fig2.json --levels 4,8,...,64 --reference 128 --plot\n";
  }
  if (command == "minima") {
    const MinimaOptions mo;
    return std::string(
               "usage: hemicontact minima SCENE.json [--starts N] [--seed S] [--backends a,b,...] [--start FILE]...\n"
               "                          [--group-tol T] [--load-path-steps N] [--box B] [--until-complete\n"
               "                          [--max-starts M]] [--barriers] [--out DIR]\n"
               "                          [--set path=value]... [--force] [--quiet]\n"
               "Distinct solutions when the smallness condition (21) fails: solves from zero, all at g, all\n"
               "separated, N random starts, a load path up and down and each --start, with each backend;\n"
               "certified results within T of each other (relative energy norm) are one solution, classified\n"
               "local minimum or saddle. Writes DIR/minima.csv, DIR/minima.json, DIR/solution_<k>.vtu and\n"
               "DIR/minima.png; DIR defaults to out/<scene name>-minima. Exit code 3/4 if no run converged /\n"
               "certified.\n"
               "options:\n"
               "  --starts N         random starts (default ") +
           std::to_string(mo.starts) + ", at most " + std::to_string(MAX_STARTS) +
           ")\n  --seed S           seed of the random starts (default " + std::to_string(mo.seed) +
           "; 0 to 4294967295)\n"
           "  --box B            random starts in the box +-B*U_s (default " + help_number(mo.box) + ")\n"
           "  --backends LIST    backends to run every start with (default: the scene's)\n"
           "  --start FILE       a start: a JSON array of [u_nu, u_tau] per Gamma3 node, or a report.json\n"
           "                     (repeatable)\n"
           "  --group-tol T      relative energy-norm distance below which two results are one (default " +
           help_number(mo.group_tol) + ")\n  --load-path-steps N  load path steps per unit load, up and down (default " +
           std::to_string(mo.load_path_steps) + "; 0: none)\n" +
           "  --until-complete   random starts in batches of N until the Chao1 estimate of distinct\n"
           "                     solutions no random start reached is below one (stdout and minima.json\n"
           "                     'unseen' report it in every run: seen once f1, twice f2, estimate, interval)\n"
           "  --max-starts M     the cap of --until-complete (default " + std::to_string(mo.max_starts) + ")\n" +
           "  --barriers         energy barriers between the lowest " + std::to_string(BarrierOptions{}.minima) +
           " local minima (2D): string method, saddle refined\n"
           "                     and verified; DIR/barriers.csv, DIR/saddle_<k>.vtu, DIR/barriers.png\n" +
           scene_options_help() +
           "example:\n"
           "  hemicontact minima problems/minima-softening.json --starts 16 --seed 3 --backends ipopt,newton\n";
  }
  if (command == "path") return path_help();
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

namespace {

// solver.engine = petsc: replace this process by hemicontact-mpi (petsc_engine_program) with the
// same arguments; under mpirun every rank does so and the ranks meet in its MPI_Init. A separate
// program because this one links Ipopt, whose MUMPS (libdmumps_seq) defines stub MPI_Init and
// MPI_Comm_rank that would take the place of the real MPI's in one process.
[[noreturn]] void exec_petsc_engine_impl(const std::vector<std::string>& args) {
#if HEMICONTACT_HAS_PETSC
  const std::filesystem::path mpi = petsc_engine_program();
  if (const std::string missing = petsc_engine_missing(); !missing.empty())
    throw Error("solver.engine = petsc: " + missing, EXIT_INPUT);
  std::vector<std::string> all{mpi.string(), "solve"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : all) argv.push_back(s.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);
  ::execv(mpi.c_str(), argv.data());
  throw Error("solver.engine = petsc: cannot run " + mpi.string() + ": " + std::strerror(errno), EXIT_INTERNAL);
#else
  (void)args;
  throw Error(
      "solver.engine = petsc: this build has no PETSc engine; install PETSc (Debian: apt-get install "
      "libpetsc-real-dev openmpi-bin, or scripts/install-deps.sh) and rebuild, or use solver.engine = cholmod",
      EXIT_INPUT);
#endif
}

}  // namespace

int exec_petsc_engine(const std::vector<std::string>& args) { exec_petsc_engine_impl(args); }

int cmd_solve(const std::vector<std::string>& args) {
  const SceneArgs a = parse_scene_args(args, {"--magnification"});
  if (a.quiet) set_log_level(LogLevel::WARN);
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<std::string> plot_args = solve_plot_args(a);
  const nlohmann::json scene = load_scene(a.scene, a.overrides);
  // solver.engine = auto: the engine from the scene's numbers (solver/method_choice.hpp). The
  // petsc engine is its own program (before the output folder is locked: it locks it itself).
  const EngineChoice engine = choose_engine(scene, scene_directory(a.scene), petsc_engine_available(), adapt_requested(scene));
  log_engine_choice(engine);
  // stdout's first row, before either engine's summary: which engine, and why (as its "method" row).
  std::fputs(summary_row("engine", describe(engine)).c_str(), stdout);
  if (engine.engine == "petsc") {
    refuse_adaptive_outside_cholmod(scene);
    std::fflush(nullptr);
    return exec_petsc_engine(args);
  }
  refuse_mpi_ranks("solve");  // before the folder: ranks racing for it is what this prevents
  // Held until the program ends: no other run writes into this folder meanwhile.
  const OutputLock lock = prepare_output_dir(a.out, a.force, solve_output_names());
  // adapt.target_error set: the adaptive loop from the scene's mesh (solve_scene). Each certified
  // level is kept as it ends (adapt_levels.json, rewritten whole and atomically, labelled partial
  // until the loop ends): an interrupted or failed run keeps its certified levels.
  const auto keep_levels = [&](const std::vector<AdaptLevel>& levels) {
    const nlohmann::json j = adapt_levels_json(levels, adapt_options_from_scene(scene), /*partial=*/true);
    write_text_file((std::filesystem::path(a.out) / ADAPT_LEVELS_FILE).string(), j.dump(2) + "\n");
  };
  SceneSolve r = solve_scene(scene, scene_directory(a.scene), keep_levels);
  r.solution.timings["wall_total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (r.adapt) {
    const AdaptLevel& last = r.adapt_levels.back();
    std::printf("adapt: %zu levels, %lld dofs, estimate %.3g (target %.3g, %s), %.3g s\n", r.adapt_levels.size(),
                static_cast<long long>(last.dofs), last.estimate, r.adapt->target_error, r.stop_reason.c_str(),
                last.cumulative_seconds);
    if (std::isfinite(last.reference_error))
      std::printf("adapt: error against the reference energy %.3g (efficiency index %.3g)\n", last.reference_error,
                  last.estimate / last.reference_error);
  }
  r.extra["engine_choice"] = engine_choice_json(engine);
  write_solve_results(a, plot_args, r, scene_solve_report(r));
  return solve_exit_code(r);
}

int cmd_backends(const std::vector<std::string>& args) {
  if (!args.empty()) throw UsageError("'backends' takes no arguments");
  for (const auto& [name, doc] : available_backends()) std::printf("%-20s %s\n", name.c_str(), doc.c_str());
  return EXIT_OK;
}

}  // namespace hemicontact::cli
