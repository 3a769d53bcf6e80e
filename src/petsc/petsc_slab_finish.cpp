#include "engine_impl.hpp"

#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/solver/run_messages.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace hemicontact::petsc_engine::detail {

namespace {

// The judge's reduction over the ranks (check/judge.hpp's combine, by MPI_Allreduce): maxima,
// sums, and each residual's place from the rank that holds the largest value (on a tie the
// smallest place, as the serial judge's first occurrence).
struct MpiReduction final : Reduction {
  MPI_Comm comm;
  explicit MpiReduction(MPI_Comm c) : comm(c) {}
  void reduce(ScaleParts& p) const override {
    double mx[4] = {p.u_max, p.f_max, p.h_max, p.traction_max}, sm[2] = {p.w_sum, p.count};
    MPI_Allreduce(MPI_IN_PLACE, mx, 4, MPI_DOUBLE, MPI_MAX, comm);
    MPI_Allreduce(MPI_IN_PLACE, sm, 2, MPI_DOUBLE, MPI_SUM, comm);
    p.u_max = mx[0], p.f_max = mx[1], p.h_max = mx[2], p.traction_max = mx[3], p.w_sum = sm[0], p.count = sm[1];
  }
  void reduce(VerdictParts& p) const override {
    for (auto& c : p.residuals) {
      const double mine = c.value;
      MPI_Allreduce(&mine, &c.value, 1, MPI_DOUBLE, MPI_MAX, comm);
      long at = mine == c.value ? static_cast<long>(c.worst) : std::numeric_limits<long>::max();
      MPI_Allreduce(MPI_IN_PLACE, &at, 1, MPI_LONG, MPI_MIN, comm);
      c.worst = static_cast<Index>(at);
    }
    double sums[2] = {p.j, p.friction};
    MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm);
    p.j = sums[0], p.friction = sums[1];
    MPI_Allreduce(MPI_IN_PLACE, &p.u_nu_max, 1, MPI_DOUBLE, MPI_MAX, comm);
    MPI_Allreduce(MPI_IN_PLACE, p.counts.data(), static_cast<int>(p.counts.size()), MPI_LONG, MPI_SUM, comm);
  }
};

}  // namespace

// The distributed path's end: the piece of this rank, then the certificate, the statuses and the
// energies from the pieces by reductions (check/certificate.cpp's formulas, node by node).
void Engine::finish_slabs(Solution& s, ::Vec x, clk::time_point t0) {
  const auto t1 = clk::now();
  for (auto& h : s.history) h.solver = s.backend;
  s.backend_use.requested = opt.backend;
  s.backend_use.ran = !s.history.empty();
  if (!s.backend_use.ran) s.backend_use.not_run = "linear elasticity without contact: one CG solve is the answer";
  PVec R;
  HC_PETSC(VecDuplicate(x, &R.v));
  HC_PETSC(MatMult(K.m, x, R.v));
  HC_PETSC(VecAXPY(R.v, -1.0, f.v));
  slab_piece(x, R.v, slab_out.piece);
  slab_judge(slab_out.piece, opt);
  s.certificate = slab_out.piece.certificate;
  slab_energies(s, x, R.v);
  close_record(s, t0, t1);
  slab_report(s);
}

// x and K x − f at every unknown of the slab (owned and ghost) from their owners, and the state
// of every Γ3 node of the slab by check/'s contact_state from that residual: T (K x + f_x) − f,
// the owners' rows of K plus the slab's own f_x, which is internal_force − f on every free component
// (the slab's own f is partial on its ghosts; this sum does not use it).
void Engine::slab_piece(::Vec x, ::Vec R, Solution& p) {
  const auto nx = static_cast<PetscInt>(md.dofs.n_free());
  // The unknowns with a row: all but an outer ghost's whose unknowns differ from its owner's
  // (Piece::complete), which keep 0 here and are read by nothing this rank reports.
  std::vector<PetscInt> from, to;
  for (PetscInt i = 0; i < nx; ++i)
    if (perm[static_cast<size_t>(i)] >= 0) from.push_back(perm[static_cast<size_t>(i)]), to.push_back(i);
  IS is, ist;
  HC_PETSC(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(from.size()), from.data(), PETSC_USE_POINTER, &is));
  HC_PETSC(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(to.size()), to.data(), PETSC_USE_POINTER, &ist));
  PVec xl, Rl;
  HC_PETSC(VecCreateSeq(PETSC_COMM_SELF, nx, &xl.v));
  HC_PETSC(VecDuplicate(xl.v, &Rl.v));
  HC_PETSC(VecSet(xl.v, 0.0));
  HC_PETSC(VecSet(Rl.v, 0.0));
  VecScatter sc;
  HC_PETSC(VecScatterCreate(x, is, xl.v, ist, &sc));
  for (auto [from, to] : {std::pair<::Vec, ::Vec>{x, xl.v}, std::pair<::Vec, ::Vec>{R, Rl.v}}) {
    HC_PETSC(VecScatterBegin(sc, from, to, INSERT_VALUES, SCATTER_FORWARD));
    HC_PETSC(VecScatterEnd(sc, from, to, INSERT_VALUES, SCATTER_FORWARD));
  }
  VecScatterDestroy(&sc);
  ISDestroy(&is);
  ISDestroy(&ist);
  Eigen::VectorXd xe(nx), kx(nx);
  const PetscScalar *px, *pr;
  HC_PETSC(VecGetArrayRead(xl.v, &px));
  HC_PETSC(VecGetArrayRead(Rl.v, &pr));
  for (PetscInt i = 0; i < nx; ++i) xe[i] = px[i], kx[i] = pr[i] + md.fx[i];
  HC_PETSC(VecRestoreArrayRead(xl.v, &px));
  HC_PETSC(VecRestoreArrayRead(Rl.v, &pr));
  p.u = md.dofs.to_full(xe);
  p.x = std::move(xe);
  p.state = contact_state(md, p.u, md.dofs.to_full(kx) - md.f);
}

// The judge (check/judge.hpp) over the owned nodes of the piece @p p (slab_piece's), reduced over
// the ranks, at @p o's tolerances (the polish reads a second time at a coarser status_tol): the
// certificate, the statuses of the slab's Γ3 nodes, the Γ3 energy terms and the status counts.
void Engine::slab_judge(Solution& p, const SolveOptions& o) const {
  JudgeScope scope;
  scope.nodes = my_nodes;
  scope.owns = [this](Index v) { return slab.owned_node[static_cast<size_t>(v)] != 0; };
  scope.node_at = [this](Index k) { return static_cast<Index>(cdof(k)); };
  scope.dof_at = [this, sel = md.dofs.cartesian_selection()](Index c) {
    return static_cast<Index>(P(sel[static_cast<size_t>(c)]));
  };
  apply_judgement(md, o, p, scope, MpiReduction(comm));
}

// A candidate's evaluation on the pieces (the polish's s0 and s1): as finish_slabs reads x, into a
// Solution of its own, so that the run's piece and records stay as they are.
Solution Engine::slab_evaluate(::Vec x, const SolveOptions& o) {
  PVec R;
  HC_PETSC(VecDuplicate(x, &R.v));
  HC_PETSC(MatMult(K.m, x, R.v));
  HC_PETSC(VecAXPY(R.v, -1.0, f.v));
  Solution p;
  slab_piece(x, R.v, p);
  slab_judge(p, o);
  return p;
}

// The energies of eq. (22) from the pieces: a(u, u) = xᵀ K x and f·u = f_x·x by PETSc's
// reductions, the Γ3 terms from the judge (slab_judge).
void Engine::slab_energies(Solution& s, ::Vec x, ::Vec R) const {
  PetscScalar xr, xf;
  HC_PETSC(VecDot(x, R, &xr));
  HC_PETSC(VecDot(x, f.v, &xf));
  s.a_uu = xr + xf;
  s.f_u = xf;
  const Solution& p = slab_out.piece;
  s.j_term = p.j_term;
  s.friction_term = p.friction_term;
  s.max_u_nu = p.max_u_nu;
  s.counts = p.counts;
  s.elastic_energy = 0.5 * s.a_uu;
  s.energy = s.elastic_energy - s.f_u + s.j_term + s.friction_term;
  s.energy_norm = std::sqrt(std::max(0.0, s.a_uu));
}

// The distributed path's own record: the status counts and sizes, by reductions only.
void Engine::slab_report(Solution& s) {
  slab_out.status_counts = s.status_counts();
  long g3 = static_cast<long>(my_nodes.size()), nodes = static_cast<long>(md.mesh.num_nodes());
  MPI_Allreduce(&g3, &slab_out.gamma3_nodes, 1, MPI_LONG, MPI_SUM, comm);
  MPI_Allreduce(&nodes, &slab_out.local_nodes_max, 1, MPI_LONG, MPI_MAX, comm);
  long nodes_sum = 0;
  MPI_Allreduce(&nodes, &nodes_sum, 1, MPI_LONG, MPI_SUM, comm);
  rep.json["mesh"] = slab.describe();
  rep.json["local_nodes"] = slab_out.local_nodes_max;
  rep.json["global_nodes"] = slab.global_nodes;
  // The ranks' ghosts (local nodes not owned, counted on each rank that holds one) and those that got
  // their owners' rows (exchange_ghosts): the same number unless an outer ghost kept none.
  rep.json["ghost_nodes"] = nodes_sum - slab.global_nodes;
  rep.json["ghost_nodes_given_rows"] = slab_out.ghosts;
  if (slab.layout == "slabs")
    rep.json["slab_layers"] = {{"axis", std::string(1, "xyz"[slab.axis])}, {"layers", slab.layers},
                               {"first", slab.c0}, {"end", slab.c1}};
  else if (slab.layout == "blocks")  // rank 0's block, as slab_layers gives rank 0's layers
    rep.json["blocks"] = {{"grid", {slab.grid_x, slab.grid_y}},
                          {"columns", {{"x", {slab.block.i0, slab.block.i1}}, {"y", {slab.block.j0, slab.block.j1}}}}};
}

}  // namespace hemicontact::petsc_engine::detail
