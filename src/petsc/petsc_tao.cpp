#include "engine_impl.hpp"

#include <hemicontact/core/log.hpp>
#include <hemicontact/solver/run_messages.hpp>
#include <hemicontact/nlp/backend.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <string>

namespace hemicontact::petsc_engine::detail {

// Π_λ,ε at x = U_s zs, in the cholmod engine's units: value / (F_s U_s), gradient / F_s. The Γ3
// terms are energy/'s per-node kernels (contact_energy.hpp) on this rank's nodes.
double Engine::energy(::Vec z, ::Vec g) {
  HC_PETSC(VecCopy(z, work.v));
  HC_PETSC(VecScale(work.v, U_s));
  HC_PETSC(MatMult(K.m, work.v, g));  // g = K x
  PetscScalar xKx, fx;
  HC_PETSC(VecDot(work.v, g, &xKx));
  HC_PETSC(VecDot(work.v, f.v, &fx));
  HC_PETSC(VecAXPY(g, -1.0, f.v));  // g = K x − f
  double local = 0;
  const PetscScalar* px;
  PetscScalar* pg;
  HC_PETSC(VecGetArrayRead(work.v, &px));
  HC_PETSC(VecGetArray(g, &pg));
  NodalVector xk(d);
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    const Index i = cdof(my_nodes[q]) - lo;
    const auto node = static_cast<Index>(q);  // the node's index in the owned layout
    for (int a = 0; a < d; ++a) xk[a] = px[i + a];
    if (normal_term) {
      local += normal_term->node_value(node, xk);
      pg[i] += normal_term->node_gradient(node, xk)[0];
    }
    if (friction_term && lambda[q] > 0) {
      local += friction_term->node_value(node, xk);
      const NodalVector gk = friction_term->node_gradient(node, xk);
      for (int c = 1; c < d; ++c) pg[i + c] += gk[c];
    }
  }
  HC_PETSC(VecRestoreArrayRead(work.v, &px));
  HC_PETSC(VecRestoreArray(g, &pg));
  HC_PETSC(VecScale(g, 1.0 / F_s));
  const double value = 0.5 * xKx - fx + allreduce_sum(local, comm);
  return value / (F_s * U_s);
}

// H = (K + Σ nodal blocks) U_s / F_s, the blocks energy/'s kernels. The normal block is
// w max(p_ε′, 0): the softening branch (c2 < 0) is clamped (Psd::CLAMP, as the newton backend
// does), so that CG sees a positive semidefinite Hessian; friction's block w λ ∇²f0 is positive
// semidefinite as it is (smooth_norm.hpp).
void Engine::hessian(::Vec z, ::Mat H) {
  HC_PETSC(MatCopy(K.m, H, SAME_NONZERO_PATTERN));
  const PetscScalar* pz;
  HC_PETSC(VecGetArrayRead(z, &pz));
  NodalVector xk(d);
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    const PetscInt i0 = cdof(my_nodes[q]);
    const auto node = static_cast<Index>(q);
    for (int a = 0; a < d; ++a) xk[a] = U_s * pz[i0 - lo + a];
    NodalMatrix Hk = NodalMatrix::Zero(d, d);
    if (normal_term) Hk += normal_term->node_hessian(node, xk, Psd::CLAMP);
    if (friction_term && lambda[q] > 0) Hk += friction_term->node_hessian(node, xk, Psd::CLAMP);
    double B[9];
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b) B[a * d + b] = Hk(a, b);
    PetscInt idx[3] = {i0, i0 + 1, i0 + 2};
    HC_PETSC(MatSetValues(H, d, idx, d, idx, B, ADD_VALUES));
  }
  HC_PETSC(VecRestoreArrayRead(z, &pz));
  HC_PETSC(MatAssemblyBegin(H, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatAssemblyEnd(H, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatScale(H, U_s / F_s));
}

// The owned Γ3 nodes as energy/'s nodal terms see them: node q of my_nodes with its weight, its
// unknowns at q d .. q d + d − 1 of a local vector. The blocks go into PETSc's H here (hessian),
// not into an Eigen pattern, so the layout's pattern is empty and its positions unused.
std::shared_ptr<const NodalLayout> Engine::owned_layout() const {
  NodalDofs nd;
  nd.dim = d;
  nd.w.resize(static_cast<Index>(my_nodes.size()));
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    nd.first.push_back(static_cast<Index>(q) * d);
    nd.w[static_cast<Index>(q)] = md.contact.w[my_nodes[q]];
  }
  SpMat none(static_cast<Index>(my_nodes.size()) * d, static_cast<Index>(my_nodes.size()) * d);
  none.makeCompressed();
  return std::make_shared<const NodalLayout>(std::move(nd), none);
}

// The frozen bounds λ of the owned nodes, as the friction term holds them.
Vec Engine::owned_lambda() const { return Eigen::Map<const Vec>(lambda.data(), static_cast<Index>(lambda.size())); }

PetscErrorCode Engine::tao_objgrad(Tao, ::Vec x, PetscReal* fval, ::Vec g, void* ctx) {
  try {
    *fval = static_cast<Engine*>(ctx)->energy(x, g);
    return 0;
  } catch (const std::exception& e) {
    log_warn() << "petsc: objective: " << e.what();
    return PETSC_ERR_LIB;
  }
}

PetscErrorCode Engine::tao_hessian(Tao, ::Vec x, ::Mat H, ::Mat, void* ctx) {
  try {
    static_cast<Engine*>(ctx)->hessian(x, H);
    return 0;
  } catch (const std::exception& e) {
    log_warn() << "petsc: Hessian: " << e.what();
    return PETSC_ERR_LIB;
  }
}

// The backends' first-order residual (nlp/backend.hpp's, on this rank's rows), max over ranks:
// max_i min(|g_i|, room towards the bound that −g_i points to), in scaled units; @p lo_s, @p up_s
// are the scaled bounds (scaled_bound), ±PETSC_INFINITY where there is none.
double Engine::first_order_residual(::Vec z, ::Vec g, ::Vec lo_s, ::Vec up_s) const {
  const PetscScalar *pz, *pg, *pl, *pu;
  HC_PETSC(VecGetArrayRead(z, &pz));
  HC_PETSC(VecGetArrayRead(g, &pg));
  HC_PETSC(VecGetArrayRead(lo_s, &pl));
  HC_PETSC(VecGetArrayRead(up_s, &pu));
  const Index nloc = hi - lo;
  const double r = hemicontact::first_order_residual(Eigen::Map<const Vec>(pz, nloc), Eigen::Map<const Vec>(pg, nloc),
                                                     Eigen::Map<const Vec>(pl, nloc), Eigen::Map<const Vec>(pu, nloc));
  HC_PETSC(VecRestoreArrayRead(z, &pz));
  HC_PETSC(VecRestoreArrayRead(g, &pg));
  HC_PETSC(VecRestoreArrayRead(lo_s, &pl));
  HC_PETSC(VecRestoreArrayRead(up_s, &pu));
  return allreduce_max(r, comm);
}

// One TAO bounded-Newton run from the current zs (warm start), with λ and ε frozen.
OuterIteration Engine::minimize(size_t stage) {
  OuterIteration rec;
  rec.k = k_total++;
  rec.stage = static_cast<int>(stage);
  rec.eps_tau = eps_tau;
  rec.eps_nu = eps_nu;
  const auto t0 = clk::now();
  PTao tao;
  PMat H;
  PVec lo_s, up_s;
  HC_PETSC(MatDuplicate(K.m, MAT_DO_NOT_COPY_VALUES, &H.m));
  HC_PETSC(VecDuplicate(lower.v, &lo_s.v));
  HC_PETSC(VecDuplicate(upper.v, &up_s.v));
  scaled_bound(lower.v, lo_s.v);
  scaled_bound(upper.v, up_s.v);
  HC_PETSC(TaoCreate(comm, &tao.t));
  HC_PETSC(TaoSetType(tao.t, tao_type(opt.backend).c_str()));
  HC_PETSC(TaoSetSolution(tao.t, zs.v));
  HC_PETSC(TaoSetObjectiveAndGradient(tao.t, grad.v, &Engine::tao_objgrad, this));
  HC_PETSC(TaoSetHessian(tao.t, H.m, H.m, &Engine::tao_hessian, this));
  HC_PETSC(TaoSetVariableBounds(tao.t, lo_s.v, up_s.v));
  // Converged when the projected gradient (scaled units, as every backend's solver.tol) is ≤ tol.
  HC_PETSC(TaoSetTolerances(tao.t, opt.backend_options.tol, 0.0, 0.0));
  HC_PETSC(TaoSetMaximumIterations(tao.t, opt.backend_options.max_iter));
  HC_PETSC(TaoSetMaximumFunctionEvaluations(tao.t, 100 * opt.backend_options.max_iter));
  KSP ksp;
  HC_PETSC(TaoGetKSP(tao.t, &ksp));
  if (ksp) {
    set_pc(ksp, opt.petsc.newton_pc);
    HC_PETSC(KSPSetTolerances(ksp, opt.petsc.ksp_rtol, PETSC_DEFAULT, PETSC_DEFAULT, opt.petsc.ksp_max_it));
  }
  HC_PETSC(TaoSetFromOptions(tao.t));
  HC_PETSC(TaoGetKSP(tao.t, &ksp));
  if (ksp) {
    hypre_defaults(ksp);
    if (opt.petsc.newton_pc == "gamg") fresh_gamg(ksp);
  }
  HC_PETSC(TaoSolve(tao.t));
  TaoConvergedReason reason;
  PetscInt its, lits, nfev;
  HC_PETSC(TaoGetConvergedReason(tao.t, &reason));
  HC_PETSC(TaoGetIterationNumber(tao.t, &its));
  HC_PETSC(TaoGetLinearSolveIterations(tao.t, &lits));
  HC_PETSC(TaoGetCurrentFunctionEvaluations(tao.t, &nfev));
  newton_total += its;
  krylov_total += lits;
  // The same first-order residual every backend reports, at the returned point.
  const double fval = energy(zs.v, grad.v);
  const double kkt = first_order_residual(zs.v, grad.v, lo_s.v, up_s.v);
  rec.backend.iterations = static_cast<int>(its);
  rec.backend.evaluations = static_cast<int>(nfev);
  rec.backend.f = fval;
  rec.backend.kkt_norm = kkt;
  rec.backend.seconds = since(t0);
  rec.backend.message = std::string("TAO ") + TaoConvergedReasons[reason] + ", " + std::to_string(lits) +
                        " Krylov iterations";
  if (reason > 0)
    rec.backend.status = SolveStatus::CONVERGED;
  else if (reason == TAO_DIVERGED_MAXITS)
    rec.backend.status = SolveStatus::MAX_ITERATIONS;
  else if (kkt <= opt.petsc.acceptable_tol)
    rec.backend.status = SolveStatus::ACCEPTABLE;  // a line search stopped at round-off
  else
    rec.backend.status = SolveStatus::FAILED;
  stages.push_back({{"k", rec.k}, {"stage", rec.stage}, {"newton", its}, {"krylov", lits},
                    {"krylov_per_newton", its > 0 ? double(lits) / double(its) : 0.0}, {"tao_reason", TaoConvergedReasons[reason]},
                    {"seconds", rec.backend.seconds}});
  const Eigen::VectorXd c = local_gamma3(zs.v);
  double dmax = 0, smax = 0;
  if (c.size()) {
    dmax = (c - prev_c).cwiseAbs().maxCoeff();
    smax = std::max(c.cwiseAbs().maxCoeff(), prev_c.cwiseAbs().maxCoeff());
  }
  dmax = allreduce_max(dmax, comm);
  smax = allreduce_max(smax, comm);
  rec.change_u = smax > 0 ? dmax / smax : 0.0;
  prev_c = c;
  rec.grad_norm = kkt;
  return rec;
}

// λ ← (1−θ)λ + θ F_b(u_ν) on the owned Γ3 nodes (solver/solve.cpp's relax_lambda).
LambdaChange Engine::relax_lambda() {
  const PetscScalar* p;
  VecGetArrayRead(zs.v, &p);
  double dmax = 0, lmax = 0;
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    const double fb = md.friction->F(U_s * p[cdof(my_nodes[q]) - lo]);
    const double l = (1 - opt.relaxation) * lambda[q] + opt.relaxation * fb;
    dmax = std::max(dmax, std::abs(l - lambda[q]));
    lmax = std::max({lmax, std::abs(l), std::abs(lambda[q])});
    lambda[q] = l;
  }
  friction_term->set_lambda(owned_lambda());
  VecRestoreArrayRead(zs.v, &p);
  return LambdaChange{allreduce_max(dmax, comm), allreduce_max(lmax, comm)};
}

// The smoothing widths of a stage (absolute: relative widths × U_s), and energy/'s nodal terms
// on the owned Γ3 nodes made for them.
void Engine::set_smoothing(size_t stage) {
  eps_tau = schedule[stage].first * U_s;
  eps_nu = schedule[stage].second * U_s;
  if (!nodal) nodal = owned_layout();
  if (md.normal_law)
    normal_term = std::make_unique<NormalComplianceEnergy>(
        nodal, std::make_shared<const MollifiedLaw>(md.normal_law, eps_nu, "solver.eps_nu"));
  if (md.friction) friction_term = std::make_unique<FrictionEnergy>(nodal, eps_tau, owned_lambda());
}

}  // namespace hemicontact::petsc_engine::detail
