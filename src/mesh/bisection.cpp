#include <hemicontact/mesh/bisection.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/mesh/edge_key.hpp>

#include <algorithm>
#include <cstdint>

namespace hemicontact {
namespace {

void require_2d(const Mesh& m, const char* what) {
  if (m.dim != 2)
    input_error(std::string(what) + ": this is the triangles' (2D) bisection; a " + std::to_string(m.dim) +
                "D mesh is refined with its tagged tetrahedra (label_tetrahedra, bisect with labels)");
}

}  // namespace

BisectionRule parse_bisection_rule(const std::string& name) {
  if (name == "newest_vertex") return BisectionRule::NEWEST_VERTEX;
  if (name == "bisec3") return BisectionRule::BISEC3;
  input_error("adapt.bisection: unknown rule '" + name + "' (expected newest_vertex or bisec3)");
}

const char* to_string(BisectionRule rule) { return rule == BisectionRule::BISEC3 ? "bisec3" : "newest_vertex"; }

void label_longest_edges(Mesh& mesh) {
  require_2d(mesh, "label_longest_edges");
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    const int v[3] = {mesh.cells(c, 0), mesh.cells(c, 1), mesh.cells(c, 2)};
    // Edge opposite vertex r: (v[r+1], v[r+2]).
    double len[3];
    for (int r = 0; r < 3; ++r) len[r] = (mesh.points.row(v[(r + 1) % 3]) - mesh.points.row(v[(r + 2) % 3])).norm();
    int best = 0;
    for (int r = 1; r < 3; ++r)
      if (len[r] > len[best] * (1 + 1e-12)) best = r;
    for (int r = 0; r < 3; ++r) mesh.cells(c, r) = v[(best + r) % 3];
  }
}

namespace {

// The coarse mesh's edges: per cell its refinement edge (c1,c2) and the two others.
struct CoarseEdges {
  std::vector<std::array<int, 2>> edge_nodes;
  std::vector<std::array<int, 3>> cell_edges;  // [0] refinement edge
  std::vector<std::array<int, 2>> edge_cells;  // ≤ 2 cells per edge
};

// The midpoint node of each marked edge, by edge_key.
using EdgeMidpoints = EdgeMap;

CoarseEdges coarse_edges(const Mesh& coarse) {
  const Index M = coarse.num_cells();
  CoarseEdges E;
  EdgeMap edge_id(static_cast<size_t>(2 * M + coarse.num_facets()));
  E.cell_edges.resize(static_cast<size_t>(M));
  for (Index c = 0; c < M; ++c) {
    const int v0 = coarse.cells(c, 0), v1 = coarse.cells(c, 1), v2 = coarse.cells(c, 2);
    const int ends[3][2] = {{v1, v2}, {v2, v0}, {v0, v1}};
    for (int k = 0; k < 3; ++k) {
      const auto [id, fresh] = edge_id.emplace(edge_key(ends[k][0], ends[k][1]), static_cast<int>(E.edge_nodes.size()));
      if (fresh) {
        E.edge_nodes.push_back({ends[k][0], ends[k][1]});
        E.edge_cells.push_back({static_cast<int>(c), -1});
      } else {
        E.edge_cells[static_cast<size_t>(id)][1] = static_cast<int>(c);
      }
      E.cell_edges[static_cast<size_t>(c)][static_cast<size_t>(k)] = id;
    }
  }
  return E;
}

// Mark, then close: a cell with a marked edge must have its refinement edge marked.
std::vector<char> close_marking(const CoarseEdges& E, const std::vector<char>& marked, BisectionRule rule) {
  std::vector<char> edge_marked(E.edge_nodes.size(), 0);
  std::vector<int> queue;
  const auto mark = [&](int e) {
    if (!edge_marked[static_cast<size_t>(e)]) {
      edge_marked[static_cast<size_t>(e)] = 1;
      queue.push_back(e);
    }
  };
  for (size_t c = 0; c < marked.size(); ++c)
    if (marked[c]) {
      mark(E.cell_edges[c][0]);
      if (rule == BisectionRule::BISEC3) {
        mark(E.cell_edges[c][1]);
        mark(E.cell_edges[c][2]);
      }
    }
  while (!queue.empty()) {
    const int e = queue.back();
    queue.pop_back();
    for (int c : E.edge_cells[static_cast<size_t>(e)])
      if (c >= 0) mark(E.cell_edges[static_cast<size_t>(c)][0]);
  }
  return edge_marked;
}

// Recursive bisection along marked refinement edges (depth ≤ 2: the grandchildren's refinement
// edges are new edges, never marked).
void bisect_cells(const Mesh& coarse, const EdgeMidpoints& midpoint, Bisection& out) {
  const Index M = coarse.num_cells();
  std::vector<std::array<int, 3>> cells;
  cells.reserve(static_cast<size_t>(M) + 3 * midpoint.size());
  const auto refine = [&](auto&& self, int a0, int a1, int a2, int parent) -> void {
    const int m = midpoint.find(edge_key(a1, a2));
    if (m < 0) {
      cells.push_back({a0, a1, a2});
      out.cell_parent.push_back(parent);
      return;
    }
    self(self, m, a0, a1, parent);
    self(self, m, a2, a0, parent);
  };
  for (Index c = 0; c < M; ++c)
    refine(refine, coarse.cells(c, 0), coarse.cells(c, 1), coarse.cells(c, 2), static_cast<int>(c));
  Mesh& fine = out.mesh;
  fine.cells.resize(static_cast<Index>(cells.size()), 3);
  for (size_t c = 0; c < cells.size(); ++c)
    for (int k = 0; k < 3; ++k) fine.cells(static_cast<Index>(c), k) = cells[c][static_cast<size_t>(k)];
}

// Boundary facets: a split facet (a, b) becomes (a, m), (m, b), same part, load and groups.
void split_facets(const Mesh& coarse, const EdgeMidpoints& midpoint, Mesh& fine) {
  std::vector<std::vector<Index>> children(static_cast<size_t>(coarse.num_facets()));
  std::vector<std::array<int, 2>> facets;
  for (Index f = 0; f < coarse.num_facets(); ++f) {
    const int a = coarse.facets(f, 0), b = coarse.facets(f, 1);
    const int m = midpoint.find(edge_key(a, b));
    auto& ch = children[static_cast<size_t>(f)];
    if (m < 0) {
      ch.push_back(static_cast<Index>(facets.size()));
      facets.push_back({a, b});
    } else {
      ch.push_back(static_cast<Index>(facets.size()));
      facets.push_back({a, m});
      ch.push_back(static_cast<Index>(facets.size()));
      facets.push_back({m, b});
    }
  }
  fine.facets.resize(static_cast<Index>(facets.size()), 2);
  fine.facet_part.resize(facets.size(), Part::NONE);
  fine.facet_load.resize(facets.size(), -1);
  for (Index f = 0; f < coarse.num_facets(); ++f)
    for (Index g : children[static_cast<size_t>(f)]) {
      fine.facets(g, 0) = facets[static_cast<size_t>(g)][0];
      fine.facets(g, 1) = facets[static_cast<size_t>(g)][1];
      fine.facet_part[static_cast<size_t>(g)] = coarse.facet_part[static_cast<size_t>(f)];
      fine.facet_load[static_cast<size_t>(g)] = coarse.facet_load[static_cast<size_t>(f)];
    }
  for (const auto& [name, list] : coarse.facet_groups) {
    std::vector<Index>& to = fine.facet_groups[name];
    for (Index f : list) for (Index g : children[static_cast<size_t>(f)]) to.push_back(g);
  }
  fine.tractions = coarse.tractions;
}

// Rollers: a node inserted on a boundary edge is held in the components both ends are held in
// (a roller selects whole facets, so both ends of a roller facet carry its mask; the AND leaves
// out a corner's other roller). Interior midpoints are free.
void inherit_rollers(const Mesh& coarse, const EdgeMidpoints& midpoint, Mesh& fine) {
  if (coarse.node_fixed.empty()) return;
  fine.node_fixed.assign(static_cast<size_t>(fine.num_nodes()), 0);
  std::copy(coarse.node_fixed.begin(), coarse.node_fixed.end(), fine.node_fixed.begin());
  for (Index f = 0; f < coarse.num_facets(); ++f) {
    const int a = coarse.facets(f, 0), b = coarse.facets(f, 1);
    const int m = midpoint.find(edge_key(a, b));
    if (m >= 0)
      fine.node_fixed[static_cast<size_t>(m)] =
          coarse.node_fixed[static_cast<size_t>(a)] & coarse.node_fixed[static_cast<size_t>(b)];
  }
}

}  // namespace

Bisection bisect(const Mesh& coarse, const std::vector<char>& marked, BisectionRule rule, Index max_nodes) {
  require_2d(coarse, "bisect");
  const Index M = coarse.num_cells();
  if (static_cast<Index>(marked.size()) != M)
    throw Error("bisect: " + std::to_string(marked.size()) + " flags for " + std::to_string(M) + " cells",
                EXIT_INTERNAL);
  const CoarseEdges E = coarse_edges(coarse);
  const std::vector<char> edge_marked = close_marking(E, marked, rule);

  // One new node per marked edge, numbered in edge order (deterministic).
  Bisection out;
  const Index N0 = coarse.num_nodes();
  out.nodes = N0 + std::count(edge_marked.begin(), edge_marked.end(), char(1));
  if (out.nodes > max_nodes) return out;
  out.built = true;
  EdgeMidpoints midpoint;
  for (size_t e = 0; e < E.edge_nodes.size(); ++e)
    if (edge_marked[e]) {
      midpoint.emplace(edge_key(E.edge_nodes[e][0], E.edge_nodes[e][1]),
                       static_cast<int>(N0 + static_cast<Index>(out.new_node_parents.size())));
      out.new_node_parents.push_back(E.edge_nodes[e]);
    }
  Mesh& fine = out.mesh;
  fine.dim = 2;
  fine.points.resize(N0 + static_cast<Index>(out.new_node_parents.size()), 2);
  fine.points.topRows(N0) = coarse.points;
  for (size_t k = 0; k < out.new_node_parents.size(); ++k)
    fine.points.row(N0 + static_cast<Index>(k)) =
        0.5 * (coarse.points.row(out.new_node_parents[k][0]) + coarse.points.row(out.new_node_parents[k][1]));

  bisect_cells(coarse, midpoint, out);
  split_facets(coarse, midpoint, fine);
  inherit_rollers(coarse, midpoint, fine);
  fine.origin = coarse.origin;
  return out;
}

Vec prolongate_bisection(const Bisection& b, const Vec& u_coarse, int components) {
  const Index N = b.mesh.num_nodes(), N0 = N - static_cast<Index>(b.new_node_parents.size());
  if (u_coarse.size() != N0 * components)
    throw Error("prolongate_bisection: field of size " + std::to_string(u_coarse.size()) + " for " +
                    std::to_string(N0) + " nodes",
                EXIT_INTERNAL);
  Vec u(N * components);
  u.head(N0 * components) = u_coarse;
  for (size_t k = 0; k < b.new_node_parents.size(); ++k) {
    const Index n = N0 + static_cast<Index>(k);
    for (int i = 0; i < components; ++i)
      u[n * components + i] = 0.5 * (u[b.new_node_parents[k][0] * components + i] +
                                     u[b.new_node_parents[k][1] * components + i]);
  }
  return u;
}

}  // namespace hemicontact
