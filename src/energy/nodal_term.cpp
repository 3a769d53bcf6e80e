#include <hemicontact/energy/nodal_term.hpp>

#include <hemicontact/core/error.hpp>

#include <algorithm>
#include <string>

namespace hemicontact {
namespace {

// Position of lower entry (row, col) in a compressed column-major pattern, or −1 if absent.
Index find_position(const SpMat& H, Index row, Index col) {
  const int* begin = H.innerIndexPtr() + H.outerIndexPtr()[col];
  const int* end = H.innerIndexPtr() + H.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, static_cast<int>(row));
  return (it == end || *it != row) ? -1 : it - H.innerIndexPtr();
}

}  // namespace

NodalLayout::NodalLayout(NodalDofs dofs, const SpMat& pattern) : m_dofs(std::move(dofs)) {
  const int d = m_dofs.dim;
  if (d != 2 && d != 3) throw Error("NodalLayout: d = " + std::to_string(d) + ", expected 2 or 3", EXIT_INTERNAL);
  if (m_dofs.w.size() != m_dofs.size())
    throw Error(
        "NodalLayout: " + std::to_string(m_dofs.size()) + " nodes but " + std::to_string(m_dofs.w.size()) + " weights",
        EXIT_INTERNAL);
  if (pattern.rows() != pattern.cols() || !pattern.isCompressed())
    throw Error("NodalLayout: the Hessian pattern must be square and compressed", EXIT_INTERNAL);
  m_n = pattern.rows();
  m_nnz = pattern.nonZeros();
  m_block = d * (d + 1) / 2;
  m_pos.resize(m_dofs.size() * m_block);
  for (Index k = 0; k < m_dofs.size(); ++k) {
    const Index f = m_dofs.first[k];
    if (f < 0 || f + d > m_n)
      throw Error(
          "NodalLayout: node " + std::to_string(k) + " has components outside the " + std::to_string(m_n) + " unknowns",
          EXIT_INTERNAL);
    for (int a = 0; a < d; ++a)
      for (int b = 0; b <= a; ++b) m_pos[k * m_block + a * (a + 1) / 2 + b] = find_position(pattern, f + a, f + b);
  }
}

bool NodalLayout::matches(const SpMat& H) const {
  if (H.rows() != m_n || H.cols() != m_n || !H.isCompressed() || H.nonZeros() != m_nnz) return false;
  const int d = m_dofs.dim;
  for (Index k = 0; k < m_dofs.size(); ++k) {
    const Index f = m_dofs.first[k];
    for (int a = 0; a < d; ++a)
      for (int b = 0; b <= a; ++b) {
        const Index pos = position(k, a, b);
        if (pos < 0) continue;  // absent then; a kernel adding there is caught when it scatters
        const Index col = f + b;
        if (pos < H.outerIndexPtr()[col] || pos >= H.outerIndexPtr()[col + 1] || H.innerIndexPtr()[pos] != f + a)
          return false;
      }
  }
  return true;
}

NodalTerm::NodalTerm(std::shared_ptr<const NodalLayout> layout) : m_layout(std::move(layout)) {
  if (!m_layout) throw Error("NodalTerm: null layout", EXIT_INTERNAL);
}

NodalVector NodalTerm::local(const Vec& x, Index k) const {
  return x.segment(m_layout->dofs().first[k], m_layout->dim());
}

double NodalTerm::value(const Vec& x) const {
  double s = 0;
  for (Index k = 0; k < m_layout->size(); ++k) s += node_value(k, local(x, k));
  return s;
}

void NodalTerm::add_gradient(const Vec& x, Vec& g) const {
  const NodalDofs& nd = m_layout->dofs();
  for (Index k = 0; k < nd.size(); ++k) g.segment(nd.first[k], nd.dim) += node_gradient(k, local(x, k));
}

void NodalTerm::add_hessian(const Vec& x, SpMat& H, Psd psd) const {
  const NodalLayout& L = *m_layout;
  if (!L.matches(H))
    throw Error(name() + ": the Hessian does not carry the pattern its NodalLayout was built for", EXIT_INTERNAL);
  double* values = H.valuePtr();
  for (Index k = 0; k < L.size(); ++k) {
    const NodalMatrix Hk = node_hessian(k, local(x, k), psd);
    for (int a = 0; a < L.dim(); ++a)
      for (int b = 0; b <= a; ++b) {
        const Index pos = L.position(k, a, b);
        if (pos >= 0) {
          values[pos] += Hk(a, b);
        } else if (Hk(a, b) != 0.0) {
          // Nodal blocks lie inside K's pattern (a node's components share every element), so this
          // is a pattern built without them: a bug, not an input error.
          throw Error(name() + ": node " + std::to_string(k) + " adds to Hessian entry (" +
                          std::to_string(L.dofs().first[k] + a) + ", " + std::to_string(L.dofs().first[k] + b) +
                          ") absent from the pattern",
                      EXIT_INTERNAL);
        }
      }
  }
}

void NodalTerm::add_hessian_triplets(const Vec& x, Triplets& out, Psd psd) const {
  const NodalDofs& nd = m_layout->dofs();
  for (Index k = 0; k < nd.size(); ++k) {
    const NodalMatrix Hk = node_hessian(k, local(x, k), psd);
    const int f = static_cast<int>(nd.first[k]);
    for (int a = 0; a < nd.dim; ++a)
      for (int b = 0; b <= a; ++b) out.emplace_back(f + a, f + b, Hk(a, b));
  }
}

}  // namespace hemicontact
