// hemicontact_bench3d — a large 3D contact solve against the linear elastic solve of the same mesh.
//
// Two phases, each in its own forked child so that its peak memory (wait4's ru_maxrss) is its own:
//   linear:  build the model, one SparseCholesky analyze + factorize + solve of K_x u = f_x
//            (the cheapest solve the mesh admits);
//   contact: build the model, hemicontact::solve (condensation onto Γ3, the NLP backend with
//            ε-continuation and the outer fixed point, polish, certificate).
// The scene is problems/sofonea2017-3d.json (or --scene) on a box of nx × ny × nz cells
// (mesh.nx/ny/nz overrides); any other `--set path=value` is applied as in `hemicontact solve`.
// Output: one line per phase on stdout and DIR/bench3d.json (--out) with every number.
//
//   hemicontact_bench3d --nx 40 --ny 40 --nz 200 --backend newton --out /tmp/b3d
//   hemicontact_bench3d --nx 12 --ny 12 --nz 12 --phases contact --set solver.polish=false

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace hemicontact;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

using clk = std::chrono::steady_clock;
double since(clk::time_point t0) { return std::chrono::duration<double>(clk::now() - t0).count(); }

struct Args {
  std::string scene = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json";
  int nx = 40, ny = 40, nz = 200;
  std::string backend = "newton";
  std::vector<std::string> overrides;
  std::vector<std::string> phases = {"linear", "contact"};
  std::string out = "out/bench3d";  // under out/, which git ignores, as `hemicontact solve`'s default
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "hemicontact_bench3d: %s\nusage: hemicontact_bench3d [--scene FILE] [--nx N] [--ny N] [--nz N] "
               "[--backend NAME] [--set path=value]... [--phases linear,contact] [--out DIR]\n",
               why.c_str());
  std::exit(EXIT_USAGE);
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (i + 1 >= argc) usage("missing value after " + k);
    const std::string v = argv[++i];
    if (k == "--scene")
      a.scene = v;
    else if (k == "--nx")
      a.nx = std::stoi(v);
    else if (k == "--ny")
      a.ny = std::stoi(v);
    else if (k == "--nz")
      a.nz = std::stoi(v);
    else if (k == "--backend")
      a.backend = v;
    else if (k == "--set")
      a.overrides.push_back(v);
    else if (k == "--out")
      a.out = v;
    else if (k == "--phases") {
      a.phases.clear();
      std::stringstream ss(v);
      for (std::string p; std::getline(ss, p, ',');) {
        if (p != "linear" && p != "contact") usage("unknown phase '" + p + "'");
        a.phases.push_back(p);
      }
    } else
      usage("unknown option " + k);
  }
  return a;
}

json load(const Args& a) {
  // mesh.n (set in the scene) would override nx, ny, nz.
  std::vector<std::string> o = {"mesh.n=null", "mesh.nx=" + std::to_string(a.nx), "mesh.ny=" + std::to_string(a.ny),
                                "mesh.nz=" + std::to_string(a.nz), "solver.backend=" + a.backend};
  o.insert(o.end(), a.overrides.begin(), a.overrides.end());
  return load_scene(a.scene, o);
}

// One phase in this (child) process; returns its stats.
json run_phase(const Args& a, const std::string& phase) {
  const json scene = load(a);
  json st;
  auto t0 = clk::now();
  const Model md = build_model(scene, fs::path(a.scene).parent_path().string());
  st["build_s"] = since(t0);
  st["dofs"] = md.dofs.n_free();
  st["gamma3_nodes"] = md.contact.size();
  for (const auto& [k, v] : md.timings) st["model_timings"][k] = v;
  if (phase == "linear") {
    t0 = clk::now();
    SparseCholesky chol;
    chol.compute(md.Kx.lower());
    const Vec y = chol.solve(md.fx);
    st["solve_s"] = since(t0);
    st["analyze_s"] = chol.analyze_seconds();
    st["factorize_s"] = chol.factorize_seconds();
    if (!y.allFinite()) throw Error("linear elastic solve: non-finite solution", EXIT_NOT_CONVERGED);
    return st;
  }
  const SolveOptions opt = solve_options_from_scene(scene);
  t0 = clk::now();
  const Solution sol = solve(md, opt);
  st["solve_s"] = since(t0);
  for (const auto& [k, v] : sol.timings) st["solve_timings"][k] = v;
  // The backend's own work, and what produced the answer (the exact solver's inner solves are not it).
  const SolverWork w = sol.work_of(sol.backend);
  st["backend_iterations"] = w.iterations;
  st["minimizations"] = w.minimizations;
  st["solved_by"] = sol.solved_by();
  st["certificate"] = sol.certificate.max_residual;
  st["ok"] = sol.ok();
  st["polish"] = {{"accepted", sol.polish.accepted}, {"before", sol.polish.before}, {"after", sol.polish.after}};
  st["status_counts"] = sol.status_counts();
  st["formulation"] = sol.formulation;
  return st;
}

}  // namespace

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  fs::create_directories(a.out);
  json all;
  all["scene"] = a.scene;
  all["cells"] = {a.nx, a.ny, a.nz};
  all["backend"] = a.backend;
  all["overrides"] = a.overrides;
  bool failed = false;
  for (const auto& phase : a.phases) {
    const std::string file = (fs::path(a.out) / (phase + ".json")).string();
    std::fflush(nullptr);
    const auto t0 = clk::now();
    const pid_t pid = ::fork();
    if (pid < 0) usage("fork failed");
    if (pid == 0) {
      int code = 0;
      try {
        std::ofstream(file) << run_phase(a, phase).dump(2) << "\n";
      } catch (const Error& e) {
        std::fprintf(stderr, "hemicontact_bench3d: %s: %s\n", phase.c_str(), e.what());
        code = e.code();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "hemicontact_bench3d: %s: %s\n", phase.c_str(), e.what());
        code = EXIT_INTERNAL;
      }
      std::fflush(nullptr);
      ::_exit(code);
    }
    int status = 0;
    rusage ru{};
    ::wait4(pid, &status, 0, &ru);
    // A failed phase wrote nothing (or a stale file from an earlier run): only a child that exited 0
    // has results; the run then fails loudly below instead of reporting another run's numbers.
    json st = json::object();
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (std::ifstream f(file); f && ok) st = json::parse(f, nullptr, false);
    if (st.is_discarded()) st = json::object();
    failed = failed || !ok;
    st["wall_s"] = since(t0);
    st["peak_rss_mb"] = static_cast<double>(ru.ru_maxrss) / 1024.0;  // Linux: kilobytes
    st["user_s"] = ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec;
    st["exit"] = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    all[phase] = st;
    std::printf("%-8s dofs %s, gamma3 %s: wall %.2f s (build %.2f, solve %.2f), peak RSS %.0f MB%s\n", phase.c_str(),
                st.value("dofs", json()).dump().c_str(), st.value("gamma3_nodes", json()).dump().c_str(),
                st["wall_s"].get<double>(), st.value("build_s", 0.0), st.value("solve_s", 0.0),
                st["peak_rss_mb"].get<double>(),
                st.contains("certificate")
                    ? (", certificate " + st["certificate"].dump() + ", solved by " + st.value("solved_by", "?")).c_str()
                    : "");
  }
  std::ofstream(fs::path(a.out) / "bench3d.json") << all.dump(2) << "\n";
  std::printf("results in %s/bench3d.json\n", a.out.c_str());
  if (failed) std::fprintf(stderr, "hemicontact_bench3d: a phase failed (its message above)\n");
  return failed ? EXIT_NOT_CONVERGED : 0;
}
