#include <hemicontact/fem/dof_map.hpp>

namespace hemicontact {

DofMap::DofMap(const Mesh& mesh, const std::vector<bool>& clamped, const ContactNodes& contact)
    : m_dim(mesh.dim) {
  const int d = mesh.dim;
  const Index N = mesh.num_nodes();
  std::vector<Index> contact_index(N, -1);
  for (Index k = 0; k < contact.size(); ++k) contact_index[contact.node[k]] = k;
  Triplets t;
  t.reserve(static_cast<size_t>(N * d + contact.size() * d * d));
  Index col = 0;
  for (Index v = 0; v < N; ++v) {
    if (clamped[v] || contact_index[v] >= 0) continue;
    for (int i = 0; i < d; ++i) t.emplace_back(static_cast<int>(d * v + i), static_cast<int>(col++), 1.0);
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

SpMat DofMap::reduce(const SpMat& A) const {
  SpMat TtA = m_T.transpose() * A;
  SpMat R = TtA * m_T;
  R.makeCompressed();
  return R;
}

}  // namespace hemicontact
