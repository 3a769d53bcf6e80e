#include <hemicontact/check/node_kernels.hpp>

#include <algorithm>
#include <cmath>

namespace hemicontact {

namespace {

// std::max(0, NaN) and std::min(x, NaN) drop the NaN: these keep it, so that a non-finite state
// reads as an infinite residual (judge.cpp), never as a pass.
double pos(double v) { return std::isnan(v) ? v : std::max(0.0, v); }
double min_nan(double a, double b) { return std::isnan(a) || std::isnan(b) ? NAN : std::min(a, b); }

}  // namespace

NodeData node_data(const Model& md, Index k) {
  NodeData n;
  n.d = md.dim();
  const int v = md.contact.node[static_cast<size_t>(k)];
  n.nu.head(n.d) = md.contact.normal.row(k).transpose();
  if (n.d == 2) n.tau.head(2) = md.contact.tangent.row(k).transpose();
  n.w = md.contact.w[k];
  n.g = md.contact.g[k];
  n.held = md.mesh.held(v);
  n.normal_law = md.normal_law.get();
  n.friction = md.friction.get();
  return n;
}

NodeState node_state(const NodeData& n, const double* u_k, const double* r_k) {
  NodeState s;
  Eigen::Vector3d u = Eigen::Vector3d::Zero(), sigma = Eigen::Vector3d::Zero();
  for (int c = 0; c < n.d; ++c) {
    u[c] = u_k[c];
    // The nodal traction σν = (K u − f)_i / w_i (docs/model.md §4); a roller's reaction is not a
    // contact traction: the held components are dropped (they are tangent to Γ3).
    sigma[c] = (n.held & (1u << c)) ? 0.0 : r_k[c] / n.w;
  }
  s.u_nu = u.dot(n.nu);
  s.sigma_nu = sigma.dot(n.nu);
  s.u_tau_vec = u - s.u_nu * n.nu;
  s.sigma_tau_vec = sigma - s.sigma_nu * n.nu;
  s.u_tau = n.d == 2 ? s.u_tau_vec.dot(n.tau) : s.u_tau_vec.norm();
  s.sigma_tau = n.d == 2 ? s.sigma_tau_vec.dot(n.tau) : s.sigma_tau_vec.norm();
  if (n.normal_law) {
    // ξ ∈ ∂j_ν(u_ν), eq. (5): the point of the Clarke interval nearest to −σ_ν (p_ν where continuous).
    const Interval I = n.normal_law->subdifferential(s.u_nu);
    s.xi = std::clamp(-s.sigma_nu, I.lo, I.hi);
  }
  s.lambda = n.friction ? n.friction->F(s.u_nu) : 0.0;
  return s;
}

NodeStatus node_status(const NodeData& n, const NodeState& s, const JudgeScales& sc, double tol) {
  const double t = tol * sc.U, tr = tol * sc.S;
  const bool near_zero = s.u_nu <= t;
  NodeStatus st;
  // Contact first: a smoothed answer stops ~ε U short of g, and the polish's coarse reading
  // (10 ε) must then read contact (solver/polish.cpp). Where g ≤ 2t the position cannot tell the
  // foundation from the unloaded layer; contact is the reading there too.
  if (s.u_nu >= n.g - t)
    st.normal = NormalStatus::CONTACT;
  else if (!near_zero || s.xi > tr)
    st.normal = NormalStatus::COMPLIANCE;
  else
    st.normal = NormalStatus::SEPARATED;
  const double y = std::abs(s.u_tau);
  if (y <= t)
    st.tangential = TangentialStatus::STICK;
  else if (n.d == 2)
    st.tangential = s.u_tau > 0 ? TangentialStatus::SLIP_PLUS : TangentialStatus::SLIP_MINUS;
  else
    st.tangential = TangentialStatus::SLIP;
  return st;
}

std::array<double, NODE_TERMS> node_terms(const NodeData& n, const NodeState& s, const JudgeScales& sc, double tol) {
  std::array<double, NODE_TERMS> r{};
  const double U = sc.U, S = sc.S, sn = s.sigma_nu + s.xi;
  r[FEASIBILITY] = pos(s.u_nu - n.g) / U;                       // u_ν ≤ g
  r[NORMAL] = pos(sn) / S;                                      // σ_ν + ξ ≤ 0
  r[COMPLEMENTARITY] = std::abs(min_nan((n.g - s.u_nu) / U, -sn / S));
  r[FRICTION_CONE] = pos(std::abs(s.sigma_tau) - s.lambda) / S;  // |σ_τ| ≤ F_b(u_ν), eq. (6)
  const double y = s.u_tau_vec.norm();
  if (y > tol * U)  // −σ_τ = λ u_τ/|u_τ| on slipping nodes, eq. (6)
    r[SLIP_DIRECTION] = (s.sigma_tau_vec + s.lambda * s.u_tau_vec / y).norm() / S;
  return r;
}

NodeEnergy node_energy(const NodeData& n, const NodeState& s) {
  NodeEnergy e;
  if (n.normal_law) e.j = n.w * n.normal_law->j(s.u_nu);
  e.friction = n.w * s.lambda * s.u_tau_vec.norm();
  return e;
}

NodeState load_node(const ContactState& cs, Index k) {
  NodeState s;
  s.u_nu = cs.u_nu[k];
  s.u_tau = cs.u_tau[k];
  s.sigma_nu = cs.sigma_nu[k];
  s.sigma_tau = cs.sigma_tau[k];
  s.xi = cs.xi[k];
  s.lambda = cs.lambda[k];
  const Index d = cs.u_tau_vec.cols();
  s.u_tau_vec.head(d) = cs.u_tau_vec.row(k).transpose();
  s.sigma_tau_vec.head(d) = cs.sigma_tau_vec.row(k).transpose();
  return s;
}

void store_node(ContactState& cs, Index k, const NodeState& s) {
  cs.u_nu[k] = s.u_nu;
  cs.u_tau[k] = s.u_tau;
  cs.sigma_nu[k] = s.sigma_nu;
  cs.sigma_tau[k] = s.sigma_tau;
  cs.xi[k] = s.xi;
  cs.lambda[k] = s.lambda;
  const Index d = cs.u_tau_vec.cols();
  cs.u_tau_vec.row(k) = s.u_tau_vec.head(d).transpose();
  cs.sigma_tau_vec.row(k) = s.sigma_tau_vec.head(d).transpose();
}

}  // namespace hemicontact
