#include <hemicontact/check/evaluate.hpp>

#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/check/judge.hpp>

#include <algorithm>
#include <cmath>

namespace hemicontact {

void evaluate_solution(const Model& md, const SolveOptions& opt, Solution& sol) {
  sol.state = contact_state(md, sol.u);
  apply_judgement(md, opt, sol, whole_model_scope(md), SerialReduction{});
  sol.a_uu = md.a(sol.u, sol.u);
  sol.f_u = md.f.dot(sol.u);
  sol.elastic_energy = md.elastic_energy(sol.u);  // ½ uᵀK u (= ½ a_uu) for a linear law
  sol.energy = sol.elastic_energy - sol.f_u + sol.j_term + sol.friction_term;
  sol.energy_norm = std::sqrt(std::max(0.0, sol.a_uu));
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
