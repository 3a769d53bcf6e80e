// hemicontact_adapt_study — the numbers of docs/adaptivity.md: the work-precision study (uniform,
// graded, adaptive against one reference; studies/adapt_study.hpp) and the whole-process time to a
// target.
//
//   hemicontact_adapt_study [--scene problems/sofonea2017-fig2.json] [--reference adaptive:0.002]
//                           [--target 0.01] [--repeats 3] [--out DIR] [--set KEY=VALUE ...]
//                           [--no-study]
//
// --set is applied to the study's scene and passed to every timed `solve` (e.g. --set mesh.n=8,
// the initial mesh of docs/adaptivity.md); --no-study times the solve only (part 2, no true error).
// 1. The study, in this process: uniform n = 4..128, graded n = 4..128 (x both, y high, β = 2)
//    and the adaptive sequence from the scene's mesh down to the target, every mesh's true error
//    against the reference, its estimate, efficiency index and certificate; DIR/work_precision.csv
//    and .json, and DIR/work_precision.png (scripts/plot_work_precision.py).
// 2. What a user waits for: `hemicontact solve SCENE --set adapt.target_error=T` with the VTU and
//    CSV off (the answer is report.json), start to exit, in a forked child, --repeats times; the
//    minimum is reported (the machine is shared: the spread is printed too), wall and CPU (the
//    child's user + system time, wait4). The true error of that run's final mesh is the study's
//    adaptive point with the same number of unknowns (the same deterministic sequence); a final
//    step cut by adapt.landing is not in the study's sequence, and its true error is then reported
//    as unknown (null).
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/options.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/studies/adapt_study.hpp>

#include "bench_limits.hpp"
#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace hemicontact;

namespace {

struct ChildTime {
  double wall = 0, cpu = 0;  // seconds: start to exit; user + system of the child
};

ChildTime run_child(const std::vector<std::string>& argv) {
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> a;
    for (const auto& s : argv) a.push_back(const_cast<char*>(s.c_str()));
    a.push_back(nullptr);
    execv(a[0], a.data());
    _exit(127);
  }
  int status = 0;
  struct rusage ru {};
  wait4(pid, &status, 0, &ru);
  ChildTime t;
  t.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t.cpu = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
          1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "adapt_study: %s exited with %d\n", argv[0].c_str(), WEXITSTATUS(status));
    std::exit(1);
  }
  return t;
}

// The command line (USAGE).
struct BenchArgs {
  std::string scene_path = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json";
  std::string out = "out/adapt-study", reference = "adaptive:0.002";
  double target = 0.01;
  int repeats = 3;
  bool study = true, force = false, help = false;
  std::vector<std::string> sets;
};

const char* const USAGE =
    "usage: hemicontact_adapt_study [--scene S] [--reference R] [--target T] [--repeats N] [--out DIR]\n"
    "                               [--set K=V ...] [--no-study] [--force]\n"
    "The work-precision study (DIR/work_precision.csv, .json, .png) and the whole-process time of\n"
    "`hemicontact solve --set adapt.target_error=T` (its last run's results stay in DIR/solve). DIR\n"
    "follows `hemicontact solve --out`'s rules: earlier results replaced only with --force. Exit\n"
    "codes: 0, 1 usage, 2 bad input or output folder.\n";

// The options, checked as `hemicontact`'s are (core/options.hpp): a bad value is a usage error.
BenchArgs parse_bench_args(int argc, char** argv) {
  BenchArgs A;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("option " + k + " needs a value", EXIT_USAGE);
      return argv[++i];
    };
    if (k == "--no-study") A.study = false;
    else if (k == "--force") A.force = true;
    else if (k == "-h" || k == "--help") A.help = true;
    else if (k == "--scene") A.scene_path = value();
    else if (k == "--set") A.sets.push_back(value());
    else if (k == "--out") A.out = value();
    else if (k == "--reference") A.reference = value();
    else if (k == "--target") A.target = parse_positive_option(k, value());
    else if (k == "--repeats") A.repeats = static_cast<int>(parse_integer_option(k, value(), 1, bench::MAX_REPEATS));
    else throw Error("unknown option '" + k + "' (see hemicontact_adapt_study --help)", EXIT_USAGE);
  }
  return A;
}

// 1. The study, in this process: its CSV, its JSON into @p js, and its table on stdout.
WorkPrecisionStudy run_study(const nlohmann::json& scene, const BenchArgs& A, nlohmann::json& js) {
  WorkPrecisionRequest req;
  req.reference = A.reference;
  req.uniform_levels = {4, 8, 16, 32, 64, 128};
  req.graded_levels = {4, 8, 16, 32, 64, 128};
  req.adapt = adapt_options_from_scene(scene);
  req.adapt.target_error = A.target;
  WorkPrecisionStudy st = run_work_precision(scene, scene_directory(A.scene_path), req);
  write_text_file((fs::path(A.out) / "work_precision.csv").string(), work_precision_csv(st));
  js = work_precision_json(st);
  std::printf("reference %s: %lld dofs, its own estimate %.3g\n", st.reference.c_str(),
              static_cast<long long>(st.reference_dofs), st.reference_estimate);
  std::printf("%-9s %6s %9s %9s %10s %10s %10s %8s %9s\n", "family", "level", "dofs", "seconds", "error",
              "corrected", "estimate", "eff.", "cert.");
  for (const StudyPoint& p : st.points)
    std::printf("%-9s %6d %9lld %9.3g %10.4g %10.4g %10.4g %8.3f %9.1e\n", p.family.c_str(), p.level,
                static_cast<long long>(p.dofs), p.seconds, p.error, p.error_corrected, p.estimate, p.efficiency,
                p.certificate);
  for (const char* f : {"uniform", "graded", "adaptive"}) std::printf("%s: error ~ N^%.3f\n", f, st.slope(f));
  return st;
}

// 2. The whole process to the target, start to exit (the scene's own check.smallness), --repeats
// times: js["whole_process"].
void time_whole_process(const BenchArgs& A, const WorkPrecisionStudy& st, nlohmann::json& js) {
  const double target = A.target;
  const int repeats = A.repeats;
  const std::string cli = HEMICONTACT_CLI_PATH;
  std::vector<std::string> argv_solve = {cli, "solve", A.scene_path, "--set",
                                         "adapt.target_error=" + std::to_string(target)};
  for (const std::string& kv : A.sets) argv_solve.insert(argv_solve.end(), {"--set", kv});
  argv_solve.insert(argv_solve.end(), {"--set", "output.vtu=false", "--set", "output.csv=false", "--out",
                                       (fs::path(A.out) / "solve").string(), "--force", "--quiet"});
  std::vector<double> walls, cpus;
  for (int r = 0; r < repeats; ++r) {
    const ChildTime t = run_child(argv_solve);
    walls.push_back(t.wall);
    cpus.push_back(t.cpu);
  }
  std::ifstream rin(fs::path(A.out) / "solve" / "report.json");
  const nlohmann::json rep = nlohmann::json::parse(rin);
  const auto& a = rep.at("adapt");
  const StudyPoint* last = nullptr;
  for (const StudyPoint& p : st.points)
    if (p.family == "adaptive" && p.dofs == a.at("history").back().at("dofs").get<Index>()) last = &p;
  std::sort(walls.begin(), walls.end());
  std::sort(cpus.begin(), cpus.end());
  std::printf("solve --set adapt.target_error=%g: %zu levels, %lld dofs, estimate %.4g, true error %.4g; "
              "whole process %.3f s wall, %.3f s CPU (min of %d; max %.3f s wall, %.3f s CPU)\n",
              target, a.at("history").size(), a.at("history").back().at("dofs").get<long long>(),
              a.at("final_estimate").get<double>(), last ? last->error_corrected : std::nan(""), walls.front(),
              cpus.front(), repeats, walls.back(), cpus.back());
  js["whole_process"] = {{"target", target},
                         {"levels", a.at("history").size()},
                         {"dofs", a.at("history").back().at("dofs")},
                         {"estimate", a.at("final_estimate")},
                         {"true_error", last ? nlohmann::json(last->error_corrected) : nlohmann::json(nullptr)},
                         {"seconds_min", walls.front()},
                         {"seconds_max", walls.back()},
                         {"cpu_seconds_min", cpus.front()},
                         {"cpu_seconds_max", cpus.back()},
                         {"repeats", repeats},
                         {"history", a.at("history")}};
}

int adapt_main(int argc, char** argv) {
  const BenchArgs A = parse_bench_args(argc, argv);
  if (A.help) {
    std::fputs(USAGE, stdout);
    return EXIT_OK;
  }
  set_log_level(LogLevel::WARN);
  // The CLI's folder rules (output/output_dir.hpp) for this program's files; DIR/solve is the timed
  // `hemicontact solve`'s own folder (run with --force), kept: the child names it as its results.
  std::vector<std::string> overrides = {"check.smallness=false"};
  overrides.insert(overrides.end(), A.sets.begin(), A.sets.end());
  const nlohmann::json scene = load_scene(A.scene_path, overrides);  // before the folder, as the CLI
  const OutputLock lock =
      prepare_output_dir(A.out, A.force, {"work_precision.csv", "work_precision.json", "work_precision.png"});
  WorkPrecisionStudy st;
  nlohmann::json js;
  if (A.study) st = run_study(scene, A, js);
  js["scene_file"] = fs::path(A.scene_path).filename().string();
  js["target_error"] = A.target;
  js["set"] = A.sets;
  time_whole_process(A, st, js);
  write_text_file((fs::path(A.out) / "work_precision.json").string(), js.dump(2) + "\n");
  if (A.study) {
    const std::string plot = "/usr/bin/python3 " HEMICONTACT_SOURCE_DIR "/scripts/plot_work_precision.py " +
                             (fs::path(A.out) / "work_precision.csv").string() + " --title fig2";
    record_output_file((fs::path(A.out) / "work_precision.png").string());
    if (std::system(plot.c_str()) != 0) std::fprintf(stderr, "adapt_study: the plot was not drawn\n");
  }
  return EXIT_OK;
}

}  // namespace

int main(int argc, char** argv) {
  install_interrupt_handlers();
  return run_program("hemicontact_adapt_study", [&] { return adapt_main(argc, argv); });
}
