#include <hemicontact/fem/dof_map.hpp>

#include <algorithm>

namespace hemicontact {

DofMap::DofMap(const Mesh& mesh, const std::vector<bool>& clamped, const ContactNodes& contact) : m_dim(mesh.dim) {
  const int d = mesh.dim;
  const Index N = mesh.num_nodes();
  std::vector<Index> contact_index(N, -1);
  for (Index k = 0; k < contact.size(); ++k) contact_index[contact.node[k]] = k;
  Triplets t;
  t.reserve(static_cast<size_t>(N * d + contact.size() * d * d));
  Index col = 0;
  for (Index v = 0; v < N; ++v) {
    if (clamped[v] || contact_index[v] >= 0) continue;
    const unsigned char fixed = mesh.held(v);  // rollers
    for (int i = 0; i < d; ++i)
      if (!(fixed & (1u << i))) t.emplace_back(static_cast<int>(d * v + i), static_cast<int>(col++), 1.0);
  }
  m_n_interior = col;
  for (Index k = 0; k < contact.size(); ++k) {
    const int v = contact.node[k];
    Mat R(d, d);  // columns: ν, τ (, ν × τ)
    R.col(0) = contact.normal.row(k).transpose();
    R.col(1) = contact.tangent.row(k).transpose();
    if (d == 3) R.col(2) = Eigen::Vector3d(R.col(0)).cross(Eigen::Vector3d(R.col(1)));
    for (int c = 0; c < d; ++c, ++col)
      for (int i = 0; i < d; ++i)
        if (R(i, c) != 0.0) t.emplace_back(static_cast<int>(d * v + i), static_cast<int>(col), R(i, c));
  }
  m_T.resize(N * d, col);
  m_T.setFromTriplets(t.begin(), t.end());
}

MovableSpMat DofMap::reduce(SpMat A) const {
  // Tᵀ A T without general sparse products (two of them cost ~2.6 s at 2.1M dofs): T is a
  // selection/permutation except for the rotations R_k of the Γ3 nodes, which only mix the d
  // components of one node. So: (1) rotate the Γ3 node blocks of A in place (the pattern is
  // unchanged because A has full d×d node blocks), (2) select and renumber rows/columns.
  // Falls back to the products if A lacks full node blocks.
  const int d = m_dim;
  // A is ours: a caller that passes a temporary (a prvalue, e.g. assemble_stiffness(...)) pays no
  // copy (C++17 elision); std::move would not help, Eigen 3.4's SparseMatrix has no move
  // constructor. Its pattern is checked before anything is rotated, so the fallback still sees the
  // original values.
  A.makeCompressed();
  SpMat& B = A;
  const Index n_full = B.rows();
  std::vector<Index> red(n_full, -1);  // full dof → reduced index (after rotation: local component)
  std::vector<Mat> rot;                // per Γ3 node: R (columns ν, τ...)
  std::vector<Index> rot_node;         // its mesh node
  for (Index c = 0; c < m_T.cols(); ++c) {
    for (SpMat::InnerIterator it(m_T, c); it; ++it) {
      if (c < m_n_interior) red[it.row()] = c;
    }
  }
  for (Index c = m_n_interior; c < m_T.cols(); c += d) {
    Mat R = Mat::Zero(d, d);
    Index node = -1;
    for (int k = 0; k < d; ++k)
      for (SpMat::InnerIterator it(m_T, c + k); it; ++it) {
        node = it.row() / d;
        R(it.row() % d, k) = it.value();
      }
    for (int k = 0; k < d; ++k) red[d * node + k] = c + k;
    rot.push_back(R);
    rot_node.push_back(node);
  }
  int* outer = B.outerIndexPtr();
  int* inner = B.innerIndexPtr();
  double* val = B.valuePtr();
  // The fast path needs (a) the d columns of a rotated node to share one row pattern and (b) in
  // every column, the rows of a rotated node to be d consecutive entries.
  std::vector<int> is_rot(n_full / d, -1);
  for (size_t q = 0; q < rot.size(); ++q) is_rot[rot_node[q]] = static_cast<int>(q);
  for (size_t q = 0; q < rot.size(); ++q) {
    const Index v = rot_node[q];
    const Index len = outer[d * v + 1] - outer[d * v];
    for (int k = 1; k < d; ++k)
      if (outer[d * v + k + 1] - outer[d * v + k] != len ||
          !std::equal(inner + outer[d * v], inner + outer[d * v + 1], inner + outer[d * v + k]))
        return reduce_by_products(A);
  }
  for (Index j = 0; j < B.cols(); ++j)
    for (int p = outer[j]; p < outer[j + 1];) {
      if (is_rot[inner[p] / d] < 0) {
        ++p;
        continue;
      }
      if (inner[p] % d != 0 || p + d > outer[j + 1] || inner[p + d - 1] != inner[p] + d - 1)
        return reduce_by_products(A);
      p += d;
    }
  for (size_t q = 0; q < rot.size(); ++q) {
    const Index v = rot_node[q];
    const Mat& R = rot[q];
    // Columns d·v..d·v+d−1 share one row pattern: B[:, block] ← B[:, block] R.
    const Index len = outer[d * v + 1] - outer[d * v];
    Mat cols(len, d);
    for (int k = 0; k < d; ++k) cols.col(k) = Eigen::Map<const Vec>(val + outer[d * v + k], len);
    cols = cols * R;
    for (int k = 0; k < d; ++k) Eigen::Map<Vec>(val + outer[d * v + k], len) = cols.col(k);
  }
  for (Index j = 0; j < B.cols(); ++j)
    for (int p = outer[j]; p < outer[j + 1];) {
      const int q = is_rot[inner[p] / d];
      if (q < 0) {
        ++p;
        continue;
      }
      Vec r = rot[q].transpose() * Eigen::Map<const Vec>(val + p, d);
      Eigen::Map<Vec>(val + p, d) = r;
      p += d;
    }
  // Select free dofs and renumber, straight into the result's compressed storage. The renumbering
  // keeps the interior dofs in their order and moves the Γ3 dofs to the end, so in each column the
  // interior rows come out sorted and only the few Γ3 rows (a handful of node blocks) need sorting:
  // no general sort, no intermediate arrays (issue 14: assembly at the cost of a plain CSC one).
  const Index n = m_T.cols();
  std::vector<Index> full_of(n);
  for (Index f = 0; f < n_full; ++f)
    if (red[f] >= 0) full_of[red[f]] = f;
  MovableSpMat R(n, n);  // returned by move (a SpMat would be copied: no NRVO with two kinds of return)
  int* ro = R.outerIndexPtr();  // n + 1 entries, zeroed by the constructor
  for (Index c = 0; c < n; ++c) {
    const Index j = full_of[c];
    int cnt = 0;
    for (int p = outer[j]; p < outer[j + 1]; ++p) cnt += red[inner[p]] >= 0;
    ro[c + 1] = ro[c] + cnt;
  }
  R.resizeNonZeros(ro[n]);
  int* ri = R.innerIndexPtr();
  double* rv = R.valuePtr();
  for (Index c = 0; c < n; ++c) {
    const Index j = full_of[c];
    int k = ro[c];
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      const Index r = red[inner[p]];
      if (r < 0) continue;
      // Insertion into the sorted column: interior rows arrive in order (the loop does not move),
      // Γ3 rows move past at most the other Γ3 entries of this column.
      int q = k++;
      while (q > ro[c] && ri[q - 1] > r) {
        ri[q] = ri[q - 1];
        rv[q] = rv[q - 1];
        --q;
      }
      ri[q] = static_cast<int>(r);
      rv[q] = val[p];
    }
  }
  return R;
}

SpMat DofMap::reduce_by_products(const SpMat& A) const {
  SpMat TtA = m_T.transpose() * A;
  SpMat R = TtA * m_T;
  R.makeCompressed();
  return R;
}

}  // namespace hemicontact
