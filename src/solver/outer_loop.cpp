// The outer algorithm of both engines (outer_loop.hpp): continuation in ε, the fixed point on λ,
// the early certified stop, the hand-over to the exact solver, the final polish.
#include <hemicontact/solver/outer_loop.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/solver/run_messages.hpp>

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <utility>

namespace hemicontact {

double contraction_estimate(const std::vector<OuterIteration>& history) {
  double sum = 0;
  int n = 0;
  for (const auto& h : history)
    if (std::isfinite(h.contraction)) sum += std::log(h.contraction), ++n;
  return n ? std::exp(sum / n) : std::numeric_limits<double>::quiet_NaN();
}

std::string outer_line(const OuterIteration& rec, int stage, const std::string& backend) {
  std::ostringstream os;
  os << "outer " << rec.k << " (stage " << stage << ", eps_tau " << std::setprecision(2) << rec.eps_tau << ", eps_nu "
     << rec.eps_nu << "): " << backend << " " << to_string(rec.backend.status) << " in " << rec.backend.iterations
     << " it, " << std::setprecision(3) << rec.backend.seconds << " s; |dx_G3|/|x_G3| = " << std::setprecision(2)
     << rec.change_u << ", |dlambda|/|lambda| = " << rec.change_lambda << ", first-order residual " << rec.grad_norm;
  if (std::isfinite(rec.contraction)) os << ", contraction rho = " << rec.contraction;
  return os.str();
}

namespace {

// "0.83 (last 0.91)" or "not measured": the geometric mean of the defined ρ_k and the last one.
std::string contraction_text(const std::vector<OuterIteration>& history) {
  const double est = contraction_estimate(history);
  if (!std::isfinite(est)) return "not measured";
  double last = est;
  for (const auto& h : history)
    if (std::isfinite(h.contraction)) last = h.contraction;
  return fmt(est, 3) + " (last " + fmt(last, 3) + ")";
}

std::string theta_text(const SolveOptions& opt) { return "relaxation theta = " + fmt(opt.relaxation, 3); }

std::string fixed_point_cap(const SolveOptions& opt, double change, const std::vector<OuterIteration>& history) {
  return "fixed point lambda = F_b(u_nu) did not converge in " + std::to_string(opt.max_outer) +
         " outer iterations (last change " + fmt(change, 3) + ", contraction factor " + contraction_text(history) +
         ", " + theta_text(opt) +
         "); raise solver.fixed_point.max_iters, or if the factor is near or above 1 try a "
         "smaller solver.fixed_point.relaxation";
}

std::string fixed_point_stall(const SolveOptions& opt, double change, const std::vector<OuterIteration>& history) {
  return "fixed point lambda = F_b(u_nu) does not contract: the change (" + fmt(change, 3) + ") has not decreased for " +
         std::to_string(opt.stall_iters) + " outer iterations (contraction factor " + contraction_text(history) +
         ", " + theta_text(opt) + "); try a smaller solver.fixed_point.relaxation, e.g. " +
         fmt(0.5 * opt.relaxation, 3);
}

// The certified copy after @p stage, with the note that the stages after it did not run.
Solution early_stop(Solution sol, std::size_t stage, std::size_t stages, bool last) {
  if (!last) {
    sol.skipped.push_back("continuation: stages " + std::to_string(stage + 1) + ".." + std::to_string(stages - 1) +
                          " not run: the polished answer after stage " + std::to_string(stage) +
                          " was certified (solver.continuation.certify_below)");
    log_info() << "continuation: certified after stage " << stage << "; the remaining " << stages - 1 - stage
               << " stage(s) are not needed";
  }
  return sol;
}

}  // namespace

Solution OuterStepper::exact_finish(std::size_t, const std::string& why) {
  throw Error("the exact solver was asked to take over (" + why + ") in an engine that has none", EXIT_INTERNAL);
}

void record_lambda_change(OuterIteration& rec, const LambdaChange& c, const SolveOptions& opt, bool measure,
                          double& prev_delta) {
  rec.change_lambda = c.scale > 0 ? c.delta / c.scale : 0.0;
  rec.delta_lambda = c.delta;
  const double noise = opt.contraction_floor * c.scale;
  if (measure && prev_delta > noise && c.delta > noise) rec.contraction = c.delta / prev_delta;
  prev_delta = c.delta;
}

bool run_stage(OuterStepper& s, const SolveOptions& opt, std::size_t stage) {
  s.set_smoothing(stage);
  Solution& sol = s.solution();
  const bool final_stage = stage + 1 == s.stage_count();
  const bool lagged = s.lagged();
  double prev_change = INF;
  int slow = 0;
  double prev_delta = INF;  // ‖Δλ‖∞ of the previous update in this stage
  for (int it = 0;; ++it) {
    s.check_interrupt();
    OuterIteration rec = s.minimize(stage);
    if (lagged) record_lambda_change(rec, s.relax_lambda(), opt, final_stage && it > 0, prev_delta);
    sol.history.push_back(rec);
    log_info() << outer_line(rec, static_cast<int>(stage), s.backend_name());
    if (!rec.backend.ok()) {
      sol.backend_ok = false;
      sol.message = backend_failure(s.backend_name(), rec);
      return false;
    }
    if (!lagged || !final_stage) return true;  // coarse stages: one lagged update each
    const double change = std::max(rec.change_u, rec.change_lambda);
    if (it > 0 && change <= opt.tol_u) return true;
    if (it + 1 >= opt.max_outer) {
      sol.fixed_point_converged = false;
      sol.message = fixed_point_cap(opt, change, sol.history);
      return true;
    }
    // Non-contraction: the change has not shrunk by 1 − stall_ratio for stall_iters iterations in
    // a row (an oscillating or diverging λ; large μ·slope of p_ν, docs/model.md §1 (21)).
    slow = (change > opt.stall_ratio * prev_change) ? slow + 1 : 0;
    prev_change = change;
    if (slow >= opt.stall_iters) {
      sol.fixed_point_converged = false;
      sol.message = fixed_point_stall(opt, change, sol.history);
      return true;
    }
  }
}

bool settled(OuterStepper& s, const SolveOptions& opt) {
  const Solution& sol = s.solution();
  if (!(opt.certify_below > 0) || !s.polish_exists() || !opt.polish || !sol.fixed_point_converged ||
      !sol.backend_ok || sol.history.empty())
    return false;
  const OuterIteration& last = sol.history.back();
  return last.change_u <= opt.certify_below && (!s.lagged() || last.change_lambda <= opt.certify_below);
}

Solution run_outer(OuterStepper& s, const SolveOptions& opt) {
  const std::size_t n = s.stage_count();
  for (std::size_t stage = 0; stage < n; ++stage) {
    const bool ok = run_stage(s, opt, stage);  // false: the backend failed
    const bool last = stage + 1 == n;
    // Once a stage barely moved the answer, its statuses are likely final: the exact polish on a
    // copy, and if the certificate (the unsmoothed problem, docs/model.md §4) passes, the remaining
    // stages, which only shrink ε towards an answer already in hand, are skipped.
    bool tried = false;
    if (ok && !last && settled(s, opt)) {
      tried = true;
      if (auto sol = s.certified_copy()) return early_stop(std::move(*sol), stage, n, false);
    }
    // Once the statuses stop changing, or the backend stalls or fails, the exact solver takes over
    // (the polish first, when it has not been tried: it is cheaper and often enough).
    if (s.exact_available()) {
      const std::string why = s.exact_due(stage, !ok);
      if (!why.empty()) {
        if (ok && !tried && s.solution().fixed_point_converged)
          if (auto sol = s.certified_copy()) return early_stop(std::move(*sol), stage, n, last);
        return s.exact_finish(stage, why);
      }
    }
    if (!ok) break;  // polish and judge what we have
  }
  s.solution().contraction_estimate = contraction_estimate(s.solution().history);
  return s.finish();
}

}  // namespace hemicontact
