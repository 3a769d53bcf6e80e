#include "engine_impl.hpp"

#include <hemicontact/fem/assembly.hpp>

#include <petscmat.h>
#if HEMICONTACT_HAS_PTSCOTCH
#include <scotch/ptscotch.h>
#endif

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

namespace hemicontact::petsc_engine::detail {

Engine::Engine(const Model& m, const SolveOptions& o, MPI_Comm c, EngineReport& r) : md(m), opt(o), comm(c), rep(r) {
  init();
  (void)tao_type(opt.backend);  // refuse a non-TAO backend before any work
  // A rank without a cell of its own has no rows to assemble: refused, naming both counts.
  if (size > md.mesh.num_cells())
    input_error("solver.engine = petsc: " + std::to_string(size) + " MPI ranks for a mesh of " +
                std::to_string(md.mesh.num_cells()) + " cells; use at most as many ranks as cells (mpirun -np)");
}

// What both constructors (the replicated mesh's, the slabs') set and refuse alike.
void Engine::init() {
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  d = md.dim();
  if (!md.material->is_linear())
    input_error("solver.engine = petsc: linear materials only (" + md.material->describe() +
                "); a nonlinear material needs solver.engine = cholmod");
  is_lagged = md.friction && md.friction->depends_on_u_nu();
}

// Row blocks: one node's d unknowns per block when every free node has all d components (no roller),
// so that GAMG aggregates nodes and a Γ3 node's (ν, τ) rows never straddle two ranks; otherwise
// blocks of 1 with the split still at node boundaries. The nodes go to the ranks as the graph
// partitioner says (solver.petsc.partition), or in contiguous runs of x ("natural").
void Engine::distribute() {
  const auto t0 = clk::now();
  n = static_cast<PetscInt>(md.dofs.n_free());
  bool rollers = false;
  for (Index v = 0; v < md.mesh.num_nodes(); ++v) rollers = rollers || md.mesh.held(v) != 0;
  bs = (!rollers && md.dofs.n_interior() % d == 0) ? d : 1;
  // The free nodes in x order, each with its first x index and its count of free components
  // (consecutive in x: interior nodes node-major, a Γ3 node's d local slots together).
  std::vector<Index> block_node;
  std::vector<PetscInt> block_first;
  std::vector<int> block_size;
  {
    const std::vector<Index> sel = md.dofs.cartesian_selection();
    std::vector<PetscInt> first_of(static_cast<size_t>(md.mesh.num_nodes()), -1);
    std::vector<int> count_of(static_cast<size_t>(md.mesh.num_nodes()), 0);
    for (size_t j = 0; j < sel.size(); ++j) {
      if (sel[j] < 0) continue;
      const size_t a = j / static_cast<size_t>(d);
      const auto xj = static_cast<PetscInt>(sel[j]);
      first_of[a] = first_of[a] < 0 ? xj : std::min(first_of[a], xj);
      ++count_of[a];
    }
    std::vector<Index> node_at(static_cast<size_t>(n), -1);  // node of each block's first x index
    for (size_t a = 0; a < first_of.size(); ++a)
      if (first_of[a] >= 0) node_at[static_cast<size_t>(first_of[a])] = static_cast<Index>(a);
    for (PetscInt i = 0; i < n; ++i)
      if (node_at[static_cast<size_t>(i)] >= 0) {
        const Index a = node_at[static_cast<size_t>(i)];
        block_node.push_back(a);
        block_first.push_back(i);
        block_size.push_back(count_of[static_cast<size_t>(a)]);
      }
  }
  const auto blocks = static_cast<PetscInt>(block_node.size());
  if (size > blocks)
    input_error("solver.engine = petsc: " + std::to_string(size) + " MPI ranks for " + std::to_string(blocks) +
                " free nodes; use at most as many ranks as free nodes (mpirun -np)");
  const auto at = [&](PetscInt b) { return b >= blocks ? n : block_first[static_cast<size_t>(b)]; };
  lo = at(blocks * rank / size);
  hi = at(blocks * (rank + 1) / size);
  rep.json["partition"] = {{"type", size > 1 ? opt.petsc.partition : "natural"}};
  if (size > 1 && opt.petsc.partition != "natural") partition(block_node, block_first, block_size);
  for (Index k = 0; k < md.contact.size(); ++k)
    if (cdof(k) >= lo && cdof(k) < hi) my_nodes.push_back(k);
  lambda.assign(my_nodes.size(), 0.0);
  own_nodes.assign(static_cast<size_t>(md.mesh.num_nodes()), 0);
  for (size_t b = 0; b < block_node.size(); ++b)
    if (P(block_first[b]) >= lo && P(block_first[b]) < hi) own_nodes[static_cast<size_t>(block_node[b])] = 1;
  timings["petsc_partition"] = since(t0);
}

// The graph partitioner (PT-Scotch, through MatPartitioning; -mat_partitioning_type picks another
// one PETSc has) on the free nodes' graph, each node weighted by its unknowns: the parts become
// the ranks' rows, numbered part by part in x order within each. Each rank gives the graph of the
// nodes of its natural run (lo, hi from distribute()); every rank then knows every node's part.
void Engine::partition(const std::vector<Index>& block_node, const std::vector<PetscInt>& block_first,
                       const std::vector<int>& block_size) {
  const auto blocks = static_cast<PetscInt>(block_node.size());
  const PetscInt b0 = blocks * rank / size, b1 = blocks * (rank + 1) / size, nb = b1 - b0;
  std::vector<PetscInt> block_of(static_cast<size_t>(md.mesh.num_nodes()), -1);
  for (PetscInt b = 0; b < blocks; ++b) block_of[static_cast<size_t>(block_node[static_cast<size_t>(b)])] = b;
  std::vector<char> keep(static_cast<size_t>(md.mesh.num_nodes()), 0);
  for (PetscInt b = b0; b < b1; ++b) keep[static_cast<size_t>(block_node[static_cast<size_t>(b)])] = 1;
  const NodeGraph g = node_graph(md.mesh, &keep);
  keep = std::vector<char>();
  // MatMPIAdj takes ia, ja (and the weights) over: PetscMalloc'd, no diagonal, sorted rows.
  PetscInt *ia = nullptr, *ja = nullptr, *wt = nullptr;
  HC_PETSC(PetscMalloc1(nb + 1, &ia));
  ia[0] = 0;
  for (PetscInt b = b0; b < b1; ++b) {
    const Index a = block_node[static_cast<size_t>(b)];
    PetscInt c = 0;
    for (const int* q = g.begin(a); q != g.end(a); ++q) c += block_of[static_cast<size_t>(*q)] >= 0 && *q != a;
    ia[b - b0 + 1] = ia[b - b0] + c;
  }
  HC_PETSC(PetscMalloc1(ia[nb], &ja));
  for (PetscInt b = b0; b < b1; ++b) {
    const Index a = block_node[static_cast<size_t>(b)];
    PetscInt* dst = ja + ia[b - b0];
    for (const int* q = g.begin(a); q != g.end(a); ++q)
      if (block_of[static_cast<size_t>(*q)] >= 0 && *q != a) *dst++ = block_of[static_cast<size_t>(*q)];
    std::sort(ja + ia[b - b0], dst);
  }
  ::Mat adj;
  HC_PETSC(MatCreateMPIAdj(comm, nb, blocks, ia, ja, nullptr, &adj));
  MatPartitioning mp;
  HC_PETSC(MatPartitioningCreate(comm, &mp));
  HC_PETSC(MatPartitioningSetAdjacency(mp, adj));
  HC_PETSC(MatPartitioningSetType(mp, MATPARTITIONINGPTSCOTCH));
  HC_PETSC(MatPartitioningSetNParts(mp, size));
  if (bs == 1) {  // rollers: nodes with fewer than d unknowns weigh less
    HC_PETSC(PetscMalloc1(nb, &wt));
    for (PetscInt b = b0; b < b1; ++b) wt[b - b0] = block_size[static_cast<size_t>(b)];
    HC_PETSC(MatPartitioningSetVertexWeights(mp, wt));
  }
  HC_PETSC(MatPartitioningSetFromOptions(mp));
  // Reproducible parts: Debian's Scotch runs its algorithms on threads and seeds its generator from
  // the clock, so the same run got different parts (3D scene, 24³, 2 ranks: 22 500 / 22 344 /
  // 22 566 rows on rank 0 in three runs, and 112, 139, 137 CG iterations). One thread per rank
  // (SCOTCH_PTHREAD_NUMBER, unless the user set it; the ranks already take the cores) and a fixed
  // seed make the partition, and every count that follows from it, the same each time.
  setenv("SCOTCH_PTHREAD_NUMBER", "1", 0);
#if HEMICONTACT_HAS_PTSCOTCH
  SCOTCH_randomSeed(1);
  SCOTCH_randomReset();
#endif
  IS part, all;
  HC_PETSC(MatPartitioningApply(mp, &part));
  HC_PETSC(ISAllGather(part, &all));
  const PetscInt* owner;
  HC_PETSC(ISGetIndices(all, &owner));
  // Part by part, x order within each: a counting sort of the blocks by owner.
  std::vector<PetscInt> part_start(static_cast<size_t>(size) + 1, 0);
  for (PetscInt b = 0; b < blocks; ++b) {
    if (owner[b] < 0 || owner[b] >= size) throw Error("petsc: the partitioner returned a part out of range", EXIT_INTERNAL);
    part_start[static_cast<size_t>(owner[b]) + 1] += block_size[static_cast<size_t>(b)];
  }
  for (int r = 0; r < size; ++r) part_start[static_cast<size_t>(r) + 1] += part_start[static_cast<size_t>(r)];
  perm.assign(static_cast<size_t>(n), -1);
  std::vector<PetscInt> next(part_start.begin(), part_start.end() - 1);
  for (PetscInt b = 0; b < blocks; ++b) {
    PetscInt& at = next[static_cast<size_t>(owner[b])];
    for (int c = 0; c < block_size[static_cast<size_t>(b)]; ++c)
      perm[static_cast<size_t>(block_first[static_cast<size_t>(b)] + c)] = at++;
  }
  HC_PETSC(ISRestoreIndices(all, &owner));
  ISDestroy(&all);
  ISDestroy(&part);
  MatPartitioningDestroy(&mp);
  MatDestroy(&adj);
  lo = part_start[static_cast<size_t>(rank)];
  hi = part_start[static_cast<size_t>(rank) + 1];
  mine.assign(static_cast<size_t>(hi - lo), -1);
  for (PetscInt x = 0; x < n; ++x) {
    const PetscInt p = perm[static_cast<size_t>(x)];
    if (p >= lo && p < hi) mine[static_cast<size_t>(p - lo)] = x;
  }
}

Eigen::VectorXd Engine::gather(::Vec v) const {
  VecScatter sc;
  ::Vec all;
  HC_PETSC(VecScatterCreateToAll(v, &sc, &all));
  HC_PETSC(VecScatterBegin(sc, v, all, INSERT_VALUES, SCATTER_FORWARD));
  HC_PETSC(VecScatterEnd(sc, v, all, INSERT_VALUES, SCATTER_FORWARD));
  Eigen::VectorXd out(n);
  const PetscScalar* p;
  HC_PETSC(VecGetArrayRead(all, &p));
  if (perm.empty())
    std::copy(p, p + n, out.data());
  else
    for (PetscInt x = 0; x < n; ++x) out[x] = p[perm[static_cast<size_t>(x)]];
  HC_PETSC(VecRestoreArrayRead(all, &p));
  VecScatterDestroy(&sc);
  VecDestroy(&all);
  return out;
}

Eigen::VectorXd Engine::local_gamma3(::Vec z) const {
  Eigen::VectorXd c(static_cast<Index>(my_nodes.size()) * d);
  const PetscScalar* p;
  VecGetArrayRead(z, &p);
  for (size_t q = 0; q < my_nodes.size(); ++q)
    for (int a = 0; a < d; ++a) c[static_cast<Index>(q) * d + a] = p[cdof(my_nodes[q]) + a - lo];
  VecRestoreArrayRead(z, &p);
  return c;
}

}  // namespace hemicontact::petsc_engine::detail
