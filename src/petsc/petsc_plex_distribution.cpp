// The distributed path for a Gmsh file (mesh.file), and for the generated meshes the slabs do not
// cover (perturbed, crossed cells, more ranks than layers): rank 0 reads or generates the whole
// mesh and assigns its boundary parts (build_mesh), a DMPlex of its cells is distributed by PETSc's
// partitioner, and each rank makes its Mesh of the cells it received; rank 0 then frees the whole.
//
// Why read_gmsh and not DMPlexCreateGmshFromFile: PETSc 3.18's reader also reads serially on rank
// 0 (then distributes), so it saves nothing; ours carries the input checks (an MSH header before
// Gmsh runs anything, degenerate or folded cells, a 2D mesh off z = 0), the physical groups as
// facet groups for the scene's {"physical": ...} selectors, and the node numbering (Gmsh tags in
// increasing order) that the cholmod engine's report uses, so that both engines name a node alike.
//
// What travels with the cells: the DMPlex is made uninterpolated (cells and vertices only) and
// every per-point datum goes through the migration star forest of DMPlexDistribute (PetscSFBcast
// from rank 0's points to the new ones): per vertex its whole-mesh node number, coordinates,
// roller mask and valence (cells touching it); per cell its nodes' numbers in the importer's
// (positive) order and, per face, the boundary part and traction of that face (0: not a boundary
// facet). The point SF of the distributed DMPlex gives each vertex's and cell's owner (a leaf is a
// ghost, owned by its root's rank).
//
// The overlap is 2 cell layers, not 1: with 1, each owned vertex has all its cells, but a vertex of
// such a cell (a column of the owned row) may lack the cells that carry its boundary facets, and so
// be taken for an interior node, or a free one, where its owner has it on Γ3 or clamped: its
// unknowns, and its (ν, τ) frame in the owned rows' columns, would differ from its owner's. With 2,
// every vertex of a cell that touches an owned vertex has all its cells (Piece::complete, checked
// against the valence); the outer ring of ghosts enters no owned row.
#include "engine_impl.hpp"

#include <hemicontact/core/log.hpp>
#include <hemicontact/scene/build_model.hpp>

#include <petscdmplex.h>
#include <petscsf.h>
#if HEMICONTACT_HAS_PTSCOTCH
#include <scotch/ptscotch.h>
#endif

#include <algorithm>
#include <array>
#include <cstdlib>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace hemicontact::petsc_engine {

namespace {


// A boundary facet's code in the per-cell face data: 0 none, else 1 + part + 4 (load + 1).
int facet_code(Part p, int load) { return 1 + static_cast<int>(p) + 4 * (load + 1); }
Part code_part(int code) { return static_cast<Part>((code - 1) % 4); }
int code_load(int code) { return (code - 1) / 4 - 1; }

// extract_boundary_facets' faces of a positive cell, opposite vertex s, ordered outward.
const int EDGES[3][2] = {{1, 2}, {2, 0}, {0, 1}};
const int FACES[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

std::array<Index, 3> face_of(const IMat& cells, Index c, int s, int dim) {
  std::array<Index, 3> f{-1, -1, -1};
  for (int a = 0; a < dim; ++a) f[static_cast<size_t>(a)] = cells(c, dim == 2 ? EDGES[s][a] : FACES[s][a]);
  return f;
}

// A facet's nodes sorted (its key), the unused third entry −1 in 2D left last.
std::array<Index, 3> sorted_key(std::array<Index, 3> k, int dim) {
  if (k[0] > k[1]) std::swap(k[0], k[1]);
  if (dim == 3) {
    if (k[1] > k[2]) std::swap(k[1], k[2]);
    if (k[0] > k[1]) std::swap(k[0], k[1]);
  }
  return k;
}

// Rank 0's outcome of a step only it does, shared with every rank (all throw alike).
void share_outcome(int code, std::string message, MPI_Comm comm) {
  MPI_Bcast(&code, 1, MPI_INT, 0, comm);
  int len = static_cast<int>(message.size());
  MPI_Bcast(&len, 1, MPI_INT, 0, comm);
  message.resize(static_cast<size_t>(len));
  if (len > 0) MPI_Bcast(message.data(), len, MPI_CHAR, 0, comm);
  if (code != 0) throw Error(message, static_cast<ExitCode>(code));
}

struct PDM {
  DM dm = nullptr;
  ~PDM() {
    if (dm) DMDestroy(&dm);
  }
};
struct PSF {
  PetscSF sf = nullptr;
  ~PSF() {
    if (sf) PetscSFDestroy(&sf);
  }
};

// What every rank needs of the whole mesh that rank 0 read.
struct Whole {
  int dim = 2;
  long nodes = 0, cells = 0;
  bool rollers = false;
  std::vector<Vec> tractions;
  std::string origin;
};

// Rank 0 reads the file and assigns the parts (build_mesh: read_gmsh, its checks, the parts on the
// whole mesh); every rank gets @p w, or the same error. @return the whole mesh on rank 0.
Mesh read_on_rank0(const nlohmann::json& scene, const std::string& scene_dir, MPI_Comm comm, Whole& w) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Mesh whole;
  int code = 0;
  std::string message;
  if (rank == 0) {
    try {
      whole = build_mesh(scene, scene_dir);
    } catch (const Error& e) {
      code = e.code();
      message = e.what();
    }
  }
  share_outcome(code, message, comm);
  long counts[4] = {whole.dim, whole.num_nodes(), whole.num_cells(), whole.node_fixed.empty() ? 0 : 1};
  MPI_Bcast(counts, 4, MPI_LONG, 0, comm);
  w.dim = static_cast<int>(counts[0]);
  w.nodes = counts[1];
  w.cells = counts[2];
  w.rollers = counts[3] != 0;
  int ntr = static_cast<int>(whole.tractions.size());
  MPI_Bcast(&ntr, 1, MPI_INT, 0, comm);
  std::vector<double> tr(static_cast<size_t>(ntr * w.dim));
  for (int t = 0; t < ntr && rank == 0; ++t)
    for (int c = 0; c < w.dim; ++c) tr[static_cast<size_t>(t * w.dim + c)] = whole.tractions[static_cast<size_t>(t)][c];
  if (ntr > 0) MPI_Bcast(tr.data(), ntr * w.dim, MPI_DOUBLE, 0, comm);
  for (int t = 0; t < ntr; ++t) w.tractions.push_back(Eigen::Map<const Vec>(tr.data() + static_cast<size_t>(t * w.dim), w.dim));
  w.origin = whole.origin;
  int olen = static_cast<int>(w.origin.size());
  MPI_Bcast(&olen, 1, MPI_INT, 0, comm);
  w.origin.resize(static_cast<size_t>(olen));
  MPI_Bcast(w.origin.data(), olen, MPI_CHAR, 0, comm);
  return whole;
}

// Per-point data of a DMPlex (cells first, then vertices): INTS integers and dim doubles per point.
// A cell: its nv nodes' numbers, then its nv faces' codes (facet_code; face s is opposite node s).
// A vertex: its node number, roller mask and valence (cells touching it in the whole mesh); its
// coordinates in the doubles.
struct PointData {
  std::vector<std::vector<PetscInt>> ints;
  std::vector<std::vector<PetscReal>> xyz;
  PointData(int dim, size_t points)
      : ints(static_cast<size_t>(2 * (dim + 1)), std::vector<PetscInt>(points, -1)),
        xyz(static_cast<size_t>(dim), std::vector<PetscReal>(points, 0.0)) {}
};

// Rank 0's DMPlex of the whole mesh (cells 0..M−1, vertices M..M+N−1 in the importer's order;
// no points on the other ranks), and the data of its points.
DM serial_plex(const Mesh& whole, int dim, MPI_Comm comm, PointData& root) {
  const int nv = dim + 1;
  const auto M = static_cast<PetscInt>(whole.num_cells()), N = static_cast<PetscInt>(whole.num_nodes());
  std::vector<PetscInt> cells(static_cast<size_t>(M * nv));
  std::vector<PetscReal> xyz(static_cast<size_t>(N * dim));
  for (PetscInt c = 0; c < M; ++c)
    for (int a = 0; a < nv; ++a) cells[static_cast<size_t>(c * nv + a)] = static_cast<PetscInt>(whole.cells(c, a));
  for (PetscInt v = 0; v < N; ++v)
    for (int a = 0; a < dim; ++a) xyz[static_cast<size_t>(v * dim + a)] = whole.points(v, a);
  DM dm = nullptr;
  HC_PETSC(DMPlexCreateFromCellListPetsc(comm, dim, M, N, nv, PETSC_FALSE, cells.data(), dim, xyz.data(), &dm));
  std::map<std::array<Index, 3>, Index> facet_at;
  for (Index f = 0; f < whole.num_facets(); ++f) {
    std::array<Index, 3> k{-1, -1, -1};
    for (int a = 0; a < dim; ++a) k[static_cast<size_t>(a)] = whole.facets(f, a);
    facet_at[sorted_key(k, dim)] = f;
  }
  std::vector<PetscInt> valence(static_cast<size_t>(N), 0);
  for (PetscInt c = 0; c < M; ++c)
    for (int s = 0; s < nv; ++s) {
      root.ints[static_cast<size_t>(s)][static_cast<size_t>(c)] = static_cast<PetscInt>(whole.cells(c, s));
      ++valence[static_cast<size_t>(whole.cells(c, s))];
      const auto it = facet_at.find(sorted_key(face_of(whole.cells, c, s, dim), dim));
      root.ints[static_cast<size_t>(nv + s)][static_cast<size_t>(c)] =
          it == facet_at.end() ? 0
                               : facet_code(whole.facet_part[static_cast<size_t>(it->second)],
                                            whole.facet_load[static_cast<size_t>(it->second)]);
    }
  for (PetscInt v = 0; v < N; ++v) {
    const auto p = static_cast<size_t>(M + v);
    root.ints[0][p] = v;
    root.ints[1][p] = whole.held(v);
    root.ints[2][p] = valence[static_cast<size_t>(v)];
    for (int a = 0; a < dim; ++a) root.xyz[static_cast<size_t>(a)][p] = whole.points(v, a);
  }
  return dm;
}

// The data of the new points from rank 0's (the migration SF's roots).
void carry(PetscSF sf, const PointData& root, PointData& leaf) {
  for (size_t j = 0; j < root.ints.size(); ++j) {
    HC_PETSC(PetscSFBcastBegin(sf, MPIU_INT, root.ints[j].data(), leaf.ints[j].data(), MPI_REPLACE));
    HC_PETSC(PetscSFBcastEnd(sf, MPIU_INT, root.ints[j].data(), leaf.ints[j].data(), MPI_REPLACE));
  }
  for (size_t j = 0; j < root.xyz.size(); ++j) {
    HC_PETSC(PetscSFBcastBegin(sf, MPIU_REAL, root.xyz[j].data(), leaf.xyz[j].data(), MPI_REPLACE));
    HC_PETSC(PetscSFBcastEnd(sf, MPIU_REAL, root.xyz[j].data(), leaf.xyz[j].data(), MPI_REPLACE));
  }
}

// Each point's owner from the point SF: a leaf is a ghost of its root's rank.
std::vector<int> point_owners(DM dm, PetscInt pStart, PetscInt pEnd, int rank) {
  std::vector<int> owner(static_cast<size_t>(pEnd - pStart), rank);
  PetscSF point;
  HC_PETSC(DMGetPointSF(dm, &point));
  PetscInt nroots = 0, nleaves = 0;
  const PetscInt* ilocal = nullptr;
  const PetscSFNode* iremote = nullptr;
  HC_PETSC(PetscSFGetGraph(point, &nroots, &nleaves, &ilocal, &iremote));
  if (nroots >= 0)
    for (PetscInt i = 0; i < nleaves; ++i)
      owner[static_cast<size_t>((ilocal ? ilocal[i] : i) - pStart)] = static_cast<int>(iremote[i].rank);
  return owner;
}

// This rank's Mesh from its points' data: the vertices in the whole mesh's order, the cells, the
// boundary facets of the cells (oriented outward as extract_boundary_facets orients them), and
// the piece's per-node and per-cell records (complete: every cell of the node is local).
Mesh local_mesh(DM dm, const PointData& leaf, const std::vector<int>& owner, const Whole& w, int rank, Piece& pc) {
  const int dim = w.dim, nv = dim + 1;
  PetscInt pStart = 0, pEnd = 0, cStart = 0, cEnd = 0, vStart = 0, vEnd = 0;
  HC_PETSC(DMPlexGetChart(dm, &pStart, &pEnd));
  HC_PETSC(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  HC_PETSC(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  std::vector<std::pair<long, PetscInt>> verts;
  for (PetscInt p = vStart; p < vEnd; ++p) {
    const PetscInt g = leaf.ints[0][static_cast<size_t>(p - pStart)];
    if (g < 0) throw Error("petsc engine: a vertex of the distributed mesh got no node number", EXIT_INTERNAL);
    verts.emplace_back(static_cast<long>(g), p);
  }
  std::sort(verts.begin(), verts.end());
  const auto nn = static_cast<Index>(verts.size()), nc = static_cast<Index>(cEnd - cStart);
  Mesh mesh;
  mesh.dim = dim;
  mesh.origin = w.origin;
  mesh.tractions = w.tractions;
  mesh.points.resize(nn, dim);
  if (w.rollers) mesh.node_fixed.assign(static_cast<size_t>(nn), 0);
  pc.owned_node.assign(static_cast<size_t>(nn), 0);
  pc.global_node.assign(static_cast<size_t>(nn), 0);
  pc.owner.assign(static_cast<size_t>(nn), rank);
  std::unordered_map<long, Index> local;
  std::vector<PetscInt> valence(static_cast<size_t>(nn)), star(static_cast<size_t>(nn), 0);
  for (Index v = 0; v < nn; ++v) {
    const auto p = static_cast<size_t>(verts[static_cast<size_t>(v)].second - pStart);
    local[verts[static_cast<size_t>(v)].first] = v;
    for (int a = 0; a < dim; ++a) mesh.points(v, a) = leaf.xyz[static_cast<size_t>(a)][p];
    pc.global_node[static_cast<size_t>(v)] = verts[static_cast<size_t>(v)].first;
    pc.owner[static_cast<size_t>(v)] = owner[p];
    pc.owned_node[static_cast<size_t>(v)] = owner[p] == rank;
    if (w.rollers) mesh.node_fixed[static_cast<size_t>(v)] = static_cast<unsigned char>(leaf.ints[1][p]);
    valence[static_cast<size_t>(v)] = leaf.ints[2][p];
  }
  mesh.cells.resize(nc, nv);
  pc.owned_cell.assign(static_cast<size_t>(nc), 0);
  std::vector<std::array<Index, 3>> facets;
  for (Index c = 0; c < nc; ++c) {
    const auto p = static_cast<size_t>(cStart + c - pStart);
    pc.owned_cell[static_cast<size_t>(c)] = owner[p] == rank;
    for (int a = 0; a < nv; ++a) {
      const auto it = local.find(static_cast<long>(leaf.ints[static_cast<size_t>(a)][p]));
      if (it == local.end()) throw Error("petsc engine: a cell of the distributed mesh lacks a vertex", EXIT_INTERNAL);
      mesh.cells(c, a) = it->second;
      ++star[static_cast<size_t>(it->second)];
    }
    for (int s = 0; s < nv; ++s) {
      const PetscInt code = leaf.ints[static_cast<size_t>(nv + s)][p];
      if (code <= 0) continue;
      facets.push_back(face_of(mesh.cells, c, s, dim));
      mesh.facet_part.push_back(code_part(static_cast<int>(code)));
      mesh.facet_load.push_back(code_load(static_cast<int>(code)));
    }
  }
  mesh.facets.resize(static_cast<Index>(facets.size()), dim);
  for (size_t f = 0; f < facets.size(); ++f)
    for (int a = 0; a < dim; ++a) mesh.facets(static_cast<Index>(f), a) = facets[f][static_cast<size_t>(a)];
  pc.complete.assign(static_cast<size_t>(nn), 0);
  for (size_t v = 0; v < static_cast<size_t>(nn); ++v) pc.complete[v] = star[v] == valence[v];
  return mesh;
}

// The overlap's promise (see the top): every node of a cell that touches an owned node is complete;
// and the owned nodes and cells add up to the whole mesh's.
void check_piece(const Mesh& mesh, Piece& pc, const Whole& w, MPI_Comm comm) {
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    bool touches = false, all = true;
    for (int a = 0; a < mesh.cells.cols(); ++a) {
      touches = touches || pc.owned_node[static_cast<size_t>(mesh.cells(c, a))];
      all = all && pc.complete[static_cast<size_t>(mesh.cells(c, a))];
    }
    if (touches && !all)
      throw Error("petsc engine: the DMPlex overlap left a node of an owned row without all its cells", EXIT_INTERNAL);
  }
  long mine[2] = {0, 0}, sums[2] = {0, 0};
  for (char o : pc.owned_node) mine[0] += o;
  for (char o : pc.owned_cell) mine[1] += o;
  MPI_Allreduce(mine, sums, 2, MPI_LONG, MPI_SUM, comm);
  pc.global_nodes = sums[0];
  pc.global_cells = sums[1];
  if (pc.global_nodes != w.nodes || pc.global_cells != w.cells)
    throw Error("petsc engine: the distributed mesh's owned nodes or cells do not add up to the whole mesh's",
                EXIT_INTERNAL);
}

}  // namespace

Piece make_plex_piece(const nlohmann::json& scene, const std::string& scene_dir, MPI_Comm comm, Mesh& mesh) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  Whole w;
  Mesh whole = read_on_rank0(scene, scene_dir, comm, w);
  if (w.cells < size)
    input_error("solver.petsc.mesh: " + std::to_string(size) + " MPI ranks for a mesh of " + std::to_string(w.cells) +
                " cells; use at most as many ranks as cells (mpirun -np)");
  PDM serial, dist;
  PointData root(w.dim, static_cast<size_t>(whole.num_cells() + whole.num_nodes()));
  serial.dm = serial_plex(whole, w.dim, comm, root);
  whole = Mesh();  // rank 0 keeps only the DMPlex and its points' data until it is distributed
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
  PetscPartitioner part;
  HC_PETSC(DMPlexGetPartitioner(serial.dm, &part));
  HC_PETSC(PetscPartitionerSetFromOptions(part));
  PetscPartitionerType ptype;
  HC_PETSC(PetscPartitionerGetType(part, &ptype));
  Piece pc;
  pc.layout = "dmplex";
  pc.partitioner = size == 1 ? "one rank" : ptype ? ptype : "?";  // one rank: DMPlexDistribute does nothing
  PSF migration;
  HC_PETSC(DMPlexDistribute(serial.dm, 2, &migration.sf, &dist.dm));
  DM dm = dist.dm ? dist.dm : serial.dm;
  PetscInt pStart = 0, pEnd = 0;
  HC_PETSC(DMPlexGetChart(dm, &pStart, &pEnd));
  PointData leaf(w.dim, static_cast<size_t>(pEnd - pStart));
  if (migration.sf)
    carry(migration.sf, root, leaf);
  else
    leaf = std::move(root);
  root = PointData(w.dim, 0);
  if (dist.dm) DMDestroy(&serial.dm);  // the whole mesh's DMPlex goes: rank 0 holds its piece only
  mesh = local_mesh(dm, leaf, point_owners(dm, pStart, pEnd, rank), w, rank, pc);
  check_cells(mesh);  // the importer's positive orientation, carried with the nodes' order
  check_piece(mesh, pc, w, comm);
  log_info() << "petsc: " << w.origin << " distributed by DMPlex (" << pc.partitioner << "): " << mesh.num_nodes()
             << " nodes, " << mesh.num_cells() << " cells on rank 0";
  return pc;
}

}  // namespace hemicontact::petsc_engine
