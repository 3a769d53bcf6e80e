#include <hemicontact/energy/contact_energy.hpp>
#include <hemicontact/energy/elastic_energy.hpp>
#include <hemicontact/energy/total_energy.hpp>

#include <hemicontact/contact/smooth_norm.hpp>
#include <hemicontact/core/error.hpp>

#include <algorithm>
#include <cstring>

namespace hemicontact {

Index pattern_position(const SpMat& H, Index row, Index col) {
  if (row < col) std::swap(row, col);
  const int* begin = H.innerIndexPtr() + H.outerIndexPtr()[col];
  const int* end = H.innerIndexPtr() + H.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, static_cast<int>(row));
  if (it == end || *it != row)
    throw Error("Hessian pattern lacks entry (" + std::to_string(row) + ", " + std::to_string(col) + ")",
                EXIT_INTERNAL);
  return it - H.innerIndexPtr();
}

namespace {
// A cached position is valid for H if it still addresses entry (row, col) of H's pattern; checking
// costs O(1) per entry and catches a different pattern in the same buffer (which an address key misses).
bool position_valid(const SpMat& H, Index pos, Index row, Index col) {
  if (row < col) std::swap(row, col);
  return pos >= H.outerIndexPtr()[col] && pos < H.outerIndexPtr()[col + 1] && H.innerIndexPtr()[pos] == row;
}
}  // namespace

// ------------------------------------------------------------------ elastic and load
ElasticEnergy::ElasticEnergy(const SpMat& K) : m_K(K) {
  m_lower = m_K.triangularView<Eigen::Lower>();
  m_lower.makeCompressed();
}

void ElasticEnergy::add_hessian(const Vec&, SpMat& H, Psd) const {
  // Same pattern by construction (TotalEnergy's pattern is this lower triangle): add value arrays.
  Eigen::Map<Vec>(H.valuePtr(), H.nonZeros()) += Eigen::Map<const Vec>(m_lower.valuePtr(), m_lower.nonZeros());
}

CondensedElasticEnergy::CondensedElasticEnergy(std::shared_ptr<const Mat> S, Vec y_C, double c)
    : m_S(std::move(S)), m_y(std::move(y_C)), m_c(c) {
  if (!m_S || m_S->rows() != m_S->cols() || m_S->rows() != m_y.size())
    throw Error("CondensedElasticEnergy: S must be a square matrix of the size of y_C", EXIT_INTERNAL);
}

double CondensedElasticEnergy::value(const Vec& x) const {
  const Vec d = x - m_y;
  return 0.5 * d.dot(*m_S * d) + m_c;
}

void CondensedElasticEnergy::add_hessian(const Vec&, SpMat& H, Psd) const {
  // dense_lower_pattern stores column j as rows j..m−1, so the values are S's lower columns in order.
  const Mat& S = *m_S;
  const Index m = S.rows();
  double* v = H.valuePtr();
  for (Index j = 0; j < m; ++j)
    for (Index i = j; i < m; ++i) *v++ += S(i, j);
}

SpMat dense_lower_pattern(Index m) {
  SpMat H(m, m);
  H.reserve(Eigen::VectorXi::LinSpaced(m, static_cast<int>(m), 1));
  for (Index j = 0; j < m; ++j)
    for (Index i = j; i < m; ++i) H.insert(i, j) = 0.0;
  H.makeCompressed();
  return H;
}

// ------------------------------------------------------------------ normal compliance
NormalComplianceEnergy::NormalComplianceEnergy(NodalDofs dofs, std::shared_ptr<const NormalLaw> law)
    : m_dofs(std::move(dofs)), m_law(std::move(law)) {}

double NormalComplianceEnergy::value(const Vec& x) const {
  double s = 0;
  for (Index k = 0; k < m_dofs.size(); ++k) s += m_dofs.w[k] * m_law->j(x[m_dofs.first[k]]);
  return s;
}

void NormalComplianceEnergy::add_gradient(const Vec& x, Vec& g) const {
  for (Index k = 0; k < m_dofs.size(); ++k) g[m_dofs.first[k]] += m_dofs.w[k] * m_law->p(x[m_dofs.first[k]]);
}

void NormalComplianceEnergy::add_hessian(const Vec& x, SpMat& H, Psd psd) const {
  bool valid = m_pos_for == H.innerIndexPtr() && static_cast<Index>(m_pos.size()) == m_dofs.size();
  for (Index k = 0; valid && k < m_dofs.size(); ++k) valid = position_valid(H, m_pos[k], m_dofs.first[k], m_dofs.first[k]);
  if (!valid) {
    m_pos.resize(m_dofs.size());
    for (Index k = 0; k < m_dofs.size(); ++k) m_pos[k] = pattern_position(H, m_dofs.first[k], m_dofs.first[k]);
    m_pos_for = H.innerIndexPtr();
  }
  for (Index k = 0; k < m_dofs.size(); ++k) {
    double c = m_dofs.w[k] * m_law->dp(x[m_dofs.first[k]]);
    if (psd == Psd::CLAMP) c = std::max(c, 0.0);  // softening branch c2 < 0 made convex
    H.valuePtr()[m_pos[k]] += c;
  }
}

// ------------------------------------------------------------------ friction
FrictionEnergy::FrictionEnergy(NodalDofs dofs, double eps_tau)
    : m_dofs(std::move(dofs)), m_eps(eps_tau), m_lambda(Vec::Zero(m_dofs.size())) {}

double FrictionEnergy::value(const Vec& x) const {
  double s = 0;
  const int nt = m_dofs.dim - 1;
  for (Index k = 0; k < m_dofs.size(); ++k) {
    if (m_lambda[k] == 0) continue;
    const double y = x.segment(m_dofs.first[k] + 1, nt).norm();
    s += m_dofs.w[k] * m_lambda[k] * f0(y, m_eps);
  }
  return s;
}

void FrictionEnergy::add_gradient(const Vec& x, Vec& g) const {
  const int nt = m_dofs.dim - 1;
  for (Index k = 0; k < m_dofs.size(); ++k) {
    if (m_lambda[k] == 0) continue;
    const auto ut = x.segment(m_dofs.first[k] + 1, nt);
    // ∇_u f0(|u|) = f1(|u|) u/|u| = f1_over_y(|u|) u, finite at u = 0.
    g.segment(m_dofs.first[k] + 1, nt) += m_dofs.w[k] * m_lambda[k] * f1_over_y(ut.norm(), m_eps) * ut;
  }
}

void FrictionEnergy::add_hessian(const Vec& x, SpMat& H, Psd) const {
  const int nt = m_dofs.dim - 1;
  const int nb = nt * (nt + 1) / 2;  // lower entries of the τ-block
  bool valid = m_pos_for == H.innerIndexPtr() && static_cast<Index>(m_pos.size()) == m_dofs.size() * nb;
  for (Index k = 0; valid && k < m_dofs.size(); ++k) {
    int q = 0;
    for (int a = 0; valid && a < nt; ++a)
      for (int b = 0; valid && b <= a; ++b)
        valid = position_valid(H, m_pos[k * nb + q++], m_dofs.first[k] + 1 + a, m_dofs.first[k] + 1 + b);
  }
  if (!valid) {
    m_pos.resize(m_dofs.size() * nb);
    for (Index k = 0; k < m_dofs.size(); ++k) {
      int q = 0;
      for (int a = 0; a < nt; ++a)
        for (int b = 0; b <= a; ++b)
          m_pos[k * nb + q++] = pattern_position(H, m_dofs.first[k] + 1 + a, m_dofs.first[k] + 1 + b);
    }
    m_pos_for = H.innerIndexPtr();
  }
  for (Index k = 0; k < m_dofs.size(); ++k) {
    if (m_lambda[k] == 0) continue;
    const double c = m_dofs.w[k] * m_lambda[k];
    const Vec ut = x.segment(m_dofs.first[k] + 1, nt);
    const double y = ut.norm();
    if (nt == 1) {
      // d²/du² f0(|u|) = f1'(|u|) for scalar u (including u = 0, where f1' = 2/ε).
      H.valuePtr()[m_pos[k]] += c * df1(y, m_eps);
      continue;
    }
    // ∇² f0(|u|) = f1/y I + (f1' y − f1)/y³ u uᵀ; at y = 0 the second part vanishes (u uᵀ = 0).
    const double a = f1_over_y(y, m_eps);
    const double b = (y > 0) ? f2_term(y, m_eps) : 0.0;
    int q = 0;
    for (int r = 0; r < nt; ++r)
      for (int s = 0; s <= r; ++s) H.valuePtr()[m_pos[k * nb + q++]] += c * ((r == s ? a : 0.0) + b * ut[r] * ut[s]);
  }
}

// ------------------------------------------------------------------ composite and scaling
TotalEnergy::TotalEnergy(Index n, SpMat pattern) : m_n(n), m_pattern(std::move(pattern)) {
  m_pattern.makeCompressed();
  std::fill(m_pattern.valuePtr(), m_pattern.valuePtr() + m_pattern.nonZeros(), 0.0);
}

double TotalEnergy::value(const Vec& x) const {
  double s = 0;
  for (const auto& t : m_terms) s += t->value(x);
  return s;
}

void TotalEnergy::gradient(const Vec& x, Vec& g) const {
  g.setZero(m_n);
  for (const auto& t : m_terms) t->add_gradient(x, g);
}

void TotalEnergy::hessian(const Vec& x, SpMat& H, Psd psd) const {
  // H must carry exactly the fixed pattern (ElasticEnergy adds K's values by position).
  const bool same = H.rows() == m_n && H.cols() == m_n && H.isCompressed() && H.nonZeros() == m_pattern.nonZeros() &&
                    std::equal(m_pattern.outerIndexPtr(), m_pattern.outerIndexPtr() + m_n + 1, H.outerIndexPtr()) &&
                    std::equal(m_pattern.innerIndexPtr(), m_pattern.innerIndexPtr() + m_pattern.nonZeros(), H.innerIndexPtr());
  if (!same) H = m_pattern;
  std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
  for (const auto& t : m_terms) t->add_hessian(x, H, psd);
}

void ScaledObjective::gradient(const Vec& x, Vec& g) const {
  m_f.gradient(m_sx * x, g);
  g *= m_sx / m_sf;
}

void ScaledObjective::hessian(const Vec& x, SpMat& H, Psd psd) const {
  m_f.hessian(m_sx * x, H, psd);
  Eigen::Map<Vec>(H.valuePtr(), H.nonZeros()) *= m_sx * m_sx / m_sf;
}

}  // namespace hemicontact
