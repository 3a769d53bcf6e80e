#include "engine_impl.hpp"

#include <hemicontact/check/certificate.hpp>
#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/solver/run_messages.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace hemicontact::petsc_engine::detail {

namespace {

// One residual of the certificate over all ranks: the largest value, and where (the PETSc row
// of the worst node's first unknown; the worst rank's, when two ranks tie).
void reduce_residual(CertificateResidual& c, MPI_Comm comm) {
  const double mine = c.value;
  MPI_Allreduce(&mine, &c.value, 1, MPI_DOUBLE, MPI_MAX, comm);
  long at = mine == c.value ? static_cast<long>(c.worst) : -1, worst = -1;
  MPI_Allreduce(&at, &worst, 1, MPI_LONG, MPI_MAX, comm);
  c.worst = static_cast<Index>(worst);
}

}  // namespace

// The distributed path's end: the piece of this rank, then the certificate, the statuses and the
// energies from the pieces by reductions (check/certificate.cpp's formulas, node by node).
void Engine::finish_slabs(Solution& s, ::Vec x, clk::time_point t0) {
  const auto t1 = clk::now();
  for (auto& h : s.history) h.solver = s.backend;
  s.backend_use.requested = opt.backend;
  s.backend_use.ran = !s.history.empty();
  PVec R;
  HC_PETSC(VecDuplicate(x, &R.v));
  HC_PETSC(MatMult(K.m, x, R.v));
  HC_PETSC(VecAXPY(R.v, -1.0, f.v));
  slab_piece(x, R.v, slab_out->piece);
  slab_certificate(slab_out->piece, opt);
  s.certificate = slab_out->piece.certificate;
  slab_energies(s, x, R.v);
  close_record(s, t0, t1);
  slab_report(s);
}

// x and K x − f at every unknown of the slab (owned and ghost) from their owners, and the state
// of every Γ3 node of the slab by check/'s contact_state: it reads K u − f through md.Kx_apply,
// here the owners' rows plus the slab's own f_x, so that internal_force − f is T (K x − f) on
// every free component (the slab's own f is partial on its ghosts; this sum does not use it).
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
  md.Kx_apply = [kx](const Vec&) { return kx; };  // only for this u (the engine resets it when done)
  owns_apply = true;
  p.state = contact_state(md, p.u);
}

// check/certificate.cpp's certify over the owned nodes of the piece @p p (slab_piece's), its scales
// and maxima reduced over the ranks, at @p o's tolerances (the polish reads a second time at a
// coarser status_tol); then the statuses of the slab's Γ3 nodes (classify, with the global
// displacement scale). Both into p (the caller's: the run's piece or a candidate's).
void Engine::slab_certificate(Solution& p, const SolveOptions& o) const {
  const ContactState& st = p.state;
  const auto owned = [&](Index v) { return slab->owned_node[static_cast<size_t>(v)] != 0; };
  double umax = 0, fmax = 0, wsum = 0, lmax = 0;
  for (Index v = 0; v < md.mesh.num_nodes(); ++v)
    if (owned(v))
      for (int c = 0; c < d; ++c)
        umax = std::max(umax, std::abs(p.u[d * v + c])), fmax = std::max(fmax, std::abs(md.f[d * v + c]));
  for (Index k : my_nodes) wsum += md.contact.w[k], lmax = std::max({lmax, std::abs(st.lambda[k]), std::abs(st.xi[k])});
  CertificateReport r;
  r.tol = o.certificate_tol;
  const double U = allreduce_max(umax, comm), h = allreduce_max(md.mesh.max_edge_length(), comm);
  r.length_scale = U > 0 ? U : h;
  r.force_scale = allreduce_max(fmax, comm);
  const double count = allreduce_sum(double(my_nodes.size()), comm), wbar = count > 0 ? allreduce_sum(wsum, comm) / count : 1.0;
  r.traction_scale = r.force_scale / wbar;
  if (count > 0) r.traction_scale = std::max(r.traction_scale, allreduce_max(lmax, comm));
  if (!(r.force_scale > 0)) r.force_scale = 1.0;
  if (!(r.traction_scale > 0)) r.traction_scale = 1.0;
  const double Ul = r.length_scale, S = r.traction_scale;
  CertificateResidual feas{"feasibility"}, normal{"normal"}, compl_{"complementarity"}, cone{"friction_cone"},
      slip{"slip_direction"}, eq{"equilibrium"};
  const auto take = [](CertificateResidual& c, double v, Index at) {
    if (v > c.value || std::isnan(v)) c.value = std::isnan(v) ? INF : v, c.worst = at;
  };
  const auto pos = [](double v) { return std::isnan(v) ? v : std::max(0.0, v); };
  const auto min_nan = [](double a, double b) { return std::isnan(a) || std::isnan(b) ? NAN : std::min(a, b); };
  for (Index k : my_nodes) {
    const double g = md.contact.g[k], un = st.u_nu[k], sn = st.sigma_nu[k] + st.xi[k];
    const Index at = cdof(k);
    take(feas, pos(un - g) / Ul, at);
    take(normal, pos(sn) / S, at);
    take(compl_, std::abs(min_nan((g - un) / Ul, -sn / S)), at);
    const double stt = d == 2 ? std::abs(st.sigma_tau[k]) : st.sigma_tau[k];
    take(cone, pos(stt - st.lambda[k]) / S, at);
    const double y = st.u_tau_vec.row(k).norm();
    if (y > o.status_tol * Ul)  // −σ_τ = λ u_τ/|u_τ| on slipping nodes, eq. (6)
      take(slip, (st.sigma_tau_vec.row(k) + st.lambda[k] * st.u_tau_vec.row(k) / y).norm() / S, at);
  }
  // Interior equilibrium on the owned free components that are not on Γ3 (nor a roller's).
  const std::vector<Index> sel = md.dofs.cartesian_selection();
  for (Index v = 0; v < md.mesh.num_nodes(); ++v)
    for (int i = 0; i < d; ++i) {
      const Index xi = sel[static_cast<size_t>(d * v + i)];
      if (owned(v) && xi >= 0 && xi < md.dofs.n_interior())
        take(eq, std::abs(st.residual[d * v + i]) / r.force_scale, P(xi));
    }
  r.residuals = {feas, normal, compl_, cone, slip, eq};
  r.max_residual = 0;
  for (auto& c : r.residuals) reduce_residual(c, comm), r.max_residual = std::max(r.max_residual, c.value);
  r.passed = r.max_residual <= r.tol;
  p.status = classify(md, st, r.length_scale, o.status_tol);
  p.certificate = r;
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
  slab_certificate(p, o);
  return p;
}

// The energies of eq. (22) from the pieces: a(u, u) = xᵀ K x and f·u = f_x·x by PETSc's
// reductions, the Γ3 terms summed over the owned nodes (evaluate.cpp's formulas).
void Engine::slab_energies(Solution& s, ::Vec x, ::Vec R) const {
  PetscScalar xr, xf;
  HC_PETSC(VecDot(x, R, &xr));
  HC_PETSC(VecDot(x, f.v, &xf));
  s.a_uu = xr + xf;
  s.f_u = xf;
  const ContactState& st = slab_out->piece.state;
  double j = 0, fr = 0, umax = -INF;
  for (Index k : my_nodes) {
    if (md.normal_law) j += md.contact.w[k] * md.normal_law->j(st.u_nu[k]);
    fr += md.contact.w[k] * st.lambda[k] * st.u_tau_vec.row(k).norm();
    umax = std::max(umax, st.u_nu[k]);
  }
  s.j_term = allreduce_sum(j, comm);
  s.friction_term = allreduce_sum(fr, comm);
  s.elastic_energy = 0.5 * s.a_uu;
  s.energy = s.elastic_energy - s.f_u + s.j_term + s.friction_term;
  s.energy_norm = std::sqrt(std::max(0.0, s.a_uu));
  const double m = allreduce_max(umax, comm);
  s.max_u_nu = std::isfinite(m) ? m : 0.0;
}

// The distributed path's own record: the status counts and sizes, by reductions only.
void Engine::slab_report(Solution& s) {
  (void)s;
  std::map<std::string, long> c{{"separated", 0}, {"compliance", 0}, {"contact", 0}, {"stick", 0},
                                {"slip+", 0},     {"slip-", 0},      {"slip", 0}};
  const auto& status = slab_out->piece.status;
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    const NodeStatus& t = status[static_cast<size_t>(my_nodes[q])];
    ++c[to_string(t.normal)];
    ++c[to_string(t.tangential)];
  }
  slab_out->status_counts = nlohmann::json::object();
  for (auto& [key, v] : c) {
    long all = 0;
    MPI_Allreduce(&v, &all, 1, MPI_LONG, MPI_SUM, comm);
    if (key != "slip" || all > 0) slab_out->status_counts[key] = all;
  }
  long g3 = static_cast<long>(my_nodes.size()), nodes = static_cast<long>(md.mesh.num_nodes());
  MPI_Allreduce(&g3, &slab_out->gamma3_nodes, 1, MPI_LONG, MPI_SUM, comm);
  MPI_Allreduce(&nodes, &slab_out->local_nodes_max, 1, MPI_LONG, MPI_MAX, comm);
  long nodes_sum = 0;
  MPI_Allreduce(&nodes, &nodes_sum, 1, MPI_LONG, MPI_SUM, comm);
  rep.json["mesh"] = slab->describe();
  rep.json["local_nodes"] = slab_out->local_nodes_max;
  rep.json["global_nodes"] = slab->global_nodes;
  // The ranks' ghosts (local nodes not owned, counted on each rank that holds one) and those that got
  // their owners' rows (exchange_ghosts): the same number unless an outer ghost kept none.
  rep.json["ghost_nodes"] = nodes_sum - slab->global_nodes;
  rep.json["ghost_nodes_given_rows"] = slab_out->ghosts;
  if (slab->layout == "slabs")
    rep.json["slab_layers"] = {{"axis", std::string(1, "xyz"[slab->axis])}, {"layers", slab->layers},
                               {"first", slab->c0}, {"end", slab->c1}};
  else if (slab->layout == "blocks")  // rank 0's block, as slab_layers gives rank 0's layers
    rep.json["blocks"] = {{"grid", {slab->grid_x, slab->grid_y}},
                          {"columns", {{"x", {slab->block.i0, slab->block.i1}}, {"y", {slab->block.j0, slab->block.j1}}}}};
}

}  // namespace hemicontact::petsc_engine::detail
