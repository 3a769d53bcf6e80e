#include "engine_impl.hpp"

#include <hemicontact/core/log.hpp>
#include <hemicontact/check/status_equations.hpp>
#include <hemicontact/solver/ssn.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hemicontact::petsc_engine::detail {

namespace {

// The backend's name: the Krylov methods its steps used, the preconditioner, the ranks.
std::string ssn_name(const std::string& krylov, const std::string& pc, int ranks) {
  return "ssn (semismooth Newton, " + krylov + " + " + pc + ", PETSc, " + std::to_string(ranks) + " rank" +
         (ranks > 1 ? "s" : "") + ")";
}

}  // namespace

// ssn's iterate, its work vectors and what one step passes to the next.
struct Engine::Ssn {
  PVec x, R, dx, rhs, fixv, diagK, xt, Rt;  // xt, Rt: a trial point's and its residual (the line search)
  PKsp ksp;
  BandRows band;    // K's rows that J changes, to put K back
  double diag_scale = 1;  // the fixed unknowns' diagonal in J (the mean K_ii)
  // Status per owned Γ3 node (ssn_node's code); the previous step's, to count changes.
  std::vector<int> status, prev_status;
  // The slip direction t each sliding node was given this step (0: not sliding).
  std::vector<Eigen::Vector2d> slip_dir;
  // A node whose slip reversed in the last step: held at stick for one step (ssn_stop_reversals).
  std::vector<char> hold_stick;
  std::vector<PetscInt> fixed;
  nlohmann::json steps = nlohmann::json::array();
  // CG iterations per decade that the hierarchy is judged against: the larger of the step that
  // built it and the first step that reused it. The build step alone is no fair reference: the
  // first one has every Γ3 node fixed, an easier matrix than any later step's (70³: 4 per decade
  // against 7 at the next step, whatever the hierarchy), so it called for rebuilds that did not
  // lower the counts (70³, 2 ranks: 2 builds 169 CG iterations, 1 build 155).
  double built_per_decade = 0;
  bool reference_pending = false;
  bool rebuild = true;  // the AMG hierarchy is (re)built at the next step
  int unchanged = 0;    // steps in a row without a status change
  double prev_step = INF;
  // The globalization (solver/ssn.hpp, as the cholmod engine's ssn): the cycle watch, this rank's
  // node signatures summed, each owned node's coupling column, how many nodes (all ranks) this
  // step's J couples, and whether the KSP is GMRES for them.
  SsnCycleWatch watch;
  uint64_t signature = 0;
  std::vector<Eigen::Vector3d> coupling_col;
  long coupled = 0;
  bool gmres = false;
  bool used_gmres = false;  // some step's J was coupled: the backend's name says GMRES too
  bool cold = true;  // from zero: the first reading puts every node in contact (ssn_reading)
};

// This rank's arrays of the iterate, K's diagonal, the residual and the fixed unknowns' steps,
// while ssn_linearize holds them.
struct Engine::SsnArrays {
  const PetscScalar* x = nullptr;
  const PetscScalar* diag = nullptr;
  PetscScalar* r = nullptr;
  PetscScalar* fix = nullptr;
};

// Backend "ssn": a semismooth (active-set) Newton method on the unsmoothed conditions of (22) in
// the full space, every status read again at every step from the current iterate x and the
// residual R = K x − f by check/status_equations.hpp's ssn_reading (the complementarity functions
// of the primal-dual active-set method; the CHOLMOD engine's ssn reads its nodes the same way):
//   normal:  contact  iff  −(R_ν + w p(x_ν)) + c_n (x_ν − g) > 0          (eq. (5): u_ν ≤ g)
//            then x_ν = g; else R_ν + w p(x_ν) = 0 on x_ν's branch of p      (eq. (32))
//   tangent: stick    iff  |y| ≤ w λ,  y = −R_τ + c_t x_τ,  λ = F_b(x_ν)     (eq. (6))
//            then x_τ = 0; else R_τ + w λ t = 0 with t = y/|y|
// Each step solves the linearization with the fixed unknowns eliminated (MatZeroRowsColumns, so
// the matrix stays symmetric positive definite and CG + GAMG (solver.petsc.near_null_space) apply):
// J = K + w p′ (branch slope) + w λ (I − t tᵀ)/ρ on sliding nodes, ρ = max(|x_τ|, (|y| − wλ)/c_t)
// (= |x_τ| at a solution; positive where x_τ is still 0). λ is held in J: the coupling through
// F_b(u_ν) converges linearly, as the outer fixed point does, without an outer loop. No smoothing
// and no continuation: the answer is judged by the same certificate. The nonlinearity lives on Γ3
// only, so the AMG hierarchy built for the first step serves later ones (solver.petsc.pc_rebuild).
Solution Engine::run_ssn(clk::time_point t0) {
  ssn_describe();
  Ssn s;
  ssn_setup(s);
  if (start) ssn_start(s);
  bool converged = false;
  const auto t_loop = clk::now();
  int k = 0;
  for (k = 1; k <= opt.ssn.max_iters; ++k) {
    const long changed = ssn_linearize(s, k);
    const double res = ssn_right_hand_side(s);
    // Converged at this iterate: the statuses it gives are those of the last step, and the residual
    // of the semismooth system (equilibrium on the free rows, the fixed unknowns' misfit times the
    // diagonal) is at most solver.ssn.tol of the load scale. No step is taken: at 10⁷ unknowns the steps
    // that only confirmed round-off cost 50 s each.
    if (k > 1 && changed == 0 && res / F_s <= opt.ssn.tol) {
      converged = true;
      log_info() << "ssn " << k << ": statuses held, residual " << short_number(res / F_s)
                 << " <= solver.ssn.tol: converged";
      --k;  // the steps taken
      break;
    }
    if (ssn_step(s, k, changed, res)) {
      converged = true;
      break;
    }
  }
  return ssn_finish(s, k, converged, t0, t_loop);
}

// What ssn does and does not do, for the report.
void Engine::ssn_describe() {
  sol.backend = ssn_name("CG", opt.petsc.pc, size);
  sol.formulation = "full";
  sol.fixed_point_converged = true;
  sol.skipped.push_back("continuation: ssn solves the unsmoothed problem (no eps stages)");
  if (opt.smallness)
    sol.skipped.push_back("smallness: (21) is evaluated by the cholmod engine only (it needs a factorization)");
  if (!md.normal_law) sol.skipped.push_back("normal_compliance: no soft layer (contact.normal_law.type = none)");
  if (!md.friction) sol.skipped.push_back("friction: frictionless (contact.friction.type = none)");
  if (md.friction && md.friction->depends_on_u_nu())
    sol.skipped.push_back("fixed_point: lambda = F_b(u_nu) is read at every Newton step (no outer loop)");
  if (md.gap.is_infinite()) sol.skipped.push_back("bounds: no rigid obstacle (g = inf)");
  sol.skipped.push_back("polish: ssn's steps are the polish's, with statuses updated");
}

void Engine::ssn_setup(Ssn& s) {
  for (PVec* v : {&s.x, &s.R, &s.dx, &s.rhs, &s.fixv, &s.diagK, &s.xt, &s.Rt}) HC_PETSC(VecDuplicate(f.v, &v->v));
  HC_PETSC(MatGetDiagonal(K.m, s.diagK.v));
  // No second matrix: each step's J is K itself, changed in place (Γ3 blocks added, fixed rows and
  // columns zeroed) and put back from the saved rows before K is read again. A copy of K would cost
  // ~0.5 KB per unknown (44 nonzeros per row in 3D), a quarter of the engine's memory target (2 KB
  // per unknown).
  s.band = save_band();
  HC_PETSC(MatSetOption(K.m, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  HC_PETSC(MatSetOption(K.m, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
  // rtol on the true residual: the inexact-Newton forcing terms and the hierarchy's quality
  // (iterations per decade) then mean what they say.
  create_cg(s.ksp, "ssn_", KSP_NORM_UNPRECONDITIONED);
  HC_PETSC(VecSet(s.x.v, 0.0));
  // A fixed unknown's row keeps a diagonal of K's own size (the mean K_ii), not 1 against
  // K_ii ~ E h: its eigenvalue then lies inside K's spectrum, where the Chebyshev smoothers' bounds
  // and CG's convergence do not see it as an outlier.
  PetscReal diag_sum;
  HC_PETSC(VecNorm(s.diagK.v, NORM_1, &diag_sum));
  s.diag_scale = n > 0 && diag_sum > 0 ? diag_sum / static_cast<double>(n) : 1.0;
  PetscReal fmax;
  HC_PETSC(VecNorm(f.v, NORM_INFINITY, &fmax));
  F_s = fmax > 0 ? fmax : 1.0;
  s.status.assign(my_nodes.size(), -1);
  s.prev_status.assign(my_nodes.size(), -2);
  s.slip_dir.assign(my_nodes.size(), Eigen::Vector2d::Zero());
  s.hold_stick.assign(my_nodes.size(), 0);
  s.coupling_col.assign(my_nodes.size(), Eigen::Vector3d::Zero());
}

// The caller's start (--start-follows: an adaptive level's u carried from the level before) into
// x, each owned unknown at its PETSc index; the first reading is then the iterate's, not "every
// node in contact" (a guess for a start from zero).
void Engine::ssn_start(Ssn& s) {
  if (start->size() != static_cast<Index>(perm.size()))
    throw Error("the petsc engine: a start of " + std::to_string(start->size()) + " unknowns for a piece of " +
                    std::to_string(perm.size()),
                EXIT_INTERNAL);
  for (size_t i = 0; i < perm.size(); ++i)
    if (perm[i] >= lo && perm[i] < hi) HC_PETSC(VecSetValue(s.x.v, perm[i], (*start)[static_cast<Index>(i)], INSERT_VALUES));
  HC_PETSC(VecAssemblyBegin(s.x.v));
  HC_PETSC(VecAssemblyEnd(s.x.v));
  s.cold = false;
  log_info() << "ssn: from the caller's start (--start-follows), not from zero";
}

// Step k's statuses and linearization at the iterate: R = K x − f plus the Γ3 forces, J = K plus
// the Γ3 blocks (in place in K), the fixed unknowns and their prescribed steps (fixv).
// @return the number of status changes over all ranks.
long Engine::ssn_linearize(Ssn& s, int k) {
  if (k > 1) restore_band(s.band);  // K again: the last step's J changed it
  ::Mat J = K.m;
  HC_PETSC(MatMult(K.m, s.x.v, s.R.v));
  HC_PETSC(VecAXPY(s.R.v, -1.0, f.v));
  HC_PETSC(VecSet(s.fixv.v, 0.0));
  s.fixed.clear();
  SsnArrays a;
  HC_PETSC(VecGetArrayRead(s.x.v, &a.x));
  HC_PETSC(VecGetArrayRead(s.diagK.v, &a.diag));
  HC_PETSC(VecGetArray(s.R.v, &a.r));
  HC_PETSC(VecGetArray(s.fixv.v, &a.fix));
  long changed = 0;
  s.signature = 0;
  PetscReal xmax;
  HC_PETSC(VecNorm(s.x.v, NORM_INFINITY, &xmax));
  const double slope_probe = SSN_SLOPE_PROBE * xmax;
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    double B[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    s.status[q] = ssn_node(s, q, k, a, B, slope_probe);
    if (s.status[q] != s.prev_status[q]) ++changed;
    const PetscInt iv = cdof(my_nodes[q]);
    PetscInt idx[3] = {iv, iv + 1, iv + 2};
    HC_PETSC(MatSetValues(J, d, idx, d, idx, B, ADD_VALUES));
  }
  HC_PETSC(VecRestoreArrayRead(s.x.v, &a.x));
  HC_PETSC(VecRestoreArrayRead(s.diagK.v, &a.diag));
  HC_PETSC(VecRestoreArray(s.R.v, &a.r));
  HC_PETSC(VecRestoreArray(s.fixv.v, &a.fix));
  long changed_all = 0;
  MPI_Allreduce(&changed, &changed_all, 1, MPI_LONG, MPI_SUM, comm);
  uint64_t signature_all = 0;  // unsigned: the sum wraps, the same on every partition
  MPI_Allreduce(&s.signature, &signature_all, 1, MPI_UINT64_T, MPI_SUM, comm);
  s.watch.see(signature_all, changed_all);
  ssn_couple(s, J);
  HC_PETSC(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  HC_PETSC(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  s.prev_status = s.status;
  s.unchanged = changed_all == 0 ? s.unchanged + 1 : 0;
  return changed_all;
}

// Once the statuses cycle (solver/ssn.hpp): the coupling columns into J (its τ rows, the ν
// column: unsymmetric), and the KSP switched to GMRES while any node is coupled (back to CG after).
void Engine::ssn_couple(Ssn& s, ::Mat J) {
  // The watch reads the signature summed over the ranks: every rank takes this return alike, and a
  // run that never cycles pays no reduction for it (cycling() stays true once on, so the KSP is CG).
  if (!s.watch.cycling()) return;
  long mine = 0;
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    if (s.coupling_col[q].squaredNorm() == 0) continue;
    const PetscInt iv = cdof(my_nodes[q]);
    const PetscInt rows[2] = {iv + 1, iv + 2};
    const double vals[2] = {s.coupling_col[q][1], s.coupling_col[q][2]};
    HC_PETSC(MatSetValues(J, d - 1, rows, 1, &iv, vals, ADD_VALUES));
    ++mine;
  }
  MPI_Allreduce(&mine, &s.coupled, 1, MPI_LONG, MPI_SUM, comm);
  const bool gmres = s.coupled > 0;
  if (gmres == s.gmres) return;
  // GMRES with the unpreconditioned norm needs the preconditioner on the right (CG's on the left).
  HC_PETSC(KSPSetType(s.ksp.k, gmres ? KSPGMRES : KSPCG));
  HC_PETSC(KSPSetPCSide(s.ksp.k, gmres ? PC_RIGHT : PC_LEFT));
  HC_PETSC(KSPSetNormType(s.ksp.k, KSP_NORM_UNPRECONDITIONED));
  s.gmres = gmres;
  s.used_gmres = s.used_gmres || gmres;
}

// ssn's merit at @p xt (solver/ssn.hpp): ‖K xt − f‖∞ off Γ3, each Γ3 node's ssn_node_merit on it.
// K must be as assembled (restore_band).
double Engine::ssn_merit(Ssn& s, ::Vec xt) {
  HC_PETSC(MatMult(K.m, xt, s.Rt.v));
  HC_PETSC(VecAXPY(s.Rt.v, -1.0, f.v));
  const PetscScalar *px, *pd;
  PetscScalar* pr;
  HC_PETSC(VecGetArrayRead(xt, &px));
  HC_PETSC(VecGetArrayRead(s.diagK.v, &pd));
  HC_PETSC(VecGetArray(s.Rt.v, &pr));
  for (const Index kk : my_nodes) {
    const PetscInt l = cdof(kk) - lo;
    Eigen::Vector3d x = Eigen::Vector3d::Zero(), r = Eigen::Vector3d::Zero(), diag = Eigen::Vector3d::Zero();
    for (int c = 0; c < d; ++c) x[c] = px[l + c], r[c] = pr[l + c], diag[c] = pd[l + c];
    const double m = ssn_node_merit(node_data(md, kk), x, r, diag, roller_components(md, kk), s.diag_scale);
    for (int c = 0; c < d; ++c) pr[l + c] = c == 0 ? m : 0.0;
  }
  HC_PETSC(VecRestoreArrayRead(xt, &px));
  HC_PETSC(VecRestoreArrayRead(s.diagK.v, &pd));
  HC_PETSC(VecRestoreArray(s.Rt.v, &pr));
  PetscReal m;
  HC_PETSC(VecNorm(s.Rt.v, NORM_INFINITY, &m));
  return m;
}

// The step's length (solver/ssn.hpp): 1 until the statuses cycle; then the backtracking rule on
// the merit of the iterate each trial leads to (the reversal rule applied, nothing held).
double Engine::ssn_step_length_at(Ssn& s) {
  if (!s.watch.cycling()) return 1.0;
  restore_band(s.band);  // K as assembled: the merit reads K x − f (the next step restores it anyway)
  const double now = ssn_merit(s, s.x.v);
  return ssn_step_length(now, [&](double t) {
    HC_PETSC(VecWAXPY(s.xt.v, t, s.dx.v, s.x.v));
    ssn_stop_reversals(s, s.xt.v, false);
    return ssn_merit(s, s.xt.v);
  });
}

// Owned Γ3 node q at step k: its statuses read from the iterate (check/status_equations.hpp's
// ssn_reading, the CHOLMOD engine's ssn's too), its forces added to the residual, its block of J
// into @p B (row-major d×d), its fixed unknowns and their prescribed steps recorded.
// @return its status code (SsnReading::code).
int Engine::ssn_node(Ssn& s, size_t q, int k, const SsnArrays& a, double* B, double slope_probe) {
  const Index kk = my_nodes[q];
  const PetscInt iv = cdof(kk), l = iv - lo;
  Eigen::Vector3d x = Eigen::Vector3d::Zero(), r = Eigen::Vector3d::Zero(), diag = Eigen::Vector3d::Zero();
  for (int c = 0; c < d; ++c) x[c] = a.x[l + c], r[c] = a.r[l + c], diag[c] = a.diag[l + c];
  const NodeData nd = node_data(md, kk);
  const SsnReading rd = ssn_reading(nd, x, r, diag, s.cold && k == 1, s.hold_stick[q] != 0, roller_components(md, kk));
  s.slip_dir[q] = rd.slip_dir;
  s.signature += ssn_node_signature(kk, rd.code);
  s.coupling_col[q] = ssn_coupling(nd, x, rd, slope_probe);
  for (int c = 0; c < d; ++c) {
    if (rd.rows.is_pinned(c)) {
      s.fixed.push_back(iv + c);
      a.fix[l + c] = rd.rows.pin[c] - x[c];
    } else {
      a.r[l + c] += rd.rows.force[c];
    }
    for (int j = 0; j < d; ++j) B[c * d + j] = rd.rows.block(c, j);
  }
  return rd.code;
}

// rhs = −R on free rows; the fixed rows carry their prescribed step (fixv), and the columns
// MatZeroRowsColumns removes move their contribution to the right-hand side.
// @return the semismooth residual ‖rhs‖∞ (unscaled).
double Engine::ssn_right_hand_side(Ssn& s) {
  HC_PETSC(VecCopy(s.R.v, s.rhs.v));
  HC_PETSC(VecScale(s.rhs.v, -1.0));
  HC_PETSC(MatZeroRowsColumns(K.m, static_cast<PetscInt>(s.fixed.size()), s.fixed.data(), s.diag_scale, s.fixv.v,
                              s.rhs.v));
  PetscReal res;
  HC_PETSC(VecNorm(s.rhs.v, NORM_INFINITY, &res));
  return res;
}

// Step k: the CG solve of J dx = rhs, the update, the slip reversals, the log and the record.
// @return true when ssn has converged (the step reached round-off with the statuses held).
bool Engine::ssn_step(Ssn& s, int k, long changed_all, double res) {
  // Inexact Newton: a step that may still change statuses needs only solver.ssn.step_rtol; once
  // they hold, step_rtol² per step (the λ coupling contracts by about that much anyway), never
  // below ksp_rtol.
  const double rtol = std::max(opt.petsc.ksp_rtol, changed_all > 0 ? opt.ssn.step_rtol
                                                                   : opt.ssn.step_rtol * opt.ssn.step_rtol);
  PC pc;
  HC_PETSC(KSPGetPC(s.ksp.k, &pc));
  HC_PETSC(KSPSetOperators(s.ksp.k, K.m, K.m));
  HC_PETSC(PCSetReusePreconditioner(pc, s.rebuild ? PETSC_FALSE : PETSC_TRUE));
  HC_PETSC(KSPSetTolerances(s.ksp.k, rtol, PETSC_DEFAULT, PETSC_DEFAULT, opt.petsc.ksp_max_it));
  const auto t_ksp = clk::now();
  HC_PETSC(VecSet(s.dx.v, 0.0));
  HC_PETSC(KSPSolve(s.ksp.k, s.rhs.v, s.dx.v));
  PetscInt its;
  HC_PETSC(KSPGetIterationNumber(s.ksp.k, &its));
  krylov_total += its;
  ++newton_total;
  const bool built = ssn_judge_hierarchy(s, its);
  ksp_check(s.ksp.k, "ssn Newton step " + std::to_string(k));  // exit 3 naming PETSc's reason
  const double theta = ssn_step_length_at(s);
  if (theta != 1.0) HC_PETSC(VecScale(s.dx.v, theta));
  HC_PETSC(VecAXPY(s.x.v, 1.0, s.dx.v));
  const long projected = ssn_stop_reversals(s, s.x.v, true);
  PetscReal step, scale;
  HC_PETSC(VecNorm(s.dx.v, NORM_INFINITY, &step));
  HC_PETSC(VecNorm(s.x.v, NORM_INFINITY, &scale));
  const double rel = scale > 0 ? step / scale : 0.0;
  const char* krylov = s.gmres ? "GMRES" : "CG";
  s.steps.push_back({{"step", k}, {"status_changes", changed_all}, {"slip_reversals", projected}, {"krylov", its},
                     {"krylov_method", krylov}, {"coupled_nodes", s.coupled}, {"theta", theta}, {"rtol", rtol},
                     {"pc_built", built}, {"residual", res / F_s}, {"dx_rel", rel}, {"seconds", since(t_ksp)}});
  log_info() << "ssn " << k << ": " << changed_all << " status changes, residual " << short_number(res / F_s)
             << ", " << krylov << " " << its << " it (rtol " << short_number(rtol) << (built ? ", AMG built" : "")
             << ")" << (s.coupled > 0 ? ", " + std::to_string(s.coupled) + " nodes coupled" : "")
             << (theta != 1.0 ? ", step " + short_number(theta) : "") << ", |dx|/|x| " << short_number(rel)
             << (projected > 0 ? ", " + std::to_string(projected) + " slip reversals set to 0" : "") << ", memory "
             << short_number(double(current_rss_kb()) / 1024.0) << " MB (rank 0)";
  // Done when the statuses have held for two steps and the step reached round-off or stopped
  // decreasing there (the λ coupling contracts linearly; round-off ends it).
  if (ssn_step_settled(s.unchanged, rel, step, s.prev_step)) return true;
  s.prev_step = s.unchanged >= 1 ? step : INF;
  return false;
}

// The hierarchy's quality: CG iterations per decade of residual reduction. Rebuilt when a step
// with the reused hierarchy needs pc_rebuild times the reference (built_per_decade).
// @return whether this step built the hierarchy.
bool Engine::ssn_judge_hierarchy(Ssn& s, PetscInt its) {
  PetscReal rnorm;
  HC_PETSC(KSPGetResidualNorm(s.ksp.k, &rnorm));
  PetscReal bnorm;
  HC_PETSC(VecNorm(s.rhs.v, NORM_2, &bnorm));
  const double decades = (rnorm > 0 && bnorm > 0) ? std::max(0.5, std::log10(bnorm / rnorm)) : 1.0;
  const double per_decade = static_cast<double>(its) / decades;
  const bool built = s.rebuild;
  if (s.rebuild) {
    s.built_per_decade = per_decade, s.rebuild = false, s.reference_pending = true;
  } else if (s.reference_pending) {
    s.built_per_decade = std::max(s.built_per_decade, per_decade), s.reference_pending = false;
  } else if (per_decade > opt.petsc.pc_rebuild * std::max(s.built_per_decade, 1.0)) {
    s.rebuild = true;
  }
  return built;
}

// A sliding node whose step carried x_τ through 0 (x_τ · t < 0: the friction force it was
// given is more than equilibrium needs, so it should stick) is put at x_τ = 0 and held at stick
// for the next step; the step after that reads stick or slip from the relaxed neighbours.
// Without this, nodes at the stick limit chattered (slip, reversal, slip...) and the iteration
// stalled at a residual ~1e-4 (3D scene, n = 48 and 70). On @p xt: the iterate (@p hold: the
// nodes are held) or a trial point of the line search (nothing held). @return the count over all ranks.
long Engine::ssn_stop_reversals(Ssn& s, ::Vec xt, bool hold) {
  long projected = 0;
  PetscScalar* px;
  HC_PETSC(VecGetArray(xt, &px));
  for (size_t q = 0; q < my_nodes.size(); ++q) {
    const PetscInt l = cdof(my_nodes[q]) - lo;
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int c = 0; c < d; ++c) x[c] = px[l + c];
    const bool reversed = ssn_reversed(s.slip_dir[q], d, x);
    if (hold) s.hold_stick[q] = reversed;  // one step only
    if (reversed) {
      for (int c = 1; c < d; ++c) px[l + c] = 0;
      ++projected;
    }
  }
  HC_PETSC(VecRestoreArray(xt, &px));
  long all = 0;
  MPI_Allreduce(&projected, &all, 1, MPI_LONG, MPI_SUM, comm);
  return all;
}

// K put back, the record of the run, and the certified answer.
Solution Engine::ssn_finish(Ssn& s, int k, bool converged, clk::time_point t0, clk::time_point t_loop) {
  restore_band(s.band);  // K as assembled, for the certificate (K x − f) and the energies
  if (s.used_gmres) sol.backend = ssn_name("CG and GMRES", opt.petsc.pc, size);
  timings["backend"] = since(t_loop);
  U_s = 1;
  sol.x_scale = 1;
  sol.f_scale = F_s;
  OuterIteration rec;
  rec.backend.iterations = static_cast<int>(std::min(k, opt.ssn.max_iters));
  rec.backend.seconds = timings["backend"];
  rec.backend.message = converged ? "ssn converged in " + std::to_string(k) + " Newton steps, " +
                                        std::to_string(krylov_total) + " CG iterations"
                                  : "ssn: no convergence in " + std::to_string(opt.ssn.max_iters) +
                                        " Newton steps (solver.ssn.max_iters; the statuses still changed or "
                                        "the step did not reach round-off)";
  rec.backend.status = converged ? SolveStatus::CONVERGED : SolveStatus::MAX_ITERATIONS;
  sol.history.push_back(rec);
  sol.backend_ok = converged;
  if (!converged) sol.message = rec.backend.message;
  stages = s.steps;
  finish_slabs(sol, s.x.v, t0);  // nothing global is gathered
  timings.erase("backend");
  return std::move(sol);
}

}  // namespace hemicontact::petsc_engine::detail
