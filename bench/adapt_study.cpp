// hemicontact_adapt_study — issue 17's numbers: the work-precision study (uniform, graded,
// adaptive against one reference; driver/adapt_study.hpp) and the whole-process time to a target.
//
//   hemicontact_adapt_study [--scene problems/sofonea2017-fig2.json] [--reference adaptive:0.002]
//                           [--target 0.01] [--repeats 3] [--out DIR]
//
// 1. The study, in this process: uniform n = 4..128, graded n = 4..128 (x both, y high, β = 2)
//    and the adaptive sequence from the scene's mesh down to the target, every mesh's true error
//    against the reference, its estimate, efficiency index and certificate; DIR/work_precision.csv
//    and .json, and DIR/work_precision.png (scripts/plot_work_precision.py).
// 2. What a user waits for: `hemicontact solve SCENE --set adapt.target_error=T` with the VTU and
//    CSV off (the answer is report.json), start to exit, in a forked child, --repeats times; the
//    minimum is reported (the machine is shared: the spread is printed too). The true error of that
//    run's final mesh is the study's adaptive point where the estimate first reached T (the same
//    deterministic sequence).
#include <hemicontact/driver/adapt_study.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/scene/config.hpp>

#include <nlohmann/json.hpp>

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

double run_child(const std::vector<std::string>& argv) {
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
  waitpid(pid, &status, 0);
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "adapt_study: %s exited with %d\n", argv[0].c_str(), WEXITSTATUS(status));
    std::exit(1);
  }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json";
  std::string out = "out/adapt-study", reference = "adaptive:0.002";
  double target = 0.01;
  int repeats = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--scene") scene_path = v;
    else if (k == "--out") out = v;
    else if (k == "--reference") reference = v;
    else if (k == "--target") target = std::stod(v);
    else if (k == "--repeats") repeats = std::stoi(v);
    else {
      std::fprintf(stderr, "usage: %s [--scene S] [--reference R] [--target T] [--repeats N] [--out DIR]\n", argv[0]);
      return 1;
    }
  }
  try {
    set_log_level(LogLevel::WARN);
    fs::create_directories(out);
    const nlohmann::json scene = load_scene(scene_path, {"check.smallness=false"});
    WorkPrecisionRequest req;
    req.reference = reference;
    req.uniform_levels = {4, 8, 16, 32, 64, 128};
    req.graded_levels = {4, 8, 16, 32, 64, 128};
    req.adapt = adapt_options_from_scene(scene);
    req.adapt.target_error = target;
    const WorkPrecisionStudy st = run_work_precision(scene, scene_directory(scene_path), req);
    std::ofstream(fs::path(out) / "work_precision.csv") << work_precision_csv(st);
    nlohmann::json js = work_precision_json(st);
    js["scene_file"] = fs::path(scene_path).filename().string();
    js["target_error"] = target;

    std::printf("reference %s: %lld dofs, its own estimate %.3g\n", st.reference.c_str(),
                static_cast<long long>(st.reference_dofs), st.reference_estimate);
    std::printf("%-9s %6s %9s %9s %10s %10s %10s %8s %9s\n", "family", "level", "dofs", "seconds", "error",
                "corrected", "estimate", "eff.", "cert.");
    for (const StudyPoint& p : st.points)
      std::printf("%-9s %6d %9lld %9.3g %10.4g %10.4g %10.4g %8.3f %9.1e\n", p.family.c_str(), p.level,
                  static_cast<long long>(p.dofs), p.seconds, p.error, p.error_corrected, p.estimate, p.efficiency,
                  p.certificate);
    for (const char* f : {"uniform", "graded", "adaptive"}) std::printf("%s: error ~ N^%.3f\n", f, st.slope(f));

    // 2. The whole process to the target, start to exit.
    const std::string cli = HEMICONTACT_CLI_PATH;
    std::vector<double> times;
    for (int r = 0; r < repeats; ++r)
      times.push_back(run_child({cli, "solve", scene_path, "--set", "adapt.target_error=" + std::to_string(target),
                                 "--set", "output.vtu=false", "--set", "output.csv=false", "--out",
                                 (fs::path(out) / "solve").string(), "--force", "--quiet"}));
    std::ifstream rin(fs::path(out) / "solve" / "report.json");
    const nlohmann::json rep = nlohmann::json::parse(rin);
    const auto& a = rep.at("adapt");
    const StudyPoint* last = nullptr;
    for (const StudyPoint& p : st.points)
      if (p.family == "adaptive" && p.dofs == a.at("history").back().at("dofs").get<Index>()) last = &p;
    std::sort(times.begin(), times.end());
    std::printf("solve --set adapt.target_error=%g: %zu levels, %lld dofs, estimate %.4g, true error %.4g; "
                "whole process %.3f s (min of %d; max %.3f s)\n",
                target, a.at("history").size(), a.at("history").back().at("dofs").get<long long>(),
                a.at("final_estimate").get<double>(), last ? last->error_corrected : std::nan(""), times.front(), repeats,
                times.back());
    js["whole_process"] = {{"target", target},
                           {"levels", a.at("history").size()},
                           {"dofs", a.at("history").back().at("dofs")},
                           {"estimate", a.at("final_estimate")},
                           {"true_error", last ? nlohmann::json(last->error_corrected) : nlohmann::json(nullptr)},
                           {"seconds_min", times.front()},
                           {"seconds_max", times.back()},
                           {"repeats", repeats},
                           {"history", a.at("history")}};
    std::ofstream(fs::path(out) / "work_precision.json") << js.dump(2) << '\n';
    fs::remove_all(fs::path(out) / "solve");
    const std::string plot = "/usr/bin/python3 " HEMICONTACT_SOURCE_DIR "/scripts/plot_work_precision.py " +
                             (fs::path(out) / "work_precision.csv").string() + " --title fig2";
    if (std::system(plot.c_str()) != 0) std::fprintf(stderr, "adapt_study: the plot was not drawn\n");
  } catch (const Error& e) {
    std::fprintf(stderr, "adapt_study: %s\n", e.what());
    return e.code();
  }
  return 0;
}
