// hemicontact_whole_process — what a user waits for: `hemicontact solve SCENE` with default
// settings, start to exit, against a plain linear-elastic program on the same mesh (the yardstick:
// what one linear solve of that size costs), both measured in the same run.
//
// The plain program is what a careful user writes for one linear elastic solve, and nothing else:
//   mesh      the same generator and boundary tags (scene/build_model: build_mesh), timed apart;
//   assemble  P1 plane stress/strain into CSC directly: the pattern from the node graph (each node
//             pair a 2×2 block), element matrices scattered by a position lookup, no triplets;
//             clamped (Γ1) dofs dropped by a renumbering;
//   analyse   cholmod_l_analyze (CHOLMOD's default ordering choice, supernodal);
//   factor    cholmod_l_factorize;  solve  cholmod_l_solve for the body force + Γ2 tractions.
// Each program runs in its own forked child (the solve as `hemicontact solve ... --quiet`), so
// wall time and peak memory (wait4's ru_maxrss) are its own.
//
//   hemicontact_whole_process --levels 256,1024 --backends ipopt,newton --out docs/whole-process
//
// Output: a table on stdout and DIR/whole_process.json (--out) with every number.

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/options.hpp>
#include <hemicontact/mesh/mesh.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/studies/convergence.hpp>

#include "bench_limits.hpp"
#include <cholmod.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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
  std::string scene = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json";
  std::vector<int> levels = {256, 1024};
  std::vector<std::string> backends = {"auto", "ipopt", "newton"};  // auto: what a default solve runs
  std::string cli = HEMICONTACT_CLI_PATH;
  std::string out = "out/whole-process";  // under out/, which git ignores: run from the source tree, never committed
  int repeats = 1;
  bool force = false, help = false;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream in(s);
  for (std::string t; std::getline(in, t, ',');)
    if (!t.empty()) v.push_back(t);
  return v;
}

// ---------------------------------------------------------------- the plain linear program

// Plane stress/strain D (Voigt, engineering shear) from the scene's material block.
Eigen::Matrix3d elasticity(const json& scene) {
  const json& m = scene.at("material");
  const double E = m.at("E").get<double>(), nu = m.at("nu").get<double>();
  const bool strain = m.at("plane").get<std::string>() == "strain";
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
  if (strain) {
    const double c = E / ((1 + nu) * (1 - 2 * nu));
    D << c * (1 - nu), c * nu, 0, c * nu, c * (1 - nu), 0, 0, 0, c * (1 - 2 * nu) / 2;
  } else {
    const double c = E / (1 - nu * nu);
    D << c, c * nu, 0, c * nu, c, 0, 0, 0, c * (1 - nu) / 2;
  }
  return D;
}

struct PlainTimes {
  double mesh = 0, assemble = 0, analyse = 0, factor = 0, solve = 0;
  long dofs = 0, nnz = 0;
  double max_u = 0;
  double f_u = 0;  ///< fᵀu = a(u, u): checked against report.json's f_u of a linear scene
};

// Dof numbering without clamped nodes: each free node's equation number (−1: clamped).
std::vector<long> free_node_numbers(const Mesh& mesh, long& n_free_nodes) {
  const Index N = mesh.num_nodes();
  std::vector<char> clamped(N, 0);
  for (Index f = 0; f < mesh.num_facets(); ++f)
    if (mesh.facet_part[f] == Part::GAMMA1)
      for (int a = 0; a < 2; ++a) clamped[mesh.facets(f, a)] = 1;
  std::vector<long> node_eq(N, -1);
  n_free_nodes = 0;
  for (Index v = 0; v < N; ++v)
    if (!clamped[v]) node_eq[v] = n_free_nodes++;
  return node_eq;
}

// Node graph (upper triangle incl. diagonal, by column): neighbours of each free node.
std::vector<std::vector<long>> node_graph(const Mesh& mesh, const std::vector<long>& node_eq, long n_free_nodes) {
  std::vector<std::vector<long>> nbr(n_free_nodes);
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const long p = node_eq[mesh.cells(c, a)], q = node_eq[mesh.cells(c, b)];
        if (p >= 0 && q >= 0 && p <= q) nbr[q].push_back(p);
      }
  for (auto& v : nbr) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  return nbr;
}

// CSC, upper triangle (stype = 1): column 2q+j holds rows 2p+i for p ≤ q (p = q: i ≤ j). The
// pattern filled in, the values zero; @p colptr the column pointers.
cholmod_sparse* csc_pattern(const std::vector<std::vector<long>>& nbr, std::vector<long>& colptr, cholmod_common& cc) {
  const long n_free_nodes = static_cast<long>(nbr.size()), n = 2 * n_free_nodes;
  colptr.assign(n + 1, 0);
  for (long q = 0; q < n_free_nodes; ++q) {
    const long cnt = 2 * static_cast<long>(nbr[q].size());
    colptr[2 * q + 1] = colptr[2 * q] + cnt - 1;  // column 2q: rows up to 2q
    colptr[2 * q + 2] = colptr[2 * q + 1] + cnt;  // column 2q+1: rows up to 2q+1
  }
  cholmod_sparse* K = cholmod_l_allocate_sparse(n, n, colptr[n], 1, 1, 1, CHOLMOD_REAL, &cc);
  auto* Kp = static_cast<long*>(K->p);
  auto* Ki = static_cast<long*>(K->i);
  auto* Kx = static_cast<double*>(K->x);
  std::copy(colptr.begin(), colptr.end(), Kp);
  for (long q = 0; q < n_free_nodes; ++q)
    for (int j = 0; j < 2; ++j) {
      long k = colptr[2 * q + j];
      for (long p : nbr[q])
        for (int i = 0; i < 2; ++i)
          if (2 * p + i <= 2 * q + j) Ki[k++] = 2 * p + i;
    }
  std::fill(Kx, Kx + colptr[n], 0.0);
  return K;
}

// P1 element matrices scattered into K by a position lookup, and the body force into bx.
void assemble_cells(const Mesh& mesh, const json& scene, const std::vector<long>& node_eq, cholmod_sparse* K,
                    double* bx) {
  const auto* Kp = static_cast<const long*>(K->p);
  const auto* Ki = static_cast<const long*>(K->i);
  auto* Kx = static_cast<double*>(K->x);
  const auto position = [&](long r, long c) {  // entry (r, c), r ≤ c
    return std::lower_bound(Ki + Kp[c], Ki + Kp[c + 1], r) - Ki;
  };
  const Eigen::Matrix3d D = elasticity(scene);
  const auto f0 = scene.at("loads").at("body_force").get<std::vector<double>>();
  const double scale = scene.at("loads").at("scale").get<double>();
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    Eigen::Matrix<double, 3, 2> X;
    for (int a = 0; a < 3; ++a) X.row(a) = mesh.points.row(mesh.cells(c, a));
    Eigen::Matrix2d J;
    J << X(1, 0) - X(0, 0), X(2, 0) - X(0, 0), X(1, 1) - X(0, 1), X(2, 1) - X(0, 1);
    const double area = 0.5 * J.determinant();
    const Eigen::Matrix2d Jit = J.inverse().transpose();
    Eigen::Matrix<double, 3, 2> G;  // barycentric gradients
    G.row(1) = (Jit * Eigen::Vector2d(1, 0)).transpose();
    G.row(2) = (Jit * Eigen::Vector2d(0, 1)).transpose();
    G.row(0) = -G.row(1) - G.row(2);
    Eigen::Matrix<double, 3, 6> B = Eigen::Matrix<double, 3, 6>::Zero();
    for (int a = 0; a < 3; ++a) {
      B(0, 2 * a) = G(a, 0);
      B(1, 2 * a + 1) = G(a, 1);
      B(2, 2 * a) = G(a, 1);
      B(2, 2 * a + 1) = G(a, 0);
    }
    const Eigen::Matrix<double, 6, 6> Ke = area * B.transpose() * D * B;
    for (int a = 0; a < 3; ++a) {
      const long p = node_eq[mesh.cells(c, a)];
      if (p < 0) continue;
      for (int i = 0; i < 2; ++i) bx[2 * p + i] += scale * f0[i] * area / 3;
      for (int bb = 0; bb < 3; ++bb) {
        const long q = node_eq[mesh.cells(c, bb)];
        if (q < 0) continue;
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j) {
            const long r = 2 * p + i, col = 2 * q + j;
            if (r <= col) Kx[position(r, col)] += Ke(2 * a + i, 2 * bb + j);
          }
      }
    }
  }
}

// Γ2 tractions: each facet gives half its length times f2 to its two nodes.
void add_tractions(const Mesh& mesh, const std::vector<long>& node_eq, double* bx) {
  for (Index f = 0; f < mesh.num_facets(); ++f)
    if (mesh.facet_part[f] == Part::GAMMA2 && mesh.facet_load[f] >= 0) {
      const Vec& f2 = mesh.tractions[static_cast<size_t>(mesh.facet_load[f])];
      const double len = mesh.facet_measure(f);
      for (int a = 0; a < 2; ++a) {
        const long p = node_eq[mesh.facets(f, a)];
        if (p >= 0)
          for (int i = 0; i < 2; ++i) bx[2 * p + i] += f2[i] * len / 2;
      }
    }
}

PlainTimes plain_linear(const json& scene) {
  PlainTimes t;
  auto t0 = clk::now();
  const Mesh mesh = build_mesh(scene, HEMICONTACT_SOURCE_DIR "/problems");
  t.mesh = since(t0);
  if (mesh.dim != 2) throw Error("whole_process: the plain program is 2D", EXIT_INPUT);
  t0 = clk::now();
  long n_free_nodes = 0;
  const std::vector<long> node_eq = free_node_numbers(mesh, n_free_nodes);
  const long n = 2 * n_free_nodes;
  const std::vector<std::vector<long>> nbr = node_graph(mesh, node_eq, n_free_nodes);
  cholmod_common cc;
  cholmod_l_start(&cc);
  std::vector<long> colptr;
  cholmod_sparse* K = csc_pattern(nbr, colptr, cc);
  cholmod_dense* b = cholmod_l_zeros(n, 1, CHOLMOD_REAL, &cc);
  auto* bx = static_cast<double*>(b->x);
  assemble_cells(mesh, scene, node_eq, K, bx);
  add_tractions(mesh, node_eq, bx);
  t.assemble = since(t0);
  t.dofs = n;
  t.nnz = colptr[n];
  t0 = clk::now();
  cholmod_factor* L = cholmod_l_analyze(K, &cc);
  t.analyse = since(t0);
  t0 = clk::now();
  cholmod_l_factorize(K, L, &cc);
  t.factor = since(t0);
  if (cc.status != CHOLMOD_OK) throw Error("whole_process: CHOLMOD factorization failed", EXIT_INTERNAL);
  t0 = clk::now();
  cholmod_dense* u = cholmod_l_solve(CHOLMOD_A, L, b, &cc);
  t.solve = since(t0);
  const auto* ux = static_cast<const double*>(u->x);
  for (long i = 0; i < n; ++i) {
    t.max_u = std::max(t.max_u, std::abs(ux[i]));
    t.f_u += bx[i] * ux[i];
  }
  cholmod_l_free_dense(&u, &cc);
  cholmod_l_free_dense(&b, &cc);
  cholmod_l_free_factor(&L, &cc);
  cholmod_l_free_sparse(&K, &cc);
  cholmod_l_finish(&cc);
  return t;
}

// ---------------------------------------------------------------- running children

struct Child {
  int code = -1;
  double wall = 0;
  double peak_mb = 0;
  std::string text;  // the child's result (plain program: JSON of its phases)
};

// Run @p fn in a forked child; its stdout goes to a pipe and comes back in Child::text.
template <class Fn>
Child fork_run(Fn&& fn) {
  int fd[2];
  if (pipe(fd) != 0) throw Error("whole_process: pipe failed", EXIT_INTERNAL);
  std::fflush(nullptr);
  const auto t0 = clk::now();
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    dup2(fd[1], 1);
    const int code = fn();
    std::fflush(nullptr);
    _exit(code);
  }
  close(fd[1]);
  Child c;
  char buf[4096];
  for (ssize_t k; (k = read(fd[0], buf, sizeof buf)) > 0;) c.text.append(buf, static_cast<size_t>(k));
  close(fd[0]);
  int status = 0;
  rusage ru{};
  wait4(pid, &status, 0, &ru);
  c.wall = since(t0);
  c.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  c.peak_mb = static_cast<double>(ru.ru_maxrss) / 1024.0;
  return c;
}

Child run_plain(const json& scene) {
  return fork_run([&]() {
    try {
      const PlainTimes t = plain_linear(scene);
      const json j = {{"mesh", t.mesh},     {"assemble", t.assemble}, {"analyse", t.analyse},
                      {"factor", t.factor}, {"solve", t.solve},       {"dofs", t.dofs},
                      {"nnz_upper", t.nnz}, {"max_u", t.max_u},       {"f_u", t.f_u}};
      std::fputs(j.dump().c_str(), stdout);
      return 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "plain: %s\n", e.what());
      return 5;
    }
  });
}

Child run_cli(const Args& a, int level, const std::string& backend, const fs::path& out) {
  return fork_run([&]() {
    const int null = ::open("/dev/null", O_WRONLY);
    dup2(null, 1);
    std::vector<std::string> argv_s = {a.cli,       "solve", a.scene, "--set",      "mesh.n=" + std::to_string(level),
                                       "--backend", backend, "--out", out.string(), "--force",
                                       "--quiet"};
    std::vector<char*> argv;
    for (auto& s : argv_s) argv.push_back(s.data());
    argv.push_back(nullptr);
    execv(a.cli.c_str(), argv.data());
    return 127;
  });
}

const char* const USAGE =
    "usage: hemicontact_whole_process [--scene FILE] [--levels 256,1024] [--backends auto,ipopt,newton]\n"
    "                                 [--repeats R] [--cli PATH] [--out DIR] [--force]\n"
    "`hemicontact solve` start to exit against a plain linear-elastic program on the same meshes; writes\n"
    "DIR/whole_process.json and each solve's results in DIR/solve_n<level>_<backend> (DIR follows\n"
    "`hemicontact solve --out`'s rules: earlier results replaced only with --force). --levels as\n"
    "`hemicontact converge --levels` (e.g. 8,16,...,128). Exit codes: 0, 1 usage, 2 bad input.\n";

// The options, checked with the CLI's own parsers (--levels: studies/convergence.hpp).
Args parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("option " + s + " needs a value", EXIT_USAGE);
      return argv[++i];
    };
    if (s == "--scene") a.scene = value();
    else if (s == "--levels") a.levels = parse_levels(value());
    else if (s == "--backends") a.backends = split(value());
    else if (s == "--cli") a.cli = value();
    else if (s == "--out") a.out = value();
    else if (s == "--repeats") a.repeats = static_cast<int>(parse_integer_option(s, value(), 1, bench::MAX_REPEATS));
    else if (s == "--force") a.force = true;
    else if (s == "--help" || s == "-h") a.help = true;
    else throw Error("unknown option '" + s + "' (see hemicontact_whole_process --help)", EXIT_USAGE);
  }
  if (a.backends.empty()) throw Error("--backends: no backend given", EXIT_USAGE);
  return a;
}

// The plain program's best of --repeats on one level: its row, and its wall time in @p plain_wall.
json plain_row(const Args& a, int level, const json& scene, double& plain_wall) {
  plain_wall = 1e300;
  Child plain;
  for (int r = 0; r < a.repeats; ++r) {  // best of R: the machine's noise is one-sided
    Child c = run_plain(scene);
    if (c.wall < plain_wall) plain_wall = c.wall, plain = c;
  }
  const json pt = plain.code == 0 ? json::parse(plain.text) : json();
  std::printf("%-6d %-10s %9ld %8.2f %9.0f %8s %7d %.2f/%.2f/%.2f/%.2f/%.2f\n", level, "plain",
              pt.is_null() ? 0L : pt["dofs"].get<long>(), plain.wall, plain.peak_mb, "1.00", plain.code,
              pt.value("mesh", 0.0), pt.value("assemble", 0.0), pt.value("analyse", 0.0), pt.value("factor", 0.0),
              pt.value("solve", 0.0));
  return {{"n", level}, {"program", "plain"}, {"wall", plain.wall}, {"peak_mb", plain.peak_mb}, {"exit", plain.code},
          {"phases", pt}};
}

// `hemicontact solve --backend B` on one level, best of --repeats: its row.
json solve_row(const Args& a, int level, const std::string& backend, double plain_wall) {
  const fs::path out = fs::path(a.out) / ("solve_n" + std::to_string(level) + "_" + backend);
  double best = 1e300;
  Child solve;
  for (int r = 0; r < a.repeats; ++r) {
    Child c = run_cli(a, level, backend, out);
    if (c.wall < best) best = c.wall, solve = c;
  }
  json timings, report;
  std::ifstream in(out / "report.json");
  if (in) report = json::parse(in, nullptr, false);
  if (report.is_object()) timings = report.value("timings", json());
  // What did the work, as the report says (the backend named may have handed over to the exact solver).
  const std::string solved_by = report.is_object() ? report.value("solved_by", "?") : "no report";
  std::string phases;
  for (const char* k : {"smallness", "assembly", "factorization_total", "backend", "polish", "certificate"})
    if (timings.contains(k)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s %.2f ", k, timings[k].get<double>());
      phases += buf;
    }
  std::printf("%-6d %-10s %9s %8.2f %9.0f %8.2f %7d solved by %s; %s\n", level, backend.c_str(), "", solve.wall,
              solve.peak_mb, solve.wall / plain_wall, solve.code, solved_by.c_str(), phases.c_str());
  std::fflush(stdout);
  return {{"n", level},          {"program", "hemicontact solve --backend " + backend},
          {"solved_by", solved_by}, {"wall", solve.wall},
          {"peak_mb", solve.peak_mb}, {"exit", solve.code},
          {"ratio", solve.wall / plain_wall}, {"timings", timings}};
}

int whole_main(int argc, char** argv) {
  const Args a = parse_args(argc, argv);
  if (a.help) {
    std::fputs(USAGE, stdout);
    return EXIT_OK;
  }
  // The CLI's folder rules (output/output_dir.hpp) for this program's own file; each solve's
  // folder inside is the CLI's own (run with --force: it replaces the previous measurement).
  for (const int level : a.levels) (void)load_scene(a.scene, {"mesh.n=" + std::to_string(level)});  // before the folder
  const OutputLock lock = prepare_output_dir(a.out, a.force, {"whole_process.json"});
  json rows = json::array();
  std::printf("%-6s %-10s %9s %8s %9s %8s %7s %s\n", "n", "program", "dofs", "wall s", "peak MB", "ratio", "exit",
              "phases (plain: mesh/assemble/analyse/factor/solve s; solve: report.json timings)");
  for (const int level : a.levels) {
    const json scene = load_scene(a.scene, {"mesh.n=" + std::to_string(level)});
    double plain_wall = 0;
    rows.push_back(plain_row(a, level, scene, plain_wall));
    for (const auto& backend : a.backends) rows.push_back(solve_row(a, level, backend, plain_wall));
  }
  // The scene as the repository names it (problems/...), not where this checkout happens to be.
  std::string scene_name = a.scene;
  const std::string src = HEMICONTACT_SOURCE_DIR "/";
  if (scene_name.rfind(src, 0) == 0) scene_name = scene_name.substr(src.size());
  write_text_file((fs::path(a.out) / "whole_process.json").string(),
                  json{{"scene", scene_name}, {"rows", rows}}.dump(2) + "\n");
  return EXIT_OK;
}

}  // namespace

int main(int argc, char** argv) {
  install_interrupt_handlers();
  return run_program("hemicontact_whole_process", [&] { return whole_main(argc, argv); });
}
