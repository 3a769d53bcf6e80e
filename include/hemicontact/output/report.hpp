#pragma once
/// @file report.hpp  The JSON report of a run (report.json) and a short summary for stdout.
///
/// The report's keys are an interface (the CLI, the regression tests and the plotting scripts
/// read them); their names do not change:
///  - "scene": the effective scene (every default injected); "version": HEMICONTACT_VERSION
///  - "mesh": {origin, dim, nodes, cells, gamma3_nodes, h (max edge length)}; "dofs": free unknowns
///  - "material": {description, m_F, L_F}
///  - "laws": {normal_law, friction (describe() or null when absent), gap}
///  - "backend": {name, iterations, evaluations, seconds} (sums over every minimization)
///  - "energy", "energy_norm", "a_uu", "f_u", "j_term", "friction_term", "max_u_nu"
///  - "status_counts": {separated, compliance, contact, stick, slip+, slip-[, slip]}
///  - "nodes": one object per Γ3 node, in ContactNodes order: {node, x, y[, z], w, g, u_nu,
///    u_tau, sigma_nu, sigma_tau, xi, lambda, status} with status e.g. "contact/stick"; 3D nodes
///    add slip_dir ([3] unit vector u_τ/|u_τ|, null when sticking) and slip_angle_deg (see
///    SlipDirection; null when sticking), and their u_tau, sigma_tau are magnitudes
///  - "certificate": {passed, tol, max_residual, length_scale, force_scale, traction_scale,
///    residuals: {name: {value, worst}}}
///  - "fixed_point": {converged, iterations, history: [{k, stage, eps_tau, eps_nu, change_u,
///    change_lambda, grad_norm, backend_status, backend_iterations, backend_evaluations,
///    backend_seconds, backend_message}]}
///  - "options": the SolveOptions used (backend, tolerances, continuation, fixed point)
///  - "skipped": what was not needed and not done; "scales": {x_scale, f_scale}
///  - "timings": seconds, the model's and the solve's merged (the solve's wins on a shared key)
///  - "message": the verdict; "ok": backend_ok && fixed_point_converged && certificate.passed
///
/// Non-finite numbers: JSON has no inf or nan, and nlohmann-json writes them as null. So a null
/// where a number is expected means "not finite": g = null is g = +∞ (no rigid obstacle), a null
/// residual or scale is inf/nan. The file is always valid JSON. Finite doubles are written in
/// the shortest form that reads back exactly.

#include <hemicontact/output/gamma3_rows.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace hemicontact {

/// @brief Collect everything about a run into one JSON object. Never solves.
/// @param md  the model
/// @param sol the solution (after solve() or evaluate_solution())
/// @param opt the options the solution was computed with
/// @return the report (keys listed in the file comment)
/// @throws Error (EXIT_INTERNAL) if @p sol does not match @p md (sizes)
nlohmann::json make_report(const Model& md, const Solution& sol, const SolveOptions& opt);

/// What the summary and report.json say of the whole mesh and Γ3, from one process's model
/// (summary_facts) or from the petsc engine's pieces (their reduced sizes and the Γ3 rows gathered
/// to rank 0).
struct SummaryFacts {
  std::string origin;                 ///< the mesh's origin ("" if none)
  long nodes = 0, cells = 0, dofs = 0;
  double h = 0;                       ///< the longest edge
  int dim = 2;
  bool linear = true;                 ///< linear material (the elastic energy is a(u,u)/2)
  std::vector<Gamma3Row> rows;        ///< every Γ3 node's row, in ContactNodes' order
  std::map<std::string, double> timings;
};
/// @return the facts of @p md and @p sol (one process).
SummaryFacts summary_facts(const Model& md, const Solution& sol);

/// @brief The report from @p facts: @p md gives only what every piece of a model shares (the
/// scene, the material, the laws); the sizes, the Γ3 rows and the timings are the facts'.
/// @param worst_name the certificate's key for a residual's worst place ("worst": the node or
/// unknown; the petsc engine's pieces: "worst_petsc_row")
nlohmann::json make_report(const Model& md, const SummaryFacts& facts, const Solution& sol, const SolveOptions& opt,
                           const char* worst_name = "worst");

/// @return a Γ3 row's entry in "nodes" (the keys listed above) for a mesh of dimension @p dim.
nlohmann::json gamma3_row_json(const Gamma3Row& r, int dim);

/// @brief The report's records that read the Solution and the options only, not the mesh:
/// backend, solved_by, phases, certificate, fixed_point, options, skipped, formulation, smallness,
/// polish, inner, inner_convexity, scales, message, ok. make_report writes them, and so does the
/// petsc engine's distributed path, whose rank 0 holds no whole model.
/// @param lagged whether F_b depends on u_ν (the outer fixed point λ = F_b(u_ν) runs)
nlohmann::json solve_records(const Solution& sol, const SolveOptions& opt, bool lagged);
/// @brief The inverse of solve_records for what a run did (not what its answer is worth): the
/// backend's name and use, the fixed point's history and verdict, the skipped stages, the
/// formulation, the scales, the polish and the message, read from a report.json @p r into @p sol
/// (a solve by another process, studies/petsc_process.hpp; its u is judged anew).
/// @throws nlohmann::json::exception where @p r lacks one of those keys
void read_solve_records(const nlohmann::json& r, Solution& sol);

/// @return "material": {description, m_F, L_F, is_linear} of @p md.
nlohmann::json material_json(const Model& md);

/// @return "laws": {normal_law, friction, gap} of @p md.
nlohmann::json laws_json(const Model& md);

/// @brief Write a report, pretty-printed with a 2-space indent and a final newline.
/// @param path   the file to write (its directory must exist)
/// @param report the report (make_report())
/// @throws Error (EXIT_OUTPUT) if the file cannot be written
void write_report(const std::string& path, const nlohmann::json& report);

/// @brief A short human-readable summary for stdout: mesh and dofs, backend, energies, the status
/// counts as a small table, the per-node statuses (run-length compressed beyond 33 Γ3 nodes),
/// the certificate and the timings.
/// @param md the model @param sol the solution
/// @return several lines, each ending in '\n'
std::string summary_table(const Model& md, const Solution& sol);

/// @return "" where uniqueness is not in doubt; else why other certified solutions may exist:
/// (21) fails and the inner problem is not (known to be) strongly convex. The summary's
/// "uniqueness" row and report.json's uniqueness.warning.
std::string uniqueness_warning(const Solution& sol);

/// The summary from @p facts and the solution's records (energies, counts, certificate, verdict).
std::string summary_table(const SummaryFacts& facts, const Solution& sol);

/// One row of the summary: @p label padded to the summary's column, @p text, '\n'.
std::string summary_row(const std::string& label, const std::string& text);

/// @brief The per-node statuses in Γ3 order, run-length compressed: consecutive equal statuses
/// become "status xN", e.g. "compliance/slip- x2, contact/slip- x28, contact/stick x1".
/// @param sol the solution @return the list ("" when there is no Γ3 node)
std::string status_runs(const Solution& sol);

}  // namespace hemicontact
