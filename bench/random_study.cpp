// hemicontact_random_study — the random-scene study with DEFAULT solver settings (what a user gets
// without tuning).
//
// Seeds 1..N of include/hemicontact/studies/random_scenes.hpp (draw_default_scene: E, ν, plane stress/strain,
// loads, layer law, μ, g, mesh, perturbation, aspect drawn over realistic and extreme ranges; no
// solver override), each solved in this process with the default backend (or --backend), and timed
// against the linear-elastic factor+solve of the same mesh (CHOLMOD, both best of 3, same process).
// Writes, in --out:
//   random-default.csv   one row per seed (outcome, certificate, strong convexity, hand-over,
//                        seconds, linear seconds, ratio, message, the command that reruns it)
//   random-default.md    the summary table: certified counts (all / strongly convex), time ratios
//                        (median, 90th percentile, max, scenes above 10x) and every scene that was
//                        not certified with its reason.
// Sample: hemicontact_random_study --seeds 1000 --out /tmp/random  (docs/stress/random-default.md
// is the committed summary; the CSV is regenerated, not committed).

#include <hemicontact/studies/random_scenes.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/options.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include "bench_limits.hpp"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace hemicontact;
namespace fs = std::filesystem;

namespace {

using clk = std::chrono::steady_clock;
double since(clk::time_point t0) { return std::chrono::duration<double>(clk::now() - t0).count(); }

std::string g3(double x) {
  if (std::isnan(x)) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

std::string csv_quote(std::string s) {
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

struct Row {
  stress::RandomScene rs;
  std::string outcome;  // certified | input error | not certified: <reason>
  bool ok = false, input_error = false, convex_checked = false, convex = false, handover = false;
  double certificate = NAN, min_eig = NAN, seconds = 0, linear = NAN, ratio = NAN, energy = NAN;
  std::string reason, message;
  std::string path;  // which of the solve's routes gave the answer (path_of)
  std::string solved_by;  // Solution::solved_by
  bool backend_ran = false;
  long long backend_iterations = 0, backend_evaluations = 0;
  std::map<std::string, double> timings;  // the solve's own split (Solution::timings)
  std::string command;  // the `hemicontact solve` that reruns this row (rerun_command)
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(std::floor(q * (v.size() - 1) + 0.5)));
  return v[i];
}

// Which route of ContactSolver::solve gave the answer, read off the notes it leaves (solve.cpp):
// the exact solver from the start, the continuation after a start that was not certified, the last
// resort after a continuation that was not, or the continuation alone. Where the inner problem is
// not strongly convex the routes may end in different stationary points; with `energy` this column
// lets two runs of the study be compared.
std::string path_of(const Solution& s) {
  for (const auto& k : s.skipped)
    if (k.rfind("continuation: its answer was not certified", 0) == 0) return "last resort (exact from start)";
  if (s.handover.note.rfind("the exact solver from the start was not certified", 0) == 0)
    return "backend stages after exact start";
  if (!s.backend_use.ran) return "exact from start (backend not run)";
  return s.handover.used ? "backend stages, exact hand-over" : "backend stages";
}

// The command line (USAGE).
struct StudyArgs {
  int seeds = 1000, n_min = 8, n_max = 16, first = 1, repeats = 3;
  std::string out = "out/random-study", backend;  // under out/, which git ignores
  std::vector<std::string> sets;  // --set KEY=VALUE: a solver override on every scene (not the default study)
  bool force = false;
  bool help = false;
};

const char* const USAGE =
    "usage: hemicontact_random_study [--seeds N] [--first S] [--n-min A] [--n-max B] [--backend NAME]\n"
    "                                [--set KEY=VALUE]... [--repeats R] [--out DIR] [--force]\n"
    "Seeds S..S+N-1 of the random default-settings scenes, solved and timed against the linear solve;\n"
    "writes DIR/random-default.csv (with the command that reruns each row) and DIR/random-default.md.\n"
    "DIR follows `hemicontact solve --out`'s rules: no links followed, earlier results replaced only\n"
    "with --force. Exit codes: 0, 1 usage, 2 bad input or output folder, 3 nothing certified.\n";

// The options, checked as `hemicontact`'s are (core/options.hpp): a bad value is a usage error.
StudyArgs parse_study_args(int argc, char** argv) {
  StudyArgs A;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("option " + a + " needs a value", EXIT_USAGE);
      return argv[++i];
    };
    const auto integer = [&](long lo, long hi) { return static_cast<int>(parse_integer_option(a, next(), lo, hi)); };
    if (a == "--seeds") A.seeds = integer(1, bench::MAX_SEEDS);
    else if (a == "--first") A.first = integer(0, std::numeric_limits<int>::max() - bench::MAX_SEEDS);  // seeds are ints here
    else if (a == "--n-min") A.n_min = integer(1, bench::MAX_MESH_N);
    else if (a == "--n-max") A.n_max = integer(1, bench::MAX_MESH_N);
    else if (a == "--out") A.out = next();
    else if (a == "--backend") A.backend = next();
    else if (a == "--set") A.sets.push_back(next());
    else if (a == "--repeats") A.repeats = integer(1, bench::MAX_REPEATS);
    else if (a == "--force") A.force = true;
    else if (a == "-h" || a == "--help") A.help = true;
    else throw Error("unknown option '" + a + "' (see hemicontact_random_study --help)", EXIT_USAGE);
  }
  if (A.n_min > A.n_max) throw Error("--n-min " + std::to_string(A.n_min) + " is above --n-max " + std::to_string(A.n_max), EXIT_USAGE);
  return A;
}

// Every override of a seed's scene: the drawn ones, --backend, the --set ones, in the order applied.
std::vector<std::string> scene_overrides(const StudyArgs& A, const stress::RandomScene& rs) {
  std::vector<std::string> o = rs.overrides;
  if (!A.backend.empty()) o.push_back("solver.backend=\"" + A.backend + "\"");
  o.insert(o.end(), A.sets.begin(), A.sets.end());
  return o;
}

// The `hemicontact solve` that reruns a row as it was run here (the --set overrides included: a
// failed seed rerun without them would certify).
std::string rerun_command(const StudyArgs& A, const stress::RandomScene& rs) {
  std::vector<std::string> argv = {"hemicontact", "solve", "problems/sofonea2017-fig2.json"};
  for (const std::string& o : scene_overrides(A, rs)) argv.insert(argv.end(), {"--set", o});
  return shell_command(argv);
}

// The study's own command line, every option that differs from its default (--out DIR left open).
std::string study_command(const StudyArgs& A) {
  const StudyArgs d;
  std::vector<std::string> argv = {"hemicontact_random_study", "--seeds", std::to_string(A.seeds)};
  const auto add = [&](const char* key, int v, int def) {
    if (v != def) argv.insert(argv.end(), {key, std::to_string(v)});
  };
  add("--first", A.first, d.first);
  add("--n-min", A.n_min, d.n_min);
  add("--n-max", A.n_max, d.n_max);
  if (!A.backend.empty()) argv.insert(argv.end(), {"--backend", A.backend});
  for (const std::string& kv : A.sets) argv.insert(argv.end(), {"--set", kv});
  add("--repeats", A.repeats, d.repeats);
  return shell_command(argv) + " --out DIR";
}

// The linear-elastic factor+solve of the model's mesh, best of 3, into @p best (NaN before).
void best_linear_seconds(const Model& md, double& best) {
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = clk::now();
    SparseCholesky chol;
    chol.compute(md.Kx.lower());
    const Vec x = chol.solve(md.fx);
    const double t = since(t0);
    if (!x.allFinite()) throw Error("linear solve not finite", EXIT_INTERNAL);
    best = std::isnan(best) ? t : std::min(best, t);
  }
}

// The answer's outcome in the row (r.seconds and r.linear already set).
void record_solution(const Solution& s, Row& r) {
  r.ok = s.ok();
  r.certificate = s.certificate.max_residual;
  r.convex_checked = s.inner_convexity.checked;
  r.convex = s.inner_convexity.checked && s.inner_convexity.strongly_convex;
  r.min_eig = s.inner_convexity.min_eigenvalue;
  r.handover = s.handover.used;
  r.message = s.message;
  r.timings = s.timings;
  r.energy = s.energy;
  r.path = path_of(s);
  r.solved_by = s.solved_by();
  r.backend_ran = s.backend_use.ran;
  const SolverWork w = s.work_of(s.backend);
  r.backend_iterations = w.iterations;
  r.backend_evaluations = w.evaluations;
  if (r.ok) {
    r.outcome = "certified";
  } else {
    r.reason = !s.fixed_point_converged ? "fixed point"
               : !s.backend_ok          ? "backend"
                                        : "certificate failed";
    r.outcome = "not certified: " + r.reason;
  }
  r.ratio = r.seconds / r.linear;
}

// One seed's scene, drawn, solved and timed.
Row run_seed(const StudyArgs& A, int seed) {
  Row r;
  r.rs = stress::draw_default_scene(static_cast<unsigned>(seed), A.n_min, A.n_max);
  const std::vector<std::string> o = scene_overrides(A, r.rs);
  r.command = rerun_command(A, r.rs);
  try {
    const nlohmann::json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", o);
    const Model md = build_model(scene, ".");
    const SolveOptions opt = solve_options_from_scene(scene);
    best_linear_seconds(md, r.linear);
    // Best of --repeats (3) like the linear solve above, so that a preemption on a shared machine
    // does not decide a ratio (the solve is deterministic: the answers are the same). A study of
    // certified counts alone can take --repeats 1.
    Solution s;
    for (int rep = 0; rep < A.repeats; ++rep) {
      const auto t0 = clk::now();
      Solution sr = solve(md, opt);
      const double t = since(t0);
      if (rep == 0 || t < r.seconds) {  // the fastest run's own time split, for the table below
        r.seconds = t;
        s = std::move(sr);
      }
    }
    record_solution(s, r);
  } catch (const Error& e) {
    r.input_error = e.code() == EXIT_INPUT;
    r.outcome = r.input_error ? "input error" : "error";
    r.message = e.what();
  }
  return r;
}

void write_rows_csv(const std::string& out, const std::vector<Row>& rows) {
  std::ostringstream csv;
  csv << "seed,n,E,load_scale,mu,g,aspect,outcome,certificate,strongly_convex_checked,strongly_convex,min_eigenvalue,"
         "handover,path,solved_by,backend_ran,backend_iterations,backend_evaluations,energy,seconds,linear_seconds,"
         "ratio,message,command\n";
  for (const auto& r : rows)
    csv << r.rs.seed << ',' << r.rs.n << ',' << r.rs.E << ',' << r.rs.load_scale << ',' << r.rs.mu << ','
        << (r.rs.gap_none ? std::string("none") : stress::num(r.rs.g)) << ',' << r.rs.aspect << ',' << r.outcome << ','
        << r.certificate << ',' << r.convex_checked << ',' << r.convex << ',' << r.min_eig << ',' << r.handover << ','
        << csv_quote(r.path) << ',' << csv_quote(r.solved_by) << ',' << r.backend_ran << ',' << r.backend_iterations << ','
        << r.backend_evaluations << ',' << stress::num(r.energy) << ',' << r.seconds << ',' << r.linear << ',' << r.ratio << ',' << csv_quote(r.message) << ','
        << csv_quote(r.command) << '\n';
  write_text_file((fs::path(out) / "random-default.csv").string(), csv.str());
}

// The summary's counts over the rows.
struct StudyCounts {
  int valid = 0, ok = 0, convex = 0, convex_ok = 0, handover = 0, input = 0, above10 = 0, ran = 0, worked = 0;
  std::vector<double> ratios;
  double slowest = 0;
  std::map<std::string, int> certified_by_path;
};

StudyCounts count_rows(const std::vector<Row>& rows) {
  StudyCounts c;
  for (const auto& r : rows) {
    if (r.ok) ++c.certified_by_path[r.path];
    if (r.input_error) {
      ++c.input;
      continue;
    }
    ++c.valid;
    c.ok += r.ok;
    c.convex += r.convex;
    c.convex_ok += r.convex && r.ok;
    c.handover += r.handover;
    c.ran += r.backend_ran;
    c.worked += r.backend_ran && (r.backend_iterations > 0 || r.backend_evaluations > 0);
    if (std::isfinite(r.ratio)) {
      c.ratios.push_back(r.ratio);
      c.above10 += r.ratio > 10;
    }
    c.slowest = std::max(c.slowest, r.seconds);
  }
  return c;
}

// The summary's heading and its table of counts and time ratios.
void write_counts(std::ostringstream& md, const StudyArgs& A, size_t drawn, const StudyCounts& c,
                  clk::time_point t_all) {
  const std::string& backend = A.backend;
  const std::vector<std::string>& sets = A.sets;
  md << "### Random scenes" << (backend.empty() && sets.empty() ? " with default settings" : "") << "\n\n"
     << "Seeds " << A.first << ".." << A.first + A.seeds - 1 << " of `draw_default_scene` (include/hemicontact/studies/random_scenes.hpp), n = "
     << A.n_min << ".." << A.n_max << ", backend "
     << (backend.empty() ? "auto (ipopt; its stage skipped where the inner problem is strongly convex)" : backend)
     << (sets.empty() ? std::string(", no solver override") : ", overrides: " + [&] {
          std::string j;
          for (const auto& x : sets) j += (j.empty() ? "" : ", ") + x;
          return j;
        }())
     << ". Regenerate: `" << study_command(A) << "`"
     << (A.repeats == 1 ? " (single timings: the ratios are noisier than best-of-3)" : "") << ".\n\n"
     << "| | scenes |\n|---|---|\n"
     << "| drawn | " << drawn << " |\n"
     << "| input errors (an inverted perturbed cell) | " << c.input << " |\n"
     << "| solved | " << c.valid << " |\n"
     << "| certified | " << c.ok << " (" << g3(100.0 * c.ok / std::max(c.valid, 1)) << " %) |\n"
     << "| inner problem strongly convex | " << c.convex << " |\n"
     << "| strongly convex and certified | " << c.convex_ok << " |\n"
     << "| exact solver took over | " << c.handover << " |\n"
     << "| backend ran (at least one smoothed minimization) | " << c.ran << " |\n"
     << "| backend ran with iterations or evaluations > 0 | " << c.worked << " |\n";
  for (const auto& [path, count] : c.certified_by_path) md << "| certified by: " << path << " | " << count << " |\n";
  const std::vector<double>& ratios = c.ratios;
  md << "\n"
     << "Time / linear factor+solve of the same mesh: median " << g3(percentile(ratios, 0.5)) << "x, 90th percentile "
     << g3(percentile(ratios, 0.9)) << "x, max " << g3(ratios.empty() ? NAN : *std::max_element(ratios.begin(), ratios.end()))
     << "x; " << c.above10 << " scenes above 10x. Slowest scene " << g3(c.slowest) << " s; total " << g3(since(t_all))
     << " s.\n\n";
}

void write_not_certified(std::ostringstream& md, const std::vector<Row>& rows) {
  int listed = 0;
  for (const auto& r : rows)
    if (!r.ok && !r.input_error) {
      if (!listed++) md << "Not certified (random-default.csv's `command` reruns each one):\n\n| seed | μ | g | strongly convex | reason | message |\n|---|---|---|---|---|---|\n";
      std::string m = r.message.substr(0, 160);
      for (char& c : m)
        if (c == '|') c = '/';
      md << "| " << r.rs.seed << " | " << g3(r.rs.mu) << " | " << (r.rs.gap_none ? std::string("none") : g3(r.rs.g))
         << " | " << (r.convex_checked ? (r.convex ? "yes" : "no") : "not checked") << " | " << r.reason << " | " << m
         << " |\n";
    }
  if (!listed) md << "Every solved scene was certified.\n";
}

// The slowest scenes relative to their linear solve, with the solve's own time split: where the
// time goes (set-up diagnostics, condensation, backend, exact solver, polish, certificate).
void write_slowest(std::ostringstream& md, const std::vector<Row>& rows) {
  std::vector<const Row*> by_ratio;
  for (const auto& r : rows)
    if (std::isfinite(r.ratio)) by_ratio.push_back(&r);
  std::sort(by_ratio.begin(), by_ratio.end(), [](const Row* a, const Row* b) { return a->ratio > b->ratio; });
  if (by_ratio.empty()) return;
  const auto t = [](const Row& r, const char* k) {
    const auto it = r.timings.find(k);
    return it == r.timings.end() ? std::string("-") : g3(1e3 * it->second);
  };
  md << "\nSlowest against the linear solve (times in ms; `smallness` and `convexity` are the set-up "
        "diagnostics, `backend` the backend's smoothed minimizations, `exact` the exact solver):\n\n"
        "| seed | n | ratio | total | linear | smallness | convexity | condensation | backend | exact | polish | "
        "certificate | outcome |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < std::min<size_t>(10, by_ratio.size()); ++i) {
    const Row& r = *by_ratio[i];
    md << "| " << r.rs.seed << " | " << r.rs.n << " | " << g3(r.ratio) << " | " << g3(1e3 * r.seconds) << " | "
       << g3(1e3 * r.linear) << " | " << t(r, "smallness") << " | " << t(r, "inner_convexity") << " | "
       << t(r, "factorization_total") << " | " << t(r, "backend") << " | " << t(r, "exact") << " | "
       << t(r, "polish") << " | " << t(r, "certificate") << " | " << r.outcome << " |\n";
  }
}

int study_main(int argc, char** argv) {
  const StudyArgs A = parse_study_args(argc, argv);
  if (A.help) {
    std::fputs(USAGE, stdout);
    return EXIT_OK;
  }
  set_log_level(LogLevel::QUIET);  // the outcome of every scene is in the CSV
  // The CLI's folder rules (output/output_dir.hpp): no link followed, nothing of someone else's
  // replaced, an earlier study only with --force.
  const OutputLock lock = prepare_output_dir(A.out, A.force, {"random-default.csv", "random-default.md"});
  std::vector<Row> rows;
  const auto t_all = clk::now();
  for (int seed = A.first; seed < A.first + A.seeds; ++seed) {
    rows.push_back(run_seed(A, seed));
    if (rows.size() % 50 == 0)
      std::cerr << rows.size() << " scenes, " << since(t_all) << " s\n";
  }
  write_rows_csv(A.out, rows);

  // Summary
  const StudyCounts c = count_rows(rows);
  std::ostringstream md;
  write_counts(md, A, rows.size(), c, t_all);
  write_not_certified(md, rows);
  write_slowest(md, rows);
  write_text_file((fs::path(A.out) / "random-default.md").string(), md.str());
  std::cout << md.str();
  // A study in which nothing was certified says nothing: it fails loudly.
  if (c.valid > 0 && c.ok == 0) {
    std::cerr << "hemicontact_random_study: none of the " << c.valid << " solved scenes was certified\n";
    return EXIT_NOT_CONVERGED;
  }
  return EXIT_OK;
}

}  // namespace

int main(int argc, char** argv) {
  install_interrupt_handlers();
  return run_program("hemicontact_random_study", [&] { return study_main(argc, argv); });
}
