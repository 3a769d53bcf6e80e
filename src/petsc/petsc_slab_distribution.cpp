#include "engine_impl.hpp"

#include <hemicontact/core/log.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/scene/slab_mesh.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace hemicontact::petsc_engine {

// Even split of the cell layers; each rank builds the layers it owns and the one below them (the
// cells that touch its lowest node layer), so that every owned node's row is complete locally.
Piece make_slab(const nlohmann::json& scene, MPI_Comm comm, Mesh& mesh) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const SlabCut cut = slab_cut(scene);
  if (cut.layers < size)
    input_error("solver.petsc.mesh: " + std::to_string(size) + " MPI ranks for " + std::to_string(cut.layers) +
                " cell layers along " + "xyz"[cut.axis] + "; use at most as many ranks as layers (mpirun -np)");
  Piece s;
  s.axis = cut.axis;
  s.layers = cut.layers;
  s.c0 = static_cast<int>(static_cast<long>(cut.layers) * rank / size);
  s.c1 = static_cast<int>(static_cast<long>(cut.layers) * (rank + 1) / size);
  const int first = std::max(s.c0 - 1, 0), held = s.c1 - first;
  std::vector<long> counts;
  mesh = build_slab_mesh(scene, first, s.c1, counts);
  check_selectors_somewhere(scene, counts, comm);
  // The layer of local node v along the cut (mesh/slabs.hpp's numbering).
  const Index row = cut.axis == 1 ? scene.at("mesh").at("nx").get<Index>() + 1 : 1;
  const auto layer = [&](Index v) {
    return first + static_cast<int>(cut.axis == 1 ? (v / row) % (held + 1) : v % (held + 1));
  };
  const Index N = mesh.num_nodes();
  s.owned_node.assign(static_cast<size_t>(N), 0);
  s.global_node.assign(static_cast<size_t>(N), 0);
  s.owner.assign(static_cast<size_t>(N), rank);
  for (Index v = 0; v < N; ++v) {
    const int l = layer(v);
    const bool own = (l >= s.c0 && l < s.c1) || (l == s.layers && s.c1 == s.layers);
    s.owned_node[static_cast<size_t>(v)] = own;
    s.global_node[static_cast<size_t>(v)] = slab_global_node(scene, first, s.c1, v);
    // A ghost is of layer c0 − 1 (the rank below owns it) or of layer c1 (the rank above).
    if (!own) s.owner[static_cast<size_t>(v)] = l < s.c0 ? rank - 1 : rank + 1;
  }
  s.owned_cell.assign(static_cast<size_t>(mesh.num_cells()), 0);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    int lmin = s.layers;
    for (int a = 0; a < mesh.cells.cols(); ++a) lmin = std::min(lmin, layer(mesh.cells(c, a)));
    s.owned_cell[static_cast<size_t>(c)] = lmin >= s.c0;
  }
  count_whole_mesh(s, comm);
  return s;
}

void check_selectors_somewhere(const nlohmann::json& scene, const std::vector<long>& counts, MPI_Comm comm) {
  std::vector<long> all(counts.size(), 0);
  MPI_Allreduce(counts.data(), all.data(), static_cast<int>(counts.size()), MPI_LONG, MPI_SUM, comm);
  const std::vector<std::string> names = boundary_selector_names(scene);
  for (size_t i = 0; i < all.size() && i < names.size(); ++i)
    if (all[i] == 0) input_error(names[i] + " selects no boundary facet");
}

void count_whole_mesh(Piece& s, MPI_Comm comm) {
  long nodes = 0, cells = 0;
  for (char o : s.owned_node) nodes += o;
  for (char o : s.owned_cell) cells += o;
  MPI_Allreduce(&nodes, &s.global_nodes, 1, MPI_LONG, MPI_SUM, comm);
  MPI_Allreduce(&cells, &s.global_cells, 1, MPI_LONG, MPI_SUM, comm);
}

std::vector<Index> gamma3_index_of_nodes(const Model& md) {
  std::vector<Index> k_of(static_cast<size_t>(md.mesh.num_nodes()), -1);
  for (Index k = 0; k < md.contact.size(); ++k) k_of[static_cast<size_t>(md.contact.node[k])] = k;
  return k_of;
}

// The requests: the ghosts grouped by owner (a counting sort), each group in local order; each rank
// learns how many it is asked by whom (MPI_Alltoall), receives the numbers (MPI_Alltoallv) and finds
// its owned node of each number.
GhostAsk ask_owners(const Piece& pc, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const auto S = static_cast<size_t>(size);
  GhostAsk a;
  a.scount.assign(S, 0), a.sdispl.assign(S + 1, 0), a.rcount.assign(S, 0), a.rdispl.assign(S + 1, 0);
  for (size_t v = 0; v < pc.owner.size(); ++v)
    if (!pc.owned_node[v]) {
      const int q = pc.owner[v];
      if (q < 0 || q >= size || q == rank) throw Error("petsc engine: a ghost node without another owner", EXIT_INTERNAL);
      ++a.scount[static_cast<size_t>(q)];
    }
  for (size_t q = 0; q < S; ++q) a.sdispl[q + 1] = a.sdispl[q] + a.scount[q];
  std::vector<long> ask(static_cast<size_t>(a.sdispl[S]));
  a.ghost.resize(ask.size());
  std::vector<int> at(a.sdispl.begin(), a.sdispl.end() - 1);
  for (size_t v = 0; v < pc.owner.size(); ++v)
    if (!pc.owned_node[v]) {
      const auto i = static_cast<size_t>(at[static_cast<size_t>(pc.owner[v])]++);
      ask[i] = pc.global_node[v];
      a.ghost[i] = static_cast<Index>(v);
    }
  MPI_Alltoall(a.scount.data(), 1, MPI_INT, a.rcount.data(), 1, MPI_INT, comm);
  for (size_t q = 0; q < S; ++q) a.rdispl[q + 1] = a.rdispl[q] + a.rcount[q];
  std::vector<long> asked(static_cast<size_t>(a.rdispl[S]));
  MPI_Alltoallv(ask.data(), a.scount.data(), a.sdispl.data(), MPI_LONG, asked.data(), a.rcount.data(),
                a.rdispl.data(), MPI_LONG, comm);
  a.answer = owned_nodes_of(pc, asked);
  return a;
}

// This rank's owned node of each global number asked (an internal error if it owns none).
std::vector<Index> owned_nodes_of(const Piece& pc, const std::vector<long>& asked) {
  std::vector<std::pair<long, Index>> by_global;
  for (size_t v = 0; v < pc.owned_node.size(); ++v)
    if (pc.owned_node[v]) by_global.emplace_back(pc.global_node[v], static_cast<Index>(v));
  std::sort(by_global.begin(), by_global.end());
  std::vector<Index> answer(asked.size());
  for (size_t i = 0; i < asked.size(); ++i) {
    const auto it = std::lower_bound(by_global.begin(), by_global.end(), std::make_pair(asked[i], Index(-1)));
    if (it == by_global.end() || it->first != asked[i])
      throw Error("petsc engine: a rank asked for the rows of node " + std::to_string(asked[i]) +
                      ", which its owner does not own", EXIT_INTERNAL);
    answer[i] = it->second;
  }
  return answer;
}

// Each ghost's boundary data from its owner, which holds all of the node's facets: its Γ3 sums
// (weight, normal sum), its clamping and its rollers. A piece holding only some of a ghost's
// facets, or none (a Γ3 or Γ1 that ends on the ghost layer), would give it another weight, frame,
// membership or clamping, and so other unknowns, than its owner does.
GivenBoundary ghost_boundary_from_owners(const Mesh& mesh, const Piece& pc, MPI_Comm comm) {
  const int d = mesh.dim, m = d + 3;  // per node: w, normal sum, clamped, held
  const GhostAsk ask = ask_owners(pc, comm);
  const Gamma3Sums mine = gamma3_sums(mesh);
  const std::vector<bool> clamped = clamped_nodes(mesh);
  std::vector<double> out(ask.answer.size() * static_cast<size_t>(m));
  for (size_t i = 0; i < ask.answer.size(); ++i) {
    const Index v = ask.answer[i];
    double* o = out.data() + i * m;
    o[0] = mine.w[v];
    for (int c = 0; c < d; ++c) o[1 + c] = mine.normal(v, c);
    o[d + 1] = clamped[static_cast<size_t>(v)] ? 1 : 0;
    o[d + 2] = mesh.held(v);
  }
  const std::vector<double> in = answer_ghosts(ask, out, m, MPI_DOUBLE, comm);
  GivenBoundary g;
  g.node = ask.ghost;
  const auto n = static_cast<Index>(ask.ghost.size());
  g.w.resize(n);
  g.normal.resize(n, d);
  for (Index i = 0; i < n; ++i) {
    const double* r = in.data() + i * m;
    g.w[i] = r[0];
    for (int c = 0; c < d; ++c) g.normal(i, c) = r[1 + c];
    g.clamped.push_back(r[d + 1] != 0);
    g.held.push_back(static_cast<unsigned char>(r[d + 2]));
  }
  return g;
}

namespace detail {

Engine::Engine(const Model& m, const Piece& sl, const SolveOptions& o, MPI_Comm c, EngineReport& r, SlabResult& out,
               const Vec* x0)
    : md(m), opt(o), comm(c), rep(r), slab(sl), slab_out(out), start(x0) {
  init();
}

// What the engine sets and refuses before any work.
void Engine::init() {
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  d = md.dim();
  if (!md.material->is_linear())
    input_error("solver.engine = petsc: linear materials only (" + md.material->describe() +
                "); a nonlinear material needs solver.engine = cholmod");
  is_lagged = md.friction && md.friction->depends_on_u_nu();
}

// PETSc's numbering of the pieces: each rank's owned unknowns, in its local x order (interior
// nodes node-major, then its Γ3 nodes), form the contiguous rows [lo, hi); a ghost node's rows
// come from its owner (exchange_ghosts). No rank numbers, or sees, another rank's interior.
void Engine::distribute_slabs() {
  const auto t0 = clk::now();
  const Index nx = md.dofs.n_free();
  const std::vector<Index> sel = md.dofs.cartesian_selection();
  std::vector<Index> node_of_x(static_cast<size_t>(nx), -1);
  for (size_t j = 0; j < sel.size(); ++j)
    if (sel[j] >= 0) node_of_x[static_cast<size_t>(sel[j])] = static_cast<Index>(j / static_cast<size_t>(d));
  mine.clear();
  for (Index x = 0; x < nx; ++x)
    if (slab.owned_node[static_cast<size_t>(node_of_x[static_cast<size_t>(x)])]) mine.push_back(x);
  const auto nloc = static_cast<PetscInt>(mine.size());
  PetscInt before = 0;
  MPI_Exscan(&nloc, &before, 1, MPIU_INT, MPI_SUM, comm);
  lo = rank == 0 ? 0 : before;
  hi = lo + nloc;
  MPI_Allreduce(&nloc, &n, 1, MPIU_INT, MPI_SUM, comm);
  if (nloc == 0) input_error("solver.petsc.mesh: a rank's piece of the mesh has no free node; use fewer MPI ranks");
  perm.assign(static_cast<size_t>(nx), -1);
  for (PetscInt l = 0; l < nloc; ++l) perm[static_cast<size_t>(mine[static_cast<size_t>(l)])] = lo + l;
  // Block size d where no node anywhere has a roller (every free node then has d unknowns).
  int rollers = 0, rollers_all = 0;
  for (Index v = 0; v < md.mesh.num_nodes(); ++v) rollers |= md.mesh.held(v) != 0;
  MPI_Allreduce(&rollers, &rollers_all, 1, MPI_INT, MPI_MAX, comm);
  bs = rollers_all ? 1 : d;
  exchange_ghosts(sel);
  for (Index k = 0; k < md.contact.size(); ++k)
    if (slab.owned_node[static_cast<size_t>(md.contact.node[k])]) my_nodes.push_back(k);
  lambda.assign(my_nodes.size(), 0.0);
  if (slab.layout == "slabs")
    rep.json["partition"] = {{"type", "slabs"}, {"axis", std::string(1, "xyz"[slab.axis])}};
  else if (slab.layout == "blocks")
    rep.json["partition"] = {{"type", "blocks"}, {"grid", {slab.grid_x, slab.grid_y}}};
  else
    rep.json["partition"] = {{"type", slab.layout}, {"partitioner", slab.partitioner}};
  timings["petsc_partition"] = since(t0);
}

// Every ghost's rows from its owner (ask_owners, answer_ghosts): each owner answers with the PETSc
// rows of those nodes (d per node, −1 for a component without one), their coordinates (checked
// against the ghost's: the same node) and whether they are on Γ3 (the ghost's weight itself came
// from its owner when the piece's model was built: build_piece_model). A ghost whose unknowns
// differ from its owner's is a bug where the piece says it is complete (an outer ghost keeps no
// row: its rows enter no owned row). Then each received row is checked to lie in its owner's range.
void Engine::exchange_ghosts(const std::vector<Index>& sel) {
  const Piece& pc = slab;
  const auto D = static_cast<size_t>(d);
  const GhostAsk ask = ask_owners(pc, comm);
  const std::vector<Index> k_of = gamma3_index_of_nodes(md);
  std::vector<PetscInt> rows(ask.answer.size() * D);
  std::vector<double> xout(ask.answer.size() * D), on3(ask.answer.size());
  for (size_t i = 0; i < ask.answer.size(); ++i) {
    const auto v = static_cast<size_t>(ask.answer[i]);
    for (size_t c = 0; c < D; ++c) {
      const Index x = sel[v * D + c];
      rows[i * D + c] = x < 0 ? -1 : perm[static_cast<size_t>(x)];
      xout[i * D + c] = md.mesh.points(ask.answer[i], static_cast<Index>(c));
    }
    on3[i] = k_of[v] >= 0;
  }
  const std::vector<PetscInt> got = answer_ghosts(ask, rows, d, MPIU_INT, comm);
  const std::vector<double> xin = answer_ghosts(ask, xout, d, MPI_DOUBLE, comm);
  const std::vector<double> in3 = answer_ghosts(ask, on3, 1, MPI_DOUBLE, comm);
  std::vector<PetscInt> first(static_cast<size_t>(size)), last(static_cast<size_t>(size));
  MPI_Allgather(&lo, 1, MPIU_INT, first.data(), 1, MPIU_INT, comm);
  MPI_Allgather(&hi, 1, MPIU_INT, last.data(), 1, MPIU_INT, comm);
  long given = 0;
  for (size_t i = 0; i < ask.ghost.size(); ++i) {
    const auto v = static_cast<size_t>(ask.ghost[i]);
    check_same_place(ask.ghost[i], xin.data() + i * D);
    bool same = (k_of[v] >= 0) == (in3[i] != 0);
    for (size_t c = 0; c < D; ++c) same = same && ((sel[v * D + c] < 0) == (got[i * D + c] < 0));
    if (!same) {
      if (pc.complete.empty() || pc.complete[v]) throw Error("petsc engine: a ghost node's unknowns differ from its owner's", EXIT_INTERNAL);
      continue;  // an outer ghost: no row (its unknowns are not read)
    }
    const auto q = static_cast<size_t>(pc.owner[v]);
    for (size_t c = 0; c < D; ++c) {
      const Index x = sel[v * D + c];
      const PetscInt p = got[i * D + c];
      if (x < 0) continue;
      if (p < first[q] || p >= last[q]) throw Error("petsc engine: a ghost's row is not in its owner's range", EXIT_INTERNAL);
      perm[static_cast<size_t>(x)] = p;
    }
    ++given;
  }
  for (size_t j = 0; j < sel.size(); ++j)
    if (sel[j] >= 0 && perm[static_cast<size_t>(sel[j])] < 0 && (pc.complete.empty() || pc.complete[j / D]))
      throw Error("petsc engine: a ghost unknown of the piece got no row from its owner", EXIT_INTERNAL);
  MPI_Allreduce(&given, &slab_out.ghosts, 1, MPI_LONG, MPI_SUM, comm);
}

// The owner's node of that number is this one: at the same place (both pieces made its coordinates
// by the same formula, or carried the file's).
void Engine::check_same_place(Index v, const double* there) const {
  for (int c = 0; c < d; ++c) {
    const double here = md.mesh.points(v, c);
    if (!(std::abs(here - there[c]) <= 1e-12 * std::max(1.0, std::abs(here))))
      throw Error("petsc engine: ghost node " + std::to_string(slab.global_node[static_cast<size_t>(v)]) +
                      " is not where its owner has it", EXIT_INTERNAL);
  }
}

// The owned Γ3 nodes' unknowns of @p z (my_nodes order, d each).
Eigen::VectorXd Engine::local_gamma3(::Vec z) const {
  Eigen::VectorXd c(static_cast<Index>(my_nodes.size()) * d);
  const PetscScalar* p;
  VecGetArrayRead(z, &p);
  for (size_t q = 0; q < my_nodes.size(); ++q)
    for (int a = 0; a < d; ++a) c[static_cast<Index>(q) * d + a] = p[cdof(my_nodes[q]) + a - lo];
  VecRestoreArrayRead(z, &p);
  return c;
}

}  // namespace detail

}  // namespace hemicontact::petsc_engine
