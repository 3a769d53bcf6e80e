#include "engine_impl.hpp"

#include <hemicontact/core/log.hpp>
#include <hemicontact/solver/run_messages.hpp>

#include <string>
#include <utility>

namespace hemicontact::petsc_engine {
namespace detail {

Solution Engine::run() {
  const auto t0 = clk::now();
#if defined(PETSC_HAVE_HYPRE)
  // GAMG's Galerkin products P^T A P on more than one rank: PETSc's own MPIAIJ algorithms keep
  // A P's local rows (and P^T's) for reuse, 1.2-1.9 KB per unknown at the fine level; hypre's
  // product keeps none (3D scene, 2 ranks, 48^3: 3.7 -> 2.3 KB per unknown with the rigid modes,
  // 2.4 -> 1.8 with the translations, the same CG iterations). On one rank PETSc's sequential
  // product is already lean (and hypre's made the hierarchy indefinite there). -matptap_via set
  // by the user (solver.petsc.options, PETSC_OPTIONS) wins.
  if (size > 1) option_default("-matptap_via", "hypre");
#endif
  distribute_slabs();
  assemble();
  near_null_space();
  if (tao_type(opt.backend) == "ssn") return run_ssn(t0);
  if (start) input_error("a start (--start-follows) is read by ssn only, not by " + opt.backend);
  elastic_solve();
  sol.backend = "tao:" + tao_type(opt.backend) + " (PETSc, " + std::to_string(size) + " rank" +
                (size > 1 ? "s" : "") + ")";
  sol.formulation = "full";
  sol.x_scale = U_s;
  sol.f_scale = F_s * U_s;
  sol.fixed_point_converged = true;
  if (opt.smallness)
    sol.skipped.push_back("smallness: (21) is evaluated by the cholmod engine only (it needs a factorization)");
  if (!md.normal_law) sol.skipped.push_back("normal_compliance: no soft layer (contact.normal_law.type = none)");
  if (!md.friction) sol.skipped.push_back("friction: frictionless (contact.friction.type = none)");
  if (md.friction && !md.friction->depends_on_u_nu()) sol.skipped.push_back("fixed_point: F_b does not depend on u_nu");
  if (md.gap.is_infinite()) sol.skipped.push_back("bounds: no rigid obstacle (g = inf)");

  // Nothing nonlinear and no obstacle: the elastic solve is the answer.
  if (!md.normal_law && !md.friction && md.gap.is_infinite() && md.contact.fixed_local.empty()) {
    sol.backend = "none (PETSc CG linear solve)";
    sol.skipped.push_back("backend: linear elasticity, solved by one CG solve");
    finish_slabs(sol, zfree.v, t0);
    return std::move(sol);
  }
  // The continuation schedule of solver/solve.cpp (problem/solve_options.hpp).
  if (md.normal_law || md.friction) {
    schedule = smoothing_schedule(opt);
  } else {
    schedule.emplace_back(opt.eps_tau, opt.eps_nu);  // only the bounds: no width is used
    sol.skipped.push_back("continuation: nothing is smoothed");
  }
  // Start from zero (inside the bounds: g ≥ 0), λ frozen there.
  HC_PETSC(VecSet(zs.v, 0.0));
  if (md.friction)
    for (size_t q = 0; q < my_nodes.size(); ++q) lambda[q] = md.friction->F(0.0);
  prev_c = local_gamma3(zs.v);
  t_run = t0;
  return run_outer(*this, opt);
}

// The polish of a copy of the current iterate, and its certificate (run_outer's early stop). The
// copy is finished on the pieces (finish_slabs); a trial that fails leaves the run's piece to be
// written again by the final finish.
std::optional<Solution> Engine::certified_copy() {
  PVec x;
  unscaled_iterate(x);
  const PolishResult pr = polish_with_readings(x.v, sol.history.empty() ? 0 : static_cast<size_t>(sol.history.back().stage));
  if (!pr.accepted) return std::nullopt;
  Solution trial = sol;
  trial.polish = pr;
  finish_slabs(trial, x.v, t_run);
  if (!trial.certificate.passed) return std::nullopt;
  return trial;
}

// The final polish (solver.polish, after a converged fixed point, on the owned rows), then the
// certificate by reductions over the pieces (nothing global is gathered).
Solution Engine::finish() {
  PVec x;
  unscaled_iterate(x);
  if (opt.polish && sol.fixed_point_converged) {
    sol.polish = polish_with_readings(x.v, schedule.size() - 1);
    log_info() << "polish: " << (sol.polish.accepted ? "accepted" : "rejected") << ", certificate "
               << sol.polish.before << " -> " << sol.polish.after << " in " << sol.polish.iterations
               << " Newton iterations" << (sol.polish.note.empty() ? "" : " (" + sol.polish.note + ")");
  } else if (!opt.polish) {
    sol.skipped.push_back("polish: solver.polish = false");
  }
  finish_slabs(sol, x.v, t_run);
  return std::move(sol);
}

// The report's record of the engine.
void Engine::record() {
  const long rss = peak_rss_kb();
  long rss_sum = 0, rss_max = 0;
  MPI_Allreduce(&rss, &rss_sum, 1, MPI_LONG, MPI_SUM, comm);
  MPI_Allreduce(&rss, &rss_max, 1, MPI_LONG, MPI_MAX, comm);
  MatInfo info;
  HC_PETSC(MatGetInfo(K.m, MAT_GLOBAL_SUM, &info));
  rep.json["nonzeros_per_row"] = n > 0 ? info.nz_used / double(n) : 0.0;
  rep.json["ranks"] = size;
  rep.json["block_size"] = bs;
  rep.json["unknowns"] = n;
  rep.json["method"] = tao_type(opt.backend) == "ssn" ? std::string("ssn") : "tao:" + tao_type(opt.backend);
  rep.json["newton_pc"] = opt.petsc.newton_pc;
  rep.json["pc"] = opt.petsc.pc;
  rep.json["start"] = start ? "the caller's u (--start-follows)" : "zero";
  rep.json["newton_iterations"] = newton_total;
  rep.json["krylov_iterations"] = krylov_total;
  rep.json["krylov_per_newton"] = newton_total > 0 ? double(krylov_total) / double(newton_total) : 0.0;
  rep.json["polish_newton_iterations"] = polish_newton;
  rep.json["polish_krylov_iterations"] = polish_krylov;
  rep.json["minimizations"] = stages;
  rep.json["peak_rss_mb_sum"] = double(rss_sum) / 1024.0;
  rep.json["peak_rss_mb_max"] = double(rss_max) / 1024.0;
  rep.json["bytes_per_dof"] = n > 0 ? double(rss_sum) * 1024.0 / double(n) : 0.0;
}

// What finish_slabs records once the certificate is in: its time (since @p t1), the backend's minimizations, the whole solve (since @p t0), the verdict and the
// report's engine record.
void Engine::close_record(Solution& s, clk::time_point t0, clk::time_point t1) {
  timings["certificate"] = since(t1);
  double nlp = 0;
  for (const auto& h : s.history) nlp += h.backend.seconds;
  timings["backend"] = nlp;
  timings["solve_total"] = since(t0);
  for (const auto& [key, v] : timings) s.timings[key] = v;
  state_verdict(s);
  record();
}

}  // namespace detail

Solution solve_slabs(const Model& md, const Piece& slab, const SolveOptions& opt, MPI_Comm comm, EngineReport& report,
                     SlabResult& out, const Vec* x0) {
  detail::Engine e(md, slab, opt, comm, report, out, x0);
  return e.run();
}

}  // namespace hemicontact::petsc_engine
