#include <hemicontact/check/certificate.hpp>

#include <algorithm>
#include <cmath>

namespace hemicontact {

ContactState contact_state(const Model& md, const Vec& u) {
  const int d = md.dim();
  const Index n = md.contact.size();
  ContactState s;
  s.residual = md.internal_force(u) - md.f;  // K u − f for a linear law (docs/model.md §4)
  s.u_nu.resize(n);
  s.u_tau.resize(n);
  s.sigma_nu.resize(n);
  s.sigma_tau.resize(n);
  s.xi.resize(n);
  s.lambda.resize(n);
  s.u_tau_vec.resize(n, d);
  s.sigma_tau_vec.resize(n, d);
  for (Index k = 0; k < n; ++k) {
    const int v = md.contact.node[k];
    const Vec nu = md.contact.normal.row(k).transpose();
    const Vec uk = u.segment(d * v, d);
    Vec sk = s.residual.segment(d * v, d) / md.contact.w[k];  // nodal traction σν (step-41)
    // A roller's reaction is not a contact traction: drop the held components (tangent to Γ3).
    for (int c = 0; c < d; ++c)
      if (md.mesh.held(v) & (1u << c)) sk[c] = 0;
    s.u_nu[k] = uk.dot(nu);
    s.sigma_nu[k] = sk.dot(nu);
    const Vec ut = uk - s.u_nu[k] * nu, st = sk - s.sigma_nu[k] * nu;
    s.u_tau_vec.row(k) = ut.transpose();
    s.sigma_tau_vec.row(k) = st.transpose();
    if (d == 2) {
      const Vec tau = md.contact.tangent.row(k).transpose();
      s.u_tau[k] = ut.dot(tau);
      s.sigma_tau[k] = st.dot(tau);
    } else {
      s.u_tau[k] = ut.norm();
      s.sigma_tau[k] = st.norm();
    }
    if (md.normal_law) {
      // ξ ∈ ∂j_ν(u_ν): the point of the Clarke interval nearest to −σ_ν (a point where p is continuous).
      const Interval I = md.normal_law->subdifferential(s.u_nu[k]);
      s.xi[k] = std::clamp(-s.sigma_nu[k], I.lo, I.hi);
    } else {
      s.xi[k] = 0;
    }
    s.lambda[k] = md.friction ? md.friction->F(s.u_nu[k]) : 0.0;
  }
  if (d == 3) {
    s.slip_dir = RowMat::Zero(n, 3);
    s.slip_angle_deg = Vec::Zero(n);
    for (Index k = 0; k < n; ++k) {
      const SlipDirection sd = slip_direction(md, s, k);
      s.slip_dir.row(k) = sd.dir.transpose();
      s.slip_angle_deg[k] = sd.angle_deg;
    }
  }
  return s;
}

SlipDirection slip_direction(const Model& md, const ContactState& s, Index k) {
  SlipDirection out;
  const Eigen::Vector3d ut = s.u_tau_vec.row(k).transpose();
  const double y = ut.norm();
  if (!(y > 0)) return out;
  out.dir = ut / y;
  const Eigen::Vector3d nu = md.contact.normal.row(k).transpose();
  // Reference axis: global x projected onto the tangent plane (y if x is (nearly) normal to it).
  Eigen::Vector3d e = Eigen::Vector3d::UnitX() - nu.x() * nu;
  if (e.norm() < 1e-8) e = Eigen::Vector3d::UnitY() - nu.y() * nu;
  e.normalize();
  const Eigen::Vector3d f = (-nu).cross(e);  // e rotated by +90° about −ν
  out.angle_deg = std::atan2(out.dir.dot(f), out.dir.dot(e)) * 180.0 / M_PI;
  return out;
}

double displacement_scale(const Model& md, const Vec& u) {
  double U = u.size() ? u.cwiseAbs().maxCoeff() : 0.0;
  return U > 0 ? U : md.mesh.max_edge_length();
}

std::vector<NodeStatus> classify(const Model& md, const ContactState& s, double U, double tol) {
  std::vector<NodeStatus> out(md.contact.size());
  const double t = tol * U;
  for (Index k = 0; k < md.contact.size(); ++k) {
    NodeStatus& st = out[k];
    if (s.u_nu[k] >= md.contact.g[k] - t)
      st.normal = NormalStatus::CONTACT;
    else if (s.u_nu[k] <= t)
      st.normal = NormalStatus::SEPARATED;
    else
      st.normal = NormalStatus::COMPLIANCE;
    const double y = md.dim() == 2 ? std::abs(s.u_tau[k]) : s.u_tau[k];
    if (y <= t)
      st.tangential = TangentialStatus::STICK;
    else if (md.dim() == 2)
      st.tangential = s.u_tau[k] > 0 ? TangentialStatus::SLIP_PLUS : TangentialStatus::SLIP_MINUS;
    else
      st.tangential = TangentialStatus::SLIP;
  }
  return out;
}

CertificateReport certify(const Model& md, const Vec& u, const ContactState& s, double tol, double status_tol) {
  CertificateReport r;
  r.tol = tol;
  const Index n = md.contact.size();
  const int d = md.dim();
  r.length_scale = displacement_scale(md, u);
  r.force_scale = md.f.size() ? md.f.cwiseAbs().maxCoeff() : 0.0;
  const double wbar = n ? md.contact.w.mean() : 1.0;
  r.traction_scale = r.force_scale / wbar;
  if (n) r.traction_scale = std::max({r.traction_scale, s.lambda.cwiseAbs().maxCoeff(), s.xi.cwiseAbs().maxCoeff()});
  // A problem without any load or contact force has the zero solution; any positive scale works.
  if (!(r.force_scale > 0)) r.force_scale = 1.0;
  if (!(r.traction_scale > 0)) r.traction_scale = 1.0;
  const double U = r.length_scale, S = r.traction_scale;

  CertificateResidual feas{"feasibility"}, normal{"normal"}, compl_{"complementarity"}, cone{"friction_cone"},
      slip{"slip_direction"}, eq{"equilibrium"};
  const auto take = [](CertificateResidual& c, double v, Index at) {
    if (v > c.value || std::isnan(v)) {
      c.value = std::isnan(v) ? INF : v;
      c.worst = at;
    }
  };
  // std::max(0, NaN) and std::min(x, NaN) drop the NaN: these keep it, so that take() reads a
  // non-finite state as an infinite residual, never as a pass.
  const auto pos = [](double v) { return std::isnan(v) ? v : std::max(0.0, v); };
  const auto min_nan = [](double a, double b) { return std::isnan(a) || std::isnan(b) ? NAN : std::min(a, b); };
  for (Index k = 0; k < n; ++k) {
    const double g = md.contact.g[k];
    const double un = s.u_nu[k], sn = s.sigma_nu[k] + s.xi[k];
    take(feas, pos(un - g) / U, k);
    take(normal, pos(sn) / S, k);
    take(compl_, std::abs(min_nan((g - un) / U, -sn / S)), k);
    const double st = d == 2 ? std::abs(s.sigma_tau[k]) : s.sigma_tau[k];
    take(cone, pos(st - s.lambda[k]) / S, k);
    const double y = s.u_tau_vec.row(k).norm();
    if (y > status_tol * U) {
      // −σ_τ = λ u_τ/|u_τ| on slipping nodes, eq. (6).
      const double res = (s.sigma_tau_vec.row(k) + s.lambda[k] * s.u_tau_vec.row(k) / y).norm();
      take(slip, res / S, k);
    }
  }
  // Interior equilibrium on free dofs that are not Γ3 dofs.
  std::vector<bool> skip(md.mesh.num_nodes(), false);
  for (Index v = 0; v < md.mesh.num_nodes(); ++v) skip[v] = md.clamped[v];
  for (int v : md.contact.node) skip[v] = true;
  for (Index v = 0; v < md.mesh.num_nodes(); ++v)
    if (!skip[v])
      for (int i = 0; i < d; ++i)
        if (!(md.mesh.held(v) & (1u << i)))  // not a roller reaction
          take(eq, std::abs(s.residual[d * v + i]) / r.force_scale, d * v + i);

  r.residuals = {feas, normal, compl_, cone, slip, eq};
  r.max_residual = 0;
  for (const auto& c : r.residuals) r.max_residual = std::max(r.max_residual, c.value);
  r.passed = r.max_residual <= tol;
  return r;
}

}  // namespace hemicontact
