// Labels for the bisection of an arbitrary conforming tetrahedral mesh (mesh/bisection.hpp):
// Maubach's tags where they are compatible (Kuhn meshes), AMP's initial marking everywhere else.
#include <hemicontact/mesh/bisection.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/mesh/edge_key.hpp>

#include <cstdint>
#include <set>
#include <utility>

namespace hemicontact {

bool refinement_edges_agree(const Mesh& m, const TetLabels& labels) {
  const auto ref_edge = [&](size_t c) {
    const auto e = refinement_edge(labels.order[c], labels.tag[c], labels.amp.empty() ? AmpMarks{} : labels.amp[c]);
    return edge_key(e[0], e[1]);
  };
  std::set<std::uint64_t> refinement;
  for (size_t c = 0; c < labels.order.size(); ++c) refinement.insert(ref_edge(c));
  for (size_t c = 0; c < labels.order.size(); ++c)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const std::uint64_t e = edge_key(m.cells(static_cast<Index>(c), i), m.cells(static_cast<Index>(c), j));
        if (e != ref_edge(c) && refinement.count(e)) return false;
      }
  return true;
}

TetLabels mark_tetrahedra(const Mesh& mesh) {
  if (mesh.dim != 3) input_error("mark_tetrahedra: needs a 3D mesh");
  // The strict order: squared length from the sorted ends (the same number from both cells), then the key.
  const auto rank = [&](int a, int b) {
    if (a > b) std::swap(a, b);
    return std::make_pair((mesh.points.row(b) - mesh.points.row(a)).squaredNorm(), edge_key(a, b));
  };
  TetLabels L;
  const auto M = static_cast<size_t>(mesh.num_cells());
  L.order.resize(M);
  L.tag.assign(M, 0);
  L.amp.resize(M);
  for (size_t c = 0; c < M; ++c) {
    auto& x = L.order[c];
    for (int i = 0; i < 4; ++i) x[static_cast<size_t>(i)] = mesh.cells(static_cast<Index>(c), i);
    AmpMarks& m = L.amp[c];
    const auto first = [&](int skip) {  // the first edge (i, j) of the cell, or of its face opposite skip
      std::array<unsigned char, 2> best{};
      bool any = false;
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
          if (i != skip && j != skip &&
              (!any || rank(x[static_cast<size_t>(i)], x[static_cast<size_t>(j)]) >
                           rank(x[best[0]], x[best[1]])))
            best = {static_cast<unsigned char>(i), static_cast<unsigned char>(j)}, any = true;
      return best;
    };
    m.edge = first(-1);
    for (int k = 0; k < 4; ++k) {
      const auto e = first(k);
      m.face[static_cast<size_t>(k)] = static_cast<unsigned char>(6 - k - e[0] - e[1]);
    }
  }
  return L;
}

LabelledMesh label_for_bisection(Mesh mesh, const Mesh* lattice) {
  // Compatibility is combinatorial: the same cells on other node positions label them as well.
  const bool same_cells = lattice && lattice->cells.rows() == mesh.cells.rows() &&
                          lattice->cells.cols() == mesh.cells.cols() && lattice->cells == mesh.cells;
  TetLabels labels = label_tetrahedra(same_cells ? *lattice : mesh);
  if (!refinement_edges_agree(mesh, labels)) labels = mark_tetrahedra(mesh);
  return {std::move(mesh), std::move(labels)};
}

}  // namespace hemicontact
