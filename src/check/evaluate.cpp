#include <hemicontact/check/evaluate.hpp>

#include <hemicontact/check/certificate.hpp>
#include <hemicontact/check/contact_status.hpp>

#include <algorithm>
#include <cmath>

namespace hemicontact {

void evaluate_solution(const Model& md, const SolveOptions& opt, Solution& sol) {
  sol.state = contact_state(md, sol.u);
  const double U = displacement_scale(md, sol.u);
  sol.status = classify(md, sol.state, U, opt.status_tol);
  sol.certificate = certify(md, sol.u, sol.state, opt.certificate_tol, opt.status_tol);
  sol.a_uu = md.a(sol.u, sol.u);
  sol.f_u = md.f.dot(sol.u);
  sol.j_term = sol.friction_term = 0;
  for (Index k = 0; k < md.contact.size(); ++k) {
    if (md.normal_law) sol.j_term += md.contact.w[k] * md.normal_law->j(sol.state.u_nu[k]);
    sol.friction_term += md.contact.w[k] * sol.state.lambda[k] * sol.state.u_tau_vec.row(k).norm();
  }
  sol.elastic_energy = md.elastic_energy(sol.u);  // ½ uᵀK u (= ½ a_uu) for a linear law
  sol.energy = sol.elastic_energy - sol.f_u + sol.j_term + sol.friction_term;
  sol.energy_norm = std::sqrt(std::max(0.0, sol.a_uu));
  sol.max_u_nu = md.contact.size() ? sol.state.u_nu.maxCoeff() : 0.0;
}

}  // namespace hemicontact
