#include <hemicontact/studies/convergence.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/fem/prolongation.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/studies/petsc_process.hpp>

#include <algorithm>
#include <memory>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <sstream>

namespace hemicontact {
namespace {

int parse_level(const std::string& s) {
  try {
    size_t pos = 0;
    const long v = std::stol(s, &pos);
    if (pos == s.size() && v > 0 && v <= MAX_LEVEL) return static_cast<int>(v);
  } catch (const std::exception&) {
  }
  throw Error("--levels: expected a positive integer up to " + std::to_string(MAX_LEVEL) +
                  " (2^20 cells per side, the level cap), got '" + s + "'",
              EXIT_USAGE);
}

// A level's effective scene: validate_scene() copies mesh.n into nx and ny.
nlohmann::json scene_at_level(const nlohmann::json& scene, int n) {
  nlohmann::json s = scene;
  s["mesh"]["n"] = n;
  return validate_scene(std::move(s));
}

}  // namespace

EngineChoice convergence_engine(const nlohmann::json& scene, const std::string& scene_dir, int reference,
                                bool petsc_built) {
  const std::string type = scene.at("mesh").at("type").get<std::string>();
  const bool generated = type == "rectangle" || type == "box";
  return choose_engine(generated ? scene_at_level(scene, reference) : scene, scene_dir, petsc_built, false);
}

namespace {

// Does P embed the coarse P1 space into the fine one exactly (nested meshes)? Then every fine
// cell lies inside one coarse cell, and a coarse P1 field is affine on it: its value at the
// fine cell's centroid equals the mean of its prolongated vertex values. A random coarse field
// has a kink across every coarse edge, so a fine cell cut by a coarse edge shows up.
bool is_nested(const Mesh& coarse, const Mesh& fine) {
  const int d = coarse.dim;
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Vec v(coarse.num_nodes() * d);
  for (Index i = 0; i < v.size(); ++i) v[i] = uni(rng);
  const Vec pv = prolongate(coarse, v, fine);
  Mesh centroids;
  centroids.dim = d;
  centroids.points = RowMat::Zero(fine.num_cells(), d);
  for (Index c = 0; c < fine.num_cells(); ++c)
    for (int a = 0; a <= d; ++a) centroids.points.row(c) += fine.points.row(fine.cells(c, a)) / (d + 1);
  const Vec pc = prolongate(coarse, v, centroids);
  for (Index c = 0; c < fine.num_cells(); ++c)
    for (int i = 0; i < d; ++i) {
      double mean = 0;
      for (int a = 0; a <= d; ++a) mean += pv[d * fine.cells(c, a) + i] / (d + 1);
      if (std::abs(mean - pc[d * c + i]) > 1e-9) return false;
    }
  return true;
}

// One solve of the study; fills everything but error and order.
ConvergenceLevel solve_level(const Model& md, const SolveOptions& opt, const nlohmann::json& scene, int n,
                             Solution& sol, const SceneEngine& engine) {
  const auto t0 = std::chrono::steady_clock::now();
  sol = engine(md, opt);
  ConvergenceLevel r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.n = n;
  // The paper's h: the longest side of the rectangle (box) over n.
  double longest = 0;
  for (const char* axis : {"x", "y", "z"})
    if (scene.at("mesh").contains(axis) && scene.at("mesh").at(axis).is_array()) {
      const auto& a = scene.at("mesh").at(axis);
      longest = std::max(longest, a[1].get<double>() - a[0].get<double>());
    }
  r.h = longest / n;
  r.h_max = md.mesh.max_edge_length();
  r.dofs = md.dofs.n_free();
  r.energy_norm = sol.energy_norm;
  r.order = NaN;
  r.status_counts = sol.status_counts();
  r.certificate_residual = sol.certificate.max_residual;
  r.converged = sol.backend_ok && sol.fixed_point_converged;
  r.certified = sol.certificate.passed;
  r.ok = sol.ok();  // the certificate decides, as in `solve` (a backend's own failure does not)
  r.message = sol.message;
  r.solved_by = sol.solved_by();
  r.unique_in_doubt = !uniqueness_warning(sol).empty();
  if (!r.ok)
    log_warn() << "convergence: n = " << n << ": "
               << (r.converged ? "certificate failed (max residual " + csv_number(r.certificate_residual) + ")"
                               : "not converged: " + sol.message);
  return r;
}

}  // namespace

std::vector<int> parse_levels(const std::string& text) {
  std::vector<std::string> tok;
  std::stringstream ss(text);
  for (std::string t; std::getline(ss, t, ',');) tok.push_back(t);
  std::vector<int> r;
  for (size_t i = 0; i < tok.size(); ++i) {
    if (tok[i] != "...") {
      r.push_back(parse_level(tok[i]));
      continue;
    }
    const size_t m = r.size();
    if (m < 2 || i + 1 >= tok.size() || r[m - 1] <= r[m - 2] || r[m - 1] % r[m - 2] != 0)
      throw Error("--levels '" + text +
                      "': '...' needs two increasing levels with an integer ratio before it and "
                      "one level after it, e.g. 4,8,...,128",
                  EXIT_USAGE);
    const long q = r[m - 1] / r[m - 2];
    const int last = parse_level(tok[i + 1]);
    for (long v = static_cast<long>(r.back()) * q; v < last; v *= q) r.push_back(static_cast<int>(v));
  }
  if (r.empty()) throw Error("--levels: no level given", EXIT_USAGE);
  std::sort(r.begin(), r.end());
  r.erase(std::unique(r.begin(), r.end()), r.end());
  return r;
}

ConvergenceStudy run_convergence(const nlohmann::json& scene, const std::string& scene_dir, std::vector<int> levels,
                                 int reference, const LevelSolved& on_level, bool petsc_built) {
  // ---- check the request before any solve
  if (levels.empty()) input_error("convergence: no mesh level given");
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  if (reference < 1 || levels.front() < 1)
    input_error("convergence: mesh levels must be >= 1 (reference " + std::to_string(reference) + ", smallest level " +
                std::to_string(levels.front()) + ")");
  std::string bad;
  for (const int L : levels)
    if (reference % L != 0) bad += (bad.empty() ? "" : ", ") + std::to_string(L);
  if (!bad.empty())
    input_error("convergence: level(s) " + bad + " do not divide the reference level " + std::to_string(reference) +
                " (the meshes must be nested)");
  const std::string type = scene.at("mesh").at("type").get<std::string>();
  if (type != "rectangle" && type != "box")
    input_error("convergence: mesh.type is '" + type +
                "'; a study refines a generated mesh (mesh.type = rectangle or box) through mesh.n");

  // ---- the reference first: every level is measured against it
  ConvergenceStudy st;
  st.scene = scene_at_level(scene, reference);
  log_info() << "convergence: reference n = " << reference;
  const Model ref = build_model(st.scene, scene_dir);
  const SolveOptions ref_opt = solve_options_from_scene(st.scene);
  Solution ref_sol;
  st.reference = solve_level(ref, ref_opt, st.scene, reference, ref_sol,
                             scene_engine(st.scene, scene_dir, petsc_built, "convergence: n = " + std::to_string(reference)));
  st.reference.error = 0;
  if (on_level) on_level(st, reference, ref, ref_sol);
  const double ref_norm = ref_sol.energy_norm;
  if (!(ref_norm > 0)) input_error("convergence: the reference solution is zero (no load?): no relative error");

  // ---- each level, prolongated onto the reference mesh
  for (const int L : levels) {
    ConvergenceLevel lvl;
    Vec Pu;
    std::unique_ptr<Model> level_model;  // the level's own mesh and solution (not the reference's)
    Solution level_sol;
    if (L == reference) {
      lvl = st.reference;
      Pu = prolongate(ref.mesh, ref_sol.u, ref.mesh);
    } else {
      log_info() << "convergence: level n = " << L;
      const nlohmann::json s = scene_at_level(scene, L);
      level_model = std::make_unique<Model>(build_model(s, scene_dir));
      const Model& md = *level_model;
      const SceneEngine engine = scene_engine(s, scene_dir, petsc_built, "convergence: n = " + std::to_string(L));
      lvl = solve_level(md, solve_options_from_scene(s), s, L, level_sol, engine);
      Pu = prolongate(md.mesh, level_sol.u, ref.mesh);
      lvl.nested = is_nested(md.mesh, ref.mesh);
      if (!lvl.nested)
        log_warn() << "convergence: the n = " << L << " mesh is not nested in the reference mesh (" << md.mesh.origin
                   << "): its error includes the interpolation onto the reference mesh";
    }
    const Vec e = ref_sol.u - Pu;  // vanishes on Γ1: the meshes are nested there (generated rectangles, boxes)
    lvl.error = std::sqrt(std::max(0.0, ref.a(e, e))) / ref_norm;
    lvl.order = NaN;
    if (!st.levels.empty()) {
      const ConvergenceLevel& prev = st.levels.back();
      if (prev.error > 0 && lvl.error > 0) lvl.order = std::log(prev.error / lvl.error) / std::log(prev.h / lvl.h);
    }
    st.levels.push_back(lvl);
    // The level with its error: the caller can keep it before the next (longer) solve starts.
    if (on_level && level_model) on_level(st, L, *level_model, level_sol);
  }
  // A nonconvex law's levels may lie on different branches: those are left out of the rate fit.
  for (int n : flag_other_branches(st))
    log_warn() << "convergence: n = " << n << ": "
               << std::find_if(st.levels.begin(), st.levels.end(), [n](const ConvergenceLevel& l) { return l.n == n; })
                      ->other_branch;
  // What did the work, as it ran (not the backend's name where its stage was skipped).
  st.backend.clear();
  std::vector<const ConvergenceLevel*> all{&st.reference};
  for (const auto& l : st.levels) all.push_back(&l);
  for (const ConvergenceLevel* l : all)
    if (st.backend.find(l->solved_by) == std::string::npos || st.backend.empty())
      st.backend += (st.backend.empty() ? "" : ", ") + l->solved_by;
  return st;
}

}  // namespace hemicontact
