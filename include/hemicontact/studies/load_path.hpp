#pragma once
/// @file load_path.hpp  A quasi-static load history (`hemicontact path`): the loads are scaled by a
/// factor t that runs through given corners (0 → 2 → 0, ...) in steps, and the state is carried
/// from step to step, so that the body stays on the branch it is on until that branch ends.
///
/// Each step solves (22) at the new factor t from the last certified state, with the exact solver
/// started at once from it (solver.exact.start = always) in its local form
/// (ExactInnerOptions::local_descent: coordinate steps to the nearest local minimizer downhill, Newton
/// steps that stop at the end of a piece of p_ν). Every move of that solver lowers Φ_λ and none
/// crosses a barrier, so the answer is the minimum whose basin holds the previous state: the branch
/// is followed, not re-chosen. Every state is certified (docs/model.md §4) and classified by the
/// second-order check of `minima` (studies/minima.hpp, second_order_check).
///
/// Events and bisection. A step [t0, t1] has an event when the new state's branch signature (per Γ3
/// node: normal status, tangential status and the piece of p_ν its u_ν is on) differs from the old
/// one, or its energy is off the prediction
///     E(t1) ≈ E(t0) − ½ (t1 − t0) (f·u(t0) + f·u(t1))
/// (dE/dt = −f·u along a branch of minima; exact on a fixed signature of a frictionless or Tresca
/// scene, where u is affine in t and E quadratic) by more than PathOptions::energy_tol, or it is not
/// certified. Such a step is bisected, each midpoint solved from the last state before the event,
/// until the event lies in an interval [t_lo, t_hi] of width ≤ PathOptions::bisection_tol. The state
/// at t_hi is solved once more from the one at t_lo; the event is a jump (snap-through) when
///     ‖u(t_hi) − u(t_lo)‖_E > jump_factor · (t_hi − t_lo) · L,
/// L the largest rate ‖Δu‖_E/Δt seen on the steps before (a branch is Lipschitz in t; a jump does
/// not shrink with the interval). A jump is recorded (both states, the load, the energies, the nodes
/// whose signature changed); a status change without a jump (a node reaching the layer's kink, the
/// foundation, or starting to slip) is a continuous event and only moves the step on. The history
/// then continues from t_hi to t1.
///
/// Why load control with bisection suffices here (docs/solver.md): on a fixed signature the
/// conditions of (22) are linear in (u, t) (p_ν is affine on each piece; for the Coulomb-type bound,
/// λ = μ p_ν(u_ν) on that piece), so a branch of minima is a straight segment in t that ends where a
/// node reaches the end of its piece; past the end of a softening piece steeper than the body, no
/// minimum continues it: a fold of a piecewise-linear problem is a corner, not a smooth turning
/// point. The unstable branch beyond it (a saddle) is not a state the body can be in under load
/// control, and arc-length continuation would only trace it; load control finds the fold as the end
/// of the segment, to the bisection tolerance, and the local solver finds where the body lands.

#include <hemicontact/problem/minima_report.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <functional>
#include <string>
#include <vector>

namespace hemicontact {

struct PathState;

/// The most steps per segment `path --steps` takes: each is at least one solve, and 10 000 per
/// segment is already hours on a mid-size scene.
inline constexpr long PATH_MAX_STEPS = 10000;

/// What follow_load_path() does; defaults are the ones `hemicontact path` documents.
struct PathOptions {
  /// The corners of the history as load factors (× the scene's loads); the path runs from the first
  /// to the second, to the third, ... At least two; neighbours must differ.
  std::vector<double> loads = {0, 1};
  int steps = 20;  ///< steps per segment between two corners (≥ 1)
  /// Bisect a step with an event until the event lies in an interval of load factors this wide.
  /// 1e-6: the jumps are located to 1e-6 of the load at ~20 solves per event (log2(Δt/tol)).
  double bisection_tol = 1e-6;
  /// A step's energy off the prediction E(t0) − ½Δt(f·u0 + f·u1) by more than this × max(|E0|,
  /// |E1|, E_u) is an event (E_u = ½ a(u1, u1) + ½ a(u0, u0), the elastic scale): 1e-6, far above
  /// the round-off of the exact solver's answers (1e-13) and far below a snap (a few per cent).
  double energy_tol = 1e-6;
  /// A bisected event is a jump when the displacement changed over its last interval by more than
  /// this × the interval × the largest rate seen before (the file comment). Any value between
  /// ~10 (the rate is an estimate) and (step / bisection_tol) / 10 separates the two; 1e3.
  double jump_factor = 1e3;
  /// At a load factor of exactly 0 the certificate's scales are the state's own forces (no load),
  /// which a state reached from a loaded one has only at round-off; there the certified answer from
  /// u = 0 stands in for the branch's when the two differ by at most this × the largest ‖u‖_E of
  /// the path so far in the energy norm (1e-12: round-off of the exact solver's answers).
  double zero_load_agreement = 1e-12;
  /// Events in one step at most (each costs a bisection): beyond it the path stops with a message.
  int max_events_per_step = 50;
  /// The second-order check's settings (second_order_tol, max_dense) at every state.
  MinimaOptions second_order;
  /// Called after each recorded state with the states so far (progress on stderr, files as they come).
  std::function<void(const PathState& last, int recorded)> on_state;
};

/// One recorded state of the history.
struct PathState {
  int segment = 0;      ///< index of the segment (corners k → k + 1)
  double load = 0;      ///< the load factor t
  std::string kind;     ///< "start", "step", "before jump", "after jump"
  Solution solution;    ///< the certified (or not) answer at t
  SecondOrderCheck second_order;  ///< local minimum or saddle
  double reaction = 0;  ///< the total normal reaction of Γ3, −Σ_k w_k σ_ν,k (a force; > 0 pushing)
  double mean_u_nu = 0;  ///< Σ_k w_k u_ν,k / Σ_k w_k (the mean over Γ3 by the nodal weights)
  double max_u_nu = 0;   ///< max_k u_ν,k
};

/// One snap-through: the branch of the state before ended between load_before and load_after.
struct PathJump {
  int before = -1, after = -1;  ///< indices of the two states in PathReport::states
  double load_before = 0, load_after = 0;      ///< |load_after − load_before| ≤ bisection_tol
  double energy_before = 0, energy_after = 0;  ///< Π of the two states
  double distance = 0;                         ///< ‖u_after − u_before‖_E
  std::vector<Index> switched;                 ///< Γ3 nodes whose signature changed (ContactNodes order)
  int direction = 0;                           ///< +1 while loading (t increasing), −1 while unloading
};

/// What follow_load_path() found.
struct PathReport {
  std::vector<PathState> states;  ///< every recorded state, in the order of the history
  std::vector<PathJump> jumps;    ///< every jump, in order
  PathOptions options;            ///< what was asked
  int solves = 0;                 ///< solves run (steps, bisections, the re-solves at t_hi)
  int continuous_events = 0;      ///< events bisected that were not jumps
  bool complete = false;          ///< the whole history ran, every state certified
  std::string failure;            ///< why it stopped early (empty when complete)
  double seconds = 0;             ///< wall time
  /// @return the number of recorded states whose certificate passed.
  int certified() const;
};

/// Follow the history (file comment).
/// @param md the model; its loads are the ones at factor 1
/// @param opt solver options; solver.exact.start is set to "always" with the local descent
/// @param popt the history and its tolerances
/// @return the report (never throws for a failed step: the path stops there and says why)
/// @throws Error (EXIT_INPUT) for bad options (fewer than two loads, equal neighbours, steps < 1,
///         tolerances ≤ 0) or a model without the condensed formulation (a nonlinear material: the
///         exact solver, whose local descent follows the branch, needs it)
PathReport follow_load_path(const Model& md, const SolveOptions& opt, const PathOptions& popt);

/// The branch signature of a state (file comment), one code per Γ3 node: normal status, tangential
/// status and the piece of p_ν (the number of its breakpoints ≤ u_ν) combined.
std::vector<int> branch_signature(const Model& md, const Solution& sol);

}  // namespace hemicontact
