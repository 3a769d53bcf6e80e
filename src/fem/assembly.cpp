#include <hemicontact/fem/assembly.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/p1.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hemicontact {
namespace {

using Adjacency = NodeGraph;
Adjacency node_adjacency(const Mesh& m, const std::vector<char>* keep = nullptr) { return node_graph(m, keep); }

// The element stiffness |T| Bᵀ D B of cell c (Cartesian components, nodes in cell order).
template <int D>
typename P1<D>::KMat element_stiffness(const Mesh& m, Index c,
                                       const Eigen::Matrix<double, P1<D>::NVOIGT, P1<D>::NVOIGT>& Dm) {
  double vol;
  const auto B = P1<D>::strain_matrix(P1<D>::gradients(m, c, vol));
  return vol * B.transpose() * Dm * B;
}

// Direct assembly into a precomputed compressed pattern: no triplet list (which at 2M cells would
// hold 75M entries, 1.2 GB, and cost a sort), each element block lands at a looked-up position.
template <int D>
SpMat stiffness(const Mesh& m, const Mat& Ddyn) {
  using E = P1<D>;
  const Eigen::Matrix<double, E::NVOIGT, E::NVOIGT> Dm = Ddyn;
  const auto adj = node_adjacency(m);
  const Index N = m.num_nodes(), n = N * D;
  // Column d·a+i holds rows d·b+j for b ∈ adj(a), j < d: already sorted. The pattern and values
  // are written straight into K's compressed storage: building them in vectors and copying them in
  // through a Map was one more pass over (and page faults on) the largest array of the run.
  SpMat K(n, n);
  int* outer = K.outerIndexPtr();  // n + 1 entries, zeroed by the constructor
  for (Index a = 0; a < N; ++a)
    for (int i = 0; i < D; ++i) outer[D * a + i + 1] = static_cast<int>(adj.size(a) * D);
  for (Index c = 0; c < n; ++c) outer[c + 1] += outer[c];
  K.resizeNonZeros(outer[n]);
  int* inner = K.innerIndexPtr();
  double* values = K.valuePtr();
  for (Index a = 0; a < N; ++a)
    for (int i = 0; i < D; ++i) {
      int* dst = inner + outer[D * a + i];
      for (const int* b = adj.begin(a); b != adj.end(a); ++b)
        for (int j = 0; j < D; ++j) *dst++ = D * *b + j;
    }
  std::fill(values, values + outer[n], 0.0);
  for (Index c = 0; c < m.num_cells(); ++c) {
    const typename E::KMat Ke = element_stiffness<D>(m, c, Dm);
    for (int a = 0; a < E::NV; ++a) {
      const int na = m.cells(c, a);
      const int* nb_first = adj.begin(na);
      const int* nb_last = adj.end(na);
      for (int b = 0; b < E::NV; ++b) {
        const int nb = m.cells(c, b);
        const int slot = static_cast<int>(std::lower_bound(nb_first, nb_last, nb) - nb_first);
        for (int i = 0; i < D; ++i) {
          double* col = values + outer[D * na + i] + D * slot;
          for (int j = 0; j < D; ++j) col[j] += Ke(D * b + j, D * a + i);
        }
      }
    }
  }
  return K;
}

// K_x straight into the free dofs' pattern. Column x_c of a free component of node a holds the
// free components of a's neighbours, all columns of one node sharing that row list; selection
// order keeps interior rows sorted in node order, the Γ3 ones (Cartesian components of a node in
// its d consecutive local slots, last) are sorted apart. An element's block (a, b) is placed by
// one binary search for b's first free row per column of a: b's free components are consecutive.
// Only the columns of the nodes in @p own_nodes (null: all) are filled, the others left empty: a
// rank's rows.
template <int D>
MovableSpMat reduced_stiffness(const Mesh& m, const Mat& Ddyn, const DofMap& dofs, const std::vector<char>* own_nodes) {
  using E = P1<D>;
  const Eigen::Matrix<double, E::NVOIGT, E::NVOIGT> Dm = Ddyn;
  const std::vector<Index> sel = dofs.cartesian_selection();
  const Index N = m.num_nodes(), n = dofs.n_free(), n_int = dofs.n_interior();
  const bool all = own_nodes == nullptr;
  std::vector<int> n_free_of(N, 0);  // free components per node
  for (Index a = 0; a < N; ++a)
    for (int i = 0; i < D; ++i) n_free_of[a] += sel[D * a + i] >= 0;
  const auto adj = node_adjacency(m, own_nodes);
  const auto owned = [&](Index a) { return n_free_of[a] > 0 && (all || (*own_nodes)[static_cast<size_t>(a)]); };
  MovableSpMat K(n, n);
  int* outer = K.outerIndexPtr();  // n + 1 entries, zeroed by the constructor
  for (Index a = 0; a < N; ++a) {
    if (!owned(a)) continue;
    int cnt = 0;
    for (const int* b = adj.begin(a); b != adj.end(a); ++b) cnt += n_free_of[*b];
    for (int i = 0; i < D; ++i)
      if (sel[D * a + i] >= 0) outer[sel[D * a + i] + 1] = cnt;
  }
  for (Index c = 0; c < n; ++c) outer[c + 1] += outer[c];
  K.resizeNonZeros(outer[n]);
  int* inner = K.innerIndexPtr();
  double* values = K.valuePtr();
  std::vector<int> rows;
  for (Index a = 0; a < N; ++a) {
    if (!owned(a)) continue;
    rows.clear();
    for (const int* b = adj.begin(a); b != adj.end(a); ++b)
      for (int j = 0; j < D; ++j)
        if (sel[D * *b + j] >= 0) rows.push_back(static_cast<int>(sel[D * *b + j]));
    // Interior rows are already in order; only the Γ3 ones (whole node blocks) need sorting.
    const auto first_contact = std::stable_partition(rows.begin(), rows.end(), [&](int r) { return r < n_int; });
    std::sort(first_contact, rows.end());
    for (int i = 0; i < D; ++i)
      if (sel[D * a + i] >= 0) std::copy(rows.begin(), rows.end(), inner + outer[sel[D * a + i]]);
  }
  std::fill(values, values + outer[n], 0.0);
  for (Index c = 0; c < m.num_cells(); ++c) {
    if (!all) {
      bool any = false;
      for (int a = 0; a < E::NV && !any; ++a) any = owned(m.cells(c, a));
      if (!any) continue;
    }
    const typename E::KMat Ke = element_stiffness<D>(m, c, Dm);
    for (int a = 0; a < E::NV; ++a) {
      const int na = m.cells(c, a);
      if (!owned(na)) continue;
      for (int b = 0; b < E::NV; ++b) {
        const int nb = m.cells(c, b);
        if (n_free_of[nb] == 0) continue;
        int j0 = 0;
        while (sel[D * nb + j0] < 0) ++j0;
        const int r0 = static_cast<int>(sel[D * nb + j0]);
        for (int i = 0; i < D; ++i) {
          const Index col = sel[D * na + i];
          if (col < 0) continue;
          const int p = static_cast<int>(std::lower_bound(inner + outer[col], inner + outer[col + 1], r0) - inner);
          double* v = values + p;
          for (int j = j0; j < D; ++j)
            if (sel[D * nb + j] >= 0) *v++ += Ke(D * b + j, D * a + i);
        }
      }
    }
  }
  if (!dofs.rotate_to_contact_frames(K))
    throw Error("assemble_reduced_stiffness: a Γ3 node without its full block", EXIT_INTERNAL);
  return K;
}

template <int D>
RowMat strains(const Mesh& m, const Vec& u) {
  using E = P1<D>;
  RowMat eps(m.num_cells(), E::NVOIGT);
  for (Index c = 0; c < m.num_cells(); ++c) {
    double vol;
    const auto B = E::strain_matrix(E::gradients(m, c, vol));
    Eigen::Matrix<double, E::NDOF, 1> ue;
    for (int a = 0; a < E::NV; ++a)
      for (int i = 0; i < D; ++i) ue[D * a + i] = u[D * m.cells(c, a) + i];
    eps.row(c) = (B * ue).transpose();
  }
  return eps;
}

}  // namespace

// Two passes over the cells into compressed rows: one vector per node was a million small
// allocations at n = 1024.
NodeGraph node_graph(const Mesh& m, const std::vector<char>* keep) {
  const int nv = m.dim + 1;
  const Index N = m.num_nodes();
  const auto kept = [keep](Index a) { return !keep || (*keep)[static_cast<size_t>(a)]; };
  std::vector<Index> count(N + 1, 0);  // with repeats: nv per cell a node is in
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int a = 0; a < nv; ++a)
      if (kept(m.cells(c, a))) count[m.cells(c, a) + 1] += nv;
  for (Index a = 0; a < N; ++a) count[a + 1] += count[a];
  std::vector<int> raw(count[N]);
  std::vector<Index> fill(count.begin(), count.end() - 1);
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int a = 0; a < nv; ++a) {
      const int na = m.cells(c, a);
      if (kept(na))
        for (int b = 0; b < nv; ++b) raw[fill[na]++] = m.cells(c, b);
    }
  NodeGraph adj;
  adj.ptr.assign(N + 1, 0);
  adj.nbr.reserve(raw.size() / 2);
  for (Index a = 0; a < N; ++a) {
    int* first = raw.data() + count[a];
    int* last = raw.data() + count[a + 1];
    std::sort(first, last);
    last = std::unique(first, last);
    adj.nbr.insert(adj.nbr.end(), first, last);
    adj.ptr[a + 1] = static_cast<Index>(adj.nbr.size());
  }
  return adj;
}

SpMat assemble_stiffness(const Mesh& mesh, const Material& material) {
  if (!material.is_linear()) throw Error("assemble_stiffness: material is nonlinear", EXIT_INTERNAL);
  const Vec zero = Vec::Zero(voigt_size(mesh.dim));
  return mesh.dim == 2 ? stiffness<2>(mesh, material.tangent(zero)) : stiffness<3>(mesh, material.tangent(zero));
}

SpMat assemble_stiffness(const Mesh& mesh, const Mat& D) {
  if (D.rows() != voigt_size(mesh.dim) || D.cols() != D.rows())
    throw Error("assemble_stiffness: Voigt matrix of the wrong size", EXIT_INTERNAL);
  return mesh.dim == 2 ? stiffness<2>(mesh, D) : stiffness<3>(mesh, D);
}

MovableSpMat assemble_reduced_stiffness(const Mesh& mesh, const Mat& D, const DofMap& dofs, Index col_lo,
                                        Index col_hi) {
  if (D.rows() != voigt_size(mesh.dim) || D.cols() != D.rows())
    throw Error("assemble_reduced_stiffness: Voigt matrix of the wrong size", EXIT_INTERNAL);
  if (dofs.n_full() != mesh.num_nodes() * mesh.dim)
    throw Error("assemble_reduced_stiffness: the DofMap belongs to another mesh", EXIT_INTERNAL);
  if (col_hi < 0) col_hi = dofs.n_free();
  if (col_lo <= 0 && col_hi >= dofs.n_free())
    return mesh.dim == 2 ? reduced_stiffness<2>(mesh, D, dofs, nullptr) : reduced_stiffness<3>(mesh, D, dofs, nullptr);
  // The nodes with a free column in [col_lo, col_hi).
  const std::vector<Index> sel = dofs.cartesian_selection();
  std::vector<char> own(static_cast<size_t>(mesh.num_nodes()), 0);
  for (size_t j = 0; j < sel.size(); ++j)
    if (sel[j] >= col_lo && sel[j] < col_hi) own[j / static_cast<size_t>(mesh.dim)] = 1;
  return assemble_reduced_stiffness(mesh, D, dofs, own);
}

MovableSpMat assemble_reduced_stiffness(const Mesh& mesh, const Mat& D, const DofMap& dofs,
                                        const std::vector<char>& own_nodes) {
  if (D.rows() != voigt_size(mesh.dim) || D.cols() != D.rows())
    throw Error("assemble_reduced_stiffness: Voigt matrix of the wrong size", EXIT_INTERNAL);
  if (dofs.n_full() != mesh.num_nodes() * mesh.dim)
    throw Error("assemble_reduced_stiffness: the DofMap belongs to another mesh", EXIT_INTERNAL);
  if (own_nodes.size() != static_cast<size_t>(mesh.num_nodes()))
    throw Error("assemble_reduced_stiffness: the node mask has the wrong size", EXIT_INTERNAL);
  return mesh.dim == 2 ? reduced_stiffness<2>(mesh, D, dofs, &own_nodes)
                       : reduced_stiffness<3>(mesh, D, dofs, &own_nodes);
}

Vec assemble_body_force(const Mesh& mesh, const Vec& f0) {
  const int d = mesh.dim;
  Vec f = Vec::Zero(mesh.num_nodes() * d);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    const double share = mesh.cell_measure(c) / (d + 1);
    for (int a = 0; a <= d; ++a) f.segment(d * mesh.cells(c, a), d) += share * f0;
  }
  return f;
}

Vec assemble_tractions(const Mesh& mesh) {
  const int d = mesh.dim;
  Vec f = Vec::Zero(mesh.num_nodes() * d);
  for (Index k = 0; k < mesh.num_facets(); ++k) {
    if (mesh.facet_part[k] != Part::GAMMA2) continue;
    const Vec& f2 = mesh.tractions.at(mesh.facet_load[k]);
    const double share = mesh.facet_measure(k) / d;
    for (int a = 0; a < d; ++a) f.segment(d * mesh.facets(k, a), d) += share * f2;
  }
  return f;
}

RowMat cell_strains(const Mesh& mesh, const Vec& u) {
  return mesh.dim == 2 ? strains<2>(mesh, u) : strains<3>(mesh, u);
}

double von_mises(const Eigen::Ref<const Eigen::RowVectorXd>& s, int dim) {
  if (dim == 2) return std::sqrt(s[0] * s[0] - s[0] * s[1] + s[1] * s[1] + 3 * s[2] * s[2]);
  const double a = s[0] - s[1], b = s[1] - s[2], c = s[2] - s[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

}  // namespace hemicontact
