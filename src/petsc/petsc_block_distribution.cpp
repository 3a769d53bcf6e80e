#include "engine_impl.hpp"

#include <hemicontact/core/log.hpp>
#include <hemicontact/scene/slab_mesh.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace hemicontact::petsc_engine {

namespace {

// The part of 0..n (cells [0, n)) that block r of p owns: cells [n r / p, n (r + 1) / p); node i
// belongs to the block whose cells start at or before it (the last block also owns node n).
int first_cell(int n, int p, int r) { return static_cast<int>(static_cast<long>(n) * r / p); }

int owner_block(int n, int p, int i) {
  if (i >= n) return p - 1;
  // The largest r with n r / p <= i: r = floor((i p + p − 1) / n) overshoots by at most one.
  int r = static_cast<int>(std::min<long>(p - 1, (static_cast<long>(i) * p + p - 1) / n));
  while (r > 0 && first_cell(n, p, r) > i) --r;
  while (r + 1 < p && first_cell(n, p, r + 1) <= i) ++r;
  return r;
}

}  // namespace

BlockGrid block_grid(int nx, int ny, int ranks) {
  // px·py = ranks with px <= nx, py <= ny; among those, the one whose blocks are closest to square
  // (the least cut area: the halo a CG iteration exchanges).
  BlockGrid best;
  double best_cut = std::numeric_limits<double>::infinity();
  for (int px = 1; px <= ranks; ++px) {
    if (ranks % px != 0) continue;
    const int py = ranks / px;
    if (px > nx || py > ny) continue;
    const double cut = static_cast<double>(px - 1) * ny + static_cast<double>(py - 1) * nx;
    if (cut < best_cut) best_cut = cut, best = {px, py};
  }
  return best;
}

// Each rank owns the node columns of its block and holds the cell columns that touch them: its own
// and one column of cells below in x and in y (as a slab holds one layer below), every z layer.
Piece make_block(const nlohmann::json& scene, MPI_Comm comm, Mesh& mesh) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const nlohmann::json& m = scene.at("mesh");
  if (m.at("type") != "box") input_error("solver.petsc.mesh = \"blocks\": only a generated box is made in blocks");
  const int nx = m.at("nx").get<int>(), ny = m.at("ny").get<int>();
  const BlockGrid grid = block_grid(nx, ny, size);
  if (grid.px == 0)
    input_error("solver.petsc.mesh: " + std::to_string(size) + " MPI ranks do not make a grid of blocks of the box's " +
                std::to_string(nx) + " x " + std::to_string(ny) + " cell columns (px·py = ranks, px <= nx, py <= ny)");
  Piece s;
  s.layout = "blocks";
  s.grid_x = grid.px;
  s.grid_y = grid.py;
  const int ri = rank % grid.px, rj = rank / grid.px;
  const int a0 = first_cell(nx, grid.px, ri), a1 = first_cell(nx, grid.px, ri + 1);
  const int b0 = first_cell(ny, grid.py, rj), b1 = first_cell(ny, grid.py, rj + 1);
  s.block = {a0, a1, b0, b1};
  const BlockRange held{std::max(a0 - 1, 0), a1, std::max(b0 - 1, 0), b1};
  std::vector<long> counts;
  mesh = build_block_mesh(scene, held, counts);
  check_selectors_somewhere(scene, counts, comm);
  // Local node v is (i, j, k) of the held columns (mesh/slabs.hpp's block numbering).
  const int wi = held.i1 - held.i0 + 1, wj = held.j1 - held.j0 + 1;
  const Index N = mesh.num_nodes();
  s.owned_node.assign(static_cast<size_t>(N), 0);
  s.global_node.assign(static_cast<size_t>(N), 0);
  s.owner.assign(static_cast<size_t>(N), rank);
  std::vector<int> col_i(static_cast<size_t>(N)), col_j(static_cast<size_t>(N));
  for (Index v = 0; v < N; ++v) {
    const int i = static_cast<int>(v % wi) + held.i0, j = static_cast<int>((v / wi) % wj) + held.j0;
    col_i[static_cast<size_t>(v)] = i;
    col_j[static_cast<size_t>(v)] = j;
    const int oi = owner_block(nx, grid.px, i), oj = owner_block(ny, grid.py, j);
    s.owner[static_cast<size_t>(v)] = oj * grid.px + oi;
    s.owned_node[static_cast<size_t>(v)] = s.owner[static_cast<size_t>(v)] == rank;
    s.global_node[static_cast<size_t>(v)] = block_global_node(scene, held, v);
  }
  // A cell is the block's whose cell column (its lowest node's i and j) is in [a0, a1) × [b0, b1).
  s.owned_cell.assign(static_cast<size_t>(mesh.num_cells()), 0);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    int imin = nx, jmin = ny;
    for (int a = 0; a < mesh.cells.cols(); ++a) {
      imin = std::min(imin, col_i[static_cast<size_t>(mesh.cells(c, a))]);
      jmin = std::min(jmin, col_j[static_cast<size_t>(mesh.cells(c, a))]);
    }
    s.owned_cell[static_cast<size_t>(c)] = imin >= a0 && jmin >= b0;
  }
  count_whole_mesh(s, comm);
  return s;
}

}  // namespace hemicontact::petsc_engine
