#include <hemicontact/energy/elastic_energy.hpp>
#include <hemicontact/energy/total_energy.hpp>

#include <hemicontact/core/error.hpp>

#include <algorithm>

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

// ------------------------------------------------------------------ elastic and load
void ElasticEnergy::add_hessian(const Vec&, SpMat& H, Psd) const {
  // Same pattern by construction (TotalEnergy's pattern is this lower triangle): add value arrays.
  Eigen::Map<Vec>(H.valuePtr(), H.nonZeros()) += Eigen::Map<const Vec>(m_K.lower().valuePtr(), m_K.lower().nonZeros());
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
  const bool same =
      H.rows() == m_n && H.cols() == m_n && H.isCompressed() && H.nonZeros() == m_pattern.nonZeros() &&
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
