// hemicontact_stress_report — the full numerical stress report: where the solver holds, and where it
// fails honestly.
//
// Three parts, each a CSV and a markdown table in the output directory (plus stress-report.md, all
// tables together):
//   cases   every stress case of tests/stress at a finer mesh than CI (--n, default 64): scale
//           invariance (loads × s with E, c_i × s; lengths × L), κ → 0.499 plane strain, E over
//           1e-3..1e9, c1 over 1e-2..1e8 with the Signorini limit (distance to the gap-0
//           frictionless solution as c1 grows), μ over 0..5, g = 0 and huge, ε over 1e-2..1e-12,
//           Γ3 entirely separated and entirely at g, distorted meshes (30% of h), a 100:1 body.
//           Each row: case, what was checked, outcome, certificate, iterations, time.
//   random  --seeds N randomized scenes (tests/stress/random_scenes.hpp, seeds 1..N, n in
//           [--n-min, --n-max]) with the solver's default budgets: certified, honest
//           non-convergence (which reason), or input error (an inverted perturbed mesh).
//   theta   the outer fixed point λ = F_b(u_ν): contraction factor, iterations and success for
//           θ ∈ {1, 0.75, 0.5, 0.25} over a μ × c1 grid on the sliding scene of
//           tests/stress/fixed_point_test.cpp (every Γ3 node slipping, no obstacle).
//
// Sample runs:
//   hemicontact_stress_report --out docs/stress
//   hemicontact_stress_report --out /tmp/stress --parts random --seeds 50 --n-min 8 --n-max 16
// Everything runs in this process, one solve after another; a crash would end the report (none is
// expected: that is one of the things it checks).

#include "stress/random_scenes.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/options.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include "bench_limits.hpp"
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace hemicontact;
namespace fs = std::filesystem;

namespace {

using clk = std::chrono::steady_clock;
double since(clk::time_point t0) { return std::chrono::duration<double>(clk::now() - t0).count(); }

const std::string FIG2 = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json";

std::string g3(double x) {
  if (std::isnan(x)) return "—";
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

/// What one solve gave.
struct Outcome {
  bool input_error = false;
  std::string outcome;  // "certified", "not converged: fixed point", ..., "input error"
  bool ok = false;
  double certificate = NAN;
  int outer = 0;
  long backend_iterations = 0;
  double rho = NAN;
  double seconds = 0;
  std::string message;
  Vec u;
  std::vector<NodeStatus> status;
  std::map<std::string, int> counts;
  bool finite = true;
};

Outcome run(const std::vector<std::string>& overrides, const std::string& scene = FIG2) {
  Outcome o;
  const auto t0 = clk::now();
  try {
    const nlohmann::json s = load_scene(scene, overrides);
    const Model md = build_model(s, ".");
    const Solution sol = solve(md, solve_options_from_scene(s));
    o.ok = sol.ok();
    o.certificate = sol.certificate.max_residual;
    o.outer = static_cast<int>(sol.history.size());
    for (const auto& h : sol.history) o.backend_iterations += h.backend.iterations;
    o.rho = sol.contraction_estimate;
    o.message = sol.message;
    o.u = sol.u;
    o.status = sol.status;
    o.counts = sol.status_counts();
    o.finite = sol.u.allFinite() && std::isfinite(sol.energy);
    o.outcome = sol.ok()                     ? "certified"
                : !sol.fixed_point_converged ? "not converged: fixed point"
                : !sol.backend_ok            ? "not converged: backend"
                                             : "certificate failed";
  } catch (const Error& e) {
    o.input_error = e.code() == EXIT_INPUT;
    o.outcome = o.input_error ? "input error" : "error (exit " + std::to_string(e.code()) + ")";
    o.message = e.what();
  }
  o.seconds = since(t0);
  return o;
}

int count(const Outcome& o, const std::string& status) {
  const auto it = o.counts.find(status);
  return it == o.counts.end() ? 0 : it->second;
}

double rel_diff(const Vec& a, const Vec& b) {
  if (a.size() != b.size() || a.size() == 0) return NAN;
  const double s = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  return s > 0 ? (a - b).cwiseAbs().maxCoeff() / s : 0.0;
}

std::string csv_quote(std::string s) {
  for (char& c : s)
    if (c == '\n') c = ' ';
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string md_cell(std::string s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
  return out;
}

// ============================================================== cases

struct CaseRow {
  std::string name, checked, verdict;  // verdict: "pass" / "FAIL" and the measured value
  Outcome o;
};

std::string pass(bool p) { return p ? "pass" : "FAIL"; }

// The stress cases, run in order; each adds its rows (and a progress line on stderr).
struct CaseRunner {
  int n;
  std::string N;  // "mesh.n=<n>"
  std::vector<CaseRow> rows;

  explicit CaseRunner(int n_) : n(n_), N("mesh.n=" + std::to_string(n_)) {}
  std::vector<std::string> base(std::vector<std::string> extra) const {
    std::vector<std::string> o{N, "check.smallness=false"};
    o.insert(o.end(), extra.begin(), extra.end());
    return o;
  }
  static bool honest(const Outcome& o) {
    return o.finite && !o.outcome.empty() && (o.ok ? o.certificate <= 1e-8 : !o.message.empty());
  }
  void add(std::string name, std::string checked, bool p, std::string measured, Outcome o) {
    rows.push_back(
        {std::move(name), std::move(checked), pass(p) + (measured.empty() ? "" : " (" + measured + ")"), std::move(o)});
    std::fprintf(stderr, "  %-34s %-5s %s  %.2f s\n", rows.back().name.c_str(), pass(p).c_str(),
                 rows.back().o.outcome.c_str(), rows.back().o.seconds);
  }
  Outcome scale_invariance();
  void material_extremes(const Outcome& ref);
  void layer_stiffness();
  void friction_obstacle_smoothing();
  void gamma3_and_meshes();
};

// Returns fig2's own outcome, the reference of the scaled cases.
Outcome CaseRunner::scale_invariance() {
  // ---- scale invariance
  const Outcome ref = run(base({}));
  add("fig2 (reference)", "certified", ref.ok, "", ref);
  for (double s : {1e-6, 1e-3, 1e3, 1e6}) {
    const Outcome o =
        run(base({"loads.scale=" + stress::num(s), "material.E=" + stress::num(2000 * s),
                  "contact.normal_law.c1=" + stress::num(100 * s), "contact.normal_law.c2=" + stress::num(-100 * s),
                  "contact.normal_law.c3=" + stress::num(400 * s)}));
    const double d = rel_diff(o.u, ref.u);
    add("loads, E, c_i × " + g3(s), "same u as fig2: max|Δu|/max|u| ≤ 1e-7, same statuses",
        o.ok && d <= 1e-7 && o.status.size() == ref.status.size(), "Δu " + g3(d), o);
  }
  for (double L : {1e-3, 1e3}) {
    // Lengths × L with stresses unchanged: tractions and p_ν values stay, f0 (force/volume) and
    // c_i (traction/length) scale as 1/L, r_i and g as L; then u_L(Lx) = L u(x).
    std::vector<std::string> o{"mesh.x=[0," + stress::num(L) + "]",
                               "mesh.y=[0," + stress::num(L) + "]",
                               "loads.body_force=[0," + stress::num(-500 / L) + "]",
                               "contact.gap=" + stress::num(0.15 * L),
                               "contact.normal_law.c1=" + stress::num(100 / L),
                               "contact.normal_law.c2=" + stress::num(-100 / L),
                               "contact.normal_law.c3=" + stress::num(400 / L),
                               "contact.normal_law.r1=" + stress::num(0.1 * L),
                               "contact.normal_law.r2=" + stress::num(0.15 * L)};
    for (int i = 0; i < 4; ++i) {
      const double from = i % 2 == 0 ? 0.5 : 0.0, to = i % 2 == 0 ? 1.0 : 0.5;
      o.push_back("boundary.gamma2." + std::to_string(i) + ".from=" + stress::num(from * L));
      o.push_back("boundary.gamma2." + std::to_string(i) + ".to=" + stress::num(to * L));
    }
    const Outcome r = run(base(o));
    const double d = rel_diff(r.u / L, ref.u);
    add("lengths × " + g3(L), "u/L equals fig2's u: max|Δ|/max|u| ≤ 1e-7", r.ok && d <= 1e-7, "Δu " + g3(d), r);
  }

  return ref;
}

void CaseRunner::material_extremes(const Outcome& ref) {
  // ---- material extremes
  for (double nu : {0.45, 0.49, 0.499}) {
    const Outcome o = run(base({"material.plane=strain", "material.nu=" + stress::num(nu)}));
    add("plane strain κ = " + g3(nu), "certified", o.ok, "", o);
  }
  for (double E : {1e-3, 1e0, 1e3, 1e6, 1e9}) {
    const Outcome o = run(base({"material.E=" + stress::num(E)}));
    add("E = " + g3(E) + ", fig2 loads", "certified or an honest verdict", honest(o), o.outcome, o);
  }
  for (double E : {1e-3, 1e9}) {
    const double s = E / 2000;
    const Outcome o =
        run(base({"material.E=" + stress::num(E), "loads.scale=" + stress::num(s),
                  "contact.normal_law.c1=" + stress::num(100 * s), "contact.normal_law.c2=" + stress::num(-100 * s),
                  "contact.normal_law.c3=" + stress::num(400 * s)}));
    const double d = rel_diff(o.u, ref.u);
    add("E = " + g3(E) + ", loads and c_i scaled", "same u as fig2 (≤ 1e-7)", o.ok && d <= 1e-7, "Δu " + g3(d), o);
  }
}

void CaseRunner::layer_stiffness() {
  // ---- the layer's stiffness and the Signorini limit (gap 0, frictionless)
  for (double c1 : {1e-2, 1e0, 1e2, 1e4, 1e6, 1e8}) {
    const Outcome o = run(base({"contact.normal_law.c1=" + stress::num(c1), "contact.normal_law.c2=" + stress::num(-c1),
                                "contact.normal_law.c3=" + stress::num(4 * c1)}));
    add("c1 = " + g3(c1) + " (c2 = −c1, c3 = 4 c1)", "certified or an honest verdict", honest(o), o.outcome, o);
  }
  const std::string frictionless = R"(contact.friction={"type":"none"})";
  const Outcome sig = run(base({"contact.gap=0", frictionless}));
  add("Signorini (g = 0, frictionless)", "certified", sig.ok, "", sig);
  double prev = NAN, prev_c = NAN;
  for (double c1 : {1e2, 1e4, 1e6, 1e7, 1e8}) {
    // A linear stiff layer without obstacle: penetration σ/c1, so once c1 ≫ E (the layer much
    // stiffer than the body: here c1 ≥ 500 E) the distance decays like 1/c1; before, it only
    // has to decrease.
    const Outcome o =
        run(base({"contact.gap=null", frictionless, "contact.normal_law.c1=" + stress::num(c1),
                  "contact.normal_law.c2=" + stress::num(c1), "contact.normal_law.c3=" + stress::num(c1)}));
    const double d = rel_diff(o.u, sig.u);
    const double order = std::isnan(prev) ? NAN : std::log10(d / prev) / std::log10(c1 / prev_c);
    const bool asymptotic = c1 >= 1e6;
    const bool p = o.ok && (std::isnan(order) || (asymptotic ? std::abs(order + 1) <= 0.1 : order < 0));
    add("stiff layer c1 = " + g3(c1) + " → Signorini",
        asymptotic ? "distance to Signorini ∝ 1/c1 (order −1 ± 0.1)" : "distance to Signorini decreases", p,
        "Δu " + g3(d) + (std::isnan(order) ? "" : ", order " + g3(order)), o);
    prev = d, prev_c = c1;
  }
}

void CaseRunner::friction_obstacle_smoothing() {
  // ---- friction
  for (double mu : {0.0, 0.2, 1.0, 2.0, 5.0}) {
    const Outcome o = run(base({"contact.friction.mu=" + stress::num(mu)}));
    add("μ = " + g3(mu), "certified", o.ok, "", o);
  }

  // ---- the obstacle
  {
    const Outcome o = run(base({"contact.gap=0"}));
    add("g = 0", "certified; no u_ν > 0", o.ok && count(o, "compliance") == 0, "", o);
    const Outcome h = run(base({"contact.gap=1e6"}));
    const Outcome none = run(base({"contact.gap=null"}));
    const double d = rel_diff(h.u, none.u);
    add("g = 1e6 (never reached)", "certified, no node at g, same u as no obstacle (≤ 1e-8)",
        h.ok && count(h, "contact") == 0 && d <= 1e-8, "Δu " + g3(d), h);
  }

  // ---- smoothing widths
  Outcome eps_ref;
  for (double eps : {1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2}) {
    const Outcome o = run(base({"solver.eps_tau=" + stress::num(eps), "solver.eps_nu=" + stress::num(eps)}));
    if (eps == 1e-12) eps_ref = o;
    const double d = rel_diff(o.u, eps_ref.u);
    add("ε = " + g3(eps), "certified on the unsmoothed problem", o.ok, "Δu vs ε=1e-12: " + g3(d), o);
  }
}

void CaseRunner::gamma3_and_meshes() {
  // ---- Γ3 all separated / all at g
  {
    const Outcome o = run(base({"loads.body_force=[0,500]", "boundary.gamma2=[]"}));
    add("Γ3 entirely separated (f0 upward)", "certified, every node separated",
        o.ok && count(o, "separated") == static_cast<int>(o.status.size()), "", o);
    const Outcome a = run(base({"loads.body_force=[0,-50000]", "boundary.gamma2=[]", "contact.gap=0.01"}));
    // The two end nodes of Γ3 touch Γ1/Γ2 corners; all free Γ3 nodes must be at g.
    add("Γ3 entirely at g (f0 = −5e4, g = 0.01)", "certified, every node at g",
        a.ok && count(a, "contact") == static_cast<int>(a.status.size()),
        std::to_string(count(a, "contact")) + "/" + std::to_string(a.status.size()) + " at g", a);
  }

  // ---- distorted meshes and a long thin body
  for (int seed = 1; seed <= 5; ++seed) {
    // Interior nodes moved by up to 0.3 h (Euclidean): no cell of this (symmetric) mesh can invert
    // below 0.35 h (scene_schema.cpp, mesh.perturb), so each seed must be certified.
    const Outcome o = run(base({"mesh.perturb=0.3", "mesh.seed=" + std::to_string(seed)}));
    add("perturb 0.3 h, seed " + std::to_string(seed), "certified", o.ok, "", o);
  }
  {
    const int ny = std::max(2, n / 16);
    const Outcome o = run({"mesh.n=null", "mesh.x=[0,100]", "mesh.nx=" + std::to_string(100 * ny),
                           "mesh.ny=" + std::to_string(ny), "check.smallness=false"});
    add("aspect 100:1 (" + std::to_string(100 * ny) + "×" + std::to_string(ny) + ")", "certified", o.ok, "", o);
    const Outcome t = run({"mesh.n=null", "mesh.x=[0,0.01]", "mesh.nx=" + std::to_string(ny),
                           "mesh.ny=" + std::to_string(100 * ny), "check.smallness=false"});
    add("aspect 1:100 (" + std::to_string(ny) + "×" + std::to_string(100 * ny) + ")", "certified or honest", honest(t),
        t.outcome, t);
  }
}

std::vector<CaseRow> run_cases(int n) {
  CaseRunner c(n);
  const Outcome ref = c.scale_invariance();
  c.material_extremes(ref);
  c.layer_stiffness();
  c.friction_obstacle_smoothing();
  c.gamma3_and_meshes();
  return c.rows;
}

// ============================================================== random

struct RandomRow {
  stress::RandomScene s;
  Outcome o;
};

std::vector<RandomRow> run_random(int seeds, int n_min, int n_max, int max_iter) {
  std::vector<RandomRow> rows;
  for (int k = 1; k <= seeds; ++k) {
    stress::RandomScene s = stress::draw_scene(static_cast<unsigned>(k), n_min, n_max);
    // A hard draw can keep Ipopt at its 3000-iteration default for minutes (dense condensed
    // Hessian on ~400 Γ3 unknowns); the cap bounds the report's run time and is in its header.
    if (max_iter > 0) s.overrides.push_back("solver.max_iter=" + std::to_string(max_iter));
    rows.push_back({s, run(s.overrides)});
    const Outcome& o = rows.back().o;
    std::fprintf(stderr, "  seed %3d: %-28s cert %-9s outer %3d  %.2f s\n", k, o.outcome.c_str(),
                 g3(o.certificate).c_str(), o.outer, o.seconds);
  }
  return rows;
}

// ============================================================== theta

struct ThetaRow {
  double mu, c_scale, theta;
  Outcome o;
};

std::vector<ThetaRow> run_theta(int n) {
  std::vector<ThetaRow> rows;
  for (double cs : {0.1, 1.0, 10.0})
    for (double mu : {1.0, 3.0, 5.0, 8.0, 12.0, 20.0})
      for (double theta : {1.0, 0.75, 0.5, 0.25}) {
        const Outcome o =
            run({"mesh.n=" + std::to_string(n), "check.smallness=false", "contact.gap=null", "boundary.gamma2=[]",
                 "loads.body_force=[20000,-500]", "contact.normal_law.c1=" + stress::num(100 * cs),
                 "contact.normal_law.c2=" + stress::num(-100 * cs), "contact.normal_law.c3=" + stress::num(400 * cs),
                 "contact.friction.mu=" + stress::num(mu), "solver.fixed_point.relaxation=" + stress::num(theta)});
        rows.push_back({mu, cs, theta, o});
        std::fprintf(stderr, "  c×%-4s mu %-4s theta %-4s: %-28s rho %-7s outer %3d  %.2f s\n", g3(cs).c_str(),
                     g3(mu).c_str(), g3(theta).c_str(), o.outcome.c_str(), g3(o.rho).c_str(), o.outer, o.seconds);
      }
  return rows;
}

// ============================================================== output

// Atomically and never through a link, as the CLI writes (output/output_dir.hpp).
void write(const fs::path& p, const std::string& text) { write_text_file(p.string(), text); }

std::string cases_csv(const std::vector<CaseRow>& rows) {
  std::string t =
      "case,checked,verdict,outcome,certificate,outer_iterations,backend_iterations,contraction,seconds,message\n";
  for (const auto& r : rows)
    t += csv_quote(r.name) + "," + csv_quote(r.checked) + "," + csv_quote(r.verdict) + "," + csv_quote(r.o.outcome) +
         "," + g3(r.o.certificate) + "," + std::to_string(r.o.outer) + "," + std::to_string(r.o.backend_iterations) +
         "," + g3(r.o.rho) + "," + g3(r.o.seconds) + "," + csv_quote(r.o.message) + "\n";
  return t;
}

std::string cases_md(const std::vector<CaseRow>& rows, int n) {
  std::string t =
      "### Stress cases (fig2 scene, n = " + std::to_string(n) +
      " unless stated)\n\n| case | checked | verdict | outcome | certificate | outer it. | backend it. | time (s) |\n"
      "|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    t += "| " + md_cell(r.name) + " | " + md_cell(r.checked) + " | " + md_cell(r.verdict) + " | " +
         md_cell(r.o.outcome) + " | " + g3(r.o.certificate) + " | " + std::to_string(r.o.outer) + " | " +
         std::to_string(r.o.backend_iterations) + " | " + g3(r.o.seconds) + " |\n";
  return t;
}

std::string random_csv(const std::vector<RandomRow>& rows) {
  std::string t =
      "seed,n,E,load_scale,loads_consistent,nu,plane,c1,mu,g,eps,perturb,aspect,outcome,certificate,"
      "outer_iterations,backend_iterations,contraction,seconds,message,command\n";
  for (const auto& r : rows) {
    const auto& s = r.s;
    t += std::to_string(s.seed) + "," + std::to_string(s.n) + "," + g3(s.E) + "," + g3(s.load_scale) + "," +
         (s.loads_consistent ? "yes" : "no") + "," + g3(s.nu) + "," + (s.plane_strain ? "strain" : "stress") + "," +
         g3(s.c1) + "," + g3(s.mu) + "," + (s.gap_none ? std::string("none") : g3(s.g)) + "," + g3(s.eps) + "," +
         g3(s.perturb) + "," + g3(s.aspect) + "," + csv_quote(r.o.outcome) + "," + g3(r.o.certificate) + "," +
         std::to_string(r.o.outer) + "," + std::to_string(r.o.backend_iterations) + "," + g3(r.o.rho) + "," +
         g3(r.o.seconds) + "," + csv_quote(r.o.message) + "," + csv_quote(s.command()) + "\n";
  }
  return t;
}

std::string random_md(const std::vector<RandomRow>& rows, int n_min, int n_max, int max_iter) {
  std::map<std::string, int> count;
  int nonfinite = 0;
  double worst_certified = 0, total = 0, slowest = 0;
  for (const auto& r : rows) {
    ++count[r.o.outcome];
    if (!r.o.finite) ++nonfinite;
    if (r.o.ok) worst_certified = std::max(worst_certified, r.o.certificate);
    total += r.o.seconds;
    slowest = std::max(slowest, r.o.seconds);
  }
  std::string t =
      "### Randomized scenes (" + std::to_string(rows.size()) + " seeds, n = " + std::to_string(n_min) + ".." +
      std::to_string(n_max) + ", " +
      (max_iter > 0 ? "solver.max_iter = " + std::to_string(max_iter) : std::string("default solver budgets")) +
      ")\n\n| outcome | scenes |\n|---|---|\n";
  for (const auto& [k, v] : count) t += "| " + k + " | " + std::to_string(v) + " |\n";
  t += "\nNon-finite u or energy: " + std::to_string(nonfinite) +
       ". Largest certificate among certified: " + g3(worst_certified) + ". Total time " + g3(total) +
       " s, slowest scene " + g3(slowest) + " s.\n";
  t += "\nScenes not certified (random.csv's `command` column reruns each one):\n\n| seed | E | loads | μ | g | ε | "
       "outcome | message |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    if (r.o.ok) continue;
    t += "| " + std::to_string(r.s.seed) + " | " + g3(r.s.E) + " | " + g3(r.s.load_scale) + " | " + g3(r.s.mu) + " | " +
         (r.s.gap_none ? std::string("none") : g3(r.s.g)) + " | " + g3(r.s.eps) + " | " + md_cell(r.o.outcome) + " | " +
         md_cell(r.o.message.substr(0, 160)) + " |\n";
  }
  return t;
}

std::string theta_csv(const std::vector<ThetaRow>& rows) {
  std::string t =
      "c_scale,mu,theta,outcome,contraction,outer_iterations,backend_iterations,certificate,seconds,message\n";
  for (const auto& r : rows)
    t += g3(r.c_scale) + "," + g3(r.mu) + "," + g3(r.theta) + "," + csv_quote(r.o.outcome) + "," + g3(r.o.rho) + "," +
         std::to_string(r.o.outer) + "," + std::to_string(r.o.backend_iterations) + "," + g3(r.o.certificate) + "," +
         g3(r.o.seconds) + "," + csv_quote(r.o.message) + "\n";
  return t;
}

std::string theta_md(const std::vector<ThetaRow>& rows, int n) {
  std::string t =
      "### Outer fixed point: relaxation θ vs μ and the layer's stiffness (sliding scene, n = " + std::to_string(n) +
      ")\n\nEach cell: ✓ certified / ✗ not; outer iterations; ρ = estimated contraction factor "
      "(geometric mean of ‖Δλ^{k+1}‖/‖Δλ^k‖ at the final ε); pred. = max(1 − θ, |1 − θ(1 + a)|) with a = ρ at "
      "θ = 1 when that run converged (the relaxed map's factor for a Jacobian spectrum in [−a, 0]; "
      "best θ* = 2/(2 + a)). (stall): the solver's no-contraction stop; (cap): max_iters reached.\n\n| c_i × | μ | θ = "
      "1 | θ = 0.75 | θ = 0.5 | θ = 0.25 |\n|---|---|---|---|---|---|\n";
  for (size_t i = 0; i + 3 < rows.size(); i += 4) {
    t += "| " + g3(rows[i].c_scale) + " | " + g3(rows[i].mu) + " |";
    // Prediction from the plain loop's factor a (only when θ = 1 converged, so that a is the
    // asymptotic factor): ρ(θ) = max(1 − θ, |1 − θ(1 + a)|) for a Jacobian spectrum in [−a, 0].
    const double a = rows[i].o.ok ? rows[i].o.rho : NAN;
    for (size_t j = i; j < i + 4; ++j) {
      const Outcome& o = rows[j].o;
      const double th = rows[j].theta;
      const std::string pred =
          j == i || std::isnan(a) ? "" : " (pred. " + g3(std::max(1 - th, std::abs(1 - th * (1 + a)))) + ")";
      const std::string why = o.ok ? ""
                              : o.outcome == "not converged: fixed point"
                                  ? (o.message.find("does not contract") != std::string::npos ? " (stall)" : " (cap)")
                                  : " (" + o.outcome + ")";
      t += " " + std::string(o.ok ? "✓" : "✗") + why + " " + std::to_string(o.outer) + " it, ρ " + g3(o.rho) + pred +
           " |";
    }
    t += "\n";
  }
  return t;
}

// The command line (USAGE).
struct ReportArgs {
  std::string out;
  std::string parts = "cases,random,theta";
  int n = 64, seeds = 300, n_min = 8, n_max = 16, n_theta = 16, max_iter = 500;
  bool force = false, help = false;
};

const char* const USAGE =
    "usage: hemicontact_stress_report --out DIR [--parts cases,random,theta] [--n 64] [--seeds 300] [--n-min 8]\n"
    "                                 [--n-max 16] [--n-theta 16] [--max-iter 500] [--force]\n"
    "The numerical stress report: DIR/stress-report.md and a CSV and table per part (DIR follows\n"
    "`hemicontact solve --out`'s rules: earlier results replaced only with --force). Exit codes: 0,\n"
    "1 usage, 2 bad input or output folder.\n";

ReportArgs parse_report_args(int argc, char** argv) {
  ReportArgs A;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("option " + a + " needs a value", EXIT_USAGE);
      return argv[++i];
    };
    const auto integer = [&](long hi) { return static_cast<int>(parse_integer_option(a, value(), 1, hi)); };
    if (a == "--out") A.out = value();
    else if (a == "--parts") A.parts = value();
    else if (a == "--n") A.n = integer(bench::MAX_MESH_N);
    else if (a == "--seeds") A.seeds = integer(bench::MAX_SEEDS);
    else if (a == "--n-min") A.n_min = integer(bench::MAX_MESH_N);
    else if (a == "--n-max") A.n_max = integer(bench::MAX_MESH_N);
    else if (a == "--n-theta") A.n_theta = integer(bench::MAX_MESH_N);
    else if (a == "--max-iter") A.max_iter = integer(bench::MAX_ITERATIONS);
    else if (a == "--force") A.force = true;
    else if (a == "-h" || a == "--help") A.help = true;
    else throw Error("unknown option '" + a + "' (see hemicontact_stress_report --help)", EXIT_USAGE);
  }
  if (!A.help && A.out.empty()) throw Error("missing --out DIR (see hemicontact_stress_report --help)", EXIT_USAGE);
  if (A.n_min > A.n_max) throw Error("--n-min is above --n-max", EXIT_USAGE);
  return A;
}

int report_main(int argc, char** argv) {
  const ReportArgs A = parse_report_args(argc, argv);
  if (A.help) {
    std::fputs(USAGE, stdout);
    return EXIT_OK;
  }
  set_log_level(LogLevel::QUIET);
  const fs::path out(A.out);
  const OutputLock lock = prepare_output_dir(A.out, A.force, {"cases.csv", "cases.md", "random.csv", "random.md",
                                                              "theta.csv", "theta.md", "stress-report.md"});
  const auto want = [&](const std::string& p) { return A.parts.find(p) != std::string::npos; };
  std::string report = "## Numerical stress report\n\nGenerated by `hemicontact_stress_report --out DIR --parts " +
                       A.parts + " --n " + std::to_string(A.n) + " --seeds " + std::to_string(A.seeds) + " --n-min " +
                       std::to_string(A.n_min) + " --n-max " + std::to_string(A.n_max) + " --n-theta " +
                       std::to_string(A.n_theta) + " --max-iter " + std::to_string(A.max_iter) + "`.\n\n";
  const auto t0 = clk::now();
  if (want("cases")) {
    std::fprintf(stderr, "cases (n = %d)\n", A.n);
    const auto rows = run_cases(A.n);
    write(out / "cases.csv", cases_csv(rows));
    write(out / "cases.md", cases_md(rows, A.n));
    report += cases_md(rows, A.n) + "\n";
  }
  if (want("random")) {
    std::fprintf(stderr, "random (%d seeds)\n", A.seeds);
    const auto rows = run_random(A.seeds, A.n_min, A.n_max, A.max_iter);
    write(out / "random.csv", random_csv(rows));
    write(out / "random.md", random_md(rows, A.n_min, A.n_max, A.max_iter));
    report += random_md(rows, A.n_min, A.n_max, A.max_iter) + "\n";
  }
  if (want("theta")) {
    std::fprintf(stderr, "theta (n = %d)\n", A.n_theta);
    const auto rows = run_theta(A.n_theta);
    write(out / "theta.csv", theta_csv(rows));
    write(out / "theta.md", theta_md(rows, A.n_theta));
    report += theta_md(rows, A.n_theta) + "\n";
  }
  char total[64];
  std::snprintf(total, sizeof total, "Total run time: %.0f s.\n", since(t0));
  report += total;
  write(out / "stress-report.md", report);
  std::fprintf(stderr, "%s", total);
  return EXIT_OK;
}

}  // namespace

int main(int argc, char** argv) {
  install_interrupt_handlers();
  return run_program("hemicontact_stress_report", [&] { return report_main(argc, argv); });
}
