#pragma once
/// @file minima.hpp  Many starts, many solutions: a search for the distinct solutions of (22) when
/// the smallness condition (21) fails (`hemicontact minima`).
///
/// When (21) fails, Π_λ(u) = ½a(u,u) − f(u) + Σ w_i j_ν(u_ν,i) + Σ w_i λ_i |u_τ,i| (docs/model.md §2) is
/// nonconvex and (22) may have several solutions: local minima and saddles. A local method (every
/// NLP backend here) finds the one whose basin holds its start. find_minima() therefore
///
///  1. solves from many starting points, each backend with one ContactSolver reused for all its
///     starts (one factorization/condensation per backend):
///     - "zero": u = 0;
///     - "at-gap": every Γ3 ν unknown at g_i (at +U_s where g_i = ∞), τ = 0;
///     - "separated": every ν at −U_s, τ = 0;
///     - "random-k": every Γ3 unknown uniform in a box (ν ∈ [−B, min(B, g_i)], τ ∈ [−B, B],
///       B = MinimaOptions::box · U_s), interior unknowns 0; std::mt19937 seeded with
///       MinimaOptions::seed, so the same seed gives the same starts;
///     - "load-up": a load path, loads × 1/N, 2/N, …, 1 (N = load_path_steps), each solve
///       warm-started from the previous one; "load-down": continued to × 2 and back down to × 1
///       in steps of 1/N (the hysteresis branch a softening layer leaves behind);
///     - "user-k": what the caller gives (MinimaOptions::user_starts);
///     where U_s = the solver's displacement scale (max |Γ3 unknown| of the unconstrained elastic
///     solution, Solution::x_scale);
///  2. verifies each result with the certificate (docs/model.md §4), the only judge: a result that
///     passes it is a solution of (22) even if its backend stopped short of its own tolerance
///     (MinimaRun::converged records that); uncertified results are listed but not grouped;
///  3. groups the certified results into distinct solutions: a result joins the first group whose
///     representative is within group_tol · max_k ‖u_k‖_E of it in the energy norm
///     ‖v‖_E = sqrt(a(v, v));
///  4. classifies each distinct solution by a second-order check of the smoothed energy on the
///     free subspace (see SecondOrderCheck), and sorts them by energy.
///
/// Load path: the loads are scaled on a copy of the model (f and its reduced f_x multiplied by
/// the factor). That is exact — u = 0 on Γ1, so f enters the discrete problem only through f and
/// f_x — and needs neither the scene's directory nor a new mesh or stiffness.
///
/// What the search asks and what it found (MinimaOptions, MinimaRun, DistinctSolution, MinimaReport)
/// are plain records in problem/minima_report.hpp, which the writers (output/study_writers.hpp) read.

#include <hemicontact/problem/minima_report.hpp>
#include <hemicontact/solver/solve.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace hemicontact {

/// Pair the solutions of @p R that are mirror images of each other (DistinctSolution::mirror_of):
/// 2D, Γ3 symmetric about the midpoint of its x-range, equal energies and reflected Γ3 values within
/// @p group_tol (relative). Called by find_minima after sorting.
void pair_mirror_images(const Model& md, MinimaReport& R, double group_tol);

/// The Chao1 estimate (UnseenEstimate) from how many samples reached each class.
/// @param abundances per class reached at least once, the number of samples that reached it
/// @return the estimate (samples, observed, f1, f2, chao1, the interval, unseen); all zero for none
UnseenEstimate chao1_estimate(const std::vector<int>& abundances);

/// Solve from many starts, group, classify (see the file comment).
/// @param md      the model; its loads are the ones at load factor 1
/// @param opt     solver options (backend replaced by each of MinimaOptions::backends)
/// @param mopt    the search
/// @return the report (never throws for non-convergence; uncertified runs are listed)
/// @throws Error (EXIT_INPUT) for a user start of a size that fits nothing, an unknown backend,
///         or bad options (negative starts, group_tol ≤ 0)
MinimaReport find_minima(const Model& md, const SolveOptions& opt, const MinimaOptions& mopt);

/// Second-order check of a certified solution with @p solver (whose model the solution is of).
/// @param solver the solver (its energy() is modified: final ε, friction frozen at the solution)
/// @param md the model @param opt the options the solution was computed with
/// @param sol the solution @param mopt tolerance and size limit
/// @return the verdict (see SecondOrderCheck)
SecondOrderCheck second_order_check(ContactSolver& solver, const Model& md, const SolveOptions& opt,
                                    const Solution& sol, const MinimaOptions& mopt);

/// Read caller starts from JSON: an array of [u_ν, u_τ] (3D: [u_ν, u_τ, u_τ2]) pairs, one per Γ3
/// node in ContactNodes order; or an object with "nodes" (a report.json: each node's "u_nu",
/// "u_tau"); or an array of such arrays/objects (several starts). 2D only for report.json input
/// (its nodes carry the signed u_tau).
/// @param js the parsed file @param md the model (number of Γ3 nodes, dimension)
/// @param context name for error messages (the file name)
/// @return one Vec of size d·n_Γ3 per start
/// @throws Error (EXIT_INPUT) naming @p context for a malformed or wrongly sized start
std::vector<Vec> read_gamma3_starts(const nlohmann::json& js, const Model& md, const std::string& context);

}  // namespace hemicontact
