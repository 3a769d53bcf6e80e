// hemicontact minima — the distinct solutions of a scene where the smallness condition (21) fails.
//
// Sample runs:
//   hemicontact minima problems/minima-softening.json --starts 16 --seed 3
//   hemicontact minima problems/minima-laminate.json --backends ipopt,newton --out out/laminate
//   hemicontact minima problems/minima-one-node.json --start my-start.json   (or a report.json)
//
// When (21) fails, the discrete problem (22) — min Π_λ(u) = ½a(u,u) − f(u) + Σ w j_ν(u_ν) +
// Σ w λ |u_τ| subject to u_ν ≤ g, λ = F_b(u_ν) — may have several solutions, and a local solver
// returns the one whose basin holds its start. This command solves from many starts (zero, all
// at g, all separated, random in a box, a load path up and down, the user's), keeps the results
// that pass the certificate (docs/model.md §4), groups them by energy-norm distance, and classifies
// each distinct solution as a local minimum or a saddle by a second-order check on the free
// subspace (studies/minima.hpp). Output: a table on stdout, DIR/minima.csv, DIR/minima.json,
// DIR/solution_<k>.vtu per distinct solution (k as in the table, lowest energy first), and
// DIR/minima.png (Γ3 profiles of u_ν and σ_ν per solution, scripts/plot_minima.py; without
// matplotlib a warning, not a failure). Exit code 0 when at least one certified solution was
// found, 3 when no run converged, 4 when runs converged but none certified.
#include "cli.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/options.hpp>
#include <hemicontact/core/text.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/study_writers.hpp>
#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/config.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/engine_choice.hpp>
#include <hemicontact/studies/barriers.hpp>
#include <hemicontact/studies/study_json.hpp>
#include <hemicontact/studies/minima.hpp>
#include <hemicontact/studies/petsc_process.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace hemicontact::cli {
namespace {


// The command's own options (--starts, --seed, ...) into @p mo; the --start files into @p start_files.
void parse_minima_options(const SceneArgs& a, MinimaOptions& mo, std::vector<std::string>& start_files) {
  for (const auto& [key, value] : a.extra) {
    if (key == "--starts")
      mo.starts = static_cast<int>(parse_integer_option(key, value, 0, MAX_STARTS));
    else if (key == "--seed")
      mo.seed = static_cast<unsigned>(parse_integer_option(key, value, 0, MINIMA_MAX_SEED));
    else if (key == "--group-tol")
      mo.group_tol = parse_positive_option(key, value);
    else if (key == "--box")
      mo.box = parse_positive_option(key, value);
    else if (key == "--load-path-steps")
      mo.load_path_steps = static_cast<int>(parse_integer_option(key, value, 0, MINIMA_MAX_LOAD_PATH_STEPS));
    else if (key == "--max-starts")
      mo.max_starts = static_cast<int>(parse_integer_option(key, value, 1, MAX_STARTS));
    else if (key == "--start")
      start_files.push_back(value);
    else if (key == "--backends") {
      mo.backends.clear();
      std::stringstream ss(value);
      for (std::string b; std::getline(ss, b, ',');)
        if (!b.empty()) mo.backends.push_back(b);
      if (mo.backends.empty()) throw UsageError("--backends: expected a comma-separated list, got '" + value + "'");
    }
  }
}

// The starts in the --start files (Γ3 values, or a report.json) into mo.user_starts.
void read_start_files(const std::vector<std::string>& start_files, const Model& md, MinimaOptions& mo) {
  for (const auto& f : start_files) {
    if (std::filesystem::is_directory(f)) input_error("--start '" + f + "': is a directory, not a start file");
    std::ifstream in(f);
    if (!in) input_error("--start '" + f + "': cannot read the file");
    nlohmann::json js;
    try {
      js = nlohmann::json::parse(in);
    } catch (const nlohmann::json::parse_error& e) {
      input_error("--start '" + f + "': " + printable(e.what()));
    } catch (const nlohmann::json::exception& e) {
      // out_of_range.406: a number beyond the double range (1e400); JSON has no inf
      input_error("--start '" + f + "': " + e.what() + " (start values must be finite numbers)");
    }
    for (Vec& v : read_gamma3_starts(js, md, "--start '" + f + "'")) mo.user_starts.push_back(std::move(v));
  }
}

// solution_<k>.vtu per distinct solution and minima.pvd, the steps of one collection.
void write_minima_vtus(const std::filesystem::path& out, const nlohmann::json& scene, const Model& md,
                       const MinimaReport& r) {
  const VtuFormat vtu_format =
      scene.at("output").at("vtu_format").get<std::string>() == "ascii" ? VtuFormat::ASCII : VtuFormat::BINARY;
  std::vector<std::pair<double, std::string>> vtus;
  for (size_t k = 0; k < r.solutions.size(); ++k) {
    const std::string file = "solution_" + std::to_string(k) + ".vtu";
    write_vtu((out / file).string(), md, r.solutions[k].solution, vtu_format);
    vtus.emplace_back(static_cast<double>(k), file);
  }
  // The distinct solutions, lowest energy first, as the steps of one collection.
  if (!vtus.empty()) write_pvd((out / "minima.pvd").string(), vtus);
}

// minima.png: the Γ3 profile of each solution; nothing to draw without Γ3 (or solutions).
void draw_minima_plot(const std::filesystem::path& out, const std::string& name, const Model& md,
                      const MinimaReport& r) {
  if (md.contact.size() == 0)
    log_info() << "minima: no Gamma3 nodes, so no minima.png (the problem is linear elasticity: one solution)";
  else if (!r.solutions.empty()) {
    const int code = run_plot_script(
        "plot_minima.py", {(out / "minima.json").string(), "--out", (out / "minima.png").string(), "--title", name},
        (out / "minima.png").string());
    // The scripts exit with 2 exactly when matplotlib is missing (after saying so themselves).
    if (code != 0)
      log_warn() << "minima: " << (out / "minima.png").string() << " was not drawn"
                 << (code == 2 ? " (needs /usr/bin/python3 with matplotlib)" : "")
                 << "; the table, CSV, JSON and VTU files are written";
  }
  if (std::filesystem::exists(out / "minima.png")) record_output_file((out / "minima.png").string());
}

// barriers.csv, saddle_<k>.vtu per verified saddle (k: the row), and the JSON for minima.json.
nlohmann::json write_barriers(const std::filesystem::path& out, const nlohmann::json& scene, const Model& md,
                              const SolveOptions& opt, const std::vector<Barrier>& bars) {
  const VtuFormat fmt_vtu =
      scene.at("output").at("vtu_format").get<std::string>() == "ascii" ? VtuFormat::ASCII : VtuFormat::BINARY;
  std::ostringstream csv;
  csv << "k,a,b,side,lambda,neighbours,verified,energy_min,energy_saddle,barrier,residual,negative_eigenvalues,vtu\n";
  nlohmann::json js = nlohmann::json::array();
  for (size_t k = 0; k < bars.size(); ++k) {
    const Barrier& b = bars[k];
    std::string vtu;
    if (b.from_a.verified) {
      vtu = "saddle_" + std::to_string(k) + ".vtu";
      write_vtu((out / vtu).string(), md, state_of_gamma3(md, opt, b.from_a.saddle), fmt_vtu);
    }
    for (const BarrierSide* s : {&b.from_a, &b.from_b})
      csv << k << ',' << b.a << ',' << b.b << ',' << s->minimum << ",\"" << s->lambda << "\"," << s->neighbours << ','
          << s->verified << ',' << round_trip(s->energy_min) << ',' << round_trip(s->energy_saddle) << ','
          << round_trip(s->barrier) << ',' << round_trip(s->residual) << ',' << s->negative << ',' << vtu << '\n';
    nlohmann::json j = barrier_json(b);
    j["vtu"] = vtu;
    js.push_back(std::move(j));
  }
  write_text_file((out / "barriers.csv").string(), csv.str());
  return js;
}

// The barrier table on stdout.
void print_barriers(const std::vector<Barrier>& bars) {
  std::printf("barriers (string method on the condensed Gamma3 unknowns, lambda frozen; saddles refined and verified):\n");
  std::printf("  %-6s %-18s %-10s %-14s %-14s %s\n", "pair", "saddle energy", "verified", "barrier from a",
              "barrier from b", "lambda");
  for (const Barrier& b : bars) {
    const std::string pair = std::to_string(b.a) + "-" + std::to_string(b.b);
    const bool ok = b.from_a.verified && b.from_b.verified;
    std::printf("  %-6s %-18s %-10s %-14s %-14s %s\n", pair.c_str(), fmt(b.from_a.energy_saddle, 10).c_str(),
                ok ? "yes" : "NO", fmt(b.from_a.barrier, 6).c_str(), fmt(b.from_b.barrier, 6).c_str(),
                b.from_a.lambda == b.from_b.lambda ? b.from_a.lambda.c_str() : "each side at its own minimum's lambda");
    if (!ok) std::printf("         %s %s\n", b.from_a.note.c_str(), b.from_b.note.c_str());
    if (!b.from_a.neighbours)
      std::printf("         not neighbours: the path runs through %d intermediate minimum/minima; %zu saddle(s) on it, "
                  "the highest is the barrier\n", b.from_a.intermediate, b.from_a.saddles.size());
    if (b.from_a.energy_saddle != b.from_b.energy_saddle)
      std::printf("         saddle energy from b's side: %s\n", fmt(b.from_b.energy_saddle, 10).c_str());
  }
}

void draw_barrier_plot(const std::filesystem::path& out, const std::string& name) {
  const std::string png = (out / "barriers.png").string();
  const int code = run_plot_script("plot_barriers.py", {(out / "minima.json").string(), "--out", png, "--title", name}, png);
  if (code != 0) log_warn() << "minima: " << png << " was not drawn; barriers.csv and minima.json have the profiles";
  if (std::filesystem::exists(out / "barriers.png")) record_output_file(png);
}

// One line on stdout: how many distinct solutions the random starts have not reached yet.
void print_unseen(const UnseenEstimate& e, const MinimaOptions& mo) {
  if (e.samples == 0) {
    std::printf("unseen solutions: no certified random start, no estimate (--starts N)\n");
    return;
  }
  std::printf("random starts: %d certified reached %d distinct solution(s), %d of them once, %d twice; "
              "Chao1 estimate %.2f [%.2f, %.2f] (95%%): %.2f unseen\n",
              e.samples, e.observed, e.f1, e.f2, e.chao1, e.lo, e.hi, e.unseen);
  if (mo.until_complete)
    std::printf("--until-complete: %s after %d random starts per backend\n",
                e.complete ? "fewer than one unseen solution estimated" : "stopped at --max-starts, estimate not below one",
                e.random_starts);
}

// The command's flags without a value (--until-complete, --barriers) taken out of @p all_args;
// the rest, for the scene parser, into @p args.
void take_minima_flags(const std::vector<std::string>& all_args, std::vector<std::string>& args, bool& until_complete,
                       bool& barriers) {
  for (size_t i = 0; i < all_args.size(); ++i) {
    if (all_args[i] == "--until-complete")
      until_complete = true;
    else if (all_args[i] == "--barriers")
      barriers = true;
    else
      args.push_back(all_args[i]);
    if (all_args[i] == "--set" && i + 1 < all_args.size()) args.push_back(all_args[++i]);  // a value, never a flag
  }
}

// The stdout summary: the table, the unseen estimate, the barriers.
void print_minima_summary(const std::string& name, const MinimaReport& r, const std::vector<Barrier>* bars) {
  std::printf("%s: distinct solutions (lowest energy first)\n", name.c_str());
  std::fputs(minima_table(r).c_str(), stdout);
  print_unseen(r.unseen, r.options);
  if (bars) print_barriers(*bars);
}

// 0 when a certified solution was found; else 4 if some run converged, 3 if none did.
int minima_exit_code(const MinimaReport& r) {
  if (!r.solutions.empty()) return EXIT_OK;
  const bool any_converged = std::any_of(r.runs.begin(), r.runs.end(), [](const MinimaRun& run) { return run.converged; });
  std::fprintf(stderr, "hemicontact: minima: no run gave a certified solution\n");
  return any_converged ? EXIT_CERTIFICATE : EXIT_NOT_CONVERGED;
}

}  // namespace

int cmd_minima(const std::vector<std::string>& all_args) {
  refuse_mpi_ranks("minima");
  std::vector<std::string> args;
  bool until_complete = false, barriers = false;
  take_minima_flags(all_args, args, until_complete, barriers);
  SceneArgs a = parse_scene_args(args, {"--starts", "--seed", "--backends", "--start", "--group-tol",
                                        "--load-path-steps", "--box", "--max-starts"});
  const std::string name = std::filesystem::path(a.scene).stem().string();
  if (std::find(args.begin(), args.end(), "--out") == args.end()) a.out = "out/" + name + "-minima";
  if (a.quiet) set_log_level(LogLevel::WARN);
  MinimaOptions mo;
  std::vector<std::string> start_files;
  parse_minima_options(a, mo, start_files);
  mo.until_complete = until_complete;
  if (until_complete && mo.max_starts < mo.starts)
    throw UsageError("--max-starts: must be at least --starts (" + std::to_string(mo.starts) + "), the batch size");

  require_utf8_scene_name(a.scene, "minima.json");
  const nlohmann::json scene = load_scene(a.scene, a.overrides);
  const EngineChoice engine =
      minima_engine(scene, scene_directory(a.scene), petsc_engine_available(), !mo.backends.empty(), barriers);
  log_engine_choice(engine);
  const Model md = build_model(scene, scene_directory(a.scene));
  read_start_files(start_files, md, mo);
  if (barriers) require_barrier_scene(md);  // before the search, not after it
  // solution_<k>.vtu (saddle_<k>.vtu): one per distinct solution (verified saddle), known at the end.
  const OutputLock lock = prepare_output_dir(
      a.out, a.force, {"minima.csv", "minima.json", "minima.png", "minima.pvd", "minima-runs.csv", "barriers.csv", "barriers.png"},
      {{"solution_", ".vtu"}, {"saddle_", ".vtu"}});
  const std::filesystem::path out(a.out);

  const SolveOptions opt = solve_options_from_scene(scene);
  if (engine.engine == "petsc") petsc_minima_starts(scene, scene_directory(a.scene), opt, mo);
  // Each finished run is kept as it ends: an interrupted search loses only the run it was in, and
  // the interrupt message names minima-runs.csv.
  mo.on_run = [&](const std::vector<MinimaRun>& runs) {
    write_minima_runs_csv((out / "minima-runs.csv").string(), runs);
  };
  const MinimaReport r = find_minima(md, opt, mo);

  nlohmann::json js = minima_json(md, r);
  js["unseen"] = unseen_json(r.unseen, r.options);
  std::vector<Barrier> bars;
  if (barriers) {
    bars = find_barriers(md, opt, r, BarrierOptions{});
    js["barriers"] = write_barriers(out, scene, md, opt, bars);
  }
  js["name"] = name;
  js["scene_file"] = a.scene;
  js["scene"] = scene;
  js["engine_choice"] = engine_choice_json(engine);
  write_minima_csv((out / "minima.csv").string(), r);
  write_minima_vtus(out, scene, md, r);
  // minima.json last of the set: it marks the search complete (and the picture is drawn from it).
  write_text_file((out / "minima.json").string(), js.dump(2) + '\n');
  print_minima_summary(name, r, barriers ? &bars : nullptr);
  std::printf("results in %s\n", a.out.c_str());
  draw_minima_plot(out, name, md, r);
  if (barriers && !bars.empty()) draw_barrier_plot(out, name);

  return minima_exit_code(r);
}

}  // namespace hemicontact::cli
