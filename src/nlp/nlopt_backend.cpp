// The "nlopt:ALGO" backends: NLopt's gradient-based algorithms that take bound constraints, run on
// an NlpProblem through the NLopt C++ API (<nlopt.hpp>). Compiled only when NLopt is found.
//
// Algorithms (the table LOCAL_ALGORITHMS below; each one is a backend name "nlopt:ALGO"):
//  - LD_MMA, LD_CCSAQ: Svanberg's CCSA (moving asymptotes / quadratic); bounds enter the
//    subproblem directly.
//  - LD_SLSQP: Kraft's SQP with a dense BFGS matrix: O(n²) memory and O(n³) time per iteration,
//    so it is refused for n > DENSE_MAX_N = 3000 (the "condensed" formulation has a few hundred to
//    a few thousand unknowns; the "full" one up to 10^6).
//  - LD_LBFGS, LD_VAR1/2, LD_TNEWTON*: Luksan's limited-memory codes with box constraints. A line
//    search stops at the first bound it meets (bounds met together, within 1e-8, are added
//    together), so k bounds that become active one after another cost ~k evaluations. Measured
//    on ½‖x − c‖², x <= 1, c_i = 2 + i: 13 / 53 / 203 evaluations for k = 10 / 50 / 200 (MMA,
//    CCSAQ, SLSQP: 3-4). On the paper's scenes the contact bounds mostly activate together (fig2
//    at n = 32, 27 active bounds: 76 evaluations over 6 minimizations). Counts are reported as is.
//    vector_storage (extra option, default VECTOR_STORAGE = 20) is the number of stored
//    correction pairs (NLopt's default is a memory heuristic, ≥ 10).
//  - G_MLSL_LDS[+LOCAL] / G_MLSL[+LOCAL]: multi-level single-linkage global search (low-discrepancy
//    or random starts) with a local algorithm from the table (default LD_LBFGS; also
//    extra option "local_algorithm"). See "MLSL" below.
// Everything else is refused when the backend is created: unknown names with the supported list,
// known NLopt algorithms with the reason (derivative-free, no bounds, constraint wrappers, ...).
//
// Stopping (the same meaning as the ipopt and newton backends; BackendOptions is mapped, never
// ignored):
//  - tol: NLopt has no first-order test, so every evaluation with a gradient computes the driver's
//    first-order residual r = max_i min(|g_i|, distance to the bound that −g_i points to)
//    (src/solver/solve.cpp), in the O(1)-scaled unknowns the driver hands over, and stops NLopt
//    (nlopt::forced_stop) as soon as r <= tol at a point no worse than the start (f <= f(x0); a
//    trial point of a line search can be stationary without being a minimizer, e.g. a saddle).
//  - ftol_rel = ftol_abs = 0: an f-based test would stop too early. Near a stiff direction
//    (a sticking node with smoothing width ε_τ has curvature ~1/ε_τ ~ 1e10) the decrease still
//    available is ~r²/curvature, far below any relative change of f that can be resolved.
//    Luksan's codes replace ftol_rel = 0 by their own 1e-14, so they get LUKSAN_FTOL_REL = 1e-300
//    (stop only when f repeats exactly). Measured on the printed scene at n = 32 with tol = 1e-6:
//    with 1e-14, LD_LBFGS stopped at r ≈ 4e-4 on the final stage and then failed; with 1e-300 it
//    reached 8e-7.
//  - xtol_rel = XTOL_REL = 1e-15 (≈ 5 ε_mach): stops an algorithm only when no unknown moves
//    beyond round-off any more; the verdict then comes from r (below).
//  - Luksan's codes (LD_LBFGS, LD_VAR*, LD_TNEWTON*) also stop on their own test, max projected
//    gradient <= 1e-8 (tolg, fixed inside NLopt's luksan_plis/plip/pnet). When that ends a run
//    (SUCCESS) above tol, the run is repeated once from its end with NLopt seeing σ·f and σ·∇f,
//    σ = LUKSAN_TOLG / tol, so that the test means |∇f| <= tol (the remaining budget; the
//    message says so). Not from the start: with |∇f| ~ 200 a scaled first line search failed
//    (steepest descent step 1e4 times too long, Rosenbrock from (−1.2, 1)).
//  - max_iter: NLopt counts evaluations, not iterations; maxeval = EVALS_PER_ITERATION · max_iter
//    (= 10: a line search or CCSA inner loop takes 1-3 evaluations per iteration, truncated Newton
//    more), or the extra option "maxeval" verbatim.
// Verdict (the driver's certificate still decides whether the answer is accepted):
//  - forced stop on r <= tol, or NLopt's SUCCESS / STOPVAL / FTOL / XTOL / ROUNDOFF_LIMITED
//    (NLopt: "typically returns a useful result"): CONVERGED if r <= tol, ACCEPTABLE if
//    r <= ACCEPTABLE_FACTOR · tol (1e3), else FAILED;
//  - MAXEVAL_REACHED: MAX_ITERATIONS (CONVERGED if r <= tol at the returned point);
//  - FAILURE, INVALID_ARGS, OUT_OF_MEMORY: FAILED with NLopt's message. Except FAILURE from
//    Luksan's codes: NLopt turns every negative ITERM of theirs into FAILURE, and in practice that
//    is a line search that found no decrease of f at the round-off floor below (a stall, like
//    ROUNDOFF_LIMITED), so r decides as above. Measured: LD_LBFGS on the printed scene at n = 32,
//    tol = 1e-6, ended its last minimization so with r = 2e-6.
//  Exceptions thrown by the objective reach the caller unchanged (as with the ipopt backend).
// Round-off floor: every NLopt algorithm accepts a step only if f decreases (line search, CCSA's
// conservative check, SLSQP's merit function). Near a minimizer the decrease still available is
// ~r²/(2c) for a curvature c, which f cannot resolve below ε_mach·|f|, so they stall near
// r ≈ sqrt(ε_mach·|f|·c). Measured: 3e-8 to 6e-8 on the 6-unknown box QP of the tests (c ≈ 3,
// |f| ≈ 10), and 1e-7 to 1e-4 on the paper's condensed scenes (a sticking node with ε_τ = 1e-10 U
// has c ~ 1e10). The scenes' default tol = 1e-12 (chosen for the newton and ipopt backends, which
// accept a Newton step on round-off) therefore ends FAILED with these backends; solver.tol = 1e-6
// identifies the statuses and the polish makes the answer exact (tests/nlp/nlopt_backend_test.cpp).
// A failure for this reason says so in the message.
// print_level: 0 the summary at debug level, 1 at info level, >= 2 also every evaluation.
// Statistics: iterations = evaluations = objective evaluations (NLopt has no iteration count that
// means the same across its algorithms); kkt_norm = r at the returned point; seconds = wall time.
// The message also gives how many evaluations had a gradient.
//
// MLSL: needs finite bounds on every unknown. An infinite bound is replaced by the warm start ±
// box_radius (extra option, default BOX_RADIUS = 2 in the scaled unknowns, where the unconstrained
// elastic solution has ‖x‖∞ = 1; the message says how many bounds were replaced). The global phase
// runs to its evaluation budget (maxeval, as above) with population points per round ("population",
// NLopt's default 4 when 0) and local searches stopped loosely (xtol_rel = MLSL_LOCAL_XTOL_REL =
// 1e-10, ftol_rel = MLSL_LOCAL_FTOL_REL = 1e-14); the best point is then refined by one run of the
// local algorithm with the first-order stop above, whose verdict is the backend's. Evaluations of
// both phases are reported. The random generator is seeded with MLSL_SEED, so runs repeat.
// MLSL is meant for the condensed problem: refused for n > DENSE_MAX_N.

#include "nlp/backend_factories.hpp"

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/core/log.hpp>

#include <nlopt.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

constexpr Index DENSE_MAX_N = 3000;        // SLSQP and MLSL: largest n accepted
constexpr int VECTOR_STORAGE = 20;         // Luksan codes: stored correction pairs
// Bounds of the numeric pass-through options. NLopt sizes its work arrays in int arithmetic
// (luksan_plis: n·m·2 + ...): vector_storage = 2^31−1 overflowed that product and corrupted the
// heap (LD_VAR1 crashed, LD_LBFGS aborted), so both m and the stored numbers n·m are bounded.
// Limited-memory quasi-Newton gains nothing beyond a few dozen pairs. MLSL samples `population`
// points per round before it looks at maxeval again: 2^31−1 was an effective hang.
constexpr int MAX_VECTOR_STORAGE = 1000;
constexpr double MAX_STORED_PAIRS = 1e8;  // n·vector_storage: 1.6 GB of pairs, far below int overflow
constexpr int MAX_POPULATION = 100000;
constexpr int MAX_MAXEVAL = 100000000;     // 10^8 evaluations: days of work on any scene
constexpr double MAX_BOX_RADIUS = 1e6;     // scaled unknowns are O(1): a larger box samples nothing useful
constexpr int EVALS_PER_ITERATION = 10;    // maxeval = EVALS_PER_ITERATION · max_iter
constexpr double XTOL_REL = 1e-15;         // round-off stall only (see top of file)
constexpr double ACCEPTABLE_FACTOR = 1e3;  // r <= 1e3·tol: ACCEPTABLE
constexpr double BOX_RADIUS = 2.0;         // MLSL box around the warm start (scaled unknowns)
constexpr double MLSL_LOCAL_XTOL_REL = 1e-10;
constexpr double MLSL_LOCAL_FTOL_REL = 1e-14;
constexpr unsigned long MLSL_SEED = 20170611;
constexpr double LUKSAN_TOLG = 1e-8;        // fixed in NLopt's luksan_plis/plip/pnet
constexpr double LUKSAN_FTOL_REL = 1e-300;  // Luksan turns ftol_rel = 0 into 1e-14

/// A local algorithm offered as "nlopt:NAME".
struct LocalAlgorithm {
  const char* name;
  nlopt::algorithm id;
  bool luksan;  // Luksan's codes: take set_vector_storage, stop on gmax <= LUKSAN_TOLG
  bool dense;   // O(n²) memory: refused for n > DENSE_MAX_N
  const char* description;
};

const LocalAlgorithm LOCAL_ALGORITHMS[] = {
    {"LD_MMA", nlopt::LD_MMA, false, false,
     "NLopt MMA (Svanberg's moving asymptotes, CCSA), local, gradient; bounds in the subproblem"},
    {"LD_CCSAQ", nlopt::LD_CCSAQ, false, false,
     "NLopt CCSA with quadratic approximations, local, gradient; bounds in the subproblem"},
    {"LD_SLSQP", nlopt::LD_SLSQP, false, true,
     "NLopt SLSQP (dense BFGS SQP), local, gradient, bounds; O(n^2) memory, O(n^3) time: "
     "refused for n > 3000 (use the condensed formulation)"},
    {"LD_LBFGS", nlopt::LD_LBFGS, true, false,
     "NLopt L-BFGS (Luksan), local, gradient, box constraints; up to ~1 evaluation per active "
     "bound (option vector_storage, default 20)"},
    {"LD_VAR2", nlopt::LD_VAR2, true, false,
     "NLopt shifted limited-memory variable metric, rank 2 (Luksan), local, gradient, bounds"},
    {"LD_VAR1", nlopt::LD_VAR1, true, false,
     "NLopt shifted limited-memory variable metric, rank 1 (Luksan), local, gradient, bounds"},
    {"LD_TNEWTON_PRECOND_RESTART", nlopt::LD_TNEWTON_PRECOND_RESTART, true, false,
     "NLopt truncated Newton, preconditioned, restarts (Luksan), local, gradient, bounds; "
     "Hessian products by gradient differences"},
    {"LD_TNEWTON_PRECOND", nlopt::LD_TNEWTON_PRECOND, true, false,
     "NLopt truncated Newton, preconditioned (Luksan), local, gradient, bounds"},
    {"LD_TNEWTON_RESTART", nlopt::LD_TNEWTON_RESTART, true, false,
     "NLopt truncated Newton with restarts (Luksan), local, gradient, bounds"},
    {"LD_TNEWTON", nlopt::LD_TNEWTON, true, false, "NLopt truncated Newton (Luksan), local, gradient, bounds"},
};

/// The global searches, "nlopt:NAME" or "nlopt:NAME+LOCAL".
struct GlobalAlgorithm {
  const char* name;
  nlopt::algorithm id;
  const char* description;
};

const GlobalAlgorithm GLOBAL_ALGORITHMS[] = {
    {"G_MLSL_LDS", nlopt::G_MLSL_LDS,
     "NLopt MLSL global search, low-discrepancy starts, local LD_LBFGS (G_MLSL_LDS+LD_MMA etc.); "
     "box = bounds or warm start +- box_radius; condensed problems (n <= 3000)"},
    {"G_MLSL", nlopt::G_MLSL,
     "NLopt MLSL global search, random starts, local LD_LBFGS (G_MLSL+LD_MMA etc.); "
     "box = bounds or warm start +- box_radius; condensed problems (n <= 3000)"},
};

/// Known NLopt algorithms that are refused, and why.
struct Refusal {
  const char* name;  // exact name, or a prefix ending in '_' ("LN_")
  const char* reason;
};

const Refusal REFUSED[] = {
    {"LD_LBFGS_NOCEDAL", "not part of NLopt 2.7 (Nocedal's code was removed for its license); use nlopt:LD_LBFGS"},
    {"LN_NEWUOA", "derivative-free, and it ignores bound constraints (u_nu <= g is a bound)"},
    {"LN_PRAXIS", "derivative-free, and it takes bounds only as f = +inf outside the box"},
    {"LD_AUGLAG",
     "an augmented-Lagrangian wrapper for nonlinear constraints; the contact problem has bounds "
     "only, so use a local algorithm directly (e.g. nlopt:LD_LBFGS)"},
    {"LD_AUGLAG_EQ",
     "an augmented-Lagrangian wrapper for nonlinear equality constraints; the contact problem "
     "has bounds only, so use a local algorithm directly (e.g. nlopt:LD_LBFGS)"},
    {"AUGLAG",
     "an augmented-Lagrangian wrapper for nonlinear constraints; the problem has bounds "
     "only, so use a local algorithm directly (e.g. nlopt:LD_LBFGS)"},
    {"AUGLAG_EQ",
     "an augmented-Lagrangian wrapper for nonlinear constraints; the problem has "
     "bounds only, so use a local algorithm directly (e.g. nlopt:LD_LBFGS)"},
    {"GD_STOGO",
     "branch-and-bound on a finite box, exponential in n (hundreds of unknowns "
     "here); use nlopt:G_MLSL_LDS"},
    {"GD_STOGO_RAND",
     "branch-and-bound on a finite box, exponential in n (hundreds of unknowns "
     "here); use nlopt:G_MLSL_LDS"},
    {"GD_MLSL", "MLSL with an unnamed default local algorithm; use nlopt:G_MLSL+LOCAL"},
    {"GD_MLSL_LDS", "MLSL with an unnamed default local algorithm; use nlopt:G_MLSL_LDS+LOCAL"},
    {"LN_", "derivative-free (uses f only; the contact energy has a cheap exact gradient)"},
    {"GN_", "derivative-free global search (uses f only) on a finite box"},
};

std::string supported_list() {
  std::string s;
  for (const auto& a : LOCAL_ALGORITHMS) s += (s.empty() ? "" : ", ") + std::string(a.name);
  for (const auto& a : GLOBAL_ALGORITHMS) s += ", " + std::string(a.name) + "[+LOCAL]";
  return s;
}

/// NLopt's name of @p name as users write it: case-insensitive, and the family prefix optional
/// ("mma", "ld_mma" and "LD_MMA" are LD_MMA; "mlsl_lds" is G_MLSL_LDS), as NLopt's own bindings
/// and other codes' configuration files spell them. Unknown names come back upper-cased.
std::string canonical(const std::string& name) {
  std::string up = name;
  for (char& c : up) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const auto known = [](const std::string& n) {
    for (const auto& a : LOCAL_ALGORITHMS)
      if (n == a.name) return true;
    for (const auto& a : GLOBAL_ALGORITHMS)
      if (n == a.name) return true;
    return false;
  };
  if (known(up)) return up;
  for (const char* prefix : {"LD_", "G_"})
    if (known(prefix + up)) return prefix + up;
  return up;
}

/// The short alias of a supported algorithm ("LD_MMA" → "mma"), as `hemicontact backends` shows it.
std::string alias(const char* name) {
  std::string a = name;
  for (const char* prefix : {"LD_", "G_"})
    if (a.rfind(prefix, 0) == 0) a = a.substr(std::string(prefix).size());
  for (char& c : a) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return a;
}

const LocalAlgorithm* find_local(const std::string& name) {
  const std::string n = canonical(name);
  for (const auto& a : LOCAL_ALGORITHMS)
    if (n == a.name) return &a;
  return nullptr;
}

const GlobalAlgorithm* find_global(const std::string& name) {
  const std::string n = canonical(name);
  for (const auto& a : GLOBAL_ALGORITHMS)
    if (n == a.name) return &a;
  return nullptr;
}

/// @throws Error naming @p name: why it is refused, or that it is unknown (with the list).
[[noreturn]] void refuse(const std::string& name, const std::string& role) {
  for (const auto& r : REFUSED) {
    const std::string key = r.name;
    const bool prefix = key.back() == '_';
    if (prefix ? name.compare(0, key.size(), key) == 0 : name == key)
      throw Error("nlopt: " + role + "algorithm " + name + " is not supported: " + r.reason +
                      ". Supported: " + supported_list(),
                  EXIT_INPUT);
  }
  const bool known = nlopt_algorithm_from_string(name.c_str()) >= 0;
  throw Error("nlopt: " + std::string(known ? "NLopt algorithm " : "unknown algorithm '") + name +
                  (known ? " is not supported here (not gradient-based with bounds)"
                         : "' (names as in NLopt without the NLOPT_ prefix)") +
                  "; supported: " + supported_list(),
              EXIT_INPUT);
}

/// Whole-string parses (strtol/strtod accept a valid prefix; "1x" must not pass as 1).
long parse_count(const std::string& key, const std::string& s, long min, long max) {
  errno = 0;
  char* end = nullptr;
  const long v = s.empty() ? 0 : std::strtol(s.c_str(), &end, 10);
  if (s.empty() || errno != 0 || *end != '\0' || v < min || v > max)
    throw Error("nlopt: option '" + key + "' (solver.options." + key + ") expects an integer in " +
                    std::to_string(min) + ".." + std::to_string(max) + ", got '" + s + "'",
                EXIT_INPUT);
  return v;
}
double parse_positive(const std::string& key, const std::string& s, double max) {
  errno = 0;
  char* end = nullptr;
  const double v = s.empty() ? 0 : std::strtod(s.c_str(), &end);
  if (s.empty() || errno != 0 || *end != '\0' || !(v > 0) || !(v <= max)) {
    std::ostringstream range;
    range << "(0, " << max << "]";
    throw Error("nlopt: option '" + key + "' (solver.options." + key + ") expects a number in " + range.str() +
                    ", got '" + s + "'",
                EXIT_INPUT);
  }
  return v;
}

/// r = max_i min(|g_i|, distance to the bound −g_i points to): the shared first-order residual
/// (nlp/backend.hpp) on NLopt's raw arrays.
double first_order_residual(const double* x, const double* g, const Vec& lower, const Vec& upper) {
  const Index n = lower.size();
  return hemicontact::first_order_residual(Eigen::Map<const Vec>(x, n), Eigen::Map<const Vec>(g, n), lower, upper);
}

/// The objective callback's state: counts, the first-order stop, the best point seen, and an
/// exception from the objective to rethrow after NLopt has returned.
struct Evaluator {
  const NlpProblem* problem = nullptr;
  Vec x, g;  // scratch
  double tol = 0.0;
  double sigma = 1.0;   // NLopt sees σ·f (Luksan's gradient test, see top of file)
  int print_level = 0;  // >= 2: log every evaluation with a gradient
  bool stop_on_tol = true;
  double f_start = INF;
  int evaluations = 0;
  int gradients = 0;
  bool stopped = false;  // forced stop on r <= tol
  Vec x_stop;
  double f_stop = INF, r_stop = INF;
  Vec x_best;  // lowest f among evaluations with a gradient
  double f_best = INF, r_best = INF;
  std::exception_ptr error;

  static double call(unsigned n, const double* xp, double* grad, void* data) {
    auto& e = *static_cast<Evaluator*>(data);
    try {
      check_interrupt();  // Interrupted is kept in e.error and rethrown once NLopt has returned
      e.x = Eigen::Map<const Vec>(xp, Index(n));
      ++e.evaluations;
      const double f = e.problem->f->value(e.x);
      if (grad == nullptr) return e.sigma * f;
      ++e.gradients;
      e.problem->f->gradient(e.x, e.g);
      for (unsigned i = 0; i < n; ++i) grad[i] = e.sigma * e.g[Index(i)];
      const double r = first_order_residual(xp, e.g.data(), e.problem->lower, e.problem->upper);
      if (e.print_level >= 2) log_info() << "nlopt: evaluation " << e.evaluations << ": f = " << f << ", r = " << r;
      if (std::isfinite(f) && f <= e.f_best) {
        e.f_best = f;
        e.r_best = r;
        e.x_best = e.x;
      }
      if (e.stop_on_tol && r <= e.tol && f <= e.f_start) {
        e.stopped = true;
        e.x_stop = e.x;
        e.f_stop = f;
        e.r_stop = r;
        throw nlopt::forced_stop();  // caught by nlopt.hpp's wrapper: stops NLopt, rethrown
      }
      return e.sigma * f;
    } catch (const nlopt::forced_stop&) {
      throw;
    } catch (...) {
      e.error = std::current_exception();
      throw nlopt::forced_stop();
    }
  }
};

const char* result_name(nlopt::result r) {
  switch (r) {
    case nlopt::FAILURE: return "FAILURE";
    case nlopt::INVALID_ARGS: return "INVALID_ARGS";
    case nlopt::OUT_OF_MEMORY: return "OUT_OF_MEMORY";
    case nlopt::ROUNDOFF_LIMITED: return "ROUNDOFF_LIMITED";
    case nlopt::FORCED_STOP: return "FORCED_STOP";
    case nlopt::SUCCESS: return "SUCCESS";
    case nlopt::STOPVAL_REACHED: return "STOPVAL_REACHED";
    case nlopt::FTOL_REACHED: return "FTOL_REACHED";
    case nlopt::XTOL_REACHED: return "XTOL_REACHED";
    case nlopt::MAXEVAL_REACHED: return "MAXEVAL_REACHED";
    case nlopt::MAXTIME_REACHED: return "MAXTIME_REACHED";
    default: return "unknown NLopt result";
  }
}

/// Options from BackendOptions::extra, checked against what the algorithm can use.
struct Extra {
  int vector_storage = VECTOR_STORAGE;
  int maxeval = 0;  // 0: EVALS_PER_ITERATION · max_iter
  double box_radius = BOX_RADIUS;
  int population = 0;  // 0: NLopt's default
  std::string local_algorithm;
};

/// One NLopt run's outcome.
struct Run {
  nlopt::result result = nlopt::FAILURE;
  std::string what;  // NLopt's message when it threw
};

/// Runs @p opt from @p x (in/out), catching NLopt's result exceptions; rethrows the objective's.
Run run(nlopt::opt& opt, Evaluator& ev, std::vector<double>& x) {
  Run out;
  opt.set_min_objective(&Evaluator::call, &ev);
  double f = 0.0;
  try {
    out.result = opt.optimize(x, f);
  } catch (const std::exception& e) {  // forced_stop, roundoff_limited, runtime_error, ...
    out.result = opt.last_optimize_result();
    out.what = e.what();
  }
  if (ev.error) std::rethrow_exception(ev.error);
  return out;
}

/// The point do_minimize returns, with its objective and first-order residual.
struct FinalPoint {
  double f = 0.0, r = 0.0;
};

/// Global phase on a finite box, no first-order stop (it would end the search at the first
/// local minimum); the local refinement (local_phase) then starts from the best point. Appends
/// its facts to @p note.
void global_phase(const NlpProblem& problem, const Vec& x, const GlobalAlgorithm& algorithm, nlopt::opt loc,
                  const Extra& extra, int maxeval, Evaluator& ev, std::vector<double>& xv, std::ostringstream& note) {
  const Index n = problem.f->size();
  const auto to_std = [](const Vec& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  Vec lo = problem.lower, hi = problem.upper;
  int replaced = 0;
  for (Index i = 0; i < n; ++i) {
    if (!std::isfinite(lo[i])) lo[i] = x[i] - extra.box_radius, ++replaced;
    if (!std::isfinite(hi[i])) hi[i] = x[i] + extra.box_radius, ++replaced;
  }
  if (replaced > 0)
    note << "; MLSL box: " << replaced << " infinite bounds replaced by the warm start +- " << extra.box_radius;
  nlopt::srand(MLSL_SEED);
  nlopt::opt global(algorithm.id, unsigned(n));
  loc.set_xtol_rel(MLSL_LOCAL_XTOL_REL);
  loc.set_ftol_rel(MLSL_LOCAL_FTOL_REL);
  global.set_local_optimizer(loc);
  global.set_lower_bounds(to_std(lo));
  global.set_upper_bounds(to_std(hi));
  global.set_maxeval(maxeval);
  if (extra.population > 0) global.set_population(unsigned(extra.population));
  ev.stop_on_tol = false;
  const Run global_run = run(global, ev, xv);
  const int global_evaluations = ev.evaluations;
  // NLopt returns the best point it found; the refinement starts there, and "no worse than
  // the start" is measured from it.
  ev.f_start = problem.f->value(Eigen::Map<const Vec>(xv.data(), n));
  ++ev.evaluations;
  ev.stop_on_tol = true;
  note << "; global phase " << result_name(global_run.result) << " after " << global_evaluations
       << " evaluations, best f = " << ev.f_start;
}

/// The answer and its residual: the forced-stop point, else NLopt's x (normally the best point
/// it evaluated; otherwise one more evaluation gives its residual). Sets @p x.
FinalPoint final_point(const NlpProblem& problem, const std::vector<double>& xv, Evaluator& ev, Vec& x) {
  const Index n = problem.f->size();
  FinalPoint out;
  if (ev.stopped) {
    x = ev.x_stop;
    out.f = ev.f_stop;
    out.r = ev.r_stop;
  } else {
    x = Eigen::Map<const Vec>(xv.data(), n);
    x = x.cwiseMax(problem.lower).cwiseMin(problem.upper);
    if (ev.x_best.size() == n && x == ev.x_best) {
      out.f = ev.f_best;
      out.r = ev.r_best;
    } else {
      Vec g;
      out.f = problem.f->value(x);
      problem.f->gradient(x, g);
      ++ev.evaluations;
      ++ev.gradients;
      out.r = first_order_residual(x.data(), g.data(), problem.lower, problem.upper);
    }
  }
  return out;
}

/// The verdict on NLopt's result @p r (not forced-stop) given the final residual @p r_final;
/// appends the explanation to @p msg.
SolveStatus local_verdict(const Run& r, double r_final, const LocalAlgorithm& local, const BackendOptions& options,
                          int maxeval, std::ostringstream& msg) {
  const double acceptable = ACCEPTABLE_FACTOR * options.tol;
  const auto by_residual = [&]() {
    return r_final <= options.tol  ? SolveStatus::CONVERGED
           : r_final <= acceptable ? SolveStatus::ACCEPTABLE
                                   : SolveStatus::FAILED;
  };
  SolveStatus status = SolveStatus::FAILED;
  switch (r.result) {
    case nlopt::SUCCESS:
    case nlopt::STOPVAL_REACHED:
    case nlopt::FTOL_REACHED:
    case nlopt::XTOL_REACHED:
    case nlopt::ROUNDOFF_LIMITED:
    case nlopt::FORCED_STOP: status = by_residual(); break;
    case nlopt::MAXEVAL_REACHED:
    case nlopt::MAXTIME_REACHED:
      status = r_final <= options.tol ? SolveStatus::CONVERGED : SolveStatus::MAX_ITERATIONS;
      break;
    case nlopt::FAILURE:  // Luksan: a line search that found no decrease (see top of file)
      status = local.luksan ? by_residual() : SolveStatus::FAILED;
      break;
    default: status = SolveStatus::FAILED;
  }
  msg << result_name(r.result);
  if (!r.what.empty()) msg << " (" << r.what << ")";
  msg << ", first-order residual " << r_final << " (tol " << options.tol << ")";
  if (r.result == nlopt::MAXEVAL_REACHED) msg << ", maxeval " << maxeval;
  const bool stalled = r.result != nlopt::MAXEVAL_REACHED && r.result != nlopt::MAXTIME_REACHED &&
                       r.result != nlopt::INVALID_ARGS && r.result != nlopt::OUT_OF_MEMORY;
  if (stalled && status != SolveStatus::CONVERGED)
    msg << "; stalled: f-based methods stop near r ~ sqrt(eps_mach |f| curvature), where f no "
           "longer resolves a decrease (raise tol, or use newton / ipopt)";
  return status;
}

class NloptBackend final : public NlpBackend {
 public:
  NloptBackend(std::string spec, const LocalAlgorithm* local, const GlobalAlgorithm* global)
      : m_spec(std::move(spec)), m_local(local), m_global(global) {}
  std::string name() const override { return "nlopt:" + m_spec; }
  bool uses_hessian() const override { return false; }
  void check_options(const BackendOptions& options) const override {
    const LocalAlgorithm* local = nullptr;
    (void)parse_extra(options, local);
  }

 protected:
  SolveResult do_minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options) override;

 private:
  Extra parse_extra(const BackendOptions& options, const LocalAlgorithm*& local) const;
  nlopt::opt make_local(const LocalAlgorithm& a, const Extra& e, unsigned n) const;
  void check_size(Index n, const LocalAlgorithm& local, const Extra& extra) const;
  Run local_phase(const NlpProblem& problem, const LocalAlgorithm& local, const Extra& extra,
                  const BackendOptions& options, int maxeval, Evaluator& ev, std::vector<double>& xv,
                  std::ostringstream& note) const;

  std::string m_spec;               ///< what followed "nlopt:"
  const LocalAlgorithm* m_local;    ///< the local algorithm (MLSL: from "+LOCAL", may be null)
  const GlobalAlgorithm* m_global;  ///< null for a local backend
};

Extra NloptBackend::parse_extra(const BackendOptions& options, const LocalAlgorithm*& local) const {
  Extra e;
  local = m_local;
  const auto only = [&](const std::string& key, bool applies, const char* who) {
    if (!applies)
      throw Error("nlopt: option '" + key + "' does not apply to " + name() + " (only to " + who + ")", EXIT_INPUT);
  };
  for (const auto& [key, value] : options.extra) {
    if (key == "maxeval") {
      e.maxeval = int(parse_count(key, value, 1, MAX_MAXEVAL));
    } else if (key == "box_radius") {
      only(key, m_global != nullptr, "G_MLSL_LDS / G_MLSL");
      e.box_radius = parse_positive(key, value, MAX_BOX_RADIUS);
    } else if (key == "population") {
      only(key, m_global != nullptr, "G_MLSL_LDS / G_MLSL");
      e.population = int(parse_count(key, value, 0, MAX_POPULATION));
    } else if (key == "local_algorithm") {
      only(key, m_global != nullptr, "G_MLSL_LDS / G_MLSL");
      e.local_algorithm = value;
    } else if (key == "vector_storage") {
      e.vector_storage = int(parse_count(key, value, 1, MAX_VECTOR_STORAGE));
    } else {
      throw Error("nlopt: unknown option '" + key + "' (value '" + value +
                      "'); NLopt backends take: vector_storage, local_algorithm, box_radius, "
                      "population, maxeval",
                  EXIT_INPUT);
    }
  }
  if (!e.local_algorithm.empty()) {
    const LocalAlgorithm* a = find_local(e.local_algorithm);
    if (a == nullptr) refuse(e.local_algorithm, "local ");
    if (m_local != nullptr && a != m_local)
      throw Error("nlopt: option local_algorithm = " + e.local_algorithm + " contradicts " + name(), EXIT_INPUT);
    local = a;
  }
  if (local == nullptr) local = find_local("LD_LBFGS");
  if (options.extra.count("vector_storage") && !local->luksan)
    throw Error("nlopt: option 'vector_storage' does not apply to " + std::string(local->name) +
                    " (only to LD_LBFGS, LD_VAR*, LD_TNEWTON*)",
                EXIT_INPUT);
  return e;
}

nlopt::opt NloptBackend::make_local(const LocalAlgorithm& a, const Extra& e, unsigned n) const {
  nlopt::opt opt(a.id, n);
  opt.set_ftol_rel(a.luksan ? LUKSAN_FTOL_REL : 0.0);
  opt.set_ftol_abs(0.0);
  opt.set_xtol_rel(XTOL_REL);
  if (a.luksan) opt.set_vector_storage(unsigned(e.vector_storage));
  return opt;
}

void NloptBackend::check_size(Index n, const LocalAlgorithm& local, const Extra& extra) const {
  const std::string who = name();
  if ((local.dense || m_global != nullptr) && n > DENSE_MAX_N)
    throw Error(who + ": refused for n = " + std::to_string(n) + " unknowns (limit " + std::to_string(DENSE_MAX_N) +
                    ": " + (m_global ? "a global search" : "SLSQP's dense O(n^2) memory, O(n^3) time") +
                    "); use solver.formulation = condensed, or another backend",
                EXIT_INPUT);
  if (local.luksan && double(n) * extra.vector_storage > MAX_STORED_PAIRS) {
    std::ostringstream m;
    m << who << ": vector_storage = " << extra.vector_storage << " with n = " << n
      << " unknowns stores n*vector_storage = " << double(n) * extra.vector_storage << " numbers twice (limit "
      << MAX_STORED_PAIRS << "); lower solver.options.vector_storage to at most "
      << std::max<long>(1, long(MAX_STORED_PAIRS / double(n)));
    throw Error(m.str(), EXIT_INPUT);
  }
}

Run NloptBackend::local_phase(const NlpProblem& problem, const LocalAlgorithm& local, const Extra& extra,
                              const BackendOptions& options, int maxeval, Evaluator& ev, std::vector<double>& xv,
                              std::ostringstream& note) const {
  const Index n = problem.f->size();
  const auto to_std = [](const Vec& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  const int before_local = ev.evaluations;
  Run r;
  for (int pass = 0;; ++pass) {
    nlopt::opt opt = make_local(local, extra, unsigned(n));
    opt.set_lower_bounds(to_std(problem.lower));
    opt.set_upper_bounds(to_std(problem.upper));
    opt.set_maxeval(std::max(1, maxeval - (ev.evaluations - before_local)));
    for (Index i = 0; i < n; ++i)  // NLopt rejects a start outside the bounds
      xv[size_t(i)] = std::min(std::max(xv[size_t(i)], problem.lower[i]), problem.upper[i]);
    r = run(opt, ev, xv);
    // Luksan's own gradient test ended the run above tol: once more from there, scaled.
    if (ev.stopped || !local.luksan || pass > 0 || r.result != nlopt::SUCCESS || options.tol >= LUKSAN_TOLG ||
        ev.evaluations - before_local >= maxeval)
      break;
    ev.sigma = LUKSAN_TOLG / options.tol;
    note << "; restarted with f scaled by " << ev.sigma << " past Luksan's |g| <= 1e-8 test";
  }
  return r;
}

// The problem is checked, x is inside the bounds and n ≥ 1 (NlpBackend::minimize, which also sets
// the result's kkt_norm and seconds).
SolveResult NloptBackend::do_minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options) {
  const std::string who = name();
  const Index n = problem.f->size();
  if (!(options.tol > 0)) throw Error(who + ": tol must be > 0 (got " + std::to_string(options.tol) + ")", EXIT_INPUT);
  const LocalAlgorithm* local = nullptr;
  const Extra extra = parse_extra(options, local);
  check_size(n, *local, extra);

  SolveResult result;
  const int maxeval = extra.maxeval > 0 ? extra.maxeval
                                        : int(std::min<long>(long(EVALS_PER_ITERATION) * std::max(1, options.max_iter),
                                                             std::numeric_limits<int>::max()));
  Evaluator ev;
  ev.problem = &problem;
  ev.tol = options.tol;
  ev.print_level = options.print_level;
  ev.f_start = problem.f->value(x);  // not an NLopt evaluation; counted below
  ++ev.evaluations;
  std::ostringstream note;  // extra facts for the message

  std::vector<double> xv(x.data(), x.data() + n);
  if (m_global != nullptr)
    global_phase(problem, x, *m_global, make_local(*local, extra, unsigned(n)), extra, maxeval, ev, xv, note);
  const int before_local = ev.evaluations;
  const Run r = local_phase(problem, *local, extra, options, maxeval, ev, xv, note);
  const FinalPoint fin = final_point(problem, xv, ev, x);

  std::ostringstream msg;
  msg << who << ": ";
  if (ev.stopped) {
    result.status = SolveStatus::CONVERGED;
    msg << "first-order residual " << fin.r << " <= tol " << options.tol << " (forced stop)";
  } else {
    result.status = local_verdict(r, fin.r, *local, options, maxeval, msg);
  }
  msg << "; " << ev.evaluations << " evaluations (" << ev.gradients << " with gradient";
  if (m_global) msg << ", " << ev.evaluations - before_local << " in the local refinement";
  msg << ")" << note.str();
  result.message = msg.str();
  result.evaluations = ev.evaluations;
  result.iterations = ev.evaluations;
  result.f = fin.f;
  if (options.print_level >= 1)
    log_info() << result.message;
  else
    log_debug() << result.message;
  return result;
}

}  // namespace

const std::vector<NloptAlgorithmInfo>& nlopt_backend_catalog() {
  static const std::vector<std::string> names = [] {  // storage for the const char* below
    std::vector<std::string> v;
    for (const auto& a : LOCAL_ALGORITHMS) v.push_back("nlopt:" + std::string(a.name));
    for (const auto& a : GLOBAL_ALGORITHMS) v.push_back("nlopt:" + std::string(a.name));
    return v;
  }();
  static const std::vector<std::string> docs = [] {  // the description with the short alias
    std::vector<std::string> v;
    for (const auto& a : LOCAL_ALGORITHMS) v.push_back(std::string(a.description) + " [alias nlopt:" + alias(a.name) + "]");
    for (const auto& a : GLOBAL_ALGORITHMS)
      v.push_back(std::string(a.description) + " [alias nlopt:" + alias(a.name) + "]");
    return v;
  }();
  static const std::vector<NloptAlgorithmInfo> catalog = [] {
    std::vector<NloptAlgorithmInfo> c;
    for (size_t k = 0; k < names.size(); ++k) c.push_back({names[k].c_str(), docs[k].c_str()});
    return c;
  }();
  return catalog;
}

std::unique_ptr<NlpBackend> make_nlopt_backend(const std::string& algorithm) {
  // The backend's name is NLopt's canonical spelling, whatever alias or case was asked for: reports
  // and tables then name the same solver the same way.
  const size_t plus = algorithm.find('+');
  const std::string head = canonical(algorithm.substr(0, plus));
  if (const LocalAlgorithm* a = find_local(head)) {
    if (plus != std::string::npos)
      throw Error("nlopt: '" + algorithm + "': only G_MLSL_LDS / G_MLSL take a '+LOCAL' algorithm", EXIT_INPUT);
    return std::make_unique<NloptBackend>(a->name, a, nullptr);
  }
  if (const GlobalAlgorithm* g = find_global(head)) {
    const LocalAlgorithm* local = nullptr;
    if (plus != std::string::npos) {
      const std::string tail = algorithm.substr(plus + 1);
      local = find_local(tail);
      if (local == nullptr) refuse(canonical(tail), "local ");
    }
    return std::make_unique<NloptBackend>(std::string(g->name) + (local ? std::string("+") + local->name : ""), local,
                                          g);
  }
  refuse(head, "");
}

}  // namespace hemicontact
