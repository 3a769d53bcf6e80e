#include <hemicontact/solver/adapt.hpp>

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/solver/solve.hpp>

#include <dlfcn.h>

#include <algorithm>
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
  o.blas_threads = a.at("blas_threads").get<int>();
  if (o.landing > 0 && o.landing < 1)
    input_error("adapt.landing: " + std::to_string(o.landing) +
                " aims below the predicted need; use 0 (off) or a factor >= 1");
  o.estimator = parse_estimator(a.at("estimator").get<std::string>());
  o.bisection = parse_bisection_rule(a.at("bisection").get<std::string>());
  return o;
}

namespace {

// The level's record from its model, answer and estimate (the timings apart).
void record_level(AdaptLevel& L, int level, const Model& md, const Solution& sol, const ErrorEstimate& est) {
  L.level = level;
  L.nodes = md.mesh.num_nodes();
  L.cells = md.mesh.num_cells();
  L.dofs = md.dofs.n_free();
  L.contact_nodes = md.contact.size();
  L.estimate = est.relative;
  L.estimate_abs = est.total;
  L.energy_norm = sol.energy_norm;
  L.certificate = sol.certificate.max_residual;
  L.ok = sol.ok();
}

// The next mesh: Dörfler marking, cut by the landing, then bisection; sets L.marked and L.landed.
// Empty (with @p stop = "max_dofs") when the next mesh would exceed max_dofs; else @p u_start is
// this level's u carried to it.
std::optional<Bisection> refine_level(const Model& md, const Solution& sol, const ErrorEstimate& est,
                                      const AdaptOptions& aopt, int level, AdaptLevel& L, std::string& stop,
                                      Vec& u_start) {
  std::optional<Bisection> next;
  std::vector<char> marked = dorfler_mark(est.eta, aopt.theta);
  next = bisect(md.mesh, marked, aopt.bisection);
  // Landing (AdaptOptions::landing): the nodes the target needs at the rate N^(−1/2), with the
  // margin; a bigger Dörfler step is cut to the largest indicators, in proportion to the new
  // nodes it would have made (the closure makes the count approximate, hence the margin).
  const double ratio = L.estimate / aopt.target_error;  // > 1: the target is not reached
  const double need = aopt.landing * ratio * ratio * static_cast<double>(L.nodes);
  const Index n_next = next->mesh.num_nodes();
  if (aopt.landing > 0 && need < static_cast<double>(n_next)) {
    Index k = 0;
    for (char c : marked) k += c;
    const double share = (need - static_cast<double>(L.nodes)) / static_cast<double>(n_next - L.nodes);
    const Index k_land = std::max<Index>(1, std::llround(share * static_cast<double>(k)));
    marked = mark_largest(est.eta, k_land);
    next = bisect(md.mesh, marked, aopt.bisection);
    L.landed = true;
    log_info() << "adapt level " << level << ": landing, the target needs about " << std::llround(need)
               << " nodes (margin " << aopt.landing << "): " << k_land << " of Dörfler's " << k
               << " cells marked, " << next->mesh.num_nodes() << " nodes instead of " << n_next;
  }
  for (char c : marked) L.marked += c;
  // The next mesh's free unknowns are at most 2 per node: refuse it beyond max_dofs.
  if (2 * next->mesh.num_nodes() > aopt.max_dofs) {
    stop = "max_dofs";
    L.marked = 0;
    next.reset();
  } else {
    u_start = prolongate_bisection(*next, sol.u, 2);
  }
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

}  // namespace

AdaptResult run_adaptive(const nlohmann::json& scene, Mesh mesh, const AdaptOptions& aopt, const SolveOptions& sopt,
                         const AdaptLevelSolved& on_level) {
  const auto t_start = clk::now();
  if (mesh.dim != 2) input_error("adapt: adaptive refinement is implemented for 2D meshes only (mesh.type = box is 3D)");
  label_longest_edges(mesh);
  const ScopedBlasThreads blas_threads(aopt.blas_threads);
  SolveOptions level_opt = sopt;
  level_opt.smallness = false;  // evaluated once, on the final mesh (file comment)
  AdaptResult r;
  Vec u_start;  // the previous level's displacement carried to the current mesh
  for (int level = 0;; ++level) {
    const auto t_level = clk::now();
    Model md = build_model(scene, mesh);
    const auto t_solve = clk::now();
    const double build_seconds = since(t_level);
    ContactSolver solver(md, level_opt);
    const double setup_seconds = since(t_solve);
    Solution sol;
    if (u_start.size() == md.mesh.num_nodes() * 2) {
      // Warm start: the interpolated u in the solver's unknowns (reduced, local Γ3 frames).
      const Vec z0 = solver.to_unknowns(md.dofs.to_reduced(u_start));
      sol = solver.solve(&z0);
    } else {
      sol = solver.solve();
    }
    AdaptLevel L;
    L.solve_seconds = since(t_solve);
    L.build_seconds = build_seconds;
    L.setup_seconds = setup_seconds;
    L.contact_seconds = L.solve_seconds - setup_seconds;
    const auto t_estimate = clk::now();
    ErrorEstimate est = estimate_error(md, sol, aopt.estimator);
    L.estimate_seconds = since(t_estimate);
    record_level(L, level, md, sol, est);
    log_info() << "adapt level " << level << ": " << L.dofs << " dofs, estimate " << L.estimate << " ("
               << to_string(aopt.estimator) << "), certificate " << L.certificate;

    std::string stop;
    if (!L.ok) stop = "not certified";
    else if (L.estimate <= aopt.target_error) stop = "target reached";
    else if (level + 1 >= aopt.max_levels) stop = "max_levels";
    std::optional<Bisection> next;
    const auto t_refine = clk::now();
    if (stop.empty()) next = refine_level(md, sol, est, aopt, level, L, stop, u_start);
    L.refine_seconds = since(t_refine);
    L.seconds = since(t_level);
    L.cumulative_seconds = since(t_start);
    r.history.push_back(L);
    if (on_level) on_level(L, md, sol, est);
    if (!stop.empty()) {
      r.stop_reason = stop;
      r.reached = stop == "target reached";
      if (sopt.smallness) final_smallness(solver, sol);
      r.model = std::move(md);
      r.solution = std::move(sol);
      r.estimate = std::move(est);
      return r;
    }
    mesh = std::move(next->mesh);
  }
}

nlohmann::json adapt_report(const AdaptResult& r, const AdaptOptions& aopt) {
  nlohmann::json j;
  j["target_error"] = aopt.target_error;
  j["estimator"] = to_string(aopt.estimator);
  j["theta"] = aopt.theta;
  j["landing"] = aopt.landing;
  j["blas_threads"] = aopt.blas_threads;
  j["bisection"] = aopt.bisection == BisectionRule::BISEC3 ? "bisec3" : "newest_vertex";
  j["max_dofs"] = aopt.max_dofs;
  j["max_levels"] = aopt.max_levels;
  j["reached"] = r.reached;
  j["stop_reason"] = r.stop_reason;
  j["final_estimate"] = r.history.empty() ? 0.0 : r.history.back().estimate;
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
                 {"landed", L.landed}});
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
