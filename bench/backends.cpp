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
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

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

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes = {"sofonea2017-fig2.json:mesh.n=64", "minima-softening.json:check.smallness=false",
                                     "minima-laminate.json:check.smallness=false"};
  std::vector<std::string> backends;
  std::string out = "backends";
  int repeats = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << a << " needs a value\n";
        std::exit(1);
      }
      return argv[++i];
    };
    if (a == "--scenes") scenes = split(next(), ',');
    else if (a == "--backends") backends = split(next(), ',');
    else if (a == "--out") out = next();
    else if (a == "--repeats") repeats = std::max(1, std::stoi(next()));
    else {
      std::cerr << "usage: hemicontact_backends [--scenes FILE[:key=value...],...] [--backends a,b,...] "
                   "[--repeats N] [--out DIR]\n";
      return 1;
    }
  }
  if (backends.empty())
    for (const auto& [name, doc] : available_backends())
      if (name != AUTO_BACKEND && name != "ssn" && name.rfind("tao:", 0) != 0) backends.push_back(name);
  set_log_level(LogLevel::QUIET);
  fs::create_directories(out);
  std::ostringstream md;
  json all = json::array();
  int failures = 0;
  md << "Generated by `hemicontact_backends --repeats " << repeats << "` (bench/backends.cpp). Per scene: the default "
     << "solve (`auto`), the exact solver's own path (`exact`: solver.exact.start = always), then each backend "
        "named (its first ε-stage, then the exact solver). `backend it / ev / s`: the backend's own iterations, "
        "evaluations and seconds; `exact s`: the exact solver's; `total s`: the whole solve (best of "
     << repeats << "); `Δu`, `ΔE`: relative distance to the default's displacement and energy; `statuses`: nodes "
        "whose status differs from the default's.\n\n";
  for (const std::string& spec : scenes) {
    const std::vector<std::string> parts = split(spec, ':');
    const std::string path = fs::exists(parts.front()) ? parts.front()
                                                       : std::string(HEMICONTACT_SOURCE_DIR "/problems/") + parts.front();
    const json scene = load_scene(path, std::vector<std::string>(parts.begin() + 1, parts.end()));
    const Model model = build_model(scene, fs::path(path).parent_path().string());
    const SolveOptions base = solve_options_from_scene(scene);
    std::vector<std::pair<std::string, SolveOptions>> runs{{"auto (default)", base}, {"exact", base}};
    runs[1].second.exact_start = "always";
    for (const std::string& b : backends) {
      runs.emplace_back(b, base);
      runs.back().second.backend = b;
    }
    Solution reference;
    std::vector<Row> rows;
    for (size_t r = 0; r < runs.size(); ++r) {
      std::cerr << spec << ": " << runs[r].first << "\n";
      rows.push_back(run_one(model, runs[r].first, runs[r].second, repeats, reference, r == 0));
      failures += !rows.back().ok;
      all.push_back(row_json(spec, rows.back()));
    }
    md << scene_table(spec, model, reference, rows);
  }
  std::ofstream(fs::path(out) / "backends.md") << md.str();
  std::ofstream(fs::path(out) / "backends.json") << all.dump(2) << "\n";
  std::cout << md.str();
  // A comparison in which a backend failed to certify is reported, and the exit status says so.
  if (failures > 0) std::cerr << "hemicontact_backends: " << failures << " run(s) not certified\n";
  return failures > 0 ? 3 : 0;
}
