#include <hemicontact/check/certificate.hpp>

#include <hemicontact/check/judge.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace hemicontact {

ContactState contact_state(const Model& md, const Vec& u) {
  return contact_state(md, u, md.internal_force(u) - md.f);  // K u − f for a linear law (docs/model.md §4)
}

ContactState contact_state(const Model& md, const Vec& u, Vec residual) {
  const int d = md.dim();
  const Index n = md.contact.size();
  ContactState s;
  s.residual = std::move(residual);
  for (Vec* v : {&s.u_nu, &s.u_tau, &s.sigma_nu, &s.sigma_tau, &s.xi, &s.lambda}) v->resize(n);
  s.u_tau_vec.resize(n, d);
  s.sigma_tau_vec.resize(n, d);
  for (Index k = 0; k < n; ++k) {
    const Index v = md.contact.node[static_cast<size_t>(k)];
    store_node(s, k, node_state(node_data(md, k), u.data() + d * v, s.residual.data() + d * v));
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

CertificateReport certify(const Model& md, const Vec& u, const ContactState& s, double tol, double status_tol) {
  return judge(md, u, s, whole_model_scope(md), SerialReduction{}, tol, status_tol).certificate;
}

}  // namespace hemicontact
