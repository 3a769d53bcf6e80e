#include <hemicontact/check/evaluate.hpp>

#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/check/judge.hpp>

#include <algorithm>
#include <cmath>

namespace hemicontact {

namespace {

// The energy (22) from its parts.
void close_energy(Solution& sol) {
  sol.energy = sol.elastic_energy - sol.f_u + sol.j_term + sol.friction_term;
  sol.energy_norm = std::sqrt(std::max(0.0, sol.a_uu));
}

}  // namespace

void evaluate_solution(const Model& md, const SolveOptions& opt, Solution& sol) {
  if (md.material->is_linear()) return evaluate_solution(md, opt, sol, md.Kx * md.dofs.to_reduced(sol.u));
  sol.state = contact_state(md, sol.u);
  apply_judgement(md, opt, sol, whole_model_scope(md), SerialReduction{});
  sol.a_uu = md.a(sol.u, sol.u);
  sol.f_u = md.f.dot(sol.u);
  sol.elastic_energy = md.elastic_energy(sol.u);
  close_energy(sol);
}

// A linear material: the residual K u − f (docs/model.md §4) and a(u, u) = xᵀ K_x x from K_x x.
void evaluate_solution(const Model& md, const SolveOptions& opt, Solution& sol, const Vec& Kx_x) {
  sol.state = contact_state(md, sol.u, md.dofs.to_full(Kx_x) - md.f);
  apply_judgement(md, opt, sol, whole_model_scope(md), SerialReduction{});
  sol.a_uu = md.dofs.to_reduced(sol.u).dot(Kx_x);
  sol.f_u = md.f.dot(sol.u);
  sol.elastic_energy = 0.5 * sol.a_uu;
  close_energy(sol);
}

void apply_judgement(const Model& md, const SolveOptions& opt, Solution& sol, const JudgeScope& scope,
                     const Reduction& reduce) {
  Judgement J = judge(md, sol.u, sol.state, scope, reduce, opt.certificate_tol, opt.status_tol);
  sol.certificate = std::move(J.certificate);
  sol.status = std::move(J.status);
  sol.j_term = J.j_term;
  sol.friction_term = J.friction_term;
  sol.max_u_nu = J.max_u_nu;
  sol.counts = J.counts;
}

}  // namespace hemicontact
