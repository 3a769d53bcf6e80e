#pragma once
/// @file solve_options.hpp  Every setting of a solve, read from the scene's "solver" and "check"
/// blocks (scene/build_model.hpp: solve_options_from_scene). The member initialisers below are the
/// defaults' one home: the scene schema (src/scene/scene_schema.cpp) injects these values.

#include <hemicontact/nlp/backend.hpp>

#include <string>
#include <utility>
#include <vector>

namespace hemicontact {

/// Settings of backend "ssn" (semismooth Newton on the unsmoothed statuses, solver/ssn.hpp and
/// src/petsc/petsc_ssn.cpp): the full space's exact solver of both engines (scene: solver.ssn.*).
/// The member initialisers are the defaults' one home (the scene schema injects them).
struct SsnOptions {
  /// The step cap. Each step reads every Γ3 node's status again from the current iterate, so
  /// cycling between status sets (possible with a nonmonotone p_ν) ends here with exit 3.
  int max_iters = 60;
  /// The petsc engine's Krylov rtol of a step while statuses still change (inexact Newton: such a
  /// step only has to find the next status set); a step with no status change uses
  /// solver.petsc.ksp_rtol. The cholmod engine factorizes such steps (no Krylov solve).
  double step_rtol = 1e-2;
  /// The petsc engine's stop: converged when an iterate gives the same statuses as the last step
  /// and the residual of the semismooth system (max norm, divided by max|f|) is at most this. Four
  /// orders below check.certificate_tol, two above the round-off floor measured up to 10⁷ unknowns
  /// (1.5e-13); where round-off stays above it, the iteration also ends once the Newton step stops
  /// decreasing at 1e-10 relative. The cholmod engine's ssn steps on to round-off (its steps then
  /// cost one CG iteration on the last factor).
  double tol = 1e-12;
};

/// Settings of the distributed PETSc engine (solver.engine = "petsc", hemicontact-mpi; src/petsc/).
/// The member initialisers are the defaults' one home (the scene schema injects them).
struct PetscEngineOptions {
  /// Relative residual reduction of each Krylov solve (CG): with tao:*, the elastic solve K z = f
  /// that sets the scales, every Newton step inside TAO, and every polish step; with ssn, the floor
  /// of its steps' inexact-Newton rtol (solver.ssn.step_rtol). The polish is a Newton iteration
  /// on the residual of (22), so its answer's accuracy is set by the residual, not by this: each
  /// step reduces the error by ~ksp_rtol, and 1e-10 reaches round-off in two or three steps.
  double ksp_rtol = 1e-10;
  /// Krylov iterations per solve; a solve that stops at this cap (or diverges) is a failure that
  /// names PETSc's reason (KSP_DIVERGED_ITS, ...), exit code 3.
  int ksp_max_it = 2000;
  /// Preconditioner of the full-size solves (ssn's steps; with tao:*, the elastic solve and the
  /// polish): "gamg" (smoothed aggregation, near-null space as near_null_space says) or "hypre"
  /// (BoomerAMG).
  std::string pc = "gamg";
  /// GAMG's near-null space: "translations" (d modes) or "rigid" (the translations and the
  /// rotations: 3 modes in 2D, 6 in 3D). Smoothed aggregation needs the rigid-body modes for
  /// optimal convergence, but each coarse unknown then carries 6 modes instead of 3, so the coarse
  /// operators have 4x the entries and the prolongator twice the columns. Measured on the 3D scene
  /// (ssn, 2 ranks, 48^3): rigid 116 CG iterations, 2.3 KB per unknown, 30 s; translations 208,
  /// 1.8 KB, 17 s (each V-cycle and each set-up cheaper); CG per Newton step stays at 18-21 up to
  /// 10^7 unknowns. Rigid for slender bodies (plates, beams), whose low-energy modes are rotations.
  std::string near_null_space = "translations";
  /// How the mesh is distributed; no rank holds the whole mesh. "auto" (the default): a generated
  /// box or rectangle, not perturbed, is made per rank in slabs of cell layers (a box on more ranks
  /// than layers in blocks of cell columns), any other mesh is made by rank 0 and distributed by
  /// DMPlex; report.json's scalars are reductions, and its per-node list is the owned Γ3 rows
  /// gathered to rank 0. "blocks": a box in blocks at any rank count that makes a grid. The
  /// replicated layout ("replicated": every rank built the whole mesh and DofMap) was retired:
  /// these solve every scene it solved, in less memory per rank (docs/petsc-engine.md).
  std::string mesh = "auto";
  /// Preconditioner of TAO's Newton steps, whose matrix is the Hessian restricted to the inactive
  /// set (it changes size): "hypre" (BoomerAMG) or "gamg".
  std::string newton_pc = "hypre";
  /// TAO stopped short of solver.tol (e.g. its line search failed at round-off) but the first-order
  /// residual (scaled units, nlp/backend.hpp) is at most this: the minimization counts as
  /// "acceptable", as Ipopt's acceptable level does; the polish and the certificate then decide.
  double acceptable_tol = 1e-6;
  /// Newton iterations of the exact polish (full space, statuses fixed).
  int polish_max_iters = 30;
  /// Backend "ssn": the AMG hierarchy built on the first step's matrix is reused for later steps
  /// (only Γ3 rows change) until a step needs more than this times the Krylov iterations per
  /// decade of its reference, the larger of the step that built it and the first step that
  /// reused it; then it is rebuilt on the current matrix. (The first step, every Γ3 node fixed,
  /// is easier than any later one: judged against it alone, the hierarchy was rebuilt without
  /// lowering the counts; 3D scene, 2 ranks: 70³ 42.3 -> 34.4 s, 150³ 467.8 -> 436.0 s.)
  double pc_rebuild = 2.0;
  /// Extra PETSc options, verbatim (e.g. "-ksp_monitor -pc_gamg_threshold 0.02").
  std::string options;
};


/// Settings of the exact inner solve (scene keys solver.exact.*; defaults here).
struct ExactInnerOptions {
  /// Stop when the λ-fixed stationarity residual, divided by the traction scale, is at most this:
  /// two orders below the default check.certificate_tol (1e-8), so that the λ update, the interior
  /// recovery and the final certificate have room for their own round-off.
  double tol = 1e-10;
  /// Rounds of (one coordinate sweep + one Newton step). On a strongly convex Φ_λ the statuses are
  /// right after a few sweeps and one 2D Newton step (a few in 3D) ends it; the cap is for
  /// nonconvex inner problems, whose energy still decreases monotonically.
  int max_rounds = 200;
  /// Backtracking halvings of a Newton step before it is dropped for this round (2^-30 ≈ 1e-9: a
  /// shorter step would not change x above round-off relative to the step).
  int max_halvings = 30;
  /// The polish after the exact solver (solver/polish.hpp) runs only when its coupled residual is
  /// above this (same units as tol). Its job is to take an answer stopped at tol to round-off; an
  /// answer already below is there (the active-set Newton steps end at 1e-16..1e-15), and the
  /// polish could only confirm it or, where its own status rounds do not settle, be rejected after
  /// costing most of the solve (random study seed 461: 5 ms of an 18 ms solve, rejected). 1e-13:
  /// three orders below tol, a hundred times the round-off of a double at unit scale.
  double polish_above = 1e-13;
  /// Path following (studies/load_path.hpp sets it; no scene key): each coordinate step goes to the
  /// nearest local minimizer downhill of the current value along its unknown instead of the global
  /// one along the line, and an active-set Newton step stops where a normal unknown would leave its
  /// piece of p_ν. Every move is then a descent that crosses no barrier, so the answer is the
  /// minimum whose basin holds the start (the branch a quasi-static load step follows), not the
  /// lowest one along each line (which would re-choose the branch).
  bool local_descent = false;
};


/// The cost model of solver.formulation = auto (solver/method_choice.hpp; scene keys
/// solver.method_choice.*). Work is counted in flops of CHOLMOD's symbolic analysis: the condensed
/// path is one factorization (with the dense Γ3 block) plus dense Γ3 work ~ m³ (m Γ3 unknowns),
/// the full path a factorization (without it) per Newton step; condensed is taken where its dense
/// work is a small fraction of its factorization, or its work is at most the full path's, and its
/// dense matrices fit in memory.
struct MethodChoiceOptions {
  /// The condensed path's dense Γ3 work after the factorization, in units of m³ flops: S = L_CC L_CCᵀ
  /// (m³/3), the exact solver's reduced-Hessian factorizations (m³/3 each, a few per solve) and the
  /// polish. Measured on the fig2 strip 1000 × 1 (m = 4002; Schur 9 s + exact 9 s + polish 6 s at
  /// the Schur's 2.4 GFlop/s): 0.9 m³.
  double dense_work = 1.0;
  /// The full path's numeric factorizations per solve: ssn's, one per status change; the newton
  /// backend's, one per step over the continuation stages and the fixed point.
  double full_factorizations = 10;
  /// Where the dense Γ3 work is at most this fraction of the condensation's factorization, condensed
  /// is taken at once (the full path factorizes many times): no second analysis. Above, the full
  /// formulation's factorization is analysed too (same ordering rule, no Γ3 block) and the two works
  /// compared. 0.1: the paper's 2D scenes (fig2 n = 64..1024) stay on the first test.
  double small_fraction = 0.1;
  /// Condensed whatever the full path would cost where the condensed path's whole work (its
  /// factorization and dense_work · m³) is at most this many flops (~0.3 s on the 2-core machine):
  /// there the exact solver and its polish answer to round-off, where the full formulation has the
  /// continuation alone, and the difference in time is a few milliseconds. Measured: the 1000-scene
  /// random study and the minima scenes (a 16 × 2 laminate: 6.6e4 flops) stay on the exact path;
  /// the fig2 strip 300 × 1 (2.9e9 flops) goes to the comparison.
  double condensed_below = 1e9;
  /// ... unless the full path's work is this many times less than the condensed path's: there
  /// "no real cost" no longer holds (fig2's strip 100 × 1, m = 402: condensed 1.1e8 flops, full
  /// 2.4e5, 446x; the condensed path took 31 ms, full + ssn 12 ms), where the random study's
  /// scenes and the minima scenes, whose Γ3 is a small part of the mesh, stay below it.
  double full_cheaper_by = 100;
  /// solver.engine = auto (`hemicontact solve` only): the petsc engine in one process for a 3D
  /// mesh (a generated box, or a Gmsh file sized by its header) of at least this many unknowns (3
  /// per node), the cholmod engine below it.
  /// Measured (docs/performance.md, one process each): 3D n = 16 (14 739 unknowns) 0.97 s against
  /// 1.8 s condensed, n = 24 2.7 against 4.7 s, n = 32 4.2 against 21 s; at n = 8 (2 187) the two
  /// differ by noise. 10 000: from n = 14 on.
  double petsc_above = 10000;
  /// minima's solver.engine = auto: its starts go to the petsc engine (a process each, judged
  /// here) for a 3D mesh of at least this many unknowns; below, the cholmod engine in this process,
  /// whose factorization (condensed: the Γ3 Schur complement) serves every start. Measured on the
  /// 3D scene, `--starts 2 --load-path-steps 2`, whole process (docs/solver.md): n = 24 (46 875
  /// unknowns) 39.5 against 33.0 s with 4 starts and 10 steps, n = 28 (73 167) 27.1 against
  /// 25.7 s, n = 32 (107 811) 41.8 against 55.6 s and 1.14 against 1.64 GB.
  double petsc_restarts_above = 80000;
  /// The condensed path's dense Γ3 matrices (L_CC, S, the condensed energy's dense Hessian and the
  /// solvers' copies: 7 · 8 m² bytes, from the strip's 940 MB peak at m = 4002) may use at most this
  /// fraction of the memory available to the process (physical memory free, or the address-space
  /// limit where lower); above, the full formulation.
  double memory_fraction = 0.5;
};

/// Solver settings, read from the scene's "solver", "check" blocks (defaults: this struct).
struct SolveOptions {
  /// NLP backend name (nlp/backend.hpp: make_backend). "auto", the default, is the engine's own:
  /// ipopt in this engine (newton where Ipopt was not compiled in), ssn in the petsc engine; under
  /// "auto" the backend's ε-stage is skipped where the inner problem is strongly convex (its
  /// minimizer is unique: see exact_start), and the report says so. A name runs that backend.
  std::string backend = AUTO_BACKEND;
  /// "cholmod" (this process: CHOLMOD factorization, condensation), "petsc" (hemicontact-mpi:
  /// distributed unknowns and assembly, semismooth Newton (ssn) or TAO, CG + GAMG; run under mpirun)
  /// or "auto" (`solve` chooses, solver/method_choice.hpp's choose_engine; cholmod elsewhere).
  std::string engine = "auto";
  PetscEngineOptions petsc;          ///< the petsc engine's settings
  SsnOptions ssn;                    ///< backend ssn's settings (both engines)
  /// "full", "condensed" or "auto": from the scene's numbers before any numeric work
  /// (solver/method_choice.hpp; report.json method_choice says what and why).
  std::string formulation = "auto";
  MethodChoiceOptions method_choice;  ///< the cost model of formulation = auto
  /// Fill-reducing ordering of every sparse factorization ("auto", "amd", "metis", "nesdis"): auto
  /// is fem/condensation.hpp's rule for the condensation, fem/sparse_cholesky.hpp's for the others.
  std::string ordering = "auto";
  bool polish = true;                ///< exact polish on identified statuses (condensed formulation)
  BackendOptions backend_options;    ///< tolerance, iteration cap, pass-through options
  double eps_tau = 1e-10;            ///< final friction smoothing width, relative to U_s
  double eps_nu = 1e-10;             ///< final mollification width of p_ν, relative to U_s
  double eps_start = 1e-2;           ///< first continuation width, relative to U_s
  double eps_factor = 1e-2;          ///< ε multiplied by this per continuation step
  /// After a continuation stage that moved Γ3 and λ by at most this (relative), try the exact
  /// polish and certificate; if they pass, the remaining stages are skipped. 0: always run them all.
  double certify_below = 1e-4;
  double tol_u = 1e-12;              ///< fixed point: relative change of x on Γ3 and of λ
  int max_outer = 50;                ///< fixed point: iteration cap
  double relaxation = 1.0;           ///< θ in λ ← (1−θ)λ + θ F_b(u_ν); the exact solver's Anderson mixing
  /// Fixed-point updates ‖Δλ‖∞ at or below this × ‖λ‖∞ are the inner solves' round-off (backend
  /// tol 1e-12 on O(1) scaled unknowns), not the map's contraction: they enter no ratio ρ_k.
  double contraction_floor = 1e-9;
  /// Non-contraction: the update ‖Δλ‖∞ has not shrunk by this factor for `stall_iters`
  /// consecutive outer iterations (ρ_k > stall_ratio) → stop and say so.
  double stall_ratio = 0.99;
  int stall_iters = 5;               ///< see stall_ratio
  bool allow_not_converged = false;  ///< exit 0 even if the fixed point did not converge
  double certificate_tol = 1e-8;     ///< acceptance tolerance of the certificate
  double status_tol = 1e-8;          ///< status decisions, relative to U
  bool smallness = true;             ///< evaluate the smallness condition (21)
  /// U_s given by the caller (no scene key): the scale of the smoothing widths and of the NLP
  /// where this process has no unconstrained elastic solution to take it from (minima's starts on
  /// the petsc engine judged by an in-process ssn solver); 0: max |K⁻¹f| as the set-up finds it.
  double x_scale = 0;
  /// How (21) is decided (check/smallness.hpp): "auto" brackets λ_{1,ν}, λ_{1ν,ν} by the eigenvalues
  /// of the solver's own condensed stiffness (free: no factorization) and computes them exactly
  /// (one more sparse factorization) only when the bracket cannot decide; "exact" always does.
  std::string smallness_method = "auto";
  /// Above this many Γ3 unknowns (d per Γ3 node) no dense matrix of Γ3 size is formed for the checks:
  /// the eigenvalues of (21) and of the inner-convexity test come from Lanczos on the solver's own
  /// factor (solver/sparse_checks.hpp: triangular solves with L_CC when condensed, solves with the
  /// elastic factor in the full formulation; never an extra factorization), and (21) is decided by
  /// the bracket alone (undecided: not computed, and the report says why). The dense eigensolvers
  /// cost ~m³ (9 s at m = 4002); Lanczos ~m² per step with L_CC, and it stops once the brackets
  /// decide (lanczos_decide_tol). 100, measured (both checks together, dense → Lanczos): fig2 n = 128
  /// (m = 258) 4.1 → 0.3 ms, n = 256 (m = 514) 12.2 → 0.8 ms, the strip 100 × 1 (m = 402) 9.7 →
  /// 1.0 ms; the inner-convexity test is exact either way (k_1ν > α iff S − αW_ν is positive
  /// definite, sparse_checks.hpp), and (21) is decided on every scene of the method-choice bench.
  Index dense_max_unknowns = 100;
  /// Lanczos stops when the Ritz residual of the largest eigenvalue θ of the inverse operator is at
  /// most this × θ; the eigenvalue 1/θ is then known to this relative accuracy, and the bracket of
  /// (21) is widened by it (some eigenvalue lies within the residual of θ).
  double lanczos_tol = 1e-10;
  /// A bracket that decides both (21) and the inner-convexity test ends Lanczos before
  /// lanczos_tol, once both relative Ritz residuals are at most this: the verdict needs no more
  /// digits, and a residual this small already rules out the early steps' Ritz values far below
  /// the largest eigenvalue (the bracket's upper end is sound only for a converged Ritz value).
  /// Measured: the strip 1000 × 1, 55 + 40 steps (28 ms) at lanczos_tol, 25 + 15 here.
  double lanczos_decide_tol = 1e-4;
  /// Lanczos steps at most (full reorthogonalization: memory m × this); not converged: the check is
  /// reported undecided with the residual reached.
  int lanczos_max_iter = 300;

  // The exact inner solver (solver/exact_inner.hpp) and the hand-over to it.
  /// Hand the condensed problem to the exact solver after the continuation stage whose statuses
  /// (read at 10 ε) equal the previous stage's, after a backend failure or stall, and after the
  /// last stage when the polished answer is not certified. false: the continuation alone (the
  /// design's path; tests of that path's own behaviour set it explicitly). Needs the condensed
  /// formulation; in the full space the continuation runs alone whatever this says.
  bool exact = true;
  ExactInnerOptions exact_inner;  ///< the exact solver's tolerance and caps
  /// Hand over after this continuation stage at the latest. Stage 0 (ε = 1e-2 U) already puts the
  /// iterate in the statuses' neighbourhood; every later stage costs backend iterations on an ever
  /// less smooth problem, which the exact solver does not need (measured: ipopt 5–25 s where the
  /// exact solver takes 0.02 s on the same scene).
  int exact_after_stage = 0;
  /// When the exact solver starts, before any ε-stage (the design's path otherwise: the backend's
  /// smoothed ε-stages inside the fixed point, then the hand-over to the exact solver):
  /// "auto" (the default) — when solver.backend = auto and the inner problem Φ_λ is strongly convex
  /// (inner_convexity, decided at set-up): its minimizer is unique and the exact solver's monotone
  /// sweeps reach it from any start (solver/exact_inner.hpp), so the backend's stage could not
  /// change the answer and is skipped; a backend the user named always runs its first stage;
  /// "convex" — as auto, also for a named backend; "always" — on every condensed problem (a not
  /// strongly convex Φ_λ may then end in another of its stationary points than the design's path);
  /// "never" — the backend's stage 0 first, always. Measured on 1000 random scenes
  /// (bench/README.md, hemicontact_random_study): auto certifies as many as "always", and on the
  /// scenes that are not strongly convex it returns the design path's minimum, which "always" may
  /// not (minima-one-node: −34.11 against −10.11).
  std::string exact_start = "auto";
  /// When the exact solver's answer from the start is not certified: run the continuation from the
  /// same start (true), or stop there with that answer and its reason (false, the default: in the
  /// same 1000 scenes the continuation after a failed start certified none, and on the failing scene
  /// it cost 20x the linear solve of failing at once).
  bool exact_start_fallback = false;
  /// Backend iterations per minimization while the exact solver can take over: a stage that needs
  /// more is a stalled one (the smoothed problem grows nearly nonsmooth as ε → 0) and hands over.
  /// The paper's scenes need about 20; 0: solver.max_iter alone.
  int exact_stage_max_iter = 200;
  /// The backend's first-order tolerance per minimization while the exact solver can take over
  /// (the larger of this and solver.tol): the stage only has to put the iterate in the statuses'
  /// neighbourhood, which it does long before solver.tol (the smoothing itself moves the answer by
  /// O(ε) = 1e-2 U at stage 0), and the exact solver or the polish then solves the unsmoothed
  /// problem to round-off. f-based NLopt methods stall near r ≈ 1e-7 and would otherwise run to their
  /// cap on every stage. Measured (1000 random scenes, design path): the same 1000 certified.
  double exact_stage_tol = 1e-6;
  /// The strong-convexity check of the inner problem (one dense Cholesky of S − αW_ν, m³/3 flops)
  /// is skipped above this many condensed unknowns, and the backend's stage then runs. The check
  /// costs what one backend iteration on the condensed problem costs (Ipopt and newton factor a
  /// matrix of the same size and pattern at every iteration), so wherever it can skip a backend
  /// stage it pays: fig2 at h = 1/1024 (2050 unknowns) 0.3 s (0.6 % of that solve) against 5.2 s for
  /// Ipopt's stage 0. The cap is S's own memory: 16384 unknowns is a 2 GB dense S.
  Index convexity_max_unknowns = 16384;
  /// Anderson memory of the fixed point λ = F_b(u_ν) in the exact solver (0: plain iteration).
  int anderson_memory = 5;
};

/// Does the user name the backend (anything but solver.backend = auto)?
inline bool backend_named(const SolveOptions& o) { return o.backend != AUTO_BACKEND; }

/// The continuation's smoothing widths (ε_τ, ε_ν) per stage, relative to U_s: ε_s = max(ε_final,
/// ε_start·factor^s) for each, until both are final. Both engines run this schedule.
std::vector<std::pair<double, double>> smoothing_schedule(const SolveOptions& o);

}  // namespace hemicontact
