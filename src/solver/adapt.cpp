#include <hemicontact/solver/adapt.hpp>

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/solver/solve.hpp>

#include <dlfcn.h>

#include <algorithm>
#include <memory>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <optional>

namespace hemicontact {
namespace {
// OpenBLAS's thread count for a scope (AdaptOptions::blas_threads), restored at its end, also when
// a level throws. Looked up at run time: a build against another BLAS links no OpenBLAS symbol.
class ScopedBlasThreads {
 public:
  explicit ScopedBlasThreads(int n) {
    if (n <= 0 || std::getenv("OPENBLAS_NUM_THREADS")) return;
    auto* get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
    m_set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    if (!get || !m_set) {
      m_set = nullptr;
      return;
    }
    m_old = get();
    if (m_old == n) m_set = nullptr;
    else m_set(n);
  }
  ~ScopedBlasThreads() {
    if (m_set) m_set(m_old);
  }
  ScopedBlasThreads(const ScopedBlasThreads&) = delete;
  ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;

 private:
  void (*m_set)(int) = nullptr;
  int m_old = 0;
};
}  // namespace

AdaptOptions adapt_options_from_scene(const nlohmann::json& scene) {
  const auto& a = scene.at("adapt");
  AdaptOptions o;
  if (!a.at("target_error").is_null()) o.target_error = a.at("target_error").get<double>();
  o.max_dofs = a.at("max_dofs").get<Index>();
  o.max_levels = a.at("max_levels").get<int>();
  o.theta = a.at("theta").get<double>();
  o.landing = a.at("landing").get<double>();
  o.lookahead = a.at("lookahead").get<int>();
  o.blas_threads = a.at("blas_threads").get<int>();
  if (!a.at("reference_energy").is_null()) o.reference_energy = a.at("reference_energy").get<double>();
  if (o.landing > 0 && o.landing < 1)
    input_error("adapt.landing: " + std::to_string(o.landing) +
                " aims below the predicted need; use 0 (off) or a factor >= 1");
  o.estimator = parse_estimator(a.at("estimator").get<std::string>());
  o.bisection = parse_bisection_rule(a.at("bisection").get<std::string>());
  return o;
}

namespace {

// The level's record from its model, answer and estimate (the timings apart).
void record_level(AdaptLevel& L, int level, const Model& md, const Solution& sol, const ErrorEstimate& est,
                  double reference_energy) {
  L.level = level;
  L.nodes = md.mesh.num_nodes();
  L.cells = md.mesh.num_cells();
  L.dofs = md.dofs.n_free();
  L.contact_nodes = md.contact.size();
  L.estimate = est.relative;
  L.estimate_abs = est.total;
  L.energy_norm = sol.energy_norm;
  L.energy = sol.energy;
  L.method = sol.method_choice.chosen;
  L.certificate = sol.certificate.max_residual;
  L.ok = sol.ok();
  // Π(u_h) − Π(u) ≈ ½‖u − u_h‖²_E (AdaptOptions::reference_energy); a level below the reference
  // (round-off, or a reference not fine enough) reads 0.
  if (std::isfinite(reference_energy) && sol.energy_norm > 0)
    L.reference_error = std::sqrt(2 * std::max(0.0, sol.energy - reference_energy)) / sol.energy_norm;
}

// The refinement state the loop carries: the mesh and, in 3D, its tagged tetrahedra.
struct Refinable {
  Mesh mesh;
  TetLabels labels;  // 3D only
};

// A refinement of more than @p max_nodes nodes is counted, not built (Bisection::nodes).
Bisection bisect_any(const Refinable& r, const std::vector<char>& marked, BisectionRule rule, Index max_nodes) {
  return r.mesh.dim == 3 ? bisect(r.mesh, r.labels, marked, rule, max_nodes) : bisect(r.mesh, marked, rule, max_nodes);
}

// The most nodes a mesh the loop may solve has: its free unknowns are at most d per node, and
// d n > max_dofs exactly when n > ⌊max_dofs / d⌋.
Index node_limit(const AdaptOptions& aopt, int d) { return aopt.max_dofs / d; }

// One step: Dörfler's marking of @p eta, cut to the largest indicators when its mesh would have more
// than @p need nodes (AdaptOptions::landing; the closure makes the count approximate, hence the
// margin in need). @p marked and @p landed report what was done.
Bisection refine_once(const Refinable& r, const Vec& eta, double need, const AdaptOptions& aopt, Index& marked,
                      bool& landed) {
  std::vector<char> mark = dorfler_mark(eta, aopt.theta);
  const Index max_nodes = node_limit(aopt, r.mesh.dim);
  Bisection next = bisect_any(r, mark, aopt.bisection, max_nodes);
  const Index n0 = r.mesh.num_nodes(), n_next = next.nodes;
  landed = aopt.landing > 0 && need < static_cast<double>(n_next);
  if (landed) {
    Index k = 0;
    for (char c : mark) k += c;
    const double share = (need - static_cast<double>(n0)) / static_cast<double>(n_next - n0);
    const Index k_land = std::max<Index>(1, std::llround(share * static_cast<double>(k)));
    mark = mark_largest(eta, k_land);
    next = bisect_any(r, mark, aopt.bisection, max_nodes);
    log_info() << "adapt: landing, the target needs about " << std::llround(need) << " nodes (margin " << aopt.landing
               << "): " << k_land << " of Dörfler's " << k << " cells marked, " << next.nodes
               << " nodes instead of " << n_next;
  }
  marked = 0;
  for (char c : mark) marked += c;
  return next;
}

// The indicators predicted on the refined mesh of @p b before it is solved: a child of measure
// ratio r to its parent gets η_parent² r^(1 + 2/d), the decrease of η_T² = O(|T| h_T²) for a smooth
// solution (the cells at a singularity decrease less, so the predicted step under-refines them
// rather than over-refines; the solve that follows measures what it reached).
Vec predicted_indicators(const Mesh& coarse, const Bisection& b, const Vec& eta) {
  const Mesh& fine = b.mesh;
  const double power = 1.0 + 2.0 / fine.dim;
  Vec pred(fine.num_cells());
  for (Index c = 0; c < fine.num_cells(); ++c) {
    const Index p = b.cell_parent[static_cast<size_t>(c)];
    const double ratio = fine.cell_measure(c) / coarse.cell_measure(p);
    pred[c] = eta[p] * std::pow(ratio, 0.5 * power);
  }
  return pred;
}

// The next mesh (file comment of adapt.hpp): up to AdaptOptions::lookahead Dörfler steps, the ones
// after the first on predicted indicators without a solve in between, while the mesh is predicted
// to miss the target; a step cut by the landing is the last. Empty (with @p stop =
// "max_dofs") when the next mesh would exceed max_dofs; else @p u_start is this level's u carried
// to it. Sets L.marked, L.landed, L.steps.
std::optional<Refinable> refine_level(const Refinable& cur, const Solution& sol, const ErrorEstimate& est,
                                      const AdaptOptions& aopt, AdaptLevel& L, std::string& stop, Vec& u_start) {
  const int d = cur.mesh.dim;
  // The nodes the target needs at the optimal rate η ∝ N^(−1/d), with the landing's margin; a
  // need beyond max_dofs (d unknowns per node at most) is cut to 90 % of it (the cut's node count
  // is approximate), once: from a mesh of less than half that, so the loop ends on the largest mesh
  // it may solve instead of the one before it.
  const double ratio = L.estimate / aopt.target_error;  // > 1: the target is not reached
  const double target_need = aopt.landing * std::pow(ratio, d) * static_cast<double>(L.nodes);
  const double cap = 0.9 * static_cast<double>(aopt.max_dofs) / d;
  const double need = static_cast<double>(L.nodes) < 0.5 * cap ? std::min(target_need, cap) : target_need;
  Refinable next;
  Vec eta = est.eta;
  Vec u = sol.u;
  const Refinable* from = &cur;
  for (int step = 1; step <= aopt.lookahead; ++step) {
    Index marked = 0;
    bool landed = false;
    Bisection b = refine_once(*from, eta, need, aopt, marked, landed);
    // A predicted step beyond max_dofs is not taken: the mesh before it is solved.
    if (step > 1 && !b.built) break;
    L.steps = step;
    L.marked += marked;
    L.landed = L.landed || landed;
    // The first step beyond max_dofs: no next mesh (bisect counted its nodes and built nothing).
    if (!b.built) {
      stop = "max_dofs";
      L.marked = 0;
      return std::nullopt;
    }
    u = prolongate_bisection(b, u, d);
    // Another step on predicted indicators while this mesh is predicted to miss the target (its N
    // below N (η/target)^d, the need without the margin) and the lookahead allows one.
    // A step that would grow past max_dofs at this step's growth is not tried.
    const double n_next = static_cast<double>(b.mesh.num_nodes());
    const double growth = n_next / static_cast<double>(from->mesh.num_nodes());
    const bool predict = aopt.landing > 0 && !landed && n_next < target_need / aopt.landing &&
                         d * n_next * growth <= static_cast<double>(aopt.max_dofs);
    if (predict && step < aopt.lookahead) eta = predicted_indicators(from->mesh, b, eta);
    next.mesh = std::move(b.mesh);
    next.labels = std::move(b.labels);
    from = &next;
    if (!predict) break;
  }
  u_start = std::move(u);
  return next;
}

// From the last level's condensation while the solver still holds it: the bracket of
// check/smallness.hpp decides (21) without a factorization (the exact evaluation factorized the
// ε:ε Gram matrix of the final mesh again, ~30 % of the whole adaptive run on the fig2 scene), and
// check.smallness_method = exact, 3D or an undecided bracket still get it.
void final_smallness(const ContactSolver& solver, Solution& sol) {
  sol.smallness = solver.smallness();
  sol.timings["smallness"] = sol.smallness.seconds;
  const SmallnessReport& q = sol.smallness;
  if (q.computed)
    log_info() << "smallness (21) on the final mesh, " << q.method << ": lhs = " << q.lhs
               << (q.holds ? " < " : " >= ") << "m_F = " << q.m_F
               << ": uniqueness guaranteed: " << (q.holds ? "yes" : "no");
}

// The scene's mesh labelled for bisection. 2D: longest edges. 3D: Maubach's tagged tetrahedra
// (Kuhn meshes; a perturbed box labelled on its unperturbed lattice, the same cells) or AMP's
// marked tetrahedra, said in the log and in the mesh's origin (the report's mesh line).
Refinable start_refinable(const nlohmann::json& scene, Mesh mesh) {
  if (mesh.dim == 2) {
    label_longest_edges(mesh);
    return {std::move(mesh), {}};
  }
  std::optional<Mesh> lattice;
  const nlohmann::json& m = scene.at("mesh");
  if (m.at("type") == "box" && m.at("perturb").get<double>() > 0) {
    nlohmann::json unperturbed = scene;
    unperturbed["mesh"]["perturb"] = 0.0;
    lattice = build_mesh(unperturbed, ".");
  }
  LabelledMesh lm = label_for_bisection(std::move(mesh), lattice ? &*lattice : nullptr);
  if (!lm.labels.amp.empty()) {
    log_info() << "adapt: the mesh is not a Kuhn mesh (its longest edges are no compatible Maubach labelling): "
                  "bisection of marked tetrahedra (Arnold, Mukherjee, Pouly 2000), "
               << lm.mesh.num_cells() << " cells as they are";
    lm.mesh.origin += ", bisected as marked tetrahedra (AMP)";
  }
  return {std::move(lm.mesh), std::move(lm.labels)};
}

// The level's solve, from the previous level's u carried to this mesh when there is one.
Solution solve_from(ContactSolver& solver, const Model& md, const Vec& u_start) {
  if (u_start.size() != md.mesh.num_nodes() * md.dim()) return solver.solve();
  // Warm start: the interpolated u in the solver's unknowns (reduced, local Γ3 frames).
  const Vec z0 = solver.to_unknowns(md.dofs.to_reduced(u_start));
  return solver.solve(&z0);
}

}  // namespace

AdaptResult run_adaptive(const nlohmann::json& scene, Mesh mesh, const AdaptOptions& aopt, const SolveOptions& sopt,
                         const AdaptLevelSolved& on_level, const AdaptLevelEngine& level_engine) {
  const auto t_start = clk::now();
  Refinable cur = start_refinable(scene, std::move(mesh));
  const ScopedBlasThreads blas_threads(aopt.blas_threads);
  SolveOptions level_opt = sopt;
  level_opt.smallness = false;  // evaluated once, on the final mesh (file comment)
  AdaptResult r;
  Vec u_start;  // the previous level's displacement carried to the current mesh
  Solution previous;  // the previous level's solution (what the level engine decides on)
  for (int level = 0;; ++level) {
    const auto t_level = clk::now();
    Model md = build_model(scene, cur.mesh);
    const auto t_solve = clk::now();
    const double build_seconds = since(t_level);
    // Another engine where it takes the level, else this process's solver; both from u_start.
    std::optional<Solution> handed =
        level_engine ? level_engine(md, level_opt, r.history.empty() ? nullptr : &previous, u_start) : std::nullopt;
    std::unique_ptr<ContactSolver> solver = handed ? nullptr : std::make_unique<ContactSolver>(md, level_opt);
    const double setup_seconds = handed ? 0.0 : since(t_solve);
    Solution sol = handed ? std::move(*handed) : solve_from(*solver, md, u_start);
    AdaptLevel L;
    L.solve_seconds = since(t_solve);
    L.build_seconds = build_seconds;
    L.setup_seconds = setup_seconds;
    L.contact_seconds = L.solve_seconds - setup_seconds;
    const auto t_estimate = clk::now();
    ErrorEstimate est = estimate_error(md, sol, aopt.estimator);
    L.estimate_seconds = since(t_estimate);
    record_level(L, level, md, sol, est, aopt.reference_energy);
    log_info() << "adapt level " << level << ": " << L.dofs << " dofs, estimate " << L.estimate << " ("
               << to_string(aopt.estimator) << "), certificate " << L.certificate
               << (std::isfinite(L.reference_error) ? ", error against the reference energy " + std::to_string(L.reference_error) : "");

    std::string stop;
    if (!L.ok) stop = "not certified";
    else if (L.estimate <= aopt.target_error) stop = "target reached";
    else if (level + 1 >= aopt.max_levels) stop = "max_levels";
    std::optional<Refinable> next;
    const auto t_refine = clk::now();
    if (stop.empty()) next = refine_level(cur, sol, est, aopt, L, stop, u_start);
    L.refine_seconds = since(t_refine);
    L.seconds = since(t_level);
    L.cumulative_seconds = since(t_start);
    r.history.push_back(L);
    if (on_level) on_level(L, md, sol, est);
    if (!stop.empty()) {
      r.stop_reason = stop;
      r.reached = stop == "target reached";
      if (sopt.smallness && solver) final_smallness(*solver, sol);
      if (sopt.smallness && !solver)
        sol.skipped.push_back("smallness: (21) on the final mesh needs this process's factorization; the petsc "
                              "engine solved that level");
      r.model = std::move(md);
      r.solution = std::move(sol);
      r.estimate = std::move(est);
      return r;
    }
    previous = std::move(sol);
    cur = std::move(*next);
  }
}

nlohmann::json adapt_report(const AdaptResult& r, const AdaptOptions& aopt) {
  nlohmann::json j;
  j["target_error"] = aopt.target_error;
  j["estimator"] = to_string(aopt.estimator);
  j["theta"] = aopt.theta;
  j["landing"] = aopt.landing;
  j["lookahead"] = aopt.lookahead;
  j["blas_threads"] = aopt.blas_threads;
  j["bisection"] = aopt.bisection == BisectionRule::BISEC3 ? "bisec3" : "newest_vertex";
  j["max_dofs"] = aopt.max_dofs;
  j["max_levels"] = aopt.max_levels;
  j["reached"] = r.reached;
  j["stop_reason"] = r.stop_reason;
  j["final_estimate"] = r.history.empty() ? 0.0 : r.history.back().estimate;
  if (std::isfinite(aopt.reference_energy)) {
    j["reference_energy"] = aopt.reference_energy;
    if (!r.history.empty()) j["final_reference_error"] = r.history.back().reference_error;
  }
  j["seconds"] = r.history.empty() ? 0.0 : r.history.back().cumulative_seconds;
  nlohmann::json h = nlohmann::json::array();
  for (const AdaptLevel& L : r.history)
    h.push_back({{"level", L.level},
                 {"nodes", L.nodes},
                 {"cells", L.cells},
                 {"dofs", L.dofs},
                 {"contact_nodes", L.contact_nodes},
                 {"estimate", L.estimate},
                 {"estimate_abs", L.estimate_abs},
                 {"energy_norm", L.energy_norm},
                 {"energy", L.energy},
                 {"seconds", L.seconds},
                 {"solve_seconds", L.solve_seconds},
                 {"build_seconds", L.build_seconds},
                 {"setup_seconds", L.setup_seconds},
                 {"contact_seconds", L.contact_seconds},
                 {"estimate_seconds", L.estimate_seconds},
                 {"refine_seconds", L.refine_seconds},
                 {"cumulative_seconds", L.cumulative_seconds},
                 {"certificate", L.certificate},
                 {"ok", L.ok},
                 {"marked", L.marked},
                 {"steps", L.steps},
                 {"method", L.method},
                 {"landed", L.landed}});
  if (std::isfinite(aopt.reference_energy))
    for (size_t k = 0; k < r.history.size(); ++k) h[k]["reference_error"] = r.history[k].reference_error;
  j["history"] = h;
  return j;
}

nlohmann::json adapt_levels_json(const std::vector<AdaptLevel>& levels, const AdaptOptions& aopt, bool partial) {
  AdaptResult so_far;
  for (const AdaptLevel& k : levels)
    if (k.ok) so_far.history.push_back(k);
  nlohmann::json j = adapt_report(so_far, aopt);
  j["partial"] = partial;
  j["note"] = "the certified levels of an adaptive solve, written after each level (partial: the run had "
              "not finished); report.json, written last, marks a finished run";
  j.erase("reached");
  j.erase("stop_reason");
  return j;
}

nlohmann::json adapt_solve_extra(const AdaptResult& adapted, const AdaptOptions& aopt, std::string& missed) {
  nlohmann::json extra = nlohmann::json::object();
  missed.clear();
  extra["adapt"] = adapt_report(adapted, aopt);
  const AdaptLevel& last = adapted.history.back();
  // A cap that stops the loop above the target is not success. An uncertified level is the
  // verdict's own business (not converged, or the certificate failed).
  if (!adapted.reached && adapted.solution.ok()) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "adapt.target_error = %.3g not met: stopped by adapt.%s at estimate %.3g (%zu levels, %lld dofs); "
                  "raise adapt.%s, or a larger adapt.target_error",
                  aopt.target_error, adapted.stop_reason.c_str(), last.estimate, adapted.history.size(),
                  static_cast<long long>(last.dofs), adapted.stop_reason.c_str());
    missed = buf;
    extra["ok"] = false;
    extra["adapt"]["reason"] = missed;
    extra["message"] = missed + " (the final mesh's answer is certified: " + adapted.solution.message + ")";
  }
  return extra;
}

}  // namespace hemicontact
