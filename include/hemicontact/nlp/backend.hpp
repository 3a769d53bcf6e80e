#pragma once
/// @file backend.hpp  Abstract NLP backend (polysolve-style: created by name, sees only NlpProblem).

#include <hemicontact/nlp/nlp_problem.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hemicontact {

/// Outcome of one backend run. Never a bare bool.
enum class SolveStatus {
  CONVERGED,       ///< the backend met its tolerance
  ACCEPTABLE,      ///< met a looser "acceptable" tolerance (Ipopt's Solved_To_Acceptable_Level)
  MAX_ITERATIONS,  ///< iteration cap hit
  FAILED           ///< anything else (see message)
};

/// @return "converged", "acceptable", "max_iterations" or "failed".
const char* to_string(SolveStatus s);
/// @return the status whose to_string is @p name. @throws Error (EXIT_INTERNAL) for another name.
SolveStatus solve_status_from(const std::string& name);

/// solver.backend = "auto": the engine's own backend (make_backend: ipopt, or newton where Ipopt
/// was not compiled in; the petsc engine: ssn), whose stage the solve may skip where it cannot
/// change the answer (SolveOptions::exact_start).
inline constexpr const char* AUTO_BACKEND = "auto";
/// solver.backend = "ssn": the semismooth Newton method on the unsmoothed conditions in the full
/// space, in both engines (solver/ssn.hpp with CHOLMOD; the petsc engine's with CG + AMG). No NLP
/// backend: ContactSolver (and the petsc engine) run it themselves.
inline constexpr const char* SSN_BACKEND = "ssn";
/// @return whether the petsc engine runs its ssn for solver.backend = @p backend (auto means ssn
/// there; the others it takes are TAO's).
inline bool petsc_engine_runs_ssn(const std::string& backend) { return backend == AUTO_BACKEND || backend == SSN_BACKEND; }

/// Statistics and verdict of one backend run.
struct SolveResult {
  SolveStatus status = SolveStatus::FAILED;  ///< verdict
  int iterations = 0;                        ///< backend iterations
  int evaluations = 0;                       ///< objective evaluations
  double f = 0.0;                            ///< final objective value
  double kkt_norm = 0.0;                     ///< final (unscaled) KKT/first-order residual, inf-norm
  double seconds = 0.0;                      ///< wall time
  std::string message;                       ///< backend's own status text
  /// @return true for CONVERGED or ACCEPTABLE.
  bool ok() const { return status == SolveStatus::CONVERGED || status == SolveStatus::ACCEPTABLE; }
};

/// Options common to all backends. These member initialisers are the defaults' one home: the
/// scene schema (src/scene/scene_schema.cpp) injects them as solver.tol, solver.max_iter and
/// solver.print_level.
struct BackendOptions {
  double tol = 1e-12;   ///< first-order tolerance, relative to the gradient scale at x0
  int max_iter = 3000;  ///< iteration cap
  int print_level = 0;  ///< backend verbosity (0 = silent; our logger reports progress)
  /// Backend-specific options passed through verbatim (e.g. Ipopt "mu_strategy" -> "adaptive").
  /// Values are strings; numeric/integer Ipopt options are parsed from them.
  std::map<std::string, std::string> extra;
};

/// @brief The first-order residual of min f subject to lower ≤ x ≤ upper at x, one definition for
/// every backend and the driver: r = max_i min(|g_i|, room towards the bound that −g_i points to),
/// with g = ∇f(x). Zero exactly at a first-order point; it equals ‖x − P(x − g)‖∞ (P: the
/// projection onto the box) and is in the units of g.
double first_order_residual(const Vec& x, const Vec& g, const Vec& lower, const Vec& upper);
/// @return first_order_residual at @p x of @p problem (one gradient evaluation).
double first_order_residual(const NlpProblem& problem, const Vec& x);

/// An NLP solver for bound-constrained problems.
///
/// minimize() is the one entry point and does what every backend needs (template method): it checks
/// the problem (an objective, sizes, non-empty bounds), projects the start onto the bounds, answers
/// an empty problem (n = 0) itself, times the run, and sets SolveResult::kkt_norm to
/// first_order_residual() at the returned x, so that kkt_norm means the same for every backend.
/// A backend implements do_minimize(): the algorithm and its own verdict.
class NlpBackend {
 public:
  virtual ~NlpBackend() = default;
  /// @return the backend's name as given to make_backend() (e.g. "ipopt").
  virtual std::string name() const = 0;
  /// @return true if the backend uses the Hessian.
  virtual bool uses_hessian() const = 0;
  /// Minimize from the warm start @p x (projected onto the bounds first); x receives the result.
  /// @param problem objective and bounds; @param x in: start, out: final iterate;
  /// @param options tolerances and pass-through options.
  /// @throws Error naming the backend for a malformed problem (EXIT_INTERNAL) or empty bounds
  ///         (EXIT_INPUT), and whatever do_minimize throws for bad options.
  SolveResult minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options);
  /// Refuse pass-through options (BackendOptions::extra) this backend would refuse in minimize(),
  /// without minimizing anything: the driver checks them at set-up, so that a scene's bad option
  /// is an input error even when the backend is never run (the exact solver may answer alone).
  /// @throws Error (EXIT_INPUT) naming the option, as minimize() would.
  virtual void check_options(const BackendOptions& options) const { (void)options; }

 protected:
  /// The algorithm, on a checked problem with n ≥ 1 unknowns and x inside the bounds. Sets status,
  /// iterations, evaluations, f and message (kkt_norm and seconds are minimize()'s).
  virtual SolveResult do_minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options) = 0;
};

/// Create a backend by name ("ipopt", "newton", "nlopt:LD_LBFGS", ...).
/// @throws Error naming the backend if it is unknown or was not compiled in.
std::unique_ptr<NlpBackend> make_backend(const std::string& name);

/// One line per backend that was compiled in: {name, one-line description}.
std::vector<std::pair<std::string, std::string>> available_backends();

}  // namespace hemicontact
