#pragma once
/// @file outer_loop.hpp  The outer algorithm, written once for both engines: the continuation in ε
/// (smoothing widths large → small, warm-started), the fixed point λ = F_b(u_ν) with relaxation θ
/// at the final width (docs/model.md §2), the early stop once a stage barely moved the answer and
/// its polished copy is certified, the hand-over to the exact solver, the final polish.
///
/// An engine supplies the steps (OuterStepper): the CHOLMOD engine (solver/solve.cpp) minimizes with
/// an NLP backend on the condensed or full problem; the PETSc engine (src/petsc) with TAO on
/// distributed vectors. What is decided between the steps — when a stage ends, when the fixed point
/// has converged, stalled or hit its cap, when to try the polish, and the words of each verdict —
/// is decided here only.

#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace hemicontact {

/// What one λ update moved, reduced over the engine's processes: max_i |λ_new − λ_old| and
/// max_i max(|λ_new|, |λ_old|). The outer loop turns them into the relative change and ρ_k.
struct LambdaChange {
  double delta = 0, scale = 0;
};

/// The steps one engine performs; run_outer() calls them.
class OuterStepper {
 public:
  virtual ~OuterStepper() = default;
  /// The answer being built (history, verdicts, skipped lines).
  virtual Solution& solution() = 0;
  /// The number of continuation stages (solver.continuation; 1 where nothing is smoothed).
  virtual std::size_t stage_count() const = 0;
  /// λ = F_b(u_ν) depends on the answer: the outer fixed point runs.
  virtual bool lagged() const = 0;
  /// The backend's name as reports give it (progress lines, failure messages).
  virtual std::string backend_name() const = 0;
  /// Sets the smoothing widths (ε_τ, ε_ν) of @p stage.
  virtual void set_smoothing(std::size_t stage) = 0;
  /// z ← argmin Π_λ,ε from the current iterate (warm start), λ and ε frozen; the record carries the
  /// backend's result, the relative change of the Γ3 unknowns and the first-order residual.
  virtual OuterIteration minimize(std::size_t stage) = 0;
  /// λ ← (1−θ)λ + θ F_b(u_ν) (θ = solver.fixed_point.relaxation). @return what it moved.
  virtual LambdaChange relax_lambda() = 0;
  /// The exact polish exists (the CHOLMOD engine's condensed formulation; the PETSc engine's).
  virtual bool polish_exists() const = 0;
  /// A copy of the current answer, polished and certified; nothing when the polish was rejected
  /// or the certificate failed.
  virtual std::optional<Solution> certified_copy() = 0;
  /// The final polish (where solver.polish allows it) and the certificate of the current iterate.
  virtual Solution finish() = 0;
  /// Throws when the user interrupted the run (where an engine can act on it alone).
  virtual void check_interrupt() {}
  /// The exact solver behind the backend (solver.exact.enabled, the condensed formulation).
  virtual bool exact_available() const { return false; }
  /// Why the exact solver should take over after @p stage, or "" (not yet).
  virtual std::string exact_due(std::size_t /*stage*/, bool /*backend_failed*/) { return ""; }
  /// The exact solver from the current iterate, polished and certified.
  virtual Solution exact_finish(std::size_t stage, const std::string& why);
};

/// Runs the continuation over @p s: every stage (run_stage), after each the early certified stop
/// (settled) and the hand-over (exact_due), at the end the final polish and certificate.
Solution run_outer(OuterStepper& s, const SolveOptions& opt);

/// One continuation stage: minimize with λ frozen, relax λ. A coarse stage takes one lagged update;
/// the final stage iterates to the fixed point, to its cap (solver.fixed_point.max_iters) or to the
/// non-contraction test (solver.fixed_point.stall_*), each with its message.
/// @return false when the backend failed (the run stops; the certificate still judges the iterate).
bool run_stage(OuterStepper& s, const SolveOptions& opt, std::size_t stage);

/// Worth an early polish: the last minimization moved Γ3 (and λ) by at most
/// solver.continuation.certify_below, the fixed point has not failed, and the polish exists.
bool settled(OuterStepper& s, const SolveOptions& opt);

/// The record of a λ update @p c: rec.change_lambda = delta/scale, rec.delta_lambda = delta, and,
/// when @p measure (the final stage, after its first update), ρ_k = delta/prev_delta where both
/// updates lie above the inner solves' round-off (solver.fixed_point.contraction_floor × scale):
/// ρ of λ rather than u, because λ is the variable the map λ ↦ F_b(u_ν(λ)) iterates.
void record_lambda_change(OuterIteration& rec, const LambdaChange& c, const SolveOptions& opt, bool measure,
                          double& prev_delta);

/// The geometric mean of the measured contraction factors ρ_k (NaN where none was measured).
double contraction_estimate(const std::vector<OuterIteration>& history);

/// The progress line (stderr) of one minimization.
std::string outer_line(const OuterIteration& rec, int stage, const std::string& backend);

}  // namespace hemicontact
