#pragma once
/// @file minima_report.hpp  What the search for distinct solutions (studies/minima.hpp,
/// find_minima) is asked and what it found: the options, every run, each distinct solution with its
/// second-order check, and the report. Plain data that the search fills and the writers
/// (output/study_writers.hpp) read, so that output/ needs nothing of the search's code.

#include <hemicontact/core/types.hpp>
#include <hemicontact/problem/reports.hpp>
#include <hemicontact/problem/solution.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace hemicontact {

struct MinimaRun;
struct Model;

/// The ranges of the minima search's counts, the CLI's (`minima --starts ...`) and the Python
/// module's alike. Each start is a full solve, so 10 000 starts are hours at n = 64 already, and
/// 10 000 load-path steps per unit load as many solves: more is an effective hang, not a study.
inline constexpr long MINIMA_MAX_STARTS = 10000;
inline constexpr long MINIMA_MAX_LOAD_PATH_STEPS = 10000;
inline constexpr long MINIMA_MAX_SEED = 4294967295L;  ///< std::mt19937's seed: 32 bits

/// What find_minima() does; defaults are the ones `hemicontact minima` documents.
struct MinimaOptions {
  int starts = 8;                     ///< random starts per backend (≥ 0)
  unsigned seed = 1;                  ///< seed of the random starts (std::mt19937)
  std::vector<std::string> backends;  ///< backends to use; empty: the scene's (SolveOptions::backend)
  double group_tol = 1e-6;            ///< relative energy-norm distance under which two results are one solution
  double box = 1.0;                   ///< random box half-width B in units of U_s
  int load_path_steps = 10;           ///< N: load-path step 1/N; 0: no load path
  /// Caller's starts. Each is a full displacement u (size N·d, i.e. md.dofs.n_full()), or the
  /// Γ3 unknowns (u_ν, u_τ[, u_τ2]) node after node (size d·n_Γ3, ContactNodes order), or
  /// the solver unknowns (size ContactSolver::size(), full formulation). Checked in that order.
  std::vector<Vec> user_starts;
  /// Second-order check: λ_min ≥ −second_order_tol · scale counts as a local minimum (see
  /// SecondOrderCheck::scale).
  double second_order_tol = 1e-8;
  /// Largest number of kept unknowns for which the dense Hessian's eigenvalues are computed;
  /// beyond it λ_min comes from one sparse Cholesky of the shifted Hessian and Lanczos on its
  /// inverse (studies/minima.cpp: sparse_lambda_min), no dense matrix.
  Index max_dense = 4000;
  /// Run random starts in batches of `starts` until the estimated number of distinct solutions no
  /// random start has reached yet (UnseenEstimate::unseen) is below one, or max_starts random starts
  /// have run (`minima --until-complete`).
  bool until_complete = false;
  int max_starts = 1024;  ///< the cap of until_complete (random starts per backend, all batches together)
  /// Called as each run ends, with the runs so far (the last one just finished): the caller keeps
  /// them as they come (the CLI: minima-runs.csv), so that an interrupted search loses only the
  /// run it was in. The driver knows no files.
  std::function<void(const std::vector<MinimaRun>& runs_so_far)> on_run;
  /// Where set, every start is solved by this engine instead of the in-process solver (the CLI:
  /// the petsc engine, a process of its own, where `solve` would take it): the model with its
  /// loads × @p load_scale (the load path) to judge on, and the whole mesh's u to start from
  /// (null: the engine's own start). The backends are then the engine's; the second-order check
  /// stays here (studies/minima.hpp).
  std::function<Solution(const Model& scaled, double load_scale, const Vec* u_start)> engine;
  std::string engine_name;  ///< the runs' backend column where engine is set ("ssn on the petsc engine")
};


/// One run: a start, a backend, and what it gave.
struct MinimaRun {
  std::string start;       ///< "zero", "at-gap", "separated", "random-3", "load-up", "load-down", "user-1"
  std::string backend;     ///< the backend requested for this run
  std::string solved_by;   ///< what produced the answer (Solution::solved_by: "ipopt+exact", "exact", ...)
  bool converged = false;  ///< backend_ok && fixed_point_converged
  bool certified = false;  ///< certificate passed (whatever the backend said: the certificate is the judge)
  double energy = 0;       ///< Π (unsmoothed) of the result
  double certificate = 0;  ///< certificate max residual
  double seconds = 0;      ///< wall time of this run (including its load path)
  int group = -1;          ///< index into MinimaReport::solutions, −1 if not certified
  std::string message;     ///< the solve's verdict
};

/// One distinct solution.
struct DistinctSolution {
  Solution solution;                    ///< representative: the member with the smallest certificate residual
  SecondOrderCheck second_order;        ///< local minimum or saddle
  std::vector<int> runs;                ///< indices into MinimaReport::runs that reached it
  std::vector<std::string> starts;      ///< their start labels (in run order)
  std::map<std::string, int> backends;  ///< what solved them (MinimaRun::solved_by) → how many runs reached it
  double spread = 0;                    ///< max relative energy-norm distance of a member to the representative
  /// The index of this solution's mirror image (2D: Γ3 reflected about the midpoint of its x-range,
  /// u_ν kept and u_τ reversed, the same energy), −1 if none: the two are one solution of a
  /// mirror-symmetric scene, found once per side.
  int mirror_of = -1;
};

/// How many distinct solutions the random starts have not reached yet: the bias-corrected Chao1
/// estimator of species richness (Chao 1987; Chao, Biometrics 61, 2005), with the random starts as
/// the samples and the distinct solutions they reached as the species. Only random starts are a
/// random sample of the basins (the others are chosen), so only they count. With n certified
/// random runs, S_obs distinct solutions among them, f1 reached once and f2 twice, c = (n − 1)/n:
///   f2 > 0: S = S_obs + c f1²/(2 f2),
///           var = f2 [½ c (f1/f2)² + c² (f1/f2)³ + ¼ c² (f1/f2)⁴];
///   f2 = 0: S = S_obs + c f1 (f1 − 1)/2,
///           var = c f1(f1 − 1)/2 + c² f1 (2 f1 − 1)²/4 − c² f1⁴/(4 S);
/// the 95 % interval is Chao's log-normal one, [S_obs + T/K, S_obs + T K], T = S − S_obs,
/// K = exp(1.96 sqrt(ln(1 + var/T²))); for T = 0 (no solution seen once) it is [S_obs, S_obs].
/// It estimates the basins the start distribution reaches with positive probability, not basins
/// it cannot reach; a lower bound in that sense.
struct UnseenEstimate {
  int samples = 0;   ///< n: certified random-start runs
  int observed = 0;  ///< S_obs: distinct solutions among them
  int f1 = 0;        ///< reached by exactly one random start
  int f2 = 0;        ///< reached by exactly two
  double chao1 = 0;  ///< S, the estimated number of distinct solutions
  double lo = 0, hi = 0;  ///< 95 % interval of S
  double unseen = 0;      ///< S − S_obs
  int random_starts = 0;  ///< random starts run per backend (until_complete: all batches)
  bool complete = false;  ///< until_complete: stopped because unseen < 1 (false: at the cap, or not asked)
};

/// Everything find_minima() found.
struct MinimaReport {
  std::vector<DistinctSolution> solutions;  ///< sorted by energy, lowest first
  std::vector<MinimaRun> runs;              ///< every start, in the order run
  SmallnessReport smallness;                ///< (21) of the scene (at load factor 1)
  double x_scale = 1;                       ///< U_s
  double norm_scale = 0;                    ///< max ‖u‖_E over certified results (group_tol is relative to it)
  MinimaOptions options;                    ///< what was asked (backends filled in)
  double seconds = 0;                       ///< total wall time
  UnseenEstimate unseen;                    ///< how many the random starts have not reached yet
  /// @return the number of distinct solutions judged local minima.
  int local_minima() const;
  /// @return the number of runs whose result was certified.
  int certified_runs() const;
};

}  // namespace hemicontact
