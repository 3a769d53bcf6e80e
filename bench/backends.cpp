// hemicontact_backends — every NLP backend on the same scenes, side by side: what each one did
// (its own iterations, evaluations and time), what the exact solver then did, the whole solve's
// time, and whether the answers agree (energy, u, statuses) with the default solve's.
//
// For each scene the default solve (solver.backend = auto) runs first, then the exact solver's own
// path (solver.exact.start = always, no backend stage), then each backend named (each runs its
// first ε-stage and hands over: the design's path). Each solve is the best of --repeats (the
// answers are deterministic; the best time keeps a preemption on a shared machine out of the
// table). Writes DIR/backends.md (the table docs/backends.md quotes) and DIR/backends.json.
//
//   hemicontact_backends --out docs/backends
//   hemicontact_backends --scenes sofonea2017-fig2.json:mesh.n=64,minima-softening.json --repeats 3 --out DIR
//
// A scene is a file in problems/ (or a path) with optional ':'-separated overrides. The default
// backends are those `hemicontact backends` lists for this engine, less the global searches on
// scenes above 3000 unknowns (refused there) and the petsc engine's.

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/options.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include "bench_limits.hpp"
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace hemicontact;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

std::string g3(double x) {
  if (!std::isfinite(x)) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

struct Row {
  std::string label, solved_by;
  bool ok = false, ran = false;
  SolverWork backend, exact;
  double seconds = NAN, energy = NAN, certificate = NAN, du = NAN, de = NAN;
  int status_diff = -1;
  std::string message;
};

// One run: the best of @p repeats solves, compared with @p reference (the default's answer; the
// first run, r == 0, is the reference itself).
Row run_one(const Model& model, const std::string& label, const SolveOptions& o, int repeats, Solution& reference,
            bool is_reference) {
  Row row;
  row.label = label;
  try {
    Solution best;
    for (int k = 0; k < repeats; ++k) {
      const auto t0 = clk::now();
      Solution s = solve(model, o);
      const double t = since(t0);
      if (k == 0 || t < row.seconds) row.seconds = t, best = std::move(s);
    }
    if (is_reference) reference = best;
    row.ok = best.ok();
    row.ran = best.backend_use.ran;
    row.solved_by = best.solved_by();
    row.backend = best.work_of(best.backend);
    row.exact = best.work_of(EXACT_SOLVER);
    row.exact.seconds = best.handover.seconds;
    row.energy = best.energy;
    row.certificate = best.certificate.max_residual;
    row.du = (best.u - reference.u).cwiseAbs().maxCoeff() / std::max(reference.u.cwiseAbs().maxCoeff(), 1e-300);
    row.de = std::abs(best.energy - reference.energy) / std::max(std::abs(reference.energy), 1e-300);
    row.status_diff = 0;
    for (size_t k = 0; k < best.status.size(); ++k) row.status_diff += best.status[k].str() != reference.status[k].str();
    row.message = best.message;
  } catch (const Error& e) {
    row.message = e.what();
  }
  return row;
}

json row_json(const std::string& spec, const Row& row) {
  return {{"scene", spec},
          {"run", row.label},
          {"solved_by", row.solved_by},
          {"certified", row.ok},
          {"backend_ran", row.ran},
          {"backend_minimizations", row.backend.minimizations},
          {"backend_iterations", row.backend.iterations},
          {"backend_evaluations", row.backend.evaluations},
          {"backend_seconds", row.backend.seconds},
          {"exact_seconds", row.exact.seconds},
          {"seconds", row.seconds},
          {"energy", row.energy},
          {"certificate", row.certificate},
          {"du", row.du},
          {"dE", row.de},
          {"status_diff", row.status_diff},
          {"message", row.message}};
}

// The scene's table (markdown).
std::string scene_table(const std::string& spec, const Model& model, const Solution& reference,
                        const std::vector<Row>& rows) {
  std::ostringstream md;
  const InnerConvexity& c = reference.inner_convexity;
  md << "**" << spec << "** (" << model.dofs.n_free() << " dofs, " << model.contact.size() << " Γ3 nodes; inner "
     << "problem " << (c.checked ? (c.strongly_convex ? "strongly convex" : "not strongly convex") : "not checked")
     << ")\n\n| run | solved by | certified | backend it / ev / s | exact s | total s | energy | Δu | ΔE | statuses |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    md << "| " << r.label << " | " << (r.solved_by.empty() ? "-" : r.solved_by) << " | "
       << (r.ok ? "yes (" + g3(r.certificate) + ")" : "NO") << " | "
       << (r.ran ? std::to_string(r.backend.iterations) + " / " + std::to_string(r.backend.evaluations) + " / " +
                       g3(r.backend.seconds)
                 : std::string("not run"))
       << " | " << g3(r.exact.seconds) << " | " << g3(r.seconds) << " | " << g3(r.energy) << " | " << g3(r.du)
       << " | " << g3(r.de) << " | " << r.status_diff << " |\n";
    if (!r.ok) md << "| | " << r.message.substr(0, 200) << " | | | | | | | | |\n";
  }
  return md.str() + "\n";
}

// The command line (USAGE).
struct BackendsArgs {
  std::vector<std::string> scenes = {"sofonea2017-fig2.json:mesh.n=64", "minima-softening.json:check.smallness=false",
                                     "minima-laminate.json:check.smallness=false"};
  std::vector<std::string> backends;
  std::string out = "out/backends";  // under out/, which git ignores, as `hemicontact solve`'s default
  int repeats = 3;
  bool force = false, help = false;
};

const char* const USAGE =
    "usage: hemicontact_backends [--scenes FILE[:key=value...],...] [--backends a,b,...] [--repeats N]\n"
    "                            [--out DIR] [--force]\n"
    "Every NLP backend on the same scenes; writes DIR/backends.md and DIR/backends.json (DIR follows\n"
    "`hemicontact solve --out`'s rules: earlier results replaced only with --force). Exit codes: 0, 1\n"
    "usage, 2 bad input or output folder, 3 a run not certified.\n";

BackendsArgs parse_backends_args(int argc, char** argv) {
  BackendsArgs A;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("option " + a + " needs a value", EXIT_USAGE);
      return argv[++i];
    };
    if (a == "--scenes") A.scenes = split(next(), ',');
    else if (a == "--backends") A.backends = split(next(), ',');
    else if (a == "--out") A.out = next();
    else if (a == "--repeats") A.repeats = static_cast<int>(parse_integer_option(a, next(), 1, bench::MAX_REPEATS));
    else if (a == "--force") A.force = true;
    else if (a == "-h" || a == "--help") A.help = true;
    else throw Error("unknown option '" + a + "' (see hemicontact_backends --help)", EXIT_USAGE);
  }
  if (A.scenes.empty()) throw Error("--scenes: no scene given", EXIT_USAGE);
  return A;
}

// A --scenes entry FILE[:key=value...]: the file (as given, else in problems/) and its scene.
json scene_of(const std::string& spec, std::string& path) {
  const std::vector<std::string> parts = split(spec, ':');
  path = fs::exists(parts.front()) ? parts.front() : std::string(HEMICONTACT_SOURCE_DIR "/problems/") + parts.front();
  return load_scene(path, std::vector<std::string>(parts.begin() + 1, parts.end()));
}

// One scene's runs (the default, the exact solver's path, each backend) into @p md and @p all;
// @return how many were not certified.
int compare_on_scene(const std::string& spec, const BackendsArgs& A, std::ostringstream& md, json& all) {
  std::string path;
  const json scene = scene_of(spec, path);
  const Model model = build_model(scene, fs::path(path).parent_path().string());
  const SolveOptions base = solve_options_from_scene(scene);
  std::vector<std::pair<std::string, SolveOptions>> runs{{"auto (default)", base}, {"exact", base}};
  runs[1].second.exact_start = "always";
  for (const std::string& b : A.backends) {
    runs.emplace_back(b, base);
    runs.back().second.backend = b;
  }
  Solution reference;
  std::vector<Row> rows;
  int failures = 0;
  for (size_t r = 0; r < runs.size(); ++r) {
    std::cerr << spec << ": " << runs[r].first << "\n";
    rows.push_back(run_one(model, runs[r].first, runs[r].second, A.repeats, reference, r == 0));
    failures += !rows.back().ok;
    all.push_back(row_json(spec, rows.back()));
  }
  md << scene_table(spec, model, reference, rows);
  return failures;
}

int backends_main(int argc, char** argv) {
  BackendsArgs A = parse_backends_args(argc, argv);
  if (A.help) {
    std::fputs(USAGE, stdout);
    return EXIT_OK;
  }
  if (A.backends.empty())
    for (const auto& [name, doc] : available_backends())
      if (name != AUTO_BACKEND && name != "ssn" && name.rfind("tao:", 0) != 0) A.backends.push_back(name);
  set_log_level(LogLevel::QUIET);
  // Every scene read before the folder is touched, as the CLI does: a bad one leaves nothing.
  for (const std::string& spec : A.scenes) {
    std::string path;
    (void)scene_of(spec, path);
  }
  // The CLI's folder rules (output/output_dir.hpp): no link followed, earlier results only with --force.
  const OutputLock lock = prepare_output_dir(A.out, A.force, {"backends.md", "backends.json"});
  std::ostringstream md;
  json all = json::array();
  int failures = 0;
  md << "Generated by `hemicontact_backends --repeats " << A.repeats << "` (bench/backends.cpp). Per scene: the default "
     << "solve (`auto`), the exact solver's own path (`exact`: solver.exact.start = always), then each backend "
        "named (its first ε-stage, then the exact solver). `backend it / ev / s`: the backend's own iterations, "
        "evaluations and seconds; `exact s`: the exact solver's; `total s`: the whole solve (best of "
     << A.repeats << "); `Δu`, `ΔE`: relative distance to the default's displacement and energy; `statuses`: nodes "
        "whose status differs from the default's.\n\n";
  for (const std::string& spec : A.scenes) failures += compare_on_scene(spec, A, md, all);
  write_text_file((fs::path(A.out) / "backends.md").string(), md.str());
  write_text_file((fs::path(A.out) / "backends.json").string(), all.dump(2) + "\n");
  std::cout << md.str();
  // A comparison in which a backend failed to certify is reported, and the exit status says so.
  if (failures > 0) std::cerr << "hemicontact_backends: " << failures << " run(s) not certified\n";
  return failures > 0 ? EXIT_NOT_CONVERGED : EXIT_OK;
}

}  // namespace

int main(int argc, char** argv) {
  install_interrupt_handlers();
  return run_program("hemicontact_backends", [&] { return backends_main(argc, argv); });
}
