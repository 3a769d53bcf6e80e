#include "engine_impl.hpp"

#include <hemicontact/check/status_equations.hpp>

#include <hemicontact/problem/node_rules.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>
#include <vector>

namespace hemicontact::petsc_engine::detail {

void Engine::unscaled_iterate(PVec& x) const {
  HC_PETSC(VecDuplicate(zs.v, &x.v));
  HC_PETSC(VecCopy(zs.v, x.v));
  HC_PETSC(VecScale(x.v, U_s));
}

// The exact polish in the full space (solver/polish.hpp's status system, without condensation):
// with the statuses of @p s0 fixed, Newton's method on
//   interior rows:     (K x − f)_i = 0
//   contact:           x_ν = g                              (eq. (5): the rigid part takes the rest)
//   compliance/sep.:   (K x − f)_ν + w p(x_ν) = 0           (p affine on the node's branch, eq. (32))
//   stick:             x_τ = 0;   frictionless:  (K x − f)_τ = 0
//   slip:              (K x − f)_τ + w λ t = 0,  t = x_τ/|x_τ|,  λ = F_b(x_ν)   (eq. (6))
// λ is evaluated at the current iterate and held in the Jacobian (K + w p′ + w λ (I − t tᵀ)/|x_τ|,
// symmetric, so CG + GAMG apply); the iteration then converges linearly in λ with the fixed point's
// contraction, and stops when the step reaches round-off (1e-14 relative) or stops decreasing.
// Fixed unknowns (contact ν, stick τ, rollers) are eliminated with MatZeroRowsColumns.
// Everything it reads is on the owned rows and the owned Γ3 nodes (my_nodes), with the statuses of
// s0 (indexed by the piece's Γ3 node); the evaluations are the pieces' judge (slab_evaluate).
PolishResult Engine::polish(::Vec x_io, const SolveOptions& read_opt, const Solution& s0_user) {
  PolishResult r;
  r.attempted = true;
  r.before = s0_user.certificate.max_residual;
  const Solution s0 = read_opt.status_tol == opt.status_tol ? s0_user : slab_evaluate(x_io, read_opt);
  const double delta = 1e-7 * s0.certificate.length_scale;
  PVec x, R, dx;
  PMat J;
  PKsp ksp;
  HC_PETSC(VecDuplicate(f.v, &x.v));
  HC_PETSC(VecDuplicate(f.v, &R.v));
  HC_PETSC(VecDuplicate(f.v, &dx.v));
  HC_PETSC(MatDuplicate(K.m, MAT_DO_NOT_COPY_VALUES, &J.m));
  HC_PETSC(MatSetNearNullSpace(J.m, rigid));
  create_cg(ksp, "polish_");
  HC_PETSC(VecCopy(x_io, x.v));
  const std::vector<PetscInt> fixed = polish_start(x.v, s0, delta);
  double prev = INF;
  for (r.iterations = 1; r.iterations <= opt.petsc.polish_max_iters; ++r.iterations) {
    if (!polish_linearize(x.v, R.v, J.m, s0, delta, fixed)) {
      r.note = "a slipping node reached u_tau = 0";
      return r;
    }
    HC_PETSC(MatZeroRowsColumns(J.m, static_cast<PetscInt>(fixed.size()), fixed.data(), 1.0, nullptr, nullptr));
    HC_PETSC(VecScale(R.v, -1.0));
    HC_PETSC(KSPSetOperators(ksp.k, J.m, J.m));
    HC_PETSC(KSPSolve(ksp.k, R.v, dx.v));
    KSPConvergedReason reason;
    PetscInt its;
    HC_PETSC(KSPGetConvergedReason(ksp.k, &reason));
    HC_PETSC(KSPGetIterationNumber(ksp.k, &its));
    polish_krylov += its;
    ++polish_newton;
    if (reason < 0) {
      r.note = std::string("CG on the status system: ") + KSPConvergedReasons[reason];
      return r;
    }
    HC_PETSC(VecAXPY(x.v, 1.0, dx.v));
    PetscReal change, scale;
    HC_PETSC(VecNorm(dx.v, NORM_INFINITY, &change));
    HC_PETSC(VecNorm(x.v, NORM_INFINITY, &scale));
    if (!(change > 1e-14 * scale) || (r.iterations > 2 && change >= prev)) break;
    prev = change;
  }
  polish_accept(x.v, s0, delta, r, x_io);
  return r;
}

// Node k's status equations at the local unknowns @p px (check/status_equations.hpp, s0's
// statuses). Without F_b's x_ν coupling: it is an unsymmetric column, and the status system is
// solved by CG (the λ coupling then converges linearly over the Newton steps).
NodeRows Engine::polish_rows(Index k, const PetscScalar* px, const Solution& s0, double delta) const {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int c = 0; c < d; ++c) x[c] = px[cdof(k) + c - lo];
  return status_rows(node_data(md, k), x, s0.status[static_cast<size_t>(k)],
                     frictionless_at(md, s0.state.u_nu[k], delta), roller_components(md, k), delta, false);
}

// The polish's start: @p x, a copy of the smoothed answer, gets the pinned unknowns' values.
// @return the pinned unknowns (PETSc's numbering, this rank's rows).
std::vector<PetscInt> Engine::polish_start(::Vec x, const Solution& s0, double delta) const {
  std::vector<PetscInt> fixed;
  PetscScalar* px;
  HC_PETSC(VecGetArray(x, &px));
  for (Index k : my_nodes) {
    const NodeRows rows = polish_rows(k, px, s0, delta);
    for (int c = 0; c < d; ++c)
      if (rows.is_pinned(c)) px[cdof(k) + c - lo] = rows.pin[c], fixed.push_back(cdof(k) + c);
  }
  HC_PETSC(VecRestoreArray(x, &px));
  return fixed;
}

// The status system at @p x: its residual into @p R (0 on the fixed unknowns) and its Jacobian
// into @p J (K plus the Γ3 nodes' blocks, before the fixed rows and columns are removed).
// @return false, on every rank, when a slipping node reached u_τ = 0 (its status is wrong).
bool Engine::polish_linearize(::Vec x, ::Vec R, ::Mat J, const Solution& s0, double delta,
                              const std::vector<PetscInt>& fixed) {
  HC_PETSC(MatMult(K.m, x, R));
  HC_PETSC(VecAXPY(R, -1.0, f.v));
  HC_PETSC(MatCopy(K.m, J, SAME_NONZERO_PATTERN));
  const PetscScalar* px;
  PetscScalar* pr;
  HC_PETSC(VecGetArrayRead(x, &px));
  HC_PETSC(VecGetArray(R, &pr));
  int local_bad = 0;
  for (Index k : my_nodes) {
    const NodeRows rows = polish_rows(k, px, s0, delta);
    local_bad = local_bad || rows.singular;
    const PetscInt iv = cdof(k);
    double B[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int c = 0; c < d; ++c) {
      pr[iv + c - lo] += rows.force[c];
      for (int j = 0; j < d; ++j) B[c * d + j] = rows.block(c, j);
    }
    PetscInt idx[3] = {iv, iv + 1, iv + 2};
    HC_PETSC(MatSetValues(J, d, idx, d, idx, B, ADD_VALUES));
  }
  for (PetscInt i : fixed) pr[i - lo] = 0;  // fixed unknowns keep their value: δ = 0 there
  HC_PETSC(VecRestoreArrayRead(x, &px));
  HC_PETSC(VecRestoreArray(R, &pr));
  HC_PETSC(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  return allreduce_max(local_bad, comm) == 0;
}

// Keep the candidate @p x only if the statuses stay and the certificate does not get worse
// (solver/polish.cpp's accept_if_better, the same rule): then @p x_io takes it. The rule is read on
// each rank's owned Γ3 nodes and reduced (piece_rejection).
void Engine::polish_accept(::Vec x, const Solution& s0, double delta, PolishResult& r, ::Vec x_io) {
  // A finite candidate on every rank's rows.
  const PetscScalar* px;
  int bad = 0;
  HC_PETSC(VecGetArrayRead(x, &px));
  for (PetscInt l = 0; l < hi - lo; ++l)
    if (!std::isfinite(px[l])) bad = 1;
  HC_PETSC(VecRestoreArrayRead(x, &px));
  if (allreduce_max(bad, comm) != 0) {
    r.note = "singular status system";
    return;
  }
  const Solution s1 = slab_evaluate(x, opt);
  r.after = s1.certificate.max_residual;
  r.note = piece_rejection(s0, s1, delta, r.before);
  if (!r.note.empty()) return;
  r.accepted = true;
  HC_PETSC(VecCopy(x, x_io));
}

// polish_rejection on the pieces. It loops over every Γ3 node of the model, which here is the
// piece's, ghosts included: a ghost's status is its owner's to judge (an outer ghost's state is not
// even complete, Piece::complete), so each rank reads its owned nodes (my_nodes) and the verdict is
// reduced. The note names the first changed node by its whole-mesh number (the piece's Γ3 index
// means nothing to the other ranks), with its statuses sent by its owner; every rank gets the same.
// The certificate's rule is polish_certificate_rejection on the reduced max residual.
std::string Engine::piece_rejection(const Solution& s0, const Solution& s1, double delta, double before) const {
  long first = LONG_MAX;
  int sts[4] = {0, 0, 0, 0};
  for (Index k : my_nodes) {
    const NodeStatus& a = s0.status[static_cast<size_t>(k)];
    const NodeStatus& b = s1.status[static_cast<size_t>(k)];
    const long g = slab.global_node[static_cast<size_t>(md.contact.node[static_cast<size_t>(k)])];
    if (!polish_status_kept(md, a, b, s0.state.u_nu[k], delta) && g < first) {
      first = g;
      sts[0] = static_cast<int>(a.normal), sts[1] = static_cast<int>(a.tangential);
      sts[2] = static_cast<int>(b.normal), sts[3] = static_cast<int>(b.tangential);
    }
  }
  long all_first = LONG_MAX;
  MPI_Allreduce(&first, &all_first, 1, MPI_LONG, MPI_MIN, comm);
  if (all_first != LONG_MAX) {
    int who = first == all_first ? rank : -1, owner = -1;
    MPI_Allreduce(&who, &owner, 1, MPI_INT, MPI_MAX, comm);
    MPI_Bcast(sts, 4, MPI_INT, owner, comm);
    NodeStatus a, b;
    a.normal = static_cast<NormalStatus>(sts[0]), a.tangential = static_cast<TangentialStatus>(sts[1]);
    b.normal = static_cast<NormalStatus>(sts[2]), b.tangential = static_cast<TangentialStatus>(sts[3]);
    return "statuses changed at mesh node " + std::to_string(all_first) + " (" + a.str() + " -> " + b.str() + ")";
  }
  return polish_certificate_rejection(s1.certificate.max_residual, before);
}

// The statuses read at check.status_tol and, when the stage's ε is larger, at 10 ε (a sticking
// node shows |u_τ| ~ ε U): solver/polish.cpp's first two readings.
PolishResult Engine::polish_with_readings(::Vec x, size_t stage) {
  const auto t0 = clk::now();
  const Solution s0 = slab_evaluate(x, opt);
  PolishResult r = polish(x, opt, s0);
  const double coarse = 10 * std::max(schedule[stage].first, schedule[stage].second);
  if (!r.accepted && coarse > opt.status_tol) {
    SolveOptions o = opt;
    o.status_tol = coarse;
    PolishResult r2 = polish(x, o, s0);
    r2.iterations += r.iterations;
    if (r2.accepted) r2.note = "statuses read at 10 eps";
    else r2.note = r.note + "; at 10 eps: " + r2.note;
    r = r2;
  }
  timings["polish"] += since(t0);
  return r;
}

}  // namespace hemicontact::petsc_engine::detail
