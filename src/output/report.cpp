#include <hemicontact/output/report.hpp>

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <limits>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

using json = nlohmann::json;

// The backend's smoothed ε-stages that ran, e.g. "0" or "0..2" (empty when none).
std::string stages_run(const Solution& sol) {
  int lo = -1, hi = -1;
  for (const auto& h : sol.history)
    if (h.solver == sol.backend) {
      if (lo < 0) lo = h.stage;
      hi = std::max(hi, h.stage);
    }
  if (lo < 0) return "";
  return lo == hi ? std::to_string(lo) : std::to_string(lo) + ".." + std::to_string(hi);
}

// What each phase of the solve did, and which solver did it: the backend's ε-stages (smoothed
// problem, λ lagged), the exact solver (unsmoothed, Anderson on λ = F_b(u_ν)), the polish, and the
// outer fixed point that wraps the stages.
json phases(const Solution& sol, bool lagged) {
  const SolverWork b = sol.work_of(sol.backend), e = sol.work_of(EXACT_SOLVER);
  json p = json::array();
  json backend = {{"phase", "backend"},
                  {"solver", sol.backend},
                  {"ran", sol.backend_use.ran},
                  {"minimizations", b.minimizations},
                  {"stages", stages_run(sol)},
                  {"iterations", b.iterations},
                  {"evaluations", b.evaluations},
                  {"seconds", b.seconds}};
  if (!sol.backend_use.ran) backend["not_run"] = sol.backend_use.not_run;
  p.push_back(std::move(backend));
  const HandoverReport& h = sol.handover;
  p.push_back({{"phase", "exact"},
               {"solver", EXACT_SOLVER},
               {"ran", h.used},
               {"after_stage", h.after_stage},
               {"reason", h.reason},
               {"lambda_updates", h.outer_iterations},
               {"inner_solves", e.minimizations},
               {"inner_rounds", h.inner_rounds},
               {"newton_steps", h.newton_steps},
               {"seconds", h.seconds}});
  const auto polish_time = sol.timings.find("polish");
  p.push_back({{"phase", "polish"},
               {"solver", "polish"},
               {"ran", sol.polish.attempted},
               {"accepted", sol.polish.accepted},
               {"iterations", sol.polish.iterations},
               {"seconds", polish_time == sol.timings.end() ? 0.0 : polish_time->second}});
  p.push_back({{"phase", "fixed_point"},
               {"solver", b.minimizations && h.used ? sol.backend + " stages, then exact (Anderson)"
                          : h.used                  ? std::string("exact (Anderson)")
                                                    : sol.backend + " stages"},
               {"ran", lagged},
               {"converged", sol.fixed_point_converged},
               {"iterations", b.minimizations + h.outer_iterations}});  // backend stages' updates + Anderson's
  return p;
}

// One line: what the backend did, or why it did not run.
std::string backend_line(const Solution& sol) {
  const std::string name = sol.backend.empty() ? std::string("(none)") : sol.backend;
  const bool auto_pick = sol.backend_use.requested == AUTO_BACKEND;
  const std::string who = name + (auto_pick ? " (solver.backend = auto)" : "");
  if (!sol.backend_use.ran) return who + ": not run: " + sol.backend_use.not_run;
  const SolverWork b = sol.work_of(sol.backend);
  return who + ": " + std::to_string(b.minimizations) + (b.minimizations == 1 ? " minimization" : " minimizations") +
         " (eps-stage " + stages_run(sol) + "), " + std::to_string(b.iterations) + " iterations, " +
         std::to_string(b.evaluations) + " evaluations, " + fmt(b.seconds, 3) + " s";
}

// One line: what the exact solver did (empty when it did not run).
std::string exact_line(const Solution& sol) {
  const HandoverReport& h = sol.handover;
  if (!h.used) return "";
  // From the start for the reason the backend did not run: said once, on the backend's line.
  const bool same = !sol.backend_use.ran && h.reason == sol.backend_use.not_run;
  return std::string(h.after_stage < 0 ? "from the start" : "took over after stage " + std::to_string(h.after_stage)) +
         (same ? std::string() : " (" + h.reason + ")") + ": " + std::to_string(h.outer_iterations) + " lambda updates, " +
         std::to_string(h.inner_rounds) + " rounds, " + std::to_string(h.newton_steps) + " Newton steps, " +
         fmt(h.seconds, 3) + " s";
}

// One line: the polish's verdict (empty when it was neither run nor skipped with a reason).
std::string polish_line(const Solution& sol) {
  if (sol.polish.attempted)
    return std::string(sol.polish.accepted ? "accepted" : "rejected") + ", certificate " + fmt(sol.polish.before, 3) +
           " -> " + fmt(sol.polish.after, 3) + " in " + std::to_string(sol.polish.iterations) + " iterations";
  for (const auto& s : sol.skipped)
    if (s.rfind("polish:", 0) == 0) return "skipped:" + s.substr(7);
  return "";
}

std::map<std::string, double> merged_timings(const Model& md, const Solution& sol) {
  std::map<std::string, double> t = md.timings;
  for (const auto& [k, v] : sol.timings) t[k] = v;
  return t;
}

// NaN marks "not measured"; JSON has no NaN, so it is written as null explicitly.
json finite_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

// "; the solution found is a local minimum (...)", where the second-order check ran.
std::string found_kind(const SecondOrderCheck& c) {
  if (c.verdict == "unchecked") return "";
  return "; the solution found is a " + c.verdict + " (smallest eigenvalue of the reduced Hessian " +
         fmt(c.lambda_min, 3) + ", `minima`'s check)";
}

bool report_ok(const Solution& sol) { return sol.ok(); }

// "  " + words joined by ", ", wrapped before @p width columns; continuation lines indented.
std::string wrap(const std::vector<std::string>& words, size_t indent, size_t width) {
  std::string out, line;
  for (size_t i = 0; i < words.size(); ++i) {
    const std::string w = words[i] + (i + 1 < words.size() ? "," : "");
    if (!line.empty() && indent + line.size() + 1 + w.size() > width) {
      out += line + "\n" + std::string(indent, ' ');
      line.clear();
    }
    line += (line.empty() ? "" : " ") + w;
  }
  return out + line;
}

json certificate_json(const CertificateReport& c, const char* worst_name = "worst") {
  json residuals = json::object();
  for (const auto& e : c.residuals) residuals[e.name] = {{"value", e.value}, {worst_name, e.worst}};
  return {{"passed", c.passed},
          {"tol", c.tol},
          {"max_residual", c.max_residual},
          {"length_scale", c.length_scale},
          {"force_scale", c.force_scale},
          {"traction_scale", c.traction_scale},
          {"residuals", std::move(residuals)}};
}

json fixed_point_json(const Solution& sol, const SolveOptions& opt) {
  json history = json::array();
  for (const auto& h : sol.history)
    history.push_back({{"k", h.k},
                       {"stage", h.stage},
                       {"eps_tau", h.eps_tau},
                       {"eps_nu", h.eps_nu},
                       {"change_u", h.change_u},
                       {"change_lambda", h.change_lambda},
                       {"grad_norm", h.grad_norm},
                       {"delta_lambda", h.delta_lambda},
                       {"contraction", finite_or_null(h.contraction)},
                       {"backend_status", to_string(h.backend.status)},
                       {"backend_iterations", h.backend.iterations},
                       {"backend_evaluations", h.backend.evaluations},
                       {"backend_seconds", h.backend.seconds},
                       {"backend_message", h.backend.message},
                       {"solver", h.solver}});
  // contraction: ρ_k per outer iteration (null where undefined, see OuterIteration::contraction);
  // contraction_estimate: their geometric mean, the observed factor of the relaxed map.
  json contraction = json::array();
  for (const auto& h : sol.history) contraction.push_back(finite_or_null(h.contraction));
  return {{"converged", sol.fixed_point_converged},
          {"iterations", sol.history.size()},
          {"relaxation", opt.relaxation},
          {"contraction", std::move(contraction)},
          {"contraction_estimate", finite_or_null(sol.contraction_estimate)},
          {"history", std::move(history)}};
}

// A number of a report read back: null is what a NaN or infinity was written as.
double number_at(const json& j, const char* key) {
  const json& v = j.at(key);
  return v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>();
}

// One entry of fixed_point_json's history, read back.
OuterIteration outer_iteration_from(const json& h) {
  OuterIteration it;
  it.k = h.at("k").get<int>();
  it.stage = h.at("stage").get<int>();
  it.eps_tau = number_at(h, "eps_tau");
  it.eps_nu = number_at(h, "eps_nu");
  it.change_u = number_at(h, "change_u");
  it.change_lambda = number_at(h, "change_lambda");
  it.grad_norm = number_at(h, "grad_norm");
  it.delta_lambda = number_at(h, "delta_lambda");
  it.contraction = number_at(h, "contraction");
  it.backend.status = solve_status_from(h.at("backend_status").get<std::string>());
  it.backend.iterations = h.at("backend_iterations").get<int>();
  it.backend.evaluations = h.at("backend_evaluations").get<int>();
  it.backend.seconds = number_at(h, "backend_seconds");
  it.backend.message = h.at("backend_message").get<std::string>();
  it.solver = h.at("solver").get<std::string>();
  return it;
}


json options_json(const SolveOptions& opt) {
  return {{"backend", opt.backend},
          {"tol", opt.backend_options.tol},
          {"max_iter", opt.backend_options.max_iter},
          {"backend_options", opt.backend_options.extra},
          {"eps_tau", opt.eps_tau},
          {"eps_nu", opt.eps_nu},
          {"eps_start", opt.eps_start},
          {"eps_factor", opt.eps_factor},
          {"tol_u", opt.tol_u},
          {"max_outer", opt.max_outer},
          {"relaxation", opt.relaxation},
          {"allow_not_converged", opt.allow_not_converged},
          {"certificate_tol", opt.certificate_tol},
          {"status_tol", opt.status_tol}};
}

// The exact solver's part.
json inner_json(const HandoverReport& h) {
  return {{"handover",
           {{"used", h.used},
            {"after_stage", h.after_stage},
            {"reason", h.reason},
            {"outer_iterations", h.outer_iterations},
            {"inner_rounds", h.inner_rounds},
            {"newton_steps", h.newton_steps},
            {"factorizations", h.factorizations},
            {"inner_converged", h.inner_converged},
            {"fixed_point_converged", h.fixed_point_converged},
            {"coupled_residual", h.residual},
            {"seconds", h.seconds},
            {"note", h.note}}}};
}

// How the formulation (and the auto backend) was chosen: the numbers it read and why (method_choice.hpp).
json method_choice_json(const MethodChoice& c) {
  if (c.chosen.empty()) return nullptr;  // a linear solve: nothing was chosen
  json numbers = json::object();
  for (const auto& [k, v] : c.numbers) numbers[k] = finite_or_null(v);
  return {{"chosen", c.chosen},
          {"automatic", c.automatic},
          {"backend", c.backend.empty() ? json(nullptr) : json(c.backend)},
          {"reason", c.reason},
          {"numbers", numbers}};
}

// Whether the inner problem (λ frozen) is strongly convex.
json inner_convexity_json(const InnerConvexity& c) {
  return {{"checked", c.checked},
          {"strongly_convex", c.checked && c.strongly_convex},
          {"softening", finite_or_null(c.softening)},
          {"min_eigenvalue", finite_or_null(c.min_eigenvalue)},
          {"note", c.note}};
}

}  // namespace

json gamma3_row_json(const Gamma3Row& r, int dim) {
  static const char* axes[] = {"x", "y", "z"};
  json n;
  n["node"] = r.node;
  for (int c = 0; c < dim; ++c) n[axes[c]] = r.p[c];
  n["w"] = r.w;
  n["g"] = r.g;
  n["u_nu"] = r.u_nu;
  n["u_tau"] = r.u_tau;
  n["sigma_nu"] = r.sigma_nu;
  n["sigma_tau"] = r.sigma_tau;
  n["xi"] = r.xi;
  n["lambda"] = r.lambda;
  n["status"] = r.status.str();
  if (dim == 3) {
    // 3D: the slip direction replaces 2D's ±; null on sticking nodes (it has no direction).
    if (r.status.tangential == TangentialStatus::SLIP) {
      n["slip_dir"] = {r.slip_dir[0], r.slip_dir[1], r.slip_dir[2]};
      n["slip_angle_deg"] = r.slip_angle_deg;
    } else {
      n["slip_dir"] = nullptr;
      n["slip_angle_deg"] = nullptr;
    }
  }
  return n;
}

json solve_records(const Solution& sol, const SolveOptions& opt, bool lagged) {
  json r;
  // The backend's own work only (the exact solver's inner solves are under phases and inner).
  const SolverWork bt = sol.work_of(sol.backend);
  r["backend"] = {{"name", sol.backend},
                  {"requested", sol.backend_use.requested},
                  {"ran", sol.backend_use.ran},
                  {"not_run", sol.backend_use.ran ? json(nullptr) : json(sol.backend_use.not_run)},
                  {"minimizations", bt.minimizations},
                  {"iterations", bt.iterations},
                  {"evaluations", bt.evaluations},
                  {"seconds", bt.seconds}};
  r["solved_by"] = sol.solved_by();
  r["phases"] = phases(sol, lagged);
  r["certificate"] = certificate_json(sol.certificate);
  r["fixed_point"] = fixed_point_json(sol, opt);
  r["options"] = options_json(opt);
  r["skipped"] = sol.skipped;
  r["formulation"] = sol.formulation;
  r["method_choice"] = method_choice_json(sol.method_choice);
  const SmallnessReport& q = sol.smallness;
  r["smallness"] = {{"computed", q.computed}, {"m_F", q.m_F},
                    {"L_Fb", q.L_Fb},         {"alpha_j", q.alpha_j},
                    {"lambda_1", q.lambda_1}, {"lambda_1nu", q.lambda_1nu},
                    {"lhs", q.lhs},           {"uniqueness_guaranteed", q.computed && q.holds},
                    {"method", q.method},     {"lhs_bracket", {q.lhs_lower, q.lhs_upper}},
                    {"seconds", q.seconds},   {"note", q.note}};
  r["polish"] = {{"attempted", sol.polish.attempted},     {"accepted", sol.polish.accepted},
                 {"iterations", sol.polish.iterations},   {"certificate_before", sol.polish.before},
                 {"certificate_after", sol.polish.after}, {"note", sol.polish.note}};
  r["inner"] = inner_json(sol.handover);
  r["inner_convexity"] = inner_convexity_json(sol.inner_convexity);
  const std::string warning = uniqueness_warning(sol);
  r["uniqueness"] = {{"guaranteed", q.computed && q.holds},
                     {"warning", warning.empty() ? nlohmann::json(nullptr) : nlohmann::json(warning)},
                     {"second_order", {{"verdict", sol.second_order.verdict},
                                       {"lambda_min", finite_or_null(sol.second_order.lambda_min)},
                                       {"note", sol.second_order.note}}}};
  r["scales"] = {{"x_scale", sol.x_scale}, {"f_scale", sol.f_scale}};
  r["message"] = sol.message;
  r["ok"] = report_ok(sol);
  return r;
}

void read_solve_records(const json& r, Solution& sol) {
  const json& b = r.at("backend");
  sol.backend = b.at("name").get<std::string>();
  sol.backend_use.requested = b.at("requested").get<std::string>();
  sol.backend_use.ran = b.at("ran").get<bool>();
  sol.backend_use.not_run = b.at("not_run").is_null() ? "" : b.at("not_run").get<std::string>();
  const json& fp = r.at("fixed_point");
  sol.fixed_point_converged = fp.at("converged").get<bool>();
  sol.contraction_estimate = number_at(fp, "contraction_estimate");
  sol.history.clear();
  for (const json& h : fp.at("history")) sol.history.push_back(outer_iteration_from(h));
  sol.backend_ok = sol.history.empty() || sol.history.back().backend.ok();
  sol.skipped = r.at("skipped").get<std::vector<std::string>>();
  sol.formulation = r.at("formulation").get<std::string>();
  sol.x_scale = number_at(r.at("scales"), "x_scale");
  sol.f_scale = number_at(r.at("scales"), "f_scale");
  const json& p = r.at("polish");
  sol.polish.attempted = p.at("attempted").get<bool>();
  sol.polish.accepted = p.at("accepted").get<bool>();
  sol.polish.iterations = p.at("iterations").get<int>();
  sol.polish.before = number_at(p, "certificate_before");
  sol.polish.after = number_at(p, "certificate_after");
  sol.polish.note = p.at("note").get<std::string>();
  sol.message = r.at("message").get<std::string>();
}

json make_report(const Model& md, const Solution& sol, const SolveOptions& opt) {
  if (sol.state.u_nu.size() != md.contact.size() || static_cast<Index>(sol.status.size()) != md.contact.size())
    throw Error("make_report: the solution does not match the model (was evaluate_solution() called?)", EXIT_INTERNAL);
  return make_report(md, summary_facts(md, sol), sol, opt);
}

json make_report(const Model& md, const SummaryFacts& f, const Solution& sol, const SolveOptions& opt,
                 const char* worst_name) {
  json r = solve_records(sol, opt, md.friction && md.friction->depends_on_u_nu());
  r["scene"] = md.scene;
  r["version"] = HEMICONTACT_VERSION;
  r["mesh"] = {{"origin", f.origin}, {"dim", f.dim},          {"nodes", f.nodes},
               {"cells", f.cells},   {"gamma3_nodes", static_cast<long>(f.rows.size())}, {"h", f.h}};
  r["dofs"] = f.dofs;
  r["material"] = material_json(md);
  r["laws"] = laws_json(md);
  r["energy"] = sol.energy;
  r["energy_norm"] = sol.energy_norm;
  r["a_uu"] = sol.a_uu;
  r["elastic_energy"] = sol.elastic_energy;  // ∫W(ε(u)); = a_uu/2 for a linear F (a_uu uses K(0) otherwise)
  r["f_u"] = sol.f_u;
  r["j_term"] = sol.j_term;
  r["friction_term"] = sol.friction_term;
  r["max_u_nu"] = sol.max_u_nu;
  r["status_counts"] = sol.status_counts();
  r["certificate"] = certificate_json(sol.certificate, worst_name);
  json nodes = json::array();
  for (const Gamma3Row& row : f.rows) nodes.push_back(gamma3_row_json(row, f.dim));
  r["nodes"] = std::move(nodes);
  r["timings"] = f.timings;
  return r;
}

json material_json(const Model& md) {
  return {{"description", md.material->describe()},
          {"m_F", md.material->m_F()},
          {"L_F", md.material->L_F()},
          {"is_linear", md.material->is_linear()}};
}

json laws_json(const Model& md) {
  return {{"normal_law", md.normal_law ? json(md.normal_law->describe()) : json(nullptr)},
          {"friction", md.friction ? json(md.friction->describe()) : json(nullptr)},
          {"gap", md.gap.describe()}};
}

void write_report(const std::string& path, const json& report) {
  // Non-finite doubles become null here (nlohmann's serializer), so the file is always valid JSON.
  write_text_file(path, report.dump(2) + '\n');
}

namespace {

// "a x2, b x3": consecutive equal statuses run-length compressed.
std::string runs_of(const std::vector<std::string>& statuses) {
  std::string out;
  for (size_t i = 0; i < statuses.size();) {
    size_t j = i + 1;
    while (j < statuses.size() && statuses[j] == statuses[i]) ++j;
    if (!out.empty()) out += ", ";
    out += statuses[i] + " x" + std::to_string(j - i);
    i = j;
  }
  return out;
}

std::vector<std::string> status_strings(const Solution& sol) {
  std::vector<std::string> out;
  for (const auto& s : sol.status) out.push_back(s.str());
  return out;
}

}  // namespace

std::string status_runs(const Solution& sol) { return runs_of(status_strings(sol)); }

std::string uniqueness_warning(const Solution& sol) {
  const SmallnessReport& q = sol.smallness;
  const InnerConvexity& c = sol.inner_convexity;
  // (21) decided and failing (an undecided bracket is not computed), and the inner problem (λ
  // frozen) not known to be strongly convex: Π_λ may have several stationary points.
  if (!q.computed || q.holds || (c.checked && c.strongly_convex)) return "";
  return "(21) fails (" + fmt(q.lhs, 4) + " >= m_F = " + fmt(q.m_F, 4) + ") and the inner problem is " +
         (c.checked ? "not convex (smallest eigenvalue " + fmt(c.min_eigenvalue, 3) + ")"
                    : "not known to be convex (" + c.note + ")") +
         ": other certified solutions may exist; `hemicontact minima SCENE` finds them from many starts "
         "and classifies each (local minimum or saddle), `hemicontact path SCENE --load 0,1` says which one a "
         "load history reaches" + found_kind(sol.second_order);
}

SummaryFacts summary_facts(const Model& md, const Solution& sol) {
  SummaryFacts f;
  f.origin = md.mesh.origin;
  f.nodes = static_cast<long>(md.mesh.num_nodes());
  f.cells = static_cast<long>(md.mesh.num_cells());
  f.dofs = static_cast<long>(md.dofs.n_free());
  f.h = md.mesh.max_edge_length();
  f.dim = md.dim();
  f.linear = md.material->is_linear();
  for (Index k = 0; k < md.contact.size(); ++k) f.rows.push_back(gamma3_row(md, sol, k));
  f.timings = merged_timings(md, sol);
  return f;
}

std::string summary_table(const Model& md, const Solution& sol) { return summary_table(summary_facts(md, sol), sol); }

// The summary's column: where every row's text starts, and its wrapped lines.
constexpr size_t SUMMARY_COLUMN = 14;

std::string summary_row(const std::string& label, const std::string& text) {
  return label + std::string(SUMMARY_COLUMN > label.size() ? SUMMARY_COLUMN - label.size() : 1, ' ') + text + "\n";
}

std::string summary_table(const SummaryFacts& md, const Solution& sol) {
  const size_t indent = SUMMARY_COLUMN;
  const auto& row = summary_row;
  std::string out;
  std::vector<std::string> statuses;
  for (const Gamma3Row& r : md.rows) statuses.push_back(r.status.str());
  const size_t nc = statuses.size();
  out += row("mesh", (md.origin.empty() ? std::string() : md.origin + ": ") + std::to_string(md.nodes) + " nodes, " +
                         std::to_string(md.cells) + " cells, " + std::to_string(nc) + " gamma3 nodes, h = " + fmt(md.h));
  out += row("dofs", std::to_string(md.dofs));
  if (const MethodChoice& c = sol.method_choice; !c.chosen.empty())
    out += row("method", c.chosen + (c.automatic ? " (auto): " : ": ") + c.reason);
  out += row("backend", backend_line(sol));
  if (const std::string e = exact_line(sol); !e.empty()) out += row("exact solver", e);
  if (const std::string p = polish_line(sol); !p.empty()) out += row("polish", p);
  out += row("solved by", sol.solved_by());
  out +=
      row("energy", fmt(sol.energy, 10) + "  (" + std::string(md.linear ? "a(u,u)/2" : "int W(eps(u))") +
                        " = " + fmt(sol.elastic_energy) + ", f(u) = " + fmt(sol.f_u) + ", j = " + fmt(sol.j_term) +
                        ", friction = " + fmt(sol.friction_term) + ")");
  out += row("energy_norm", fmt(sol.energy_norm, 10));
  out += row("max_u_nu", fmt(sol.max_u_nu, 10));

  // Status counts: normal | tangential, one column each, counts under their names.
  const auto counts = sol.status_counts();
  std::vector<std::string> names = {"separated", "compliance", "contact", "|", "stick", "slip+", "slip-"};
  if (md.dim == 3 || (counts.count("slip") && counts.at("slip") > 0)) names.push_back("slip");
  std::string head, vals;
  for (const auto& n : names) {
    const std::string v = n == "|" ? "|" : std::to_string(counts.count(n) ? counts.at(n) : 0);
    const size_t w = std::max(n.size(), v.size()) + 2;
    head += n + std::string(w - n.size(), ' ');
    vals += v + std::string(w - v.size(), ' ');
  }
  while (!head.empty() && head.back() == ' ') head.pop_back();
  while (!vals.empty() && vals.back() == ' ') vals.pop_back();
  out += row("status", head);
  out += row("", vals);
  if (nc > 0) {
    if (nc <= 33)
      out += row("gamma3 nodes", wrap(statuses, indent, 100));
    else
      out += row("gamma3 runs", runs_of(statuses));
  }

  const CertificateReport& c = sol.certificate;
  std::string worst;
  double worst_value = -1;
  for (const auto& e : c.residuals)
    if (e.value > worst_value) worst_value = e.value, worst = e.name;
  out += row("certificate", std::string(c.passed ? "passed" : "FAILED") + ": max residual " + fmt(c.max_residual, 3) +
                                (c.passed ? " <= " : " > ") + "tol " + fmt(c.tol, 3) +
                                (worst.empty() ? std::string() : " (" + worst + ")"));
  if (sol.smallness.computed)
    out += row("(21)", "L_Fb/lambda_1 + alpha/lambda_1nu " +
                           (sol.smallness.method == "bound" ? std::string(sol.smallness.holds ? "<= " : ">= ")
                                                            : std::string("= ")) +
                           fmt(sol.smallness.lhs, 4) + (sol.smallness.holds ? " < " : " >= ") + "m_F = " +
                           fmt(sol.smallness.m_F, 4) + ": uniqueness guaranteed: " +
                           (sol.smallness.holds ? "yes" : "no") +
                           (sol.smallness.method == "bound" ? " (bound from the condensed stiffness)" : ""));
  if (const std::string w = uniqueness_warning(sol); !w.empty()) out += row("uniqueness", "NOT guaranteed: " + w);
  out += row("fixed point", std::string(sol.fixed_point_converged ? "converged" : "NOT converged") +
                                (sol.backend_ok ? "" : "; last minimization FAILED"));
  std::vector<std::string> times;
  for (const auto& [k, v] : md.timings) times.push_back(k + " " + fmt(v, 3) + " s");
  if (!times.empty()) out += row("times", wrap(times, indent, 100));
  if (!sol.message.empty()) out += row("message", sol.message);
  return out;
}

}  // namespace hemicontact
