#include "engine_impl.hpp"

#include <hemicontact/core/log.hpp>
#include <hemicontact/scene/slab_mesh.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace hemicontact::petsc_engine {

// Even split of the cell layers; each rank builds the layers it owns and the one below them (the
// cells that touch its lowest node layer), so that every owned node's row is complete locally.
Slab make_slab(const nlohmann::json& scene, MPI_Comm comm, Mesh& mesh) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const SlabCut cut = slab_cut(scene);
  if (cut.layers < size)
    input_error("solver.petsc.mesh: " + std::to_string(size) + " MPI ranks for " + std::to_string(cut.layers) +
                " cell layers along " + "xyz"[cut.axis] + "; use at most as many ranks as layers (mpirun -np), or "
                "solver.petsc.mesh = \"replicated\"");
  Slab s;
  s.axis = cut.axis;
  s.layers = cut.layers;
  s.c0 = static_cast<int>(static_cast<long>(cut.layers) * rank / size);
  s.c1 = static_cast<int>(static_cast<long>(cut.layers) * (rank + 1) / size);
  const int first = std::max(s.c0 - 1, 0), held = s.c1 - first;
  std::vector<long> counts;
  mesh = build_slab_mesh(scene, first, s.c1, counts);
  // A selector must select something on some rank (what assign_boundary checks on a whole mesh).
  std::vector<long> all(counts.size(), 0);
  MPI_Allreduce(counts.data(), all.data(), static_cast<int>(counts.size()), MPI_LONG, MPI_SUM, comm);
  const std::vector<std::string> names = boundary_selector_names(scene);
  for (size_t i = 0; i < all.size() && i < names.size(); ++i)
    if (all[i] == 0) input_error(names[i] + " selects no boundary facet");
  // The layer of local node v along the cut (mesh/slabs.hpp's numbering).
  const Index row = cut.axis == 1 ? scene.at("mesh").at("nx").get<Index>() + 1 : 1;
  const auto layer = [&](Index v) {
    return first + static_cast<int>(cut.axis == 1 ? (v / row) % (held + 1) : v % (held + 1));
  };
  const Index N = mesh.num_nodes();
  s.owned_node.assign(static_cast<size_t>(N), 0);
  for (Index v = 0; v < N; ++v) {
    const int l = layer(v);
    const bool own = (l >= s.c0 && l < s.c1) || (l == s.layers && s.c1 == s.layers);
    s.owned_node[static_cast<size_t>(v)] = own;
    if (rank > 0 && l == s.c0 - 1) s.recv_below.push_back(v);
    if (rank > 0 && l == s.c0) s.send_below.push_back(v);
    if (rank + 1 < size && l == s.c1) s.recv_above.push_back(v);
    if (rank + 1 < size && l == s.c1 - 1) s.send_above.push_back(v);
  }
  s.owned_cell.assign(static_cast<size_t>(mesh.num_cells()), 0);
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    int lmin = s.layers;
    for (int a = 0; a < mesh.cells.cols(); ++a) lmin = std::min(lmin, layer(mesh.cells(c, a)));
    s.owned_cell[static_cast<size_t>(c)] = lmin >= s.c0;
  }
  long nodes = 0, cells = 0;
  for (char o : s.owned_node) nodes += o;
  for (char o : s.owned_cell) cells += o;
  MPI_Allreduce(&nodes, &s.global_nodes, 1, MPI_LONG, MPI_SUM, comm);
  MPI_Allreduce(&cells, &s.global_cells, 1, MPI_LONG, MPI_SUM, comm);
  return s;
}

namespace detail {

Engine::Engine(Model& m, const Slab& sl, const SolveOptions& o, MPI_Comm c, EngineReport& r, SlabResult& out)
    : md(m), opt(o), comm(c), rep(r), slab(&sl), slab_out(&out) {
  init();
}

// PETSc's numbering on the slabs: each rank's owned unknowns, in its local x order (interior
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
    if (slab->owned_node[static_cast<size_t>(node_of_x[static_cast<size_t>(x)])]) mine.push_back(x);
  const auto nloc = static_cast<PetscInt>(mine.size());
  PetscInt before = 0;
  MPI_Exscan(&nloc, &before, 1, MPIU_INT, MPI_SUM, comm);
  lo = rank == 0 ? 0 : before;
  hi = lo + nloc;
  MPI_Allreduce(&nloc, &n, 1, MPIU_INT, MPI_SUM, comm);
  if (nloc == 0) input_error("solver.petsc.mesh: a rank's slab has no free node; use fewer MPI ranks");
  perm.assign(static_cast<size_t>(nx), -1);
  for (PetscInt l = 0; l < nloc; ++l) perm[static_cast<size_t>(mine[static_cast<size_t>(l)])] = lo + l;
  // Block size d where no node anywhere has a roller (every free node then has d unknowns).
  int rollers = 0, rollers_all = 0;
  for (Index v = 0; v < md.mesh.num_nodes(); ++v) rollers |= md.mesh.held(v) != 0;
  MPI_Allreduce(&rollers, &rollers_all, 1, MPI_INT, MPI_MAX, comm);
  bs = rollers_all ? 1 : d;
  std::vector<Index> k_of(static_cast<size_t>(md.mesh.num_nodes()), -1);
  for (Index k = 0; k < md.contact.size(); ++k) k_of[static_cast<size_t>(md.contact.node[k])] = k;
  // Below first on every rank: rank 0 has no one below, so the pairs meet in turn.
  exchange_ghosts(slab->send_below, slab->recv_below, rank - 1, sel, k_of);
  exchange_ghosts(slab->send_above, slab->recv_above, rank + 1, sel, k_of);
  if (std::count(perm.begin(), perm.end(), PetscInt(-1)) != 0)
    throw Error("petsc engine: a ghost unknown of the slab got no row from its owner", EXIT_INTERNAL);
  for (Index k = 0; k < md.contact.size(); ++k)
    if (slab->owned_node[static_cast<size_t>(md.contact.node[k])]) my_nodes.push_back(k);
  lambda.assign(my_nodes.size(), 0.0);
  own_nodes = slab->owned_node;
  rep.json["partition"] = {{"type", "slabs"}, {"axis", std::string(1, "xyz"[slab->axis])}};
  timings["petsc_partition"] = since(t0);
}

// With the rank @p peer: send the rows of the owned nodes @p send (d per node, −1 for a
// component without one), receive those of the ghosts @p recv, in the same node order on both
// sides; and the Γ3 weights, which a ghost's partial set of facets would get wrong (the certificate
// and the piece's tractions read w). A component free on one side and fixed on the other is a bug.
void Engine::exchange_ghosts(const std::vector<Index>& send, const std::vector<Index>& recv, int peer,
                             const std::vector<Index>& sel, const std::vector<Index>& k_of) {
  if (peer < 0 || peer >= size) return;
  std::vector<PetscInt> out(send.size() * static_cast<size_t>(d)), in(recv.size() * static_cast<size_t>(d));
  std::vector<double> wout(send.size(), 0.0), win(recv.size(), 0.0);
  for (size_t i = 0; i < send.size(); ++i) {
    const auto v = static_cast<size_t>(send[i]);
    for (int c = 0; c < d; ++c) {
      const Index x = sel[v * static_cast<size_t>(d) + static_cast<size_t>(c)];
      out[i * static_cast<size_t>(d) + static_cast<size_t>(c)] = x < 0 ? -1 : perm[static_cast<size_t>(x)];
    }
    if (k_of[v] >= 0) wout[i] = md.contact.w[k_of[v]];
  }
  MPI_Sendrecv(out.data(), static_cast<int>(out.size()), MPIU_INT, peer, 31, in.data(), static_cast<int>(in.size()),
               MPIU_INT, peer, 31, comm, MPI_STATUS_IGNORE);
  MPI_Sendrecv(wout.data(), static_cast<int>(wout.size()), MPI_DOUBLE, peer, 32, win.data(),
               static_cast<int>(win.size()), MPI_DOUBLE, peer, 32, comm, MPI_STATUS_IGNORE);
  for (size_t i = 0; i < recv.size(); ++i) {
    const auto v = static_cast<size_t>(recv[i]);
    for (int c = 0; c < d; ++c) {
      const Index x = sel[v * static_cast<size_t>(d) + static_cast<size_t>(c)];
      const PetscInt p = in[i * static_cast<size_t>(d) + static_cast<size_t>(c)];
      if ((x < 0) != (p < 0))
        throw Error("petsc engine: a ghost node's unknowns differ from its owner's", EXIT_INTERNAL);
      if (x >= 0) perm[static_cast<size_t>(x)] = p;
    }
    if (k_of[v] >= 0) md.contact.w[k_of[v]] = win[i];
  }
}

}  // namespace detail

}  // namespace hemicontact::petsc_engine
