// Maubach bisection of tagged tetrahedra, and AMP's of marked tetrahedra, with the conforming
// closure (mesh/bisection.hpp).
#include <hemicontact/mesh/bisection.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/mesh/edge_key.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>

namespace hemicontact {
namespace {

void require_3d(const Mesh& m, const char* what) {
  if (m.dim != 3)
    input_error(std::string(what) + ": tagged-tetrahedron bisection needs a 3D mesh (got " + std::to_string(m.dim) +
                "D)");
}

// Why a closure can fail: the labelling (label_tetrahedra) is compatible on Kuhn meshes only.
const std::string NOT_KUHN =
    ": the cells' labelling is not compatible. label_tetrahedra's is compatible on Kuhn meshes only "
    "(cube diagonals as the cells' longest edges); label_for_bisection marks any other mesh (mark_tetrahedra)";

// A cell during refinement: Maubach order and tag (0: AMP's marks m), the coarse boundary facet
// each face lies in (face[i] is the face opposite x[i]; −1 inside), and the coarse cell it descends from.
struct Tet {
  std::array<int, 4> x;
  int tag;
  std::array<int, 4> face;
  int parent;
  AmpMarks m;
};

std::array<int, 2> refinement_edge(const Tet& t) { return refinement_edge(t.x, t.tag, t.m); }

// The working state of one bisect() call: cells, nodes and the midpoints by edge.
struct Refinement {
  std::vector<Tet> cells;
  std::vector<Eigen::Vector3d> points;
  EdgeMap midpoint;
  std::vector<std::array<int, 2>> parents;  // of each new node
  // Per node, the last closure pass in which an edge at it was split (−1: never; the marking is
  // pass 0): a cell needs a look in pass p only if two of its nodes were stamped in pass p − 1 or
  // later (every cell was bisected until none of its edges had a midpoint when it was scanned).
  std::vector<int> stamp;
  int pass = 0;
  int n_coarse = 0;

  int split(int a, int b) {
    const auto [m, fresh] = midpoint.emplace(edge_key(a, b), static_cast<int>(points.size()));
    if (fresh) {
      points.push_back(0.5 * (points[static_cast<size_t>(a)] + points[static_cast<size_t>(b)]));
      parents.push_back({a, b});
      stamp.push_back(-1);
      stamp[static_cast<size_t>(a)] = stamp[static_cast<size_t>(b)] = pass;
    }
    return m;
  }
  bool has_split_edge(const Tet& t) const {
    int hot = 0;
    for (int v : t.x) hot += stamp[static_cast<size_t>(v)] >= std::max(pass - 1, 0);
    if (hot < 2) return false;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (midpoint.find(edge_key(t.x[static_cast<size_t>(i)], t.x[static_cast<size_t>(j)])) >= 0) return true;
    return false;
  }
};

// The face of child @p c opposite its vertex i: the parent face it is part of (or −1, the new face
// through z and the two vertices off the refinement edge (x0, xk)).
int child_face(const Tet& p, const std::array<int, 4>& c, int i, int z) {
  std::array<int, 3> s{};
  int n = 0;
  bool has_z = false;
  for (int j = 0; j < 4; ++j)
    if (j != i) {
      if (c[static_cast<size_t>(j)] == z) has_z = true;
      else s[static_cast<size_t>(n++)] = c[static_cast<size_t>(j)];
    }
  const auto in_s = [&](int v) { return std::find(s.begin(), s.begin() + n, v) != s.begin() + n; };
  const auto [e0, ek] = refinement_edge(p);
  if (has_z && !in_s(e0) && !in_s(ek)) return -1;
  // Otherwise the parent face is the one opposite the single parent vertex missing from the
  // child's face and from the refinement edge (z stands for both ends of that edge).
  for (int j = 0; j < 4; ++j) {
    const int v = p.x[static_cast<size_t>(j)];
    const bool on_edge = v == e0 || v == ek;
    if (!in_s(v) && !(has_z && on_edge)) return p.face[static_cast<size_t>(j)];
  }
  throw Error("bisect: inconsistent child face", EXIT_INTERNAL);
}

// AMP's planar types: the marked edges of the three faces at one vertex all lie in the fourth face.
bool planar(const AmpMarks& m) {
  for (int v = 0; v < 4; ++v)
    if (std::count(m.face.begin(), m.face.end(), v) == 3) return true;
  return false;
}

// AMP's rule (AmpMarks): the child with z in place of position @p a (the other end b stays). It
// keeps the parent's face opposite a, with its mark (face[a] unchanged).
Tet amp_child(const Tet& t, int a, int b, int z) {
  Tet c = t;
  c.x[static_cast<size_t>(a)] = z;
  const int kept = t.m.face[static_cast<size_t>(a)];  // the kept face's vertex opposite its mark
  unsigned char e = 0;
  for (int v = 0; v < 4; ++v)  // the refinement edge: the kept face's marked edge
    if (v != a && v != kept) c.m.edge[e++] = static_cast<unsigned char>(v);
  for (int v = 0; v < 4; ++v)  // the halves of the two faces through the parent's refinement edge
    if (v != a && v != b) c.m.face[static_cast<size_t>(v)] = static_cast<unsigned char>(a);
  const bool p = planar(t.m);
  c.m.face[static_cast<size_t>(b)] = static_cast<unsigned char>(p && t.m.flagged ? kept : a);  // the new face
  c.m.flagged = p && !t.m.flagged;
  return c;
}

// Maubach's rule: children (x0..x_{k−1}, z, x_{k+1}..x3) and (x1..x_k, z, x_{k+1}..x3), tag k−1 (3
// after 1); AMP's (amp_child) for a marked tetrahedron.
std::array<Tet, 2> children(const Tet& t, int z) {
  const int k = t.tag;
  Tet a = t, b = t;
  if (k == 0) {
    a = amp_child(t, t.m.edge[0], t.m.edge[1], z);
    b = amp_child(t, t.m.edge[1], t.m.edge[0], z);
  } else {
    a.x[static_cast<size_t>(k)] = z;
    for (int j = 0; j < k; ++j) b.x[static_cast<size_t>(j)] = t.x[static_cast<size_t>(j + 1)];
    b.x[static_cast<size_t>(k)] = z;
    a.tag = b.tag = k > 1 ? k - 1 : 3;
  }
  for (int i = 0; i < 4; ++i) {
    a.face[static_cast<size_t>(i)] = child_face(t, a.x, i, z);
    b.face[static_cast<size_t>(i)] = child_face(t, b.x, i, z);
  }
  return {a, b};
}

// The labelled coarse cells with their boundary faces.
void initial_cells(const Mesh& coarse, const TetLabels& labels, Refinement& R) {
  std::map<std::array<int, 3>, int> facet_of;
  for (Index f = 0; f < coarse.num_facets(); ++f)
    facet_of.emplace(face_key(coarse.facets(f, 0), coarse.facets(f, 1), coarse.facets(f, 2)), static_cast<int>(f));
  R.cells.reserve(static_cast<size_t>(coarse.num_cells()));
  for (Index c = 0; c < coarse.num_cells(); ++c) {
    Tet t{labels.order[static_cast<size_t>(c)], labels.tag[static_cast<size_t>(c)], {}, static_cast<int>(c), {}};
    if (t.tag == 0) t.m = labels.amp.at(static_cast<size_t>(c));
    for (int i = 0; i < 4; ++i) {
      const auto& x = t.x;
      const auto it = facet_of.find(face_key(x[(i + 1) % 4], x[(i + 2) % 4], x[(i + 3) % 4]));
      t.face[static_cast<size_t>(i)] = it == facet_of.end() ? -1 : it->second;
    }
    R.cells.push_back(t);
  }
  R.n_coarse = static_cast<int>(coarse.num_nodes());
  R.points.resize(static_cast<size_t>(coarse.num_nodes()));
  R.stamp.assign(static_cast<size_t>(coarse.num_nodes()), -1);
  for (Index v = 0; v < coarse.num_nodes(); ++v) R.points[static_cast<size_t>(v)] = coarse.points.row(v).transpose();
}

// The closure: bisect every cell that has an edge with a midpoint, until none has. Each pass
// leaves only cells whose refinement edge was split after they were scanned; a compatible
// labelling ends after a few passes, the bound only guards against one that is not.
void close_and_bisect(Refinement& R) {
  const int max_passes = 64;
  for (int& pass = R.pass;; ++pass) {
    if (pass == max_passes)
      input_error("bisect: the closure did not end after " + std::to_string(max_passes) + " passes" + NOT_KUHN);
    bool changed = false;
    for (size_t i = 0; i < R.cells.size();) {
      if (!R.has_split_edge(R.cells[i])) {
        ++i;
        continue;
      }
      const Tet t = R.cells[i];
      const auto [e0, e1] = refinement_edge(t);
      const auto kids = children(t, R.split(e0, e1));
      R.cells[i] = kids[0];
      R.cells.push_back(kids[1]);
      changed = true;
    }
    if (!changed) return;
  }
}

double orient(const std::vector<Eigen::Vector3d>& p, int a, int b, int c, int d) {
  const auto& A = p[static_cast<size_t>(a)];
  return (p[static_cast<size_t>(b)] - A).cross(p[static_cast<size_t>(c)] - A).dot(p[static_cast<size_t>(d)] - A);
}

// Nodes, positively oriented cells and the fine labels.
void fine_cells(const Refinement& R, Bisection& out) {
  Mesh& fine = out.mesh;
  fine.dim = 3;
  fine.points.resize(static_cast<Index>(R.points.size()), 3);
  for (size_t v = 0; v < R.points.size(); ++v) fine.points.row(static_cast<Index>(v)) = R.points[v].transpose();
  const Index M = static_cast<Index>(R.cells.size());
  fine.cells.resize(M, 4);
  out.labels.order.resize(static_cast<size_t>(M));
  out.labels.tag.resize(static_cast<size_t>(M));
  if (std::any_of(R.cells.begin(), R.cells.end(), [](const Tet& t) { return t.tag == 0; }))
    out.labels.amp.resize(static_cast<size_t>(M));
  out.cell_parent.resize(static_cast<size_t>(M));
  for (Index c = 0; c < M; ++c) {
    const Tet& t = R.cells[static_cast<size_t>(c)];
    std::array<int, 4> v = t.x;
    if (orient(R.points, v[0], v[1], v[2], v[3]) < 0) std::swap(v[2], v[3]);
    for (int k = 0; k < 4; ++k) fine.cells(c, k) = v[static_cast<size_t>(k)];
    out.labels.order[static_cast<size_t>(c)] = t.x;
    out.labels.tag[static_cast<size_t>(c)] = static_cast<unsigned char>(t.tag);
    if (t.tag == 0) out.labels.amp[static_cast<size_t>(c)] = t.m;
    out.cell_parent[static_cast<size_t>(c)] = t.parent;
  }
  out.new_node_parents = R.parents;
}

// Boundary facets: every cell face that lies in a coarse boundary facet, oriented outward
// ((b−a)×(c−a) away from the cell's fourth vertex), grouped by coarse facet; part, traction and
// groups inherited.
void fine_facets(const Mesh& coarse, const Refinement& R, Mesh& fine) {
  std::vector<std::pair<int, std::array<int, 3>>> list;
  for (const Tet& t : R.cells)
    for (int i = 0; i < 4; ++i) {
      const int f = t.face[static_cast<size_t>(i)];
      if (f < 0) continue;
      std::array<int, 3> v{t.x[(i + 1) % 4], t.x[(i + 2) % 4], t.x[(i + 3) % 4]};
      if (orient(R.points, v[0], v[1], v[2], t.x[static_cast<size_t>(i)]) > 0) std::swap(v[1], v[2]);
      list.push_back({f, v});
    }
  std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const Index F = static_cast<Index>(list.size());
  fine.facets.resize(F, 3);
  fine.facet_part.resize(static_cast<size_t>(F));
  fine.facet_load.resize(static_cast<size_t>(F));
  std::vector<std::vector<Index>> kids(static_cast<size_t>(coarse.num_facets()));
  for (Index g = 0; g < F; ++g) {
    const auto& [f, v] = list[static_cast<size_t>(g)];
    for (int k = 0; k < 3; ++k) fine.facets(g, k) = v[static_cast<size_t>(k)];
    fine.facet_part[static_cast<size_t>(g)] = coarse.facet_part[static_cast<size_t>(f)];
    fine.facet_load[static_cast<size_t>(g)] = coarse.facet_load[static_cast<size_t>(f)];
    kids[static_cast<size_t>(f)].push_back(g);
  }
  for (const auto& [name, group] : coarse.facet_groups) {
    std::vector<Index>& to = fine.facet_groups[name];
    for (Index f : group) for (Index g : kids[static_cast<size_t>(f)]) to.push_back(g);
  }
  fine.tractions = coarse.tractions;
}

// Rollers: a new node on the boundary is held in the components both ends of its edge are held
// in (as in 2D); interior new nodes are free. Parents precede their midpoint, so one pass in order.
void fine_rollers(const Mesh& coarse, const Refinement& R, Mesh& fine) {
  if (coarse.node_fixed.empty()) return;
  std::vector<char> on_boundary(static_cast<size_t>(fine.num_nodes()), 0);
  for (Index g = 0; g < fine.num_facets(); ++g)
    for (int k = 0; k < 3; ++k) on_boundary[static_cast<size_t>(fine.facets(g, k))] = 1;
  fine.node_fixed.assign(static_cast<size_t>(fine.num_nodes()), 0);
  std::copy(coarse.node_fixed.begin(), coarse.node_fixed.end(), fine.node_fixed.begin());
  for (size_t k = 0; k < R.parents.size(); ++k) {
    const size_t n = static_cast<size_t>(R.n_coarse) + k;
    if (on_boundary[n])
      fine.node_fixed[n] = fine.node_fixed[static_cast<size_t>(R.parents[k][0])] &
                           fine.node_fixed[static_cast<size_t>(R.parents[k][1])];
  }
}

// A face met by more than two cells, or a one-cell face that is not a boundary facet, is a
// hanging node or a face split differently on its two sides. Faces are sorted (not hashed: a
// sort of 4 M keys is several times faster than as many hash insertions).
void check_conforming(const Mesh& fine) {
  std::vector<std::array<int, 3>> faces;
  faces.reserve(static_cast<size_t>(4 * fine.num_cells()));
  for (Index c = 0; c < fine.num_cells(); ++c)
    for (int i = 0; i < 4; ++i)
      faces.push_back(face_key(fine.cells(c, (i + 1) % 4), fine.cells(c, (i + 2) % 4), fine.cells(c, (i + 3) % 4)));
  std::sort(faces.begin(), faces.end());
  Index boundary = 0;
  for (size_t k = 0; k < faces.size();) {
    size_t e = k + 1;
    while (e < faces.size() && faces[e] == faces[k]) ++e;
    if (e - k > 2) input_error("bisect: a face shared by " + std::to_string(e - k) + " cells" + NOT_KUHN);
    boundary += e - k == 1;
    k = e;
  }
  if (boundary != fine.num_facets())
    input_error("bisect: " + std::to_string(boundary) + " one-cell faces for " + std::to_string(fine.num_facets()) +
                " boundary facets (hanging nodes)" + NOT_KUHN);
}

}  // namespace

TetLabels label_tetrahedra(const Mesh& mesh) {
  require_3d(mesh, "label_tetrahedra");
  TetLabels L;
  L.order.resize(static_cast<size_t>(mesh.num_cells()));
  L.tag.assign(static_cast<size_t>(mesh.num_cells()), 3);
  const auto len = [&](int a, int b) { return (mesh.points.row(a) - mesh.points.row(b)).norm(); };
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    std::array<int, 4> v{mesh.cells(c, 0), mesh.cells(c, 1), mesh.cells(c, 2), mesh.cells(c, 3)};
    int bi = 0, bj = 1;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (len(v[static_cast<size_t>(i)], v[static_cast<size_t>(j)]) >
            len(v[static_cast<size_t>(bi)], v[static_cast<size_t>(bj)]) * (1 + 1e-12))
          bi = i, bj = j;
    int x0 = std::min(v[static_cast<size_t>(bi)], v[static_cast<size_t>(bj)]);
    int x3 = std::max(v[static_cast<size_t>(bi)], v[static_cast<size_t>(bj)]);
    std::array<int, 2> rest{};
    int n = 0;
    for (int i = 0; i < 4; ++i)
      if (i != bi && i != bj) rest[static_cast<size_t>(n++)] = v[static_cast<size_t>(i)];
    if (len(x0, rest[1]) < len(x0, rest[0])) std::swap(rest[0], rest[1]);
    L.order[static_cast<size_t>(c)] = {x0, rest[0], rest[1], x3};
  }
  return L;
}

Bisection bisect(const Mesh& coarse, const TetLabels& labels, const std::vector<char>& marked, BisectionRule rule,
                 Index max_nodes) {
  require_3d(coarse, "bisect");
  const Index M = coarse.num_cells();
  if (static_cast<Index>(marked.size()) != M || labels.size() != M)
    throw Error("bisect: " + std::to_string(marked.size()) + " flags and " + std::to_string(labels.size()) +
                    " labels for " + std::to_string(M) + " cells",
                EXIT_INTERNAL);
  Refinement R;
  initial_cells(coarse, labels, R);
  for (Index c = 0; c < M; ++c) {
    if (!marked[static_cast<size_t>(c)]) continue;
    const Tet& t = R.cells[static_cast<size_t>(c)];
    if (rule == BisectionRule::NEWEST_VERTEX) {
      const auto [e0, e1] = refinement_edge(t);
      R.split(e0, e1);
      continue;
    }
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) R.split(t.x[static_cast<size_t>(i)], t.x[static_cast<size_t>(j)]);
  }
  close_and_bisect(R);
  Bisection out;
  out.nodes = static_cast<Index>(R.points.size());
  if (out.nodes > max_nodes) return out;
  out.built = true;
  fine_cells(R, out);
  fine_facets(coarse, R, out.mesh);
  fine_rollers(coarse, R, out.mesh);
  check_conforming(out.mesh);
  out.mesh.origin = coarse.origin;
  return out;
}

}  // namespace hemicontact

namespace hemicontact {

double min_simplex_angle(const Mesh& mesh) {
  double worst = M_PI;
  const int nv = mesh.dim + 1;
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    // The angle between the faces opposite vertices k and l: π minus the angle of their outward
    // normals, i.e. cos θ = −∇λ_k·∇λ_l / (|∇λ_k| |∇λ_l|) with λ the barycentric coordinates (in 2D
    // the faces are edges and θ the interior angle at the third vertex).
    Eigen::MatrixXd J(mesh.dim, mesh.dim);
    for (int k = 0; k < mesh.dim; ++k) J.col(k) = (mesh.points.row(mesh.cells(c, k + 1)) - mesh.points.row(mesh.cells(c, 0))).transpose();
    const Eigen::MatrixXd Jinv = J.inverse();
    Eigen::MatrixXd G(nv, mesh.dim);
    G.bottomRows(mesh.dim) = Jinv;
    G.row(0) = -Jinv.colwise().sum();
    for (int k = 0; k < nv; ++k)
      for (int l = k + 1; l < nv; ++l) {
        const double cosine = -G.row(k).dot(G.row(l)) / (G.row(k).norm() * G.row(l).norm());
        worst = std::min(worst, std::acos(std::clamp(cosine, -1.0, 1.0)));
      }
  }
  return worst;
}

}  // namespace hemicontact
