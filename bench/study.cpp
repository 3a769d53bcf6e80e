// hemicontact_study — work-precision study of the contact solver (what does accuracy cost?).
//
// For every scene × mesh level L × backend:formulation × ε the scene is solved in its own forked
// child process (so each run's peak memory is its own and a crash or hang costs one row), on the
// uniform n = L mesh, with ε_τ = ε_ν = ε. The child also times the *linear elastic* problem of the
// same mesh (one sparse Cholesky factor + solve of K_x u = f_x): the ratio solve/linear says what
// the contact nonlinearity costs over the cheapest possible solve on that mesh. Each solution is
// then compared with a reference solution on a finer mesh (level R, computed once per scene):
//     e_rel = ‖u_ref − P u_h‖_E / ‖u_ref‖_E,   ‖v‖_E² = vᵀ K_R v = a(v, v)   (docs/model.md §5),
// with P the P1 prolongation onto the reference mesh (fem/prolongation.hpp; exact embedding on
// these nested meshes).
//
// Sample runs:
//   hemicontact_study --scenes fig2 --levels 8,16,32 --reference 64 --backends ipopt:condensed --out /tmp/s
//   hemicontact_study --scenes fig2,printed --levels 8,16,...,256 --reference 512
//       --backends ipopt:full,ipopt:condensed,newton:condensed,newton:full --eps 1e-10,1e-8 --out study
// Output: DIR/study.csv (one row per run, columns in bench/README.md), DIR/runs/<run>.{json,u.bin,log},
// DIR/work_precision_<scene>.png and DIR/time_vs_dofs.png (scripts/plot_study.py), a table on stdout.

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/prolongation.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace hemicontact;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using clk = std::chrono::steady_clock;
double since(clk::time_point t0) { return std::chrono::duration<double>(clk::now() - t0).count(); }

// A number for the CSV and messages; empty when not finite (not available).
std::string fmt(double v, int prec = 6) {
  if (!std::isfinite(v)) return "";
  std::ostringstream os;
  os << std::setprecision(prec) << v;
  return os.str();
}

const char* USAGE = R"(usage: hemicontact_study --out DIR [options]

Work-precision study: each scene x level x backend:formulation x eps is solved in a forked child;
wall time, peak RSS, iterations, certificate, the linear elastic factor+solve time of the same
mesh, and the energy-norm error against a reference level are written to DIR/study.csv.

options (defaults in brackets):
  --scenes A,B          scene names (problems/sofonea2017-A.json) or .json paths [fig2]
  --levels L1,L2,...    mesh levels n (n x n cells); "8,16,...,256" continues the ratio [8,16,32]
  --reference R         reference level for the error, 0 = no error column [64]
  --reference-backend B backend:formulation of the reference run [first available condensed of --backends]
  --backends B1,B2      backend:formulation, formulation in full|condensed|auto [ipopt:condensed]
  --eps E1,E2           final smoothing widths eps_tau = eps_nu, relative to U [1e-10]
  --max-full-level L    skip full-formulation runs above level L (they are slow) [256]
  --timeout S           kill a run after S seconds, 0 = never [3600]
  --cert-tol T          a run is "ok" only if the certificate max residual <= T [1e-8]
  --set key=value       extra scene override for every run (repeatable)
  --problems DIR        where scene names are looked up [<source>/problems]
  --plot-script PATH    [<source>/scripts/plot_study.py]
  --no-plot             do not call /usr/bin/python3 plot_study.py at the end
  --help
)";

// ---------------------------------------------------------------------------------------------
// Command line

struct BackendSpec {
  std::string backend, formulation;  // "ipopt", "condensed"
  std::string label() const { return backend + ":" + formulation; }
};

struct StudyOptions {
  std::vector<std::string> scenes{"fig2"};
  std::vector<int> levels{8, 16, 32};
  int reference = 64;
  std::string reference_backend;
  std::vector<BackendSpec> backends{{"ipopt", "condensed"}};
  std::vector<std::string> eps{"1e-10"};  // kept as typed: they name the run files
  int max_full_level = 256;
  double timeout = 3600;
  double cert_tol = 1e-8;
  std::vector<std::string> sets;
  std::string problems = std::string(HEMICONTACT_SOURCE_DIR) + "/problems";
  std::string plot_script = std::string(HEMICONTACT_SOURCE_DIR) + "/scripts/plot_study.py";
  bool plot = true;
  std::string out;
};

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> r;
  std::stringstream ss(s);
  for (std::string t; std::getline(ss, t, sep);)
    if (!t.empty()) r.push_back(t);
  return r;
}

[[noreturn]] void usage_error(const std::string& msg) {
  std::cerr << "hemicontact_study: " << msg << "\n\n" << USAGE;
  std::exit(EXIT_USAGE);
}

int parse_int(const std::string& s, const std::string& what) {
  try {
    size_t pos = 0;
    const int v = std::stoi(s, &pos);
    if (pos == s.size() && v > 0) return v;
  } catch (const std::exception&) {
  }
  usage_error(what + ": expected a positive integer, got '" + s + "'");
}

double parse_double(const std::string& s, const std::string& what) {
  try {
    size_t pos = 0;
    const double v = std::stod(s, &pos);
    if (pos == s.size() && v >= 0 && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  usage_error(what + ": expected a number >= 0, got '" + s + "'");
}

// "8,16,...,256": "..." continues the integer ratio of the two preceding levels up to the next one.
std::vector<int> parse_levels(const std::string& s) {
  const auto tok = split(s, ',');
  std::vector<int> r;
  for (size_t i = 0; i < tok.size(); ++i) {
    if (tok[i] != "...") {
      r.push_back(parse_int(tok[i], "--levels"));
      continue;
    }
    if (r.size() < 2 || i + 1 >= tok.size() || r[r.size() - 1] % r[r.size() - 2] != 0 ||
        r[r.size() - 1] == r[r.size() - 2])
      usage_error("--levels: '...' needs two increasing levels with an integer ratio before it and one after");
    const int q = r[r.size() - 1] / r[r.size() - 2], last = parse_int(tok[i + 1], "--levels");
    for (long v = static_cast<long>(r.back()) * q; v < last; v *= q) r.push_back(static_cast<int>(v));
  }
  if (r.empty()) usage_error("--levels: no level given");
  std::sort(r.begin(), r.end());
  r.erase(std::unique(r.begin(), r.end()), r.end());
  return r;
}

// "nlopt:LD_LBFGS:condensed" → {nlopt:LD_LBFGS, condensed}; without a formulation suffix: auto.
BackendSpec parse_backend(const std::string& s) {
  const auto colon = s.rfind(':');
  if (colon != std::string::npos) {
    const std::string f = s.substr(colon + 1);
    if (f == "full" || f == "condensed" || f == "auto") return {s.substr(0, colon), f};
  }
  return {s, "auto"};
}

StudyOptions parse_args(int argc, char** argv) {
  StudyOptions o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      std::cout << USAGE;
      std::exit(0);
    } else if (a == "--scenes") {
      o.scenes = split(value(), ',');
    } else if (a == "--levels") {
      o.levels = parse_levels(value());
    } else if (a == "--reference") {
      const std::string v = value();
      o.reference = v == "0" ? 0 : parse_int(v, a);
    } else if (a == "--reference-backend") {
      o.reference_backend = value();
    } else if (a == "--backends") {
      o.backends.clear();
      for (const auto& b : split(value(), ',')) o.backends.push_back(parse_backend(b));
    } else if (a == "--eps") {
      o.eps = split(value(), ',');
      for (const auto& e : o.eps)
        if (parse_double(e, a) <= 0) usage_error("--eps: widths must be > 0");
    } else if (a == "--max-full-level") {
      o.max_full_level = parse_int(value(), a);
    } else if (a == "--timeout") {
      o.timeout = parse_double(value(), a);
    } else if (a == "--cert-tol") {
      o.cert_tol = parse_double(value(), a);
    } else if (a == "--set") {
      o.sets.push_back(value());
    } else if (a == "--problems") {
      o.problems = value();
    } else if (a == "--plot-script") {
      o.plot_script = value();
    } else if (a == "--no-plot") {
      o.plot = false;
    } else if (a == "--out") {
      o.out = value();
    } else {
      usage_error("unknown argument '" + a + "'");
    }
  }
  if (o.out.empty()) usage_error("--out DIR is required");
  if (o.scenes.empty() || o.backends.empty() || o.eps.empty()) usage_error("empty --scenes, --backends or --eps");
  return o;
}

// ---------------------------------------------------------------------------------------------
// Runs

struct Case {
  std::string scene, scene_path;  // short name ("fig2") and file
  int level = 0;
  BackendSpec backend;
  std::string eps;
  bool study = true;       // one of the requested runs
  bool reference = false;  // the scene's reference run (may also be a study run)
  std::string status;      // pre-run verdict: "" (to run), "unavailable", "skipped"
  std::string note;

  std::string stem() const {
    std::string b = backend.backend;
    std::replace(b.begin(), b.end(), ':', '-');
    return scene + "_L" + std::to_string(level) + "_" + b + "_" + backend.formulation + "_eps" + eps;
  }
};

struct Result {
  std::string status;  // ok, uncertified, not_converged, backend_failed, error, crashed, timeout, skipped, unavailable
  int exit_code = -1;
  double wall = NaN, cpu = NaN, rss_mb = NaN;
  json stats = json::object();  // what the child wrote (empty if it wrote nothing)
  double rel_error = NaN;
  std::string message;
};

std::string scene_file(const StudyOptions& o, const std::string& name) {
  if (name.size() > 5 && name.substr(name.size() - 5) == ".json") return name;
  for (const auto& p : {o.problems + "/sofonea2017-" + name + ".json", o.problems + "/" + name + ".json"})
    if (fs::exists(p)) return p;
  usage_error("scene '" + name + "': neither " + o.problems + "/sofonea2017-" + name + ".json nor " + o.problems + "/" +
              name + ".json exists");
}

std::vector<std::string> overrides(const StudyOptions& o, const Case& c) {
  std::vector<std::string> s = o.sets;
  s.push_back("mesh.n=" + std::to_string(c.level));
  // "exact" is the exact solver's own path (no backend stage): solver.exact.start = always.
  if (c.backend.backend == EXACT_SOLVER) {
    s.push_back("solver.backend=auto");
    s.push_back("solver.exact.start=always");
  } else {
    s.push_back("solver.backend=" + c.backend.backend);
  }
  s.push_back("solver.formulation=" + c.backend.formulation);
  s.push_back("solver.eps_tau=" + c.eps);
  s.push_back("solver.eps_nu=" + c.eps);
  // check.certificate_tol is left at the scene's: the child writes its stats whatever the verdict and
  // the study judges the residual with --cert-tol, while the solver's own path (which accepts a
  // polished answer once it passes the certificate) must be the one a user gets.
  return s;
}

// The parent's current resident set, split as /proc/self/status does: anonymous pages are what a
// forked child inherits (copy-on-write, counted in its RSS); file pages (shared libraries) count in
// a child only once it touches them.
std::string self_rss_text() {
  std::ifstream in("/proc/self/status");
  std::string line, rss, anon;
  while (std::getline(in, line)) {
    const auto value = [&] { return line.substr(line.find(':') + 1); };
    if (line.rfind("VmRSS:", 0) == 0) rss = value();
    if (line.rfind("RssAnon:", 0) == 0) anon = value();
  }
  const auto trim = [](std::string t) { return t.erase(0, t.find_first_not_of(" \t")); };
  return rss.empty() ? "unknown" : trim(rss) + " (anonymous " + trim(anon) + ")";
}

double self_peak_rss_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

// The child: build, time the linear elastic solve of the same mesh, solve, write u and stats.
// Exit code: 0 solved (any certificate), 3 backend failed / fixed point not converged, else the
// Error's code. Never returns.
[[noreturn]] void child_main(const StudyOptions& o, const Case& c, const std::string& runs) {
  const std::string base = runs + "/" + c.stem();
  // The solver's log (stderr) and anything a backend prints (stdout) go to the run's log file.
  if (!std::freopen((base + ".log").c_str(), "w", stderr)) std::_Exit(EXIT_INTERNAL);
  std::fflush(stdout);
  dup2(fileno(stderr), STDOUT_FILENO);
  if (o.timeout > 0) alarm(static_cast<unsigned>(std::ceil(o.timeout)));
  json st;
  int code = EXIT_INTERNAL;
  try {
    const auto t0 = clk::now();
    const json scene = load_scene(c.scene_path, overrides(o, c));
    const Model md = build_model(scene, scene_directory(c.scene_path));
    st["build_s"] = since(t0);
    st["h"] = md.mesh.max_edge_length();
    st["dofs"] = md.dofs.n_free();
    st["nodes"] = md.mesh.num_nodes();
    st["gamma3_nodes"] = md.contact.size();
    {
      // The cheapest solve this mesh admits: one sparse Cholesky of the unconstrained problem.
      const auto t1 = clk::now();
      SparseCholesky chol;
      chol.compute(md.Kx.lower());
      const Vec y = chol.solve(md.fx);
      st["linear_s"] = since(t1);
      st["linear_analyze_s"] = chol.analyze_seconds();
      st["linear_factor_s"] = chol.factorize_seconds();
      if (!y.allFinite()) throw Error("linear elastic solve: non-finite solution", EXIT_NOT_CONVERGED);
    }
    st["linear_rss_mb"] = self_peak_rss_mb();
    // Partial stats first: a run killed by --timeout or a crash still reports its size and times.
    std::ofstream(base + ".json") << st.dump(2) << "\n";
    const SolveOptions opt = solve_options_from_scene(scene);
    const Solution sol = solve(md, opt);
    std::ofstream(base + ".u.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(sol.u.data()),
               static_cast<std::streamsize>(sol.u.size() * sizeof(double)));
    // The backend's own work only; the exact solver's inner solves are not the backend's iterations.
    const long long backend_iters = sol.work_of(sol.backend).iterations;
    st["u_size"] = sol.u.size();
    st["solve_s"] = sol.timings.count("solve_total") ? sol.timings.at("solve_total") : NaN;
    st["backend_s"] = sol.timings.count("backend") ? sol.timings.at("backend") : NaN;
    st["timings"] = sol.timings;
    st["formulation"] = sol.formulation;
    st["solved_by"] = sol.solved_by();
    st["outer_iters"] = sol.history.size();
    st["backend_iters"] = backend_iters;
    st["cert_max_residual"] = sol.certificate.max_residual;
    st["status_counts"] = sol.status_counts();
    st["energy"] = sol.energy;
    st["energy_norm"] = sol.energy_norm;
    st["backend_ok"] = sol.backend_ok;
    st["fixed_point_converged"] = sol.fixed_point_converged;
    st["polish"] = !sol.polish.attempted ? "no" : sol.polish.accepted ? "accepted" : "rejected";
    st["message"] = sol.message;
    code = sol.backend_ok && sol.fixed_point_converged ? EXIT_OK : EXIT_NOT_CONVERGED;
  } catch (const Error& e) {
    st["error"] = e.what();
    code = e.code() == EXIT_OK ? EXIT_INTERNAL : e.code();
  } catch (const std::exception& e) {
    st["error"] = std::string("internal: ") + e.what();
    code = EXIT_INTERNAL;
  }
  std::ofstream(base + ".json") << st.dump(2) << "\n";
  std::fflush(nullptr);
  std::_Exit(code);  // no static destructors or atexit handlers of the parent's state
}

Result run_case(const StudyOptions& o, const Case& c, const std::string& runs) {
  Result r;
  const std::string base = runs + "/" + c.stem();
  fs::remove(base + ".json");
  fs::remove(base + ".u.bin");
  std::fflush(nullptr);  // or the child would flush the parent's buffered output a second time
  const auto t0 = clk::now();
  const pid_t pid = fork();
  if (pid < 0) {
    r.status = "error";
    r.message = "fork failed";
    return r;
  }
  if (pid == 0) child_main(o, c, runs);
  int wstatus = 0;
  rusage ru{};
  while (wait4(pid, &wstatus, 0, &ru) < 0)
    if (errno != EINTR) break;
  r.wall = since(t0);
  r.rss_mb = static_cast<double>(ru.ru_maxrss) / 1024.0;
  r.cpu = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
          1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  if (std::ifstream in{base + ".json"}) {
    try {
      in >> r.stats;
    } catch (const std::exception&) {
      r.stats = json::object();
    }
  }
  if (WIFSIGNALED(wstatus)) {
    const int sig = WTERMSIG(wstatus);
    r.status = sig == SIGALRM ? "timeout" : "crashed";
    r.message = sig == SIGALRM ? "killed after --timeout " + fmt(o.timeout) + " s"
                               : std::string("killed by signal ") + strsignal(sig);
    return r;
  }
  r.exit_code = WEXITSTATUS(wstatus);
  if (r.stats.contains("error")) {
    r.status = "error";
    r.message = r.stats["error"].get<std::string>();
  } else if (!r.stats.contains("cert_max_residual")) {
    r.status = "error";
    r.message = "child exited with code " + std::to_string(r.exit_code) + " and no stats (see " + base + ".log)";
  } else {
    r.message = r.stats.value("message", "");
    const double cert = r.stats["cert_max_residual"].is_number() ? r.stats["cert_max_residual"].get<double>() : NaN;
    // The certificate decides (as in the CLI): a backend that reported failure but whose polished
    // answer is certified is "ok (backend failed)"; an uncertified one keeps the backend's verdict.
    const bool certified = cert <= o.cert_tol, backend_ok = r.stats.value("backend_ok", false);
    if (!r.stats.value("fixed_point_converged", false))
      r.status = "not_converged";
    else if (!certified)
      r.status = backend_ok ? "uncertified" : "backend_failed";
    else
      r.status = backend_ok ? "ok" : "ok(backend_failed)";
  }
  return r;
}

// Every run that wrote u gets an error, failed ones included (the status says what it is worth).
bool has_solution(const Result& r) { return r.stats.contains("u_size"); }

Vec read_u(const std::string& path, Index n) {
  Vec u(n);
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(u.data()), static_cast<std::streamsize>(n * sizeof(double)));
  if (!in) throw Error("cannot read " + std::to_string(n) + " doubles from " + path);
  return u;
}

// ---------------------------------------------------------------------------------------------
// Errors against the reference, CSV, table

double num(const json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : NaN;
}

// ‖u_ref − P u_h‖_E / ‖u_ref‖_E for every run of one scene that has a solution. Runs only after all
// children have finished, so the reference K (≈ 100 MB at R = 512) never inflates a child's RSS.
void compute_errors(const StudyOptions& o, const std::vector<Case>& cases, std::vector<Result>& results,
                    const std::string& scene, size_t ref_index, const std::string& runs) {
  const Case& rc = cases[ref_index];
  if (!has_solution(results[ref_index])) {
    std::cout << "  " << scene << ": reference run " << rc.backend.label() << " at level " << rc.level
              << " has no solution (" << results[ref_index].status << "): no errors\n";
    return;
  }
  if (results[ref_index].status != "ok")
    std::cout << "  warning: " << scene << ": the reference run is '" << results[ref_index].status
              << "'; errors are against it anyway\n";
  const auto scene_at_level = [&](const Case& c) { return load_scene(c.scene_path, overrides(o, c)); };
  const json ref_scene = scene_at_level(rc);
  const Model ref = build_model(ref_scene, scene_directory(rc.scene_path));
  const Vec u_ref = read_u(runs + "/" + rc.stem() + ".u.bin", ref.mesh.num_nodes() * ref.dim());
  const double norm_ref = std::sqrt(std::max(0.0, ref.a(u_ref, u_ref)));
  std::map<int, Mesh> meshes;
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    if (c.scene != scene || !has_solution(results[i])) continue;
    try {
      if (!meshes.count(c.level)) meshes[c.level] = build_mesh(scene_at_level(c), scene_directory(c.scene_path));
      const Mesh& m = meshes[c.level];
      const Vec u = read_u(runs + "/" + c.stem() + ".u.bin", m.num_nodes() * m.dim);
      const Vec Pu = c.level == rc.level ? u : prolongate(m, u, ref.mesh);
      const Vec e = u_ref - Pu;
      results[i].rel_error = std::sqrt(std::max(0.0, ref.a(e, e))) / norm_ref;
    } catch (const std::exception& e) {
      std::cout << "  " << c.stem() << ": error not computed: " << e.what() << "\n";
    }
  }
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char ch : s) q += ch == '"' ? std::string("\"\"") : ch == '\n' ? std::string(" ") : std::string(1, ch);
  return q + "\"";
}

const char* CSV_HEADER =
    "scene,role,level,h,dofs,gamma3_nodes,backend,solved_by,formulation_requested,formulation,eps,status,exit_code,"
    "wall_s,build_s,linear_s,solve_s,ratio,backend_s,cpu_s,peak_rss_mb,linear_rss_mb,outer_iters,backend_iters,"
    "cert_max_residual,n_separated,n_compliance,n_contact,n_stick,n_slip_plus,n_slip_minus,energy,energy_norm,"
    "rel_error,polish,message";

void write_csv(const std::string& path, const std::vector<Case>& cases, const std::vector<Result>& results) {
  std::ofstream out(path);
  out << CSV_HEADER << "\n";
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const Result& r = results[i];
    const json& s = r.stats;
    const double solve_s = num(s, "solve_s"), linear_s = num(s, "linear_s");
    const auto count = [&](const char* k) {
      return s.contains("status_counts") && s["status_counts"].contains(k)
                 ? std::to_string(s["status_counts"][k].get<int>())
                 : std::string();
    };
    const auto inum = [&](const char* k) { return s.contains(k) ? std::to_string(s[k].get<long>()) : std::string(); };
    const std::string role = c.study && c.reference ? "study+reference" : c.reference ? "reference" : "study";
    out << c.scene << "," << role << "," << c.level << "," << fmt(num(s, "h"), 8) << "," << inum("dofs") << ","
        << inum("gamma3_nodes") << "," << csv_field(c.backend.backend) << "," << csv_field(s.value("solved_by", ""))
        << "," << c.backend.formulation << ","
        << s.value("formulation", "") << "," << c.eps << "," << r.status << ","
        << (r.exit_code >= 0 ? std::to_string(r.exit_code) : "") << "," << fmt(r.wall) << "," << fmt(num(s, "build_s"))
        << "," << fmt(linear_s) << "," << fmt(solve_s) << "," << fmt(solve_s / linear_s) << ","
        << fmt(num(s, "backend_s")) << "," << fmt(r.cpu) << "," << fmt(r.rss_mb, 5) << ","
        << fmt(num(s, "linear_rss_mb"), 5) << "," << inum("outer_iters") << "," << inum("backend_iters") << ","
        << fmt(num(s, "cert_max_residual"), 4) << "," << count("separated") << "," << count("compliance") << ","
        << count("contact") << "," << count("stick") << "," << count("slip+") << "," << count("slip-") << ","
        << fmt(num(s, "energy"), 12) << "," << fmt(num(s, "energy_norm"), 12) << "," << fmt(r.rel_error, 6) << ","
        << s.value("polish", "") << "," << csv_field(r.message) << "\n";
  }
}

void print_table(const std::vector<Case>& cases, const std::vector<Result>& results) {
  std::set<std::string> scenes;
  for (const auto& c : cases) scenes.insert(c.scene);
  int bw = 14;  // backend:form column: the longest label + 2
  for (const auto& c : cases) bw = std::max(bw, static_cast<int>(c.backend.label().size()) + 2);
  for (const auto& scene : scenes) {
    std::cout << "\n" << scene << "\n";
    std::cout << std::left << std::setw(5) << "L" << std::right << std::setw(8) << "dofs"
              << "  " << std::left << std::setw(bw) << "backend:form" << std::setw(7) << "eps" << std::setw(15)
              << "status" << std::right << std::setw(9) << "wall s" << std::setw(9) << "solve s" << std::setw(9)
              << "lin s" << std::setw(8) << "ratio" << std::setw(8) << "RSS MB" << std::setw(6) << "outer"
              << std::setw(7) << "b.it" << std::setw(10) << "cert" << std::setw(10) << "rel.err"
              << "\n";
    for (size_t i = 0; i < cases.size(); ++i) {
      const Case& c = cases[i];
      if (c.scene != scene) continue;
      const Result& r = results[i];
      const json& s = r.stats;
      const auto col = [](double v, int w, int prec, bool sci = false) {
        std::ostringstream os;
        if (!std::isfinite(v))
          os << std::setw(w) << "-";
        else if (sci)
          os << std::setw(w) << std::scientific << std::setprecision(prec) << v;
        else
          os << std::setw(w) << std::fixed << std::setprecision(prec) << v;
        return os.str();
      };
      const double solve_s = num(s, "solve_s"), lin = num(s, "linear_s");
      std::cout << std::left << std::setw(5) << (std::to_string(c.level) + (c.reference ? "*" : "")) << std::right
                << std::setw(8) << (s.contains("dofs") ? std::to_string(s["dofs"].get<long>()) : "-") << "  "
                << std::left << std::setw(bw) << c.backend.label() << std::setw(7) << c.eps << std::setw(15) << r.status
                << std::right << col(r.wall, 9, 3) << col(solve_s, 9, 3) << col(lin, 9, 4) << col(solve_s / lin, 8, 1)
                << col(r.rss_mb, 8, 1) << col(num(s, "outer_iters"), 6, 0) << col(num(s, "backend_iters"), 7, 0)
                << col(num(s, "cert_max_residual"), 10, 1, true) << col(r.rel_error, 10, 2, true) << "\n";
    }
  }
  std::cout << "(* = reference run; ratio = solve s / lin s, lin = sparse Cholesky factor+solve of the linear "
               "elastic problem on the same mesh)\n";
}

// ---------------------------------------------------------------------------------------------

std::vector<Case> plan(const StudyOptions& o, const std::map<std::string, std::string>& unavailable) {
  std::vector<Case> cases;
  for (const auto& scene : o.scenes) {
    const std::string path = scene_file(o, scene);
    const std::string name = fs::path(scene).extension() == ".json" ? fs::path(scene).stem().string() : scene;
    for (const int L : o.levels)
      for (const auto& b : o.backends)
        for (const auto& e : o.eps) {
          Case c;
          c.scene = name, c.scene_path = path, c.level = L, c.backend = b, c.eps = e;
          if (unavailable.count(b.backend)) {
            c.status = "unavailable";
            c.note = unavailable.at(b.backend);
          } else if (b.formulation == "full" && L > o.max_full_level) {
            c.status = "skipped";
            c.note = "full formulation above --max-full-level " + std::to_string(o.max_full_level);
          }
          cases.push_back(c);
        }
    if (o.reference <= 0) continue;
    // Reference: the requested backend, else the first available condensed one (then auto, which
    // is condensed for linear materials, then any); at the smallest ε (the most accurate); reused
    // if it is already a study run.
    BackendSpec rb;
    if (!o.reference_backend.empty()) rb = parse_backend(o.reference_backend);
    for (const std::string want : {"condensed", "auto", ""})
      for (const auto& b : o.backends)
        if (rb.backend.empty() && !unavailable.count(b.backend) && (want.empty() || b.formulation == want)) rb = b;
    if (rb.backend.empty() || unavailable.count(rb.backend)) {
      std::cout << "warning: " << name << ": no available backend for the reference run: no errors\n";
      continue;
    }
    std::string eps = o.eps.front();
    for (const auto& e : o.eps)
      if (std::stod(e) < std::stod(eps)) eps = e;
    bool found = false;
    for (auto& c : cases)
      if (c.scene == name && c.level == o.reference && c.backend.label() == rb.label() && c.eps == eps) {
        c.reference = found = true;
        c.status.clear();  // the reference runs even above --max-full-level
      }
    if (!found) {
      Case c;
      c.scene = name, c.scene_path = path, c.level = o.reference, c.backend = rb, c.eps = eps;
      c.study = false;
      c.reference = true;
      cases.push_back(c);
    }
  }
  return cases;
}

int run(const StudyOptions& o) {
  const std::string runs = o.out + "/runs";
  fs::create_directories(runs);
  set_log_level(LogLevel::WARN);

  // A backend that was not compiled in (make_backend throws) is reported once and skipped.
  std::map<std::string, std::string> unavailable;
  for (const auto& b : o.backends) {
    try {
      if (b.backend != EXACT_SOLVER) make_backend(b.backend);
    } catch (const std::exception& e) {
      if (!unavailable.count(b.backend)) std::cout << "skipping backend '" << b.backend << "': " << e.what() << "\n";
      unavailable[b.backend] = e.what();
    }
  }
  std::vector<Case> cases = plan(o, unavailable);
  std::vector<Result> results(cases.size());
  const size_t todo = std::count_if(cases.begin(), cases.end(), [](const Case& c) { return c.status.empty(); });
  std::cout << "hemicontact_study: " << cases.size() << " cases, " << todo << " to run, each in a forked child "
            << "(parent resident set " << self_rss_text() << "; its anonymous part counts in each child's peak RSS)\n";

  size_t k = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    Result& r = results[i];
    if (!c.status.empty()) {
      r.status = c.status;
      r.message = c.note;
      continue;
    }
    std::cout << "[" << ++k << "/" << todo << "] " << c.scene << " L=" << c.level << " " << c.backend.label()
              << " eps=" << c.eps << (c.reference ? " (reference)" : "") << ": " << std::flush;
    r = run_case(o, c, runs);
    std::cout << r.status << ", " << fmt(r.wall, 3) << " s wall, solve " << fmt(num(r.stats, "solve_s"), 3)
              << " s, linear " << fmt(num(r.stats, "linear_s"), 3) << " s, " << fmt(r.rss_mb, 4) << " MB"
              << (r.status == "ok" || r.message.empty() ? "" : " — " + r.message) << "\n";
  }

  std::vector<std::string> names;
  for (const auto& c : cases)
    if (std::find(names.begin(), names.end(), c.scene) == names.end()) names.push_back(c.scene);
  for (const auto& name : names)
    for (size_t i = 0; i < cases.size(); ++i)
      if (cases[i].scene == name && cases[i].reference) {
        std::cout << "errors of " << name << " against " << cases[i].backend.label() << " at level " << cases[i].level
                  << ", eps " << cases[i].eps << "\n";
        try {
          compute_errors(o, cases, results, name, i, runs);
        } catch (const std::exception& e) {
          std::cout << "  " << name << ": errors not computed: " << e.what() << "\n";
        }
      }

  const std::string csv = o.out + "/study.csv";
  write_csv(csv, cases, results);
  print_table(cases, results);
  std::cout << "wrote " << csv << " (" << cases.size() << " rows)\n";

  if (o.plot && fs::exists("/usr/bin/python3")) {
    const std::string cmd = "/usr/bin/python3 '" + o.plot_script + "' '" + csv + "' --out '" + o.out + "'";
    std::cout << "plotting: " << cmd << "\n" << std::flush;
    const int rc = std::system(cmd.c_str());
    if (rc != 0) std::cout << "plot_study.py failed (status " << rc << "); the CSV is complete\n";
  } else if (o.plot) {
    std::cout << "no /usr/bin/python3: plots skipped (scripts/plot_study.py DIR/study.csv --out DIR)\n";
  }
  // A study in which no case solved says nothing: it fails loudly rather than leave an empty table.
  size_t solved = 0, ran = 0;
  for (const auto& r : results) {
    ran += r.status != "unavailable" && r.status != "skipped";
    solved += r.status == "ok" || r.status == "ok(backend_failed)";
  }
  if (ran > 0 && solved == 0) {
    std::cerr << "hemicontact_study: none of the " << ran << " cases that ran was solved and certified (see "
              << csv << ")\n";
    return EXIT_NOT_CONVERGED;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const StudyOptions o = parse_args(argc, argv);
  try {
    return run(o);
  } catch (const Error& e) {
    std::cerr << "hemicontact_study: " << e.what() << "\n";
    return e.code();
  } catch (const std::exception& e) {
    std::cerr << "hemicontact_study: " << e.what() << "\n";
    return EXIT_INTERNAL;
  }
}
