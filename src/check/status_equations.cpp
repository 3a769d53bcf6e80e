#include <hemicontact/check/status_equations.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace hemicontact {

namespace {

// Contact: x_ν = g (eq. (5)); otherwise the layer's force w p_ν(x_ν) and its slope (eq. (32)).
void normal_rows(const NodeData& n, double x_nu, bool contact, NodeRows& rows) {
  if (contact) {
    rows.pinned |= 1u;
    rows.pin[0] = n.g;
  } else if (n.normal_law) {
    rows.force[0] += n.w * n.normal_law->p(x_nu);
    rows.block(0, 0) += n.w * n.normal_law->dp(x_nu);
  }
}

// x_τ = 0: stick, or the components a roller holds (@p mask, bit c for τ_c).
void pin_tangential(int d, unsigned mask, NodeRows& rows) {
  for (int c = 1; c < d; ++c)
    if (mask & (1u << c)) rows.pinned |= 1u << c, rows.pin[c] = 0;
}

// Slip along t: the friction force w λ t (eq. (6)) and, in 3D, its turning with x_τ over the
// radius ρ: w λ (I − t tᵀ)/ρ (in 2D the one tangent direction does not turn).
void slip_rows(const NodeData& n, const Eigen::Vector2d& t, double rho, double lambda, NodeRows& rows) {
  for (int c = 1; c < n.d; ++c) rows.force[c] += n.w * lambda * t[c - 1];
  if (n.d == 3) rows.block.block<2, 2>(1, 1) += n.w * lambda / rho * (Eigen::Matrix2d::Identity() - t * t.transpose());
}

unsigned all_tangential(int d) { return d == 3 ? 6u : 2u; }

// F_b's slope at x_ν by a central difference over δ (exact up to round-off on a linear piece).
double F_slope(const NodeData& n, double x_nu, double delta) {
  return (n.friction->F(x_nu + delta) - n.friction->F(x_nu - delta)) / (2 * delta);
}

}  // namespace

unsigned roller_components(const Model& md, Index k) {
  return md.contact.fixed_local.empty() ? 0u : md.contact.fixed_local[static_cast<std::size_t>(k)];
}

NodeRows status_rows(const NodeData& n, const Eigen::Vector3d& x, const NodeStatus& st, bool frictionless,
                     unsigned rollers, double delta, bool coupling) {
  NodeRows rows;
  const bool contact = st.normal == NormalStatus::CONTACT;
  normal_rows(n, x[0], contact, rows);
  if (frictionless) {
    // σ_τ = 0: the rows of K x − f already say it.
  } else if (st.tangential == TangentialStatus::STICK) {
    pin_tangential(n.d, all_tangential(n.d), rows);
  } else if (n.d == 2) {
    // slip±: the status is the direction (t = ±τ), whatever x_τ is now; no turning in 2D.
    const double t = st.tangential == TangentialStatus::SLIP_PLUS ? 1.0 : -1.0;
    slip_rows(n, Eigen::Vector2d(t, 0), 1.0, n.friction->F(x[0]), rows);
    if (coupling && !contact) rows.block(1, 0) += n.w * F_slope(n, x[0], delta) * t;
  } else {
    Eigen::Vector2d xt = Eigen::Vector2d::Zero();
    for (int c = 1; c < n.d; ++c) xt[c - 1] = x[c];
    const double y = xt.norm();
    if (!(y > 0)) {
      rows.singular = true;
      pin_tangential(n.d, rollers, rows);
      return rows;
    }
    const Eigen::Vector2d t = xt / y;
    slip_rows(n, t, y, n.friction->F(x[0]), rows);
    if (coupling && !contact)
      for (int c = 1; c < n.d; ++c) rows.block(c, 0) += n.w * F_slope(n, x[0], delta) * t[c - 1];
  }
  pin_tangential(n.d, rollers, rows);
  return rows;
}

SsnReading ssn_reading(const NodeData& n, const Eigen::Vector3d& x, const Eigen::Vector3d& r,
                       const Eigen::Vector3d& diag, bool first_step, bool hold_stick, unsigned rollers) {
  SsnReading out;
  const double p = n.normal_law ? n.normal_law->p(x[0]) : 0.0;
  const bool contact = std::isfinite(n.g) && (first_step || -(r[0] + n.w * p) + diag[0] * (x[0] - n.g) > 0);
  normal_rows(n, x[0], contact, out.rows);
  if (contact) out.code |= 1;
  const double lambda = n.friction ? n.friction->F(x[0]) : 0.0;
  if (rollers) {
    pin_tangential(n.d, rollers, out.rows);
  } else if (n.w * lambda > 0) {
    Eigen::Vector2d xt = Eigen::Vector2d::Zero(), rt = Eigen::Vector2d::Zero();
    for (int c = 1; c < n.d; ++c) xt[c - 1] = x[c], rt[c - 1] = r[c];
    const double ct = n.d == 2 ? diag[1] : std::max(diag[1], diag[2]);
    const Eigen::Vector2d y = -rt + ct * xt;
    const double ny = y.norm();
    if (ny <= n.w * lambda || hold_stick) {
      out.code |= 2;
      pin_tangential(n.d, all_tangential(n.d), out.rows);
    } else {
      out.slip_dir = y / ny;
      slip_rows(n, out.slip_dir, std::max(xt.norm(), (ny - n.w * lambda) / ct), lambda, out.rows);
      if (n.d == 2) out.code |= out.slip_dir[0] >= 0 ? 8 : 16;  // a reversal is a change
    }
  }
  if (n.normal_law && !contact) {
    // The branch of p: the index of the breakpoint interval x_ν lies in (eq. (32)'s pieces).
    const auto& bp = n.normal_law->breakpoints();
    out.code |= 32 * static_cast<int>(1 + (std::upper_bound(bp.begin(), bp.end(), x[0]) - bp.begin()));
  }
  return out;
}

Eigen::Vector3d ssn_coupling(const NodeData& n, const Eigen::Vector3d& x, const SsnReading& rd, double delta) {
  Eigen::Vector3d col = Eigen::Vector3d::Zero();
  if (!n.friction || rd.slip_dir.squaredNorm() == 0 || rd.rows.is_pinned(0) || !(delta > 0)) return col;
  const double slope = n.w * F_slope(n, x[0], delta);
  for (int c = 1; c < n.d; ++c)
    if (!rd.rows.is_pinned(c)) col[c] = slope * rd.slip_dir[c - 1];
  return col;
}

double ssn_node_merit(const NodeData& n, const Eigen::Vector3d& x, const Eigen::Vector3d& r,
                      const Eigen::Vector3d& diag, unsigned rollers, double diag_scale) {
  const SsnReading rd = ssn_reading(n, x, r, diag, false, false, rollers);
  double m = 0;
  for (int c = 0; c < n.d; ++c)
    m = std::max(m, rd.rows.is_pinned(c) ? diag_scale * std::abs(rd.rows.pin[c] - x[c])
                                         : std::abs(r[c] + rd.rows.force[c]));
  return m;
}

bool ssn_reversed(const Eigen::Vector2d& slip_dir, int d, Eigen::Vector3d& x) {
  if (slip_dir.squaredNorm() == 0) return false;
  double dot = 0;
  for (int c = 1; c < d; ++c) dot += x[c] * slip_dir[c - 1];
  if (!(dot < 0)) return false;
  for (int c = 1; c < d; ++c) x[c] = 0;
  return true;
}

}  // namespace hemicontact
