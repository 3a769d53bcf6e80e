// hemicontact path — a quasi-static load history with its jumps (snap-throughs) and hysteresis.
//
// Sample runs:
//   hemicontact path problems/minima-softening.json --load 0,2,0
//   hemicontact path problems/minima-one-node.json --load 0,2,0 --steps 10 --out out/one-node-path
//
// The scene's loads are scaled by a factor t that runs through the corners given by --load in
// --steps steps per segment; each step is solved from the last certified state with the exact
// solver's local descent, so the body stays on its branch until the branch ends; events (a change
// of statuses, an energy off the branch's prediction) are bisected to --bisection-tol and jumps
// recorded (studies/load_path.hpp). Output: a table of the jumps on stdout, DIR/path.csv (one row
// per state), DIR/path.json (states, jumps, options), DIR/state_<k>.vtu with DIR/path.pvd (the
// states in order), DIR/path.png (the reaction against the load and against the mean u_nu, jumps
// marked; scripts/plot_path.py, without matplotlib a warning). Exit code 0 when the whole history
// ran certified, 4 when a state could not be certified, 3 when a step had too many events.
#include "cli.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/options.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/config.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/engine_choice.hpp>
#include <hemicontact/studies/load_path.hpp>
#include <hemicontact/studies/study_json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace hemicontact::cli {
namespace {

using json = nlohmann::json;
const char* const STATUS_KEYS[] = {"separated", "compliance", "contact", "stick", "slip+", "slip-", "slip"};

// "0,2,0" → {0, 2, 0}; anything else is a usage error naming the option.
std::vector<double> parse_load_list(const std::string& key, const std::string& value) {
  std::vector<double> v;
  std::stringstream ss(value);
  for (std::string item; std::getline(ss, item, ',');) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(x))
      throw UsageError(key + ": expected comma-separated load factors such as 0,2,0, got '" + value + "'");
    v.push_back(x);
  }
  if (v.size() < 2 || value.back() == ',')
    throw UsageError(key + ": expected at least two load factors such as 0,2,0, got '" + value + "'");
  for (size_t i = 1; i < v.size(); ++i)
    if (v[i] == v[i - 1]) throw UsageError(key + ": neighbouring load factors must differ, got '" + value + "'");
  return v;
}

void parse_path_options(const SceneArgs& a, PathOptions& po) {
  for (const auto& [key, value] : a.extra) {
    if (key == "--load")
      po.loads = parse_load_list(key, value);
    else if (key == "--steps")
      po.steps = static_cast<int>(parse_integer_option(key, value, 1, PATH_MAX_STEPS));
    else if (key == "--bisection-tol")
      po.bisection_tol = parse_positive_option(key, value);
  }
}

std::string csv_number(double v) { return std::isfinite(v) ? round_trip(v) : (std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf"); }

void write_path_csv(const std::string& path, const PathReport& R) {
  std::ostringstream out;
  out << "k,segment,kind,load,energy,reaction,mean_u_nu,max_u_nu,certificate,certified,type,lambda_min";
  for (const char* c : STATUS_KEYS) out << ',' << c;
  out << '\n';
  for (size_t k = 0; k < R.states.size(); ++k) {
    const PathState& s = R.states[k];
    out << k << ',' << s.segment << ',' << s.kind << ',' << csv_number(s.load) << ',' << csv_number(s.solution.energy)
        << ',' << csv_number(s.reaction) << ',' << csv_number(s.mean_u_nu) << ',' << csv_number(s.max_u_nu) << ','
        << csv_number(s.solution.certificate.max_residual) << ',' << (s.solution.certificate.passed ? 1 : 0) << ','
        << s.second_order.verdict << ',' << csv_number(s.second_order.lambda_min);
    const auto sc = s.solution.status_counts();
    for (const char* c : STATUS_KEYS) out << ',' << (sc.count(c) ? sc.at(c) : 0);
    out << '\n';
  }
  write_text_file(path, out.str());
}

// state_<k>.vtu per state and path.pvd (the states in order: PVD times must increase, the load
// need not; path.csv maps k to the load).
void write_path_vtus(const std::filesystem::path& out, const json& scene, const Model& md, const PathReport& R) {
  const VtuFormat fmt_vtu =
      scene.at("output").at("vtu_format").get<std::string>() == "ascii" ? VtuFormat::ASCII : VtuFormat::BINARY;
  std::vector<std::pair<double, std::string>> vtus;
  for (size_t k = 0; k < R.states.size(); ++k) {
    const std::string file = "state_" + std::to_string(k) + ".vtu";
    write_vtu((out / file).string(), md, R.states[k].solution, fmt_vtu);
    vtus.emplace_back(static_cast<double>(k), file);
  }
  if (!vtus.empty()) write_pvd((out / "path.pvd").string(), vtus);
}

void print_path_summary(const std::string& name, const PathReport& R) {
  std::printf("%s: load path", name.c_str());
  for (size_t i = 0; i < R.options.loads.size(); ++i) std::printf("%s%s", i ? " -> " : " ", fmt(R.options.loads[i], 6).c_str());
  std::printf(", %d steps per segment: %zu states (%d certified), %d solves, %.2f s\n", R.options.steps,
              R.states.size(), R.certified(), R.solves, R.seconds);
  std::printf("%zu jump(s) (bisected to %s in the load factor), %d continuous status change(s)\n", R.jumps.size(),
              fmt(R.options.bisection_tol, 3).c_str(), R.continuous_events);
  if (!R.jumps.empty()) std::printf("  %-10s %-16s %-18s %-18s %s\n", "direction", "load factor", "energy before", "energy after", "nodes switched");
  for (const PathJump& J : R.jumps)
    std::printf("  %-10s %-16s %-18s %-18s %zu\n", J.direction > 0 ? "loading" : "unloading", fmt(J.load_after, 10).c_str(),
                fmt(J.energy_before, 10).c_str(), fmt(J.energy_after, 10).c_str(), J.switched.size());
  int minima = 0;
  for (const PathState& s : R.states) minima += s.second_order.verdict == "local minimum";
  std::printf("second-order check: %d of %zu states local minima\n", minima, R.states.size());
  if (!R.complete) std::printf("path stopped early: %s\n", R.failure.c_str());
}

void draw_path_plot(const std::filesystem::path& out, const std::string& name) {
  const std::string png = (out / "path.png").string();
  const int code = run_plot_script("plot_path.py", {(out / "path.json").string(), "--out", png, "--title", name}, png);
  if (code != 0)
    log_warn() << "path: " << png << " was not drawn" << (code == 2 ? " (needs /usr/bin/python3 with matplotlib)" : "")
               << "; the CSV, JSON and VTU files are written";
  if (std::filesystem::exists(out / "path.png")) record_output_file(png);
}

// A default as the help text writes it (1e-6, as a user types it).
std::string help_default(double v) {
  std::string t = round_trip(v);
  const auto e = t.find("e-0");
  if (e != std::string::npos) t.erase(e + 2, 1);
  return t;
}

}  // namespace

std::string path_help() {
  const PathOptions po;
  std::string loads;
  for (double v : po.loads) loads += (loads.empty() ? "" : ",") + help_default(v);
  return std::string(
             "usage: hemicontact path SCENE.json [--load T0,T1,...] [--steps N] [--bisection-tol T] [--out DIR]\n"
             "                        [--set path=value]... [--force] [--quiet]\n"
             "A quasi-static load history: the scene's loads times a factor that runs through the corners\n"
             "T0 -> T1 -> ... in N steps per segment, each step solved from the last certified state (the\n"
             "exact solver's local descent: the branch is followed, not re-chosen), certified and checked\n"
             "to second order. A step whose statuses change or whose energy leaves the branch's prediction\n"
             "is bisected to T; a jump (snap-through) is reported with its load factor, the energies before\n"
             "and after and the nodes that switched. Needs the condensed formulation (a linear material).\n"
             "Writes DIR/path.csv, DIR/path.json, DIR/state_<k>.vtu with DIR/path.pvd and DIR/path.png\n"
             "(reaction against load and against mean u_nu, jumps marked); DIR defaults to\n"
             "out/<scene name>-path. Exit code 4 if a state could not be certified, 3 if a step had too\n"
             "many events.\n"
             "options:\n"
             "  --load LIST        load factors of the corners (default ") +
         loads + "; e.g. 0,2,0 for a cycle)\n  --steps N          steps per segment (default " +
         std::to_string(po.steps) + ", at most " + std::to_string(PATH_MAX_STEPS) +
         ")\n  --bisection-tol T  width in the load factor to which events are bisected (default " +
         help_default(po.bisection_tol) + ")\n" + scene_options_help() +
         "example:\n"
         "  hemicontact path problems/minima-softening.json --load 0,2,0\n";
}

int cmd_path(const std::vector<std::string>& args) {
  refuse_mpi_ranks("path");
  SceneArgs a = parse_scene_args(args, {"--load", "--steps", "--bisection-tol"});
  const std::string name = std::filesystem::path(a.scene).stem().string();
  if (std::find(args.begin(), args.end(), "--out") == args.end()) a.out = "out/" + name + "-path";
  if (a.quiet) set_log_level(LogLevel::WARN);
  PathOptions po;
  parse_path_options(a, po);
  require_utf8_scene_name(a.scene, "path.json");
  const json scene = load_scene(a.scene, a.overrides);
  const EngineChoice engine = in_process_engine(scene, scene_directory(a.scene), petsc_engine_available(), "path");
  log_engine_choice(engine);
  const Model md = build_model(scene, scene_directory(a.scene));
  const OutputLock lock =
      prepare_output_dir(a.out, a.force, {"path.csv", "path.json", "path.png", "path.pvd"}, {{"state_", ".vtu"}});
  const std::filesystem::path out(a.out);
  const SolveOptions opt = solve_options_from_scene(scene);
  po.on_state = [](const PathState& s, int recorded) {
    log_info() << "path: state " << recorded - 1 << " (" << s.kind << ") at load factor " << fmt(s.load, 10)
               << ": energy " << fmt(s.solution.energy, 10) << ", "
               << (s.solution.certificate.passed ? "certified" : "NOT certified") << ", " << s.second_order.verdict;
  };
  const PathReport R = follow_load_path(md, opt, po);
  json js = path_json(md, R);
  js["name"] = name;
  js["scene_file"] = a.scene;
  js["scene"] = scene;
  js["engine_choice"] = engine_choice_json(engine);
  write_path_csv((out / "path.csv").string(), R);
  write_path_vtus(out, scene, md, R);
  write_text_file((out / "path.json").string(), js.dump(2) + '\n');  // last: the set is complete
  print_path_summary(name, R);
  std::printf("results in %s\n", a.out.c_str());
  draw_path_plot(out, name);
  if (R.complete) return EXIT_OK;
  std::fprintf(stderr, "hemicontact: path: %s\n", R.failure.c_str());
  const bool uncertified = !R.states.empty() && !R.states.back().solution.certificate.passed;
  return uncertified ? EXIT_CERTIFICATE : EXIT_NOT_CONVERGED;
}

}  // namespace hemicontact::cli
