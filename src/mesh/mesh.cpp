#include <hemicontact/mesh/mesh.hpp>

#include <hemicontact/core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace hemicontact {

const char* to_string(Part p) {
  switch (p) {
    case Part::GAMMA1: return "gamma1";
    case Part::GAMMA2: return "gamma2";
    case Part::GAMMA3: return "gamma3";
    default: return "none";
  }
}

double Mesh::cell_measure(Index c) const {
  if (dim == 2) {
    const auto a = points.row(cells(c, 0)), b = points.row(cells(c, 1)), d = points.row(cells(c, 2));
    return 0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]));
  }
  Eigen::Matrix3d J;
  for (int k = 0; k < 3; ++k) J.col(k) = (points.row(cells(c, k + 1)) - points.row(cells(c, 0))).transpose();
  return J.determinant() / 6.0;
}

double Mesh::facet_measure(Index f) const {
  if (dim == 2) return (points.row(facets(f, 1)) - points.row(facets(f, 0))).norm();
  const Eigen::Vector3d e1 = (points.row(facets(f, 1)) - points.row(facets(f, 0))).transpose();
  const Eigen::Vector3d e2 = (points.row(facets(f, 2)) - points.row(facets(f, 0))).transpose();
  return 0.5 * e1.cross(e2).norm();
}

Vec Mesh::facet_normal(Index f) const {
  // Facets are stored so that the body lies on the left of the edge a→b in 2D (counter-clockwise
  // boundary traversal), i.e. the outward normal is the edge direction turned clockwise; in 3D the
  // facet is ordered so that (b−a)×(c−a) points outward.
  if (dim == 2) {
    const Vec e = (points.row(facets(f, 1)) - points.row(facets(f, 0))).transpose();
    Vec n(2);
    n << e[1], -e[0];
    return n / n.norm();
  }
  const Eigen::Vector3d e1 = (points.row(facets(f, 1)) - points.row(facets(f, 0))).transpose();
  const Eigen::Vector3d e2 = (points.row(facets(f, 2)) - points.row(facets(f, 0))).transpose();
  const Eigen::Vector3d n = e1.cross(e2);
  return n / n.norm();
}

namespace {

// Same orientation of two orderings of one facet: equal up to a cyclic rotation (2D: equal).
bool same_orientation(const std::array<int, 3>& a, const std::array<int, 3>& b, int dim) {
  if (dim == 2) return a[0] == b[0] && a[1] == b[1];
  for (int r = 0; r < 3; ++r)
    if (a[0] == b[r] && a[1] == b[(r + 1) % 3] && a[2] == b[(r + 2) % 3]) return true;
  return false;
}

template <class F>
void for_each_edge(const Mesh& m, F&& f) {
  const int nv = m.dim + 1;
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int a = 0; a < nv; ++a)
      for (int b = a + 1; b < nv; ++b) f(m.cells(c, a), m.cells(c, b));
}
}  // namespace

double Mesh::min_edge_length() const {
  double h = INF;
  for_each_edge(*this, [&](int a, int b) { h = std::min(h, (points.row(a) - points.row(b)).norm()); });
  return h;
}

double Mesh::max_edge_length() const {
  double h = 0;
  for_each_edge(*this, [&](int a, int b) { h = std::max(h, (points.row(a) - points.row(b)).norm()); });
  return h;
}

void extract_boundary_facets(Mesh& mesh) {
  const int d = mesh.dim, nv = d + 1;
  // Every cell facet once, keyed by its sorted nodes; sorting the list brings the two copies of an
  // interior facet together (O(F log F), no node-based map: 6M facets at 2M cells).
  struct Entry {
    std::array<int, 3> key;  // sorted nodes (unused third entry −1 in 2D)
    std::array<int, 3> oriented;
    Index cell;
  };
  std::vector<Entry> all;
  all.reserve(static_cast<size_t>(mesh.num_cells()) * nv);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    for (int skip = 0; skip < nv; ++skip) {
      std::array<int, 3> f{-1, -1, -1};
      if (d == 2) {
        // For a positively oriented triangle (v0,v1,v2) the boundary edges opposite vertex s,
        // traversed counter-clockwise, are (v1,v2), (v2,v0), (v0,v1).
        static const int edges[3][2] = {{1, 2}, {2, 0}, {0, 1}};
        f[0] = mesh.cells(c, edges[skip][0]);
        f[1] = mesh.cells(c, edges[skip][1]);
      } else {
        // For a positive tet, the outward faces are (1,2,3), (0,3,2), (0,1,3), (0,2,1).
        static const int faces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
        for (int a = 0; a < 3; ++a) f[a] = mesh.cells(c, faces[skip][a]);
      }
      std::array<int, 3> key = f;
      if (d == 2) {
        if (key[0] > key[1]) std::swap(key[0], key[1]);
      } else {
        std::sort(key.begin(), key.end());
      }
      all.push_back({key, f, c});
    }
  }
  // Sorted by key in two steps (one comparison sort of all 3·cells entries was 6 % of a default run
  // at n = 256): a counting sort on the smallest node, then each bucket — the few facets whose
  // smallest node is that node — sorted in place. Same order as one full sort.
  {
    const Index N = mesh.num_nodes();
    std::vector<Index> start(static_cast<size_t>(N) + 1, 0);
    for (const Entry& e : all) {
      if (e.key[0] < 0 || e.key[d - 1] >= N)  // a bucket index out of range would write anywhere
        input_error("mesh: cell " + std::to_string(e.cell) + " refers to a node outside 0.." + std::to_string(N - 1));
      ++start[static_cast<size_t>(e.key[0]) + 1];
    }
    for (Index v = 0; v < N; ++v) start[v + 1] += start[v];
    std::vector<Entry> by_node(all.size());
    std::vector<Index> fill(start.begin(), start.end() - 1);
    for (const Entry& e : all) by_node[static_cast<size_t>(fill[e.key[0]]++)] = e;
    all.swap(by_node);
    for (Index v = 0; v < N; ++v)
      std::sort(all.begin() + start[v], all.begin() + start[v + 1],
                [](const Entry& a, const Entry& b) { return a.key < b.key; });
  }
  std::vector<std::array<int, 3>> boundary;
  for (size_t i = 0; i < all.size();) {
    size_t j = i + 1;
    while (j < all.size() && all[j].key == all[i].key) ++j;
    if (j - i > 2) {
      const auto& key = all[i].key;
      std::ostringstream os;
      os << "mesh: facet (" << key[0] << ", " << key[1] << (d == 3 ? ", " + std::to_string(key[2]) : "")
         << ") is shared by more than two cells (non-manifold mesh)";
      input_error(os.str());
    }
    if (j - i == 1) boundary.push_back(all[i].oriented);
    // Two consistently oriented cells traverse their common facet in opposite orders (each lies on
    // its own side); the same order means they overlap: the mesh is folded.
    if (j - i == 2 && same_orientation(all[i].oriented, all[i + 1].oriented, d)) {
      std::ostringstream os;
      os << "mesh: cells " << std::min(all[i].cell, all[i + 1].cell) << " and "
         << std::max(all[i].cell, all[i + 1].cell) << " overlap across their common facet (nodes";
      for (int a = 0; a < d; ++a) os << ' ' << all[i].key[a];
      os << "): the mesh is folded (an inverted cell)";
      input_error(os.str());
    }
    i = j;
  }
  mesh.facets.resize(static_cast<Index>(boundary.size()), d);
  for (Index i = 0; i < mesh.facets.rows(); ++i)
    for (int a = 0; a < d; ++a) mesh.facets(i, a) = boundary[i][a];
  mesh.facet_part.assign(boundary.size(), Part::NONE);
  mesh.facet_load.assign(boundary.size(), -1);
}

void check_cells(const Mesh& mesh) {
  if (mesh.num_cells() == 0) input_error("mesh: no cells");
  const double h = mesh.max_edge_length();
  // A cell is degenerate when its measure is below round-off relative to h^d.
  const double tiny = 1e-12 * std::pow(h, mesh.dim);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    const double m = mesh.cell_measure(c);
    if (!(m > tiny)) {
      std::ostringstream os;
      os << "mesh: cell " << c << " (nodes";
      for (int a = 0; a <= mesh.dim; ++a) os << ' ' << mesh.cells(c, a);
      os << ") is " << (m < -tiny ? "inverted" : "degenerate (zero measure)") << ", measure " << m;
      // A random perturbation of h/4 or more per coordinate can invert a cell (scene_schema.cpp,
      // mesh.perturb); name the cause.
      if (mesh.origin.find("perturbed") != std::string::npos)
        os << " (" << mesh.origin << "; lower mesh.perturb or change mesh.seed)";
      input_error(os.str());
    }
  }
}

}  // namespace hemicontact
