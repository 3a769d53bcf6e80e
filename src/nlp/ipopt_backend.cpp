// The "ipopt" backend: runs Ipopt (interior point, exact Hessian) on an NlpProblem through
// IpoptTnlp, in the shape of Ipopt's hs071 driver (hs071_main.cpp): factory → options →
// Initialize → OptimizeTNLP → read the results the TNLP recorded.
//
// Default options and why (every one can be overridden through BackendOptions::extra):
//  - hessian_approximation exact: NlpObjective supplies the true Hessian (Psd::NONE); Ipopt's
//    inertia correction handles the nonconvex c2 < 0 branch of the normal law.
//  - mu_strategy adaptive: the barrier parameter follows the complementarity of the current
//    point, so a warm start close to the solution is not pushed back to mu_init = 0.1 as with
//    the monotone (Fiacco-McCormick) strategy. Measured on a 400-unknown obstacle problem:
//    re-solve after a 1 % load change 1-2 iterations (monotone: 2-6), cold 9-10 (monotone 9-17).
//  - nlp_scaling_method user-scaling with f scaled by 1/G, G = max(1, ‖∇f(x0)‖∞): Ipopt measures
//    tol on the scaled problem, so tol is relative to the gradient scale at x0 as
//    BackendOptions::tol promises, independent of the force units of a scene (Ipopt's own
//    gradient-based scaling only scales down when ‖∇f(x0)‖∞ > 100). A warm start keeps the G of
//    the previous solve (or a larger current one): at a near-optimal start ‖∇f(x0)‖∞ is only the
//    change of the problem, and a tolerance relative to it ends below round-off (measured: 15
//    iterations ending "acceptable" instead of 1 "succeeded").
//  - dual_inf_tol = G and compl_inf_tol = 1e-4·G: Ipopt also requires these *unscaled* absolute
//    tests (defaults 1 and 1e-4) before declaring success; scaled by G they keep Ipopt's default
//    meaning in the scaled problem instead of becoming unreachable for large forces.
//  - bound_relax_factor 0: Ipopt relaxes every bound by 1e-8·max(1, |bound|) by default and
//    then projects the answer back (honor_original_bounds), which moves a point on an active
//    bound by up to 1e-8 and leaves its neighbours where they were for the relaxed problem
//    (~1e-8 errors on bounded Rosenbrock); the relaxation helps general inequality constraints,
//    but with m = 0 the iterates stay strictly inside the bounds anyway. u_ν <= g stays exact.
//  - bound_push = bound_frac = 1e-4 (cold start; Ipopt's default is 1e-2): a start on a bound is
//    moved less. Measured on 1-D obstacle problems (400 unknowns, forces 1e-4..1e6, starts on and
//    off the obstacle): 1e-4 and 1e-3 took 6-10 iterations, 1e-2 took 9-11, and 1e-8 took up to
//    17 (a start too close to the boundary only allows tiny steps).
//  - warm start (the previous successful call had the same n): warm_start_init_point yes with the
//    stored bound multipliers z_L, z_U; warm_start_bound_push/frac, warm_start_mult_bound_push
//    and mu_init 1e-9, so neither x nor z is moved off the previous solution; with adaptive mu
//    the first barrier parameter then follows the (tiny) complementarity of that point.
//  - max_soc 0: the second-order correction restores the constraints' feasibility c(x) = 0
//    after a rejected trial step; with bounds only (m = 0) there is no c to restore, yet Ipopt's
//    filter (θ = 0 before and after) still tries it after every first rejected trial, each try a
//    MUMPS solve and an evaluation. min_refinement_steps 0: iterative refinement of the KKT solve
//    only where its residual asks for it (residual_ratio_max), not once per solve by default.
//    Every MUMPS call in Debian's MUMPS 5.5 also recomputes its save/restore sizes through
//    gfortran string compares, over half of Ipopt's instructions on a 42-unknown condensed
//    problem (callgrind, random scene seed 681): both options took that run's Ipopt instructions
//    from 128M to 69M (−46 %), with the same 31 iterations and the same answer; evaluations
//    221 → 137. Measured over 1000 random scenes in docs/random-study.md.
//  - sb yes unless print_level > 0: suppresses Ipopt's banner (registered in 3.11.9).

#include "nlp/backend_factories.hpp"
#include "nlp/ipopt_tnlp.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/core/log.hpp>

#include <IpIpoptApplication.hpp>
#include <IpRegOptions.hpp>
#include <IpSolveStatistics.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <sstream>
#include <string>

namespace hemicontact {
namespace {

const char* status_name(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded: return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates: return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop: return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found: return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed: return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation: return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded: return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom: return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition: return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option: return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected: return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception: return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown: return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory: return "Insufficient_Memory";
    case Ipopt::Internal_Error: return "Internal_Error";
  }
  return "unknown Ipopt status";
}

SolveStatus map_status(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded: return SolveStatus::CONVERGED;
    case Ipopt::Solved_To_Acceptable_Level: return SolveStatus::ACCEPTABLE;
    case Ipopt::Maximum_Iterations_Exceeded: return SolveStatus::MAX_ITERATIONS;
    default: return SolveStatus::FAILED;
  }
}

// Ipopt registers most integer options without an upper bound; sizes and counts such as
// limited_memory_max_history or mumps_mem_percent at 2^31 − 1 are sized into allocations or loops
// (the NLopt analogue corrupted the heap). No option needs more than a million.
constexpr int MAX_PASSTHROUGH_INT = 1000000;

// One Set*Value, checked (OptionsList returns false for an unknown name, a wrong type or a value
// outside the registered range or list).
void set_checked(bool ok, const std::string& name, const std::string& value, ExitCode code) {
  if (!ok)
    throw Error("ipopt: option '" + name + "' rejected value '" + value +
                    "' (unknown option, wrong type or out of range; see Ipopt's option list)",
                code);
}

void set_option(Ipopt::OptionsList& o, const std::string& name, const std::string& value) {
  set_checked(o.SetStringValue(name, value), name, value, EXIT_INTERNAL);
}
void set_option(Ipopt::OptionsList& o, const std::string& name, double value) {
  std::ostringstream s;
  s << value;
  set_checked(o.SetNumericValue(name, value), name, s.str(), EXIT_INTERNAL);
}
void set_option(Ipopt::OptionsList& o, const std::string& name, int value) {
  set_checked(o.SetIntegerValue(name, value), name, std::to_string(value), EXIT_INTERNAL);
}

/// Whole-string parses (strtol/strtod accept a valid prefix; "1x" must not pass as 1).
bool parse_int(const std::string& s, int& out) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (errno != 0 || *end != '\0' || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    return false;
  out = static_cast<int>(v);
  return true;
}
bool parse_double(const std::string& s, double& out) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return errno == 0 && *end == '\0';
}

/// A pass-through option from BackendOptions::extra. The registered option type decides the
/// setter, so "bound_push" = "1" reaches SetNumericValue although "1" also parses as an int;
/// only an unregistered type falls back to trying int, then double, then string.
void set_passthrough(Ipopt::IpoptApplication& app, const std::string& name, const std::string& value) {
  Ipopt::OptionsList& o = *app.Options();
  const Ipopt::SmartPtr<const Ipopt::RegisteredOption> reg = app.RegOptions()->GetOption(name);
  if (!Ipopt::IsValid(reg)) throw Error("ipopt: unknown option '" + name + "' (value '" + value + "')", EXIT_INPUT);
  // Ipopt accepts the name of any linear solver it knows of, then fails in the first iteration
  // (exit 3, "Error in step computation") when the library is not there: Debian's build has MUMPS
  // only (the HSL codes and Pardiso are not in Debian), so anything else is refused by name here.
  if (name == "linear_solver" && value != "mumps")
    throw Error("ipopt: option 'linear_solver' = '" + value +
                    "' is not available in this Ipopt build (Debian's coinor-libipopt has mumps only; "
                    "set solver.options.linear_solver to \"mumps\" or leave it out)",
                EXIT_INPUT);
  int i = 0;
  double d = 0.0;
  switch (reg->Type()) {
    case Ipopt::OT_Integer:
      if (!parse_int(value, i))
        throw Error("ipopt: option '" + name + "' expects an integer, got '" + value + "'", EXIT_INPUT);
      if (i > MAX_PASSTHROUGH_INT)
        throw Error("ipopt: option '" + name + "' (solver.options." + name + ") = " + value + " is above " +
                        std::to_string(MAX_PASSTHROUGH_INT) + ", the bound of every integer pass-through option",
                    EXIT_INPUT);
      set_checked(o.SetIntegerValue(name, i), name, value, EXIT_INPUT);
      return;
    case Ipopt::OT_Number:
      if (!parse_double(value, d))
        throw Error("ipopt: option '" + name + "' expects a number, got '" + value + "'", EXIT_INPUT);
      set_checked(o.SetNumericValue(name, d), name, value, EXIT_INPUT);
      return;
    case Ipopt::OT_String: set_checked(o.SetStringValue(name, value), name, value, EXIT_INPUT); return;
    default: {
      const bool ok = parse_int(value, i)      ? o.SetIntegerValue(name, i)
                      : parse_double(value, d) ? o.SetNumericValue(name, d)
                                               : o.SetStringValue(name, value);
      set_checked(ok, name, value, EXIT_INPUT);
    }
  }
}

/// See the top of this file for why each default is chosen.
class IpoptBackend final : public NlpBackend {
 public:
  std::string name() const override { return "ipopt"; }
  bool uses_hessian() const override { return true; }
  void check_options(const BackendOptions& options) const override {
    if (options.extra.empty()) return;  // nothing to check: no application (its set-up costs ~ms)
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
    if (const auto console = app->Jnlst()->GetJournal("console"); Ipopt::IsValid(console))
      console->SetAllPrintLevels(Ipopt::J_NONE);  // our Error names the option
    for (const auto& [key, value] : options.extra) set_passthrough(*app, key, value);
  }

 protected:
  SolveResult do_minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options) override;

 private:
  Vec m_z_L;             ///< lower-bound multipliers of the last successful solve (empty: none)
  Vec m_z_U;             ///< upper-bound multipliers of the last successful solve (empty: none)
  double m_scale = 1.0;  ///< gradient scale G of the last successful solve (see top of file)
};

// The options of one solve: the scaled tolerances (G = scale, see top of file), the interior
// point's push off the bounds, and the warm start's from the last multipliers.
void set_ipopt_options(Ipopt::OptionsList& o, const BackendOptions& options, int print_level, double scale, bool warm) {
  set_option(o, "print_level", print_level);
  if (print_level == 0) set_option(o, "sb", std::string("yes"));
  set_option(o, "tol", options.tol);
  set_option(o, "max_iter", options.max_iter);
  set_option(o, "hessian_approximation", std::string("exact"));
  set_option(o, "mu_strategy", std::string("adaptive"));
  set_option(o, "nlp_scaling_method", std::string("user-scaling"));
  set_option(o, "dual_inf_tol", scale);
  set_option(o, "compl_inf_tol", 1e-4 * scale);
  set_option(o, "bound_relax_factor", 0.0);
  set_option(o, "bound_push", 1e-4);
  set_option(o, "bound_frac", 1e-4);
  set_option(o, "max_soc", 0);
  set_option(o, "min_refinement_steps", 0);
  if (warm) {
    set_option(o, "warm_start_init_point", std::string("yes"));
    set_option(o, "warm_start_bound_push", 1e-9);
    set_option(o, "warm_start_bound_frac", 1e-9);
    set_option(o, "warm_start_mult_bound_push", 1e-9);
    set_option(o, "mu_init", 1e-9);
  }
}

// The problem is checked, x is inside the bounds and n ≥ 1 (NlpBackend::minimize).
SolveResult IpoptBackend::do_minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options) {
  // One Ipopt solve at a time in the process: Debian's MUMPS (libdmumps_seq, Ipopt's linear
  // solver) keeps its load-balancing state in Fortran module variables, and two solves in two
  // threads (the Python module's thread pools) abort in DMUMPS_LOAD_INIT ("PB allocation"),
  // measured with 60 random scenes in 4 threads. Held until the application, and with it MUMPS's
  // instance, is gone (declared before app: destroyed after it). The rest of a solve (CHOLMOD,
  // the exact solver, the certificate) runs in parallel.
  static std::mutex mumps_mutex;
  const std::lock_guard<std::mutex> one_at_a_time(mumps_mutex);
  const Index n = problem.f->size();
  SolveResult result;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  // Exceptions from our objective (e.g. hemicontact::Error) reach the caller instead of becoming
  // NonIpopt_Exception_Thrown.
  app->RethrowNonIpoptException(true);
  const int print_level = std::clamp(options.print_level, 0, 12);
  // Initialize() sets the console verbosity from print_level; until then errors of Set*Value
  // would print at Ipopt's default level, so silence them now (our Error names the option).
  if (const auto console = app->Jnlst()->GetJournal("console"); Ipopt::IsValid(console)) {
    console->SetAllPrintLevels(static_cast<Ipopt::EJournalLevel>(print_level));
    console->SetPrintLevel(Ipopt::J_DBG, Ipopt::J_NONE);
  }

  const bool warm = m_z_L.size() == n && m_z_U.size() == n;
  Vec g0;
  problem.f->gradient(x, g0);
  const double g0_norm = g0.size() ? g0.cwiseAbs().maxCoeff() : 0.0;
  double scale = std::isfinite(g0_norm) ? std::max(1.0, g0_norm) : 1.0;
  if (warm) scale = std::max(scale, m_scale);

  Ipopt::OptionsList& o = *app->Options();
  set_ipopt_options(o, options, print_level, scale, warm);
  // Pass-through options last, so they override any default above. They are set before
  // Initialize() so that file options such as "output_file" take effect.
  for (const auto& [key, value] : options.extra) set_passthrough(*app, key, value);

  // An empty file name skips the options file: Initialize() alone would read ./ipopt.opt (the
  // "option_file_name" default) from whatever directory the program runs in. std::string is
  // spelled out because Ipopt >= 3.12 adds Initialize(bool), which a bare "" would select.
  const Ipopt::ApplicationReturnStatus init = app->Initialize(std::string());
  if (init != Ipopt::Solve_Succeeded)
    throw Error(std::string("ipopt: Initialize failed: ") + status_name(init), EXIT_INPUT);

  IpoptTnlp::Setup setup;
  setup.x = x;
  if (warm) {
    setup.z_L = m_z_L;
    setup.z_U = m_z_U;
  }
  setup.obj_scaling = 1.0 / scale;
  o.GetNumericValue("nlp_lower_bound_inf", setup.lower_inf, "");
  o.GetNumericValue("nlp_upper_bound_inf", setup.upper_inf, "");
  Ipopt::SmartPtr<IpoptTnlp> tnlp = new IpoptTnlp(problem, std::move(setup));
  log_debug() << "ipopt: n = " << n << ", " << (warm ? "warm" : "cold") << " start, tol " << options.tol
              << " relative to G = " << scale << ", max_iter " << options.max_iter;
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(Ipopt::GetRawPtr(tnlp));
  check_interrupt();  // the intermediate callback stopped Ipopt for the host's interrupt
  // Ipopt catches std::bad_alloc (its own and MUMPS's allocations) and returns this status: the
  // memory message and code of every other allocation failure, not "not converged".
  if (status == Ipopt::Insufficient_Memory)
    memory_error("Ipopt (n = " + std::to_string(n) + " unknowns; its sparse factorization, MUMPS, could not allocate)");

  const IpoptTnlp::Result& r = tnlp->result();
  if (r.finalized) x = r.x;  // Ipopt's last iterate: strictly inside the bounds (no relaxation)
  result.status = map_status(status);
  result.message = std::string("ipopt: ") + status_name(status);
  result.evaluations = r.f_evaluations;
  result.f = r.finalized ? r.f : problem.f->value(x);
  const Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics();
  result.iterations = Ipopt::IsValid(stats) ? stats->IterationCount() : std::max(0, r.callbacks - 1);
  if (Ipopt::IsValid(stats)) {
    Ipopt::Number dual_inf = 0, constr_viol = 0, compl_inf = 0, kkt = 0;
    stats->Infeasibilities(dual_inf, constr_viol, compl_inf, kkt);
    log_debug() << "ipopt: " << status_name(status) << " after " << result.iterations << " iterations, f = " << result.f
                << ", unscaled dual_inf " << dual_inf << ", compl " << compl_inf;
  }

  // Keep the multipliers only from a usable solve: after a failure they describe a bad point and
  // would mislead the next warm start more than a cold start would.
  if (result.ok() && r.finalized) {
    m_z_L = r.z_L;
    m_z_U = r.z_U;
    m_scale = scale;
  } else {
    m_z_L.resize(0);
    m_z_U.resize(0);
  }
  return result;
}

}  // namespace

std::unique_ptr<NlpBackend> make_ipopt_backend() { return std::make_unique<IpoptBackend>(); }

}  // namespace hemicontact
