#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/solver/solve.hpp>

#include <hemicontact/check/certificate.hpp>
#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/check/smallness.hpp>
#include <hemicontact/contact/mollified_law.hpp>
#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/energy/contact_energy.hpp>
#include <hemicontact/energy/elastic_energy.hpp>
#include <hemicontact/energy/nonlinear_elastic_energy.hpp>
#include <hemicontact/energy/total_energy.hpp>
#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/solver/exact_inner.hpp>
#include <hemicontact/solver/method_choice.hpp>
#include <hemicontact/solver/outer_loop.hpp>
#include <hemicontact/solver/polish.hpp>
#include <hemicontact/solver/ssn.hpp>
#include <hemicontact/solver/run_messages.hpp>
#include <hemicontact/solver/sparse_checks.hpp>

#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

namespace hemicontact {
namespace {

double rel_change(const Vec& a, const Vec& b) {
  if (a.size() == 0) return 0.0;
  const double s = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  return s > 0 ? (a - b).cwiseAbs().maxCoeff() / s : 0.0;
}

// What the continuation / fixed-point loop works on: an energy in the solver's unknowns z, the
// bounds, where each Γ3 node's (ν, τ) unknowns are in z, and the map back to the reduced x.
struct Formulation {
  std::string name;                           // "full" or "condensed"
  std::unique_ptr<TotalEnergy> energy;        // Π_λ(z), unscaled
  NodalDofs nd;                               // Γ3 node k: z[nd.first[k] + c]
  Vec lower, upper;                           // bounds on z
  Vec z_free;                                 // the unconstrained elastic solution, in z
  std::shared_ptr<const Condensation> cond;   // condensed only (shared: the elastic term holds its S)
  std::shared_ptr<const NodalLayout> layout;  // Γ3 nodes' blocks in the energy's Hessian pattern
  std::shared_ptr<NormalComplianceEnergy> normal;
  std::shared_ptr<FrictionEnergy> friction;
  std::shared_ptr<CondensedElasticEnergy> condensed_elastic;  // condensed: holds y_C = (K⁻¹f)_C
  std::shared_ptr<LoadEnergy> load;                           // full: holds f
  double load_scale = 1;                                      // loads are load_scale × the model's
  MethodChoice choice;                                        // how name was chosen, and why
  // Full formulation: the elastic factor, kept only until the set-up's checks have read it (S⁻¹ by
  // solves for their Lanczos: sparse_checks.hpp); released before the backend factorizes its own.
  std::shared_ptr<SparseCholesky> elastic_factor;
  // x from z; with scaled loads the interior is recovered for the scaled f (y scales linearly).
  Vec to_x(const Vec& z) const { return cond ? cond->recover(z, load_scale) : z; }
};

// The method (solver/method_choice.hpp) from the scene's numbers, before any numeric work; the
// condensation's symbolic analysis it reads is returned in @p plan, to be factorized if condensed.
MethodChoice choose_formulation(const Model& md, const SolveOptions& opt, std::shared_ptr<Condensation>& plan) {
  // Static condensation eliminates the interior through K⁻¹, exact only when F is linear; for a
  // nonlinear F the interior equilibrium is itself nonlinear, so the problem is solved in full.
  if (opt.formulation == "condensed" && !md.material->is_linear())
    input_error("solver.formulation = condensed: static condensation is exact only for a linear material (" +
                md.material->describe() + "); use full or auto");
  // ssn is the exact solver of the full space (solver/ssn.hpp): it reads K_x, not a Schur complement.
  if (opt.backend == SSN_BACKEND) {
    if (!md.material->is_linear())
      input_error("solver.backend = ssn: the full-space semismooth Newton needs a linear material (" +
                  md.material->describe() + "); use the design's path (solver.backend = auto)");
    if (opt.formulation == "condensed")
      input_error("solver.backend = ssn runs in the full space: use solver.formulation = full or auto");
    MethodChoice c;
    c.chosen = "full";
    c.backend = SSN_BACKEND;
    c.reason = "solver.backend = ssn runs in the full space (set explicitly)";
    return c;
  }
  SceneNumbers n;
  n.dim = md.dim();
  n.dofs = md.dofs.n_free();
  n.gamma3_unknowns = md.dim() * md.contact.size();
  n.linear_material = md.material->is_linear();
  n.memory_bytes = available_memory_bytes();
  n.cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (n.linear_material && n.gamma3_unknowns > 0 && opt.formulation != "full") {
    plan = std::make_shared<Condensation>(md.Kx.lower(), n.gamma3_unknowns, opt.ordering);
    n.factor_nnz = plan->factor_nnz();
    n.factor_flops = plan->predicted_flops();
    n.full_factor_flops_low = factor_flops_lower_bound(md.Kx.lower());
  }
  // The full formulation's factorization: the same analysis with no Γ3 block, only when asked.
  const auto full_flops = [&] { return Condensation(md.Kx.lower(), 0, opt.ordering).predicted_flops(); };
  MethodChoice c = choose_method(n, opt, full_flops);
  if (c.chosen != "condensed") plan.reset();
  return c;
}

// Whether ssn answers: named, or auto's choice for a full formulation (method_choice.hpp), unless
// solver.options are passed to the engine's default backend, which then keeps the solve.
bool runs_ssn(const MethodChoice& c, const SolveOptions& opt) {
  return opt.backend == SSN_BACKEND || (c.backend == SSN_BACKEND && opt.backend_options.extra.empty());
}

Formulation make_formulation(const Model& md, const SolveOptions& opt, std::map<std::string, double>& timings) {
  Formulation F;
  std::shared_ptr<Condensation> plan;
  F.choice = choose_formulation(md, opt, plan);
  F.name = F.choice.chosen;
  log_info() << "method: " << describe(F.choice);
  const Index nc = md.contact.size();
  const int d = md.dim();
  F.nd.dim = d;
  F.nd.w = md.contact.w;
  auto t0 = clk::now();
  if (F.name == "condensed") {
    plan->factorize(md.Kx.lower(), md.fx);  // the analysis the choice read, not a second one
    F.cond = plan;
    timings["condensation_analyze"] = F.cond->analyze_seconds();
    timings["condensation_factorize"] = F.cond->factorize_seconds();
    timings["condensation_schur"] = F.cond->schur_seconds();
    log_info() << "condensation: " << F.cond->ordering() << " ordering of the interior node graph, factor in "
               << F.cond->analyze_seconds() + F.cond->factorize_seconds() << " s";
    F.energy = std::make_unique<TotalEnergy>(d * nc, dense_lower_pattern(d * nc));
    F.condensed_elastic = std::make_shared<CondensedElasticEnergy>(std::shared_ptr<const Mat>(F.cond, &F.cond->S()),
                                                                   F.cond->y_C(), F.cond->constant());
    F.energy->add(F.condensed_elastic);
    for (Index k = 0; k < nc; ++k) F.nd.first.push_back(d * k);
    F.z_free = F.cond->y_C();
  } else if (runs_ssn(F.choice, opt)) {
    // ssn factorizes its own Newton matrices and needs no scales: no elastic factorization here,
    // which the checks alone would have read (an extra factorization: on the strip 1000 × 1, 1.4 ms
    // to factor and 7.3 ms of Lanczos for (21), of a 23 ms solve).
    F.z_free = Vec::Zero(md.dofs.n_free());
  } else {
    F.elastic_factor = std::make_shared<SparseCholesky>(opt.ordering);
    SparseCholesky& chol = *F.elastic_factor;
    chol.compute(md.Kx.lower());
    F.z_free = chol.solve(md.fx);
    timings["linear_elastic_factor"] = chol.analyze_seconds() + chol.factorize_seconds();
  }
  if (F.name == "full") {
    // z_free (from K(0) for a nonlinear law) only sets the solver's scales.
    if (md.material->is_linear()) {
      auto elastic = std::make_shared<ElasticEnergy>(md.Kx);
      F.energy = std::make_unique<TotalEnergy>(md.dofs.n_free(), elastic->lower());
      F.energy->add(elastic);
    } else {
      auto elastic = std::make_shared<NonlinearElasticEnergy>(md.mesh, md.material, md.dofs);  // copies both
      F.energy = std::make_unique<TotalEnergy>(md.dofs.n_free(), elastic->lower());
      F.energy->add(elastic);
    }
    F.load = std::make_shared<LoadEnergy>(md.fx);
    F.energy->add(F.load);
    for (Index k = 0; k < nc; ++k) F.nd.first.push_back(md.dofs.contact_dof(k, 0));
  }
  timings["factorization_total"] = since(t0);
  const Index n = F.energy->size();
  F.lower = Vec::Constant(n, -INF);
  F.upper = Vec::Constant(n, INF);
  for (Index k = 0; k < nc; ++k)
    if (std::isfinite(md.contact.g[k])) F.upper[F.nd.first[k]] = md.contact.g[k];
  // A roller on a Γ3 node fixes local tangential unknowns (ContactNodes::fixed_local): the bounds
  // 0 ≤ x_τ ≤ 0 keep the node's frame and the uniform d unknowns per node.
  if (!md.contact.fixed_local.empty())
    for (Index k = 0; k < nc; ++k)
      for (int c = 1; c < d; ++c)
        if (md.contact.fixed_local[k] & (1u << c)) F.lower[F.nd.first[k] + c] = F.upper[F.nd.first[k] + c] = 0;
  F.layout = std::make_shared<const NodalLayout>(F.nd, F.energy->hessian_pattern());
  return F;
}

// The contact terms, complete from the start: their widths are the final ones (absolute, U_s the
// displacement scale) until a solve sets each stage's, and λ = 0 until it freezes the bounds.
void add_contact_terms(Formulation& F, const Model& md, const SolveOptions& opt, double U_s) {
  if (md.normal_law) {
    F.normal = std::make_shared<NormalComplianceEnergy>(
        F.layout, std::make_shared<const MollifiedLaw>(md.normal_law, opt.eps_nu * U_s, "solver.eps_nu"));
    F.energy->add(F.normal);
  }
  if (md.friction) {
    F.friction = std::make_shared<FrictionEnergy>(F.layout, opt.eps_tau * U_s, Vec::Zero(md.contact.size()));
    F.energy->add(F.friction);
  }
}

}  // namespace

// The solve's working state and its steps, in the order solve() calls them (solve.hpp's pseudo-code).
struct ContactSolver::Impl {
  const Model* model;  // the model the answers are evaluated on (a load-scaled copy: set_loads)
  SolveOptions opt;
  std::unique_ptr<NlpBackend> backend;
  bool linear = false;  // no contact law and no obstacle: one linear solve
  Vec x_linear;         // its answer
  Formulation F;
  SmallnessReport smallness;
  std::map<std::string, double> setup_timings;
  std::vector<std::string> skipped;
  double U_s = 1, F_s = 1;
  bool U_s_known = false;  // U_s from solver.x_scale or the unconstrained elastic solution (not the fallback 1)
  std::unique_ptr<ScaledObjective> scaled;
  NlpProblem prob;
  std::vector<std::pair<double, double>> schedule;  // (eps_tau, eps_nu), relative
  bool lagged = false;                              // λ = F_b(u_ν) depends on the answer: the outer fixed point runs
  InnerConvexity convexity;                         // of Φ_λ, decided once at set-up
  mutable std::optional<Gamma3Spectrum> spectrum_;  // k_1, k_1ν by Lanczos (large Γ3 only), once
  std::string requested_backend;  // solver.backend as given (opt.backend may become the choice's ssn)
  Impl(const Model& m, const SolveOptions& o) : model(&m), opt(o), requested_backend(o.backend) {}

  /// More Γ3 unknowns than check.dense_max_unknowns: no dense Γ3 matrix for the checks.
  bool dense_checks_too_large() const { return model->dim() * model->contact.size() > opt.dense_max_unknowns; }
  /// Full formulation chosen by auto for a linear material (Γ3 large against the interior): (21)
  /// by Lanczos from the elastic factor where the set-up made one (a backend that needs its
  /// scales), not a second factorization (the Gram matrix's); where ssn answers there is none.
  bool automatic_full() const {
    return F.choice.automatic && F.name == "full" && model->material->is_linear() && model->contact.size() > 0;
  }
  /// The Lanczos spectrum from the factor at hand (the condensation's L_CC, or the elastic factor
  /// while the set-up holds it); null when neither is there.
  /// @param with_k1 false: k_1ν alone (the inner convexity's) where (21) is not asked; a later
  /// caller that needs k_1 too gets it computed then (the condensation's factor is kept).
  const Gamma3Spectrum* spectrum(bool with_k1 = true) const;
  SmallnessReport sparse_smallness() const;
  void report_smallness(SmallnessReport r, double& t_smallness);
  void take_choice_backend();

  /// One solve from a start: the answer being built and the iterate in scaled unknowns zs = z/U_s.
  struct Run {
    Solution sol;
    Vec zs;
    Vec prev_c;       // Γ3 unknowns after the previous minimization
    int k_total = 0;  // minimizations so far
    std::vector<int> prev_status;  // status signature after the previous stage (exact_due)
  };

  Solution header() const;
  Solution ssn_answer(const Vec* z0, clk::time_point t_start);
  Solution ssn_handover(Solution failed, const Vec* z0) const;
  Solution linear_answer(clk::time_point t_start) const;
  bool solve_linear(clk::time_point t_start);
  void note_skipped();
  void check_inner_convexity();
  void make_schedule();
  Run start(const Vec* z0);
  struct Stepper;  // the steps of the outer algorithm (outer_loop.hpp) on a Run
  void set_smoothing(size_t stage);
  OuterIteration minimize(Run& run, size_t stage);
  LambdaChange relax_lambda(Run& run);
  /// The polish (when @p attempt and solver.polish), then x and u from the iterate.
  void polish(Run& run, bool attempt = true);
  bool all_separated(const Vec& z) const;
  bool exact_available() const { return opt.exact && F.cond != nullptr; }
  std::vector<int> status_signature(const Run& run, size_t stage) const;
  std::string exact_due(Run& run, size_t stage, bool backend_failed);
  /// @p stage: the continuation stage it takes over after, −1 before any (exact_first).
  void exact_solve(Run& run, int stage, const std::string& reason);
  std::string exact_first() const;
  void certify(Run& run, clk::time_point t_start) const;
  Solution continuation(const Vec* z0, clk::time_point t_start);
  Vec gamma3(const Vec& z) const;
  Vec friction_bounds(const Vec& zs) const;
};

ContactSolver::ContactSolver(const Model& md, const SolveOptions& opt) : m(std::make_unique<Impl>(md, opt)) {
  const auto t_start = clk::now();
  Impl& I = *m;
  // The petsc engine is a program of its own (hemicontact-mpi, exec'd by `hemicontact solve`).
  if (opt.engine == "petsc")
    input_error("solver.engine = " + opt.engine +
                ": this command runs the cholmod engine only; the petsc engine runs `hemicontact solve` "
                "(hemicontact-mpi)");
  // ssn is no NLP backend: ContactSolver runs it itself (ssn_answer).
  if (opt.backend != SSN_BACKEND) {
    I.backend = make_backend(opt.backend);
    // The backend's options are checked now: the exact solver may answer without running it.
    I.backend->check_options(opt.backend_options);
  }

  // Nothing nonlinear and no obstacle: one sparse Cholesky solve is the answer (no backend at all).
  if (I.solve_linear(t_start)) return;

  // The smallness condition (21) is a diagnostic, timed apart from the solve (timings
  // "smallness") and switched off by check.smallness = false. By default (check.smallness_method
  // = auto) it is decided from the condensation the solve makes anyway (no factorization:
  // check/smallness.hpp), and only when that bracket cannot decide is the ε:ε Gram matrix
  // factorized. In 3D the bracket is rarely decisive (L_F/m_F = 1 + 3λ/(2μ) = 3.25 at ν = 0.3),
  // so there, as with method = exact, the exact evaluation comes first, before the solve's own
  // factorization exists: one factor in memory at a time, not two. Above check.dense_max_unknowns
  // Γ3 unknowns no dense Γ3 matrix and no extra factorization: the bracket from Lanczos on the
  // solve's own factor decides, or the report says why it could not (sparse_checks.hpp).
  double t_smallness = 0;
  const bool exact_first =
      opt.smallness && (opt.smallness_method == "exact" || (md.dim() == 3 && !I.dense_checks_too_large()));
  if (exact_first) I.report_smallness(evaluate_smallness(md), t_smallness);

  I.F = make_formulation(md, opt, I.setup_timings);
  Formulation& F = I.F;
  I.take_choice_backend();
  if (opt.smallness && !exact_first) I.report_smallness(smallness(), t_smallness);
  // A caller that asks for (21) only after the solve (the adaptive loop's final mesh) finds the
  // spectrum already read from the elastic factor, which is released now.
  if (!opt.smallness && F.elastic_factor && (I.automatic_full() || I.dense_checks_too_large())) I.spectrum();
  F.elastic_factor.reset();  // the checks have read it; the backend factorizes its own matrices
  I.lagged = md.friction && md.friction->depends_on_u_nu();
  I.note_skipped();

  // Scales from the unconstrained elastic solution: U_s sets the smoothing widths and, with
  // F_s = ‖f‖∞, nondimensionalizes the NLP so that tolerances mean the same for the printed
  // (u ~ 1e-7) and the scaled (u ~ 1e-1) scene.
  const double z_max = F.z_free.size() ? F.z_free.cwiseAbs().maxCoeff() : 0.0;
  I.U_s_known = opt.x_scale > 0 || z_max > 0;
  I.U_s = opt.x_scale > 0 ? opt.x_scale : z_max > 0 ? z_max : 1.0;
  I.F_s = md.fx.size() && md.fx.cwiseAbs().maxCoeff() > 0 ? md.fx.cwiseAbs().maxCoeff() : 1.0;
  add_contact_terms(F, md, opt, I.U_s);
  I.check_inner_convexity();
  I.scaled = std::make_unique<ScaledObjective>(*F.energy, I.U_s, I.F_s * I.U_s);
  I.prob.f = I.scaled.get();
  I.prob.lower = F.lower / I.U_s;
  I.prob.upper = F.upper / I.U_s;

  I.make_schedule();
  I.setup_timings["setup_total"] = since(t_start) - t_smallness;
}

// Nothing nonlinear and no obstacle: one sparse Cholesky solve is the answer (no backend at all).
// True if that is the case (the answer is then x_linear).
bool ContactSolver::Impl::solve_linear(clk::time_point t_start) {
  const Model& md = *model;
  if (!md.normal_law && !md.friction && md.gap.is_infinite() && md.material->is_linear() &&
      md.contact.fixed_local.empty()) {
    linear = true;
    SparseCholesky chol(opt.ordering);
    chol.compute(md.Kx.lower());
    x_linear = chol.solve(md.fx);
    setup_timings["linear_elastic_factor"] = chol.analyze_seconds() + chol.factorize_seconds();
    skipped.push_back("backend: linear elasticity, solved by one sparse Cholesky factorization");
    setup_timings["setup_total"] = since(t_start);
    return true;
  }
  return false;
}

// What the model leaves out, in the answer's skipped list.
void ContactSolver::Impl::note_skipped() {
  const Model& md = *model;
  if (!md.material->is_linear()) {
    const std::string why =
        "condensation: nonlinear material, static condensation is not exact (formulation " + F.name + ")";
    log_info() << why;
    skipped.push_back(why);
  }
  log_info() << "formulation " << F.name << ": " << F.energy->size() << " unknowns ("
             << setup_timings["factorization_total"] << " s to factor" << (F.cond ? " and condense" : "") << ")";
  if (!md.normal_law) skipped.push_back("normal_compliance: no soft layer (contact.normal_law.type = none)");
  if (!md.friction) skipped.push_back("friction: frictionless (contact.friction.type = none)");
  if (md.friction && !md.friction->depends_on_u_nu()) skipped.push_back("fixed_point: F_b does not depend on u_nu");
  if (!md.friction) skipped.push_back("fixed_point: no friction");
  if (md.gap.is_infinite()) skipped.push_back("bounds: no rigid obstacle (g = inf)");
}

// Whether the inner problem (λ frozen) is strongly convex: decided once, on the condensed S.
void ContactSolver::Impl::check_inner_convexity() {
  const Model& md = *model;
  if (F.cond) {
    const auto t_cvx = clk::now();
    // Above check.dense_max_unknowns from k_1ν (sparse_checks.hpp), not a dense Cholesky of S − αW_ν.
    convexity = dense_checks_too_large()
                    ? convexity_from_spectrum(*spectrum(opt.smallness), md.normal_law.get())
                    : inner_convexity(F.cond->S(), md.contact.w, md.dim(), md.normal_law.get(),
                                      opt.convexity_max_unknowns);
    setup_timings["inner_convexity"] = since(t_cvx);
    if (convexity.checked)
      log_info() << "inner problem (lambda frozen): "
                 << (dense_checks_too_large() ? "k_1nu - alpha (Lanczos)" : "smallest eigenvalue of S - alpha W_nu")
                 << " = " << convexity.min_eigenvalue
                 << " (alpha = " << convexity.softening
                 << "): strongly convex: " << (convexity.strongly_convex ? "yes" : "no");
  } else {
    convexity.note = "not checked: needs the condensed formulation";
  }
}

// Continuation schedule: ε_s = max(ε_final, ε_start·factor^s), until both widths are final.
void ContactSolver::Impl::make_schedule() {
  const Model& md = *model;
  if (md.normal_law || md.friction) {
    schedule = smoothing_schedule(opt);
  } else {
    schedule.emplace_back(0.0, 0.0);
    skipped.push_back("continuation: nothing is smoothed");
  }
}

ContactSolver::~ContactSolver() = default;

void ContactSolver::Impl::report_smallness(SmallnessReport r, double& t_smallness) {
  smallness = std::move(r);
  t_smallness += smallness.seconds;
  setup_timings["smallness"] = t_smallness;
  const SmallnessReport& q = smallness;
  if (q.computed)
    log_info() << "smallness (21), " << q.method << ": L_Fb/lambda_1 + alpha_j/lambda_1nu = " << q.L_Fb << "/"
               << q.lambda_1 << " + " << q.alpha_j << "/" << q.lambda_1nu << " = " << q.lhs
               << (q.holds ? " < " : " >= ") << "m_F = " << q.m_F << ": uniqueness guaranteed: "
               << (q.holds ? "yes" : "no") << (q.note.empty() ? "" : " (" + q.note + ")");
  else if (!q.note.empty())
    log_info() << "smallness (21): " << q.note;
}

// The backend the method choice resolved solver.backend = auto to (method_choice.hpp), unless the
// scene passes options through to the engine's default backend (solver.options), which another
// backend would refuse.
void ContactSolver::Impl::take_choice_backend() {
  if (!backend || F.choice.backend.empty() || F.choice.backend == backend->name()) return;  // ssn: no NLP backend
  if (runs_ssn(F.choice, opt)) {
    opt.backend = SSN_BACKEND;  // solve() runs ssn_answer; report.json still says "auto" was asked
    return;
  }
  if (!opt.backend_options.extra.empty()) {
    F.choice.reason += "; backend " + backend->name() + " kept: solver.options are passed to it";
    F.choice.backend = backend->name();
    return;
  }
  backend = make_backend(F.choice.backend);
  backend->check_options(opt.backend_options);
}

const Gamma3Spectrum* ContactSolver::Impl::spectrum(bool with_k1) const {
  if (spectrum_ && (spectrum_->has_k1 || !with_k1)) return &*spectrum_;
  const Model& md = *model;
  const int d = md.dim();
  const Index m = d * md.contact.size(), n = md.dofs.n_free();
  std::function<Vec(const Vec&)> apply;
  std::string what;
  if (F.cond) {
    apply = [this](const Vec& b) { return F.cond->solve_schur(b); };
    what = "S^-1 = L_CC^-T L_CC^-1 (the condensation's factor)";
  } else if (F.elastic_factor) {
    // The Γ3 unknowns are the trailing m of x (the condensation's layout): S⁻¹ = (K⁻¹)_CC.
    apply = [this, m, n](const Vec& b) {
      Vec x = Vec::Zero(n);
      x.tail(m) = b;
      return Vec(F.elastic_factor->solve(x).tail(m));
    };
    what = "S^-1 = (K^-1)_CC (solves with the elastic factor)";
  } else {
    return nullptr;
  }
  // Enough digits once (21) and the inner-convexity test are both decided by the brackets.
  const auto decided = [this](const Gamma3Spectrum& s) {
    return (!s.has_k1 || smallness_from_spectrum(*model, s).computed) &&
           convexity_from_spectrum(s, model->normal_law.get()).checked;
  };
  spectrum_ = gamma3_spectrum(apply, md.contact.w, d, opt, what, decided, with_k1);
  return &*spectrum_;
}

// (21) above check.dense_max_unknowns: the bracket from the Lanczos spectrum, or why there is none.
SmallnessReport ContactSolver::Impl::sparse_smallness() const {
  if (const Gamma3Spectrum* s = spectrum()) return smallness_from_spectrum(*model, *s);
  SmallnessReport r;
  r.note = "not evaluated: more than check.dense_max_unknowns Gamma3 unknowns and no factor at hand (ssn factorizes "
           "only its own Newton matrices; check.smallness_method = exact evaluates (21) with one factorization of the "
           "eps:eps Gram matrix)";
  return r;
}

SmallnessReport ContactSolver::smallness() const {
  const Impl& I = *m;
  const Model& md = *I.model;
  // The constructor's choice too: the bracket from the condensation where there is one (2D, method
  // auto), the exact evaluation otherwise; above check.dense_max_unknowns the bracket by Lanczos.
  if (I.opt.smallness_method == "exact") return evaluate_smallness(md);
  if (I.dense_checks_too_large() || I.automatic_full()) return I.sparse_smallness();
  if (md.dim() == 3 || !I.F.cond) return evaluate_smallness(md);
  return evaluate_smallness(md, I.F.cond->S());
}

void ContactSolver::set_backend(const std::string& name) {
  m->backend = make_backend(name);
  m->opt.backend = name;
}

void ContactSolver::set_exact_start(const std::string& when) {
  if (when != "auto" && when != "convex" && when != "always" && when != "never")
    throw Error("ContactSolver::set_exact_start: unknown value '" + when + "'", EXIT_INTERNAL);
  m->opt.exact_start = when;
}

void ContactSolver::set_loads(const Model& scaled, double s) {
  Impl& I = *m;
  if (scaled.dofs.n_free() != I.model->dofs.n_free() || scaled.contact.size() != I.model->contact.size())
    throw Error("ContactSolver::set_loads: the model differs in more than its loads", EXIT_INTERNAL);
  I.model = &scaled;
  if (I.linear) {
    I.x_linear *= s / I.F.load_scale;
  } else if (I.F.cond) {
    // y = K⁻¹(s f) = s y and −½(s f)ᵀ(s y) = s² c: the factorization and S are untouched.
    I.F.condensed_elastic->set_load(s * I.F.cond->y_C(), s * s * I.F.cond->constant());
  } else {
    I.F.load->set_load(scaled.fx);
  }
  I.F.load_scale = s;
}

Index ContactSolver::size() const { return m->linear ? m->model->dofs.n_free() : m->F.energy->size(); }

const std::string& ContactSolver::formulation() const { return m->F.name; }

double ContactSolver::length_scale() const { return m->U_s_known ? m->U_s : 0.0; }

Vec ContactSolver::to_unknowns(const Vec& x) const {
  if (m->linear || !m->F.cond) return x;
  return x.tail(m->F.cond->m());
}

const NodalDofs& ContactSolver::contact_dofs() const { return m->F.nd; }

ContactSolver::LaggedEnergy ContactSolver::lagged_energy(const Solution& sol) {
  Impl& I = *m;
  if (I.linear) throw Error("ContactSolver::lagged_energy: a linear solve has no contact energy", EXIT_INTERNAL);
  const Vec z = to_unknowns(sol.x);
  if (I.F.normal) I.F.normal->set_eps(I.opt.eps_nu * I.U_s, "solver.eps_nu");
  if (I.F.friction) {
    I.F.friction->set_eps(I.opt.eps_tau * I.U_s);
    Vec l(I.model->contact.size());
    for (Index k = 0; k < I.model->contact.size(); ++k) l[k] = I.model->friction->F(z[I.F.nd.first[k]]);
    I.F.friction->set_lambda(l);
  }
  return {*I.F.energy, z, I.F.nd};
}

// The algorithm (solve.hpp): ε-continuation stages, each a minimization with λ frozen and a
// relaxed λ update (to the fixed point at the final ε), then the exact polish and the certificate.
Solution ContactSolver::solve(const Vec* z0) {
  const auto t_start = clk::now();
  Impl& I = *m;
  if (I.linear) return I.linear_answer(t_start);
  if (I.opt.backend == SSN_BACKEND) {
    Solution s = I.ssn_answer(z0, t_start);
    return s.ok() ? s : I.ssn_handover(std::move(s), z0);
  }
  // What the report says of the backend: whether it ran, and why not when it did not.
  const auto done = [&](Solution&& s, const std::string& not_run = "") -> Solution {
    s.backend_use.ran = s.work_of(s.backend).minimizations > 0;
    if (!s.backend_use.ran) s.backend_use.not_run = not_run.empty() ? "not needed" : not_run;
    return std::move(s);
  };
  // Where the backend's stage cannot change the answer (solver.exact.start), the exact solver starts
  // at once; a certified answer ends the solve before any ε-stage, anything else is forgotten and
  // the design's path runs from the same start (its hand-over rules still apply).
  std::string first_note;
  if (const std::string why = I.exact_first(); !why.empty()) {
    Impl::Run first = I.start(z0);
    I.set_smoothing(0);
    first.sol.start_energy = I.F.energy->value(I.U_s * first.zs);
    I.exact_solve(first, -1, why);
    I.certify(first, t_start);
    if (first.sol.ok()) {
      first.sol.skipped.push_back("backend: " + I.backend->name() + " not run: " + why + " (solver.exact.start = " +
                                  I.opt.exact_start + ")");
      log_info() << "backend " << I.backend->name() << ": not run: " << why;
      return done(std::move(first.sol), why);
    }
    if (!I.opt.exact_start_fallback) {
      // No continuation after a failed start (solve_options.hpp: it certified none of the 1000
      // random scenes where the start failed, and costs most of a failing solve): the answer stands
      // as not certified, with its reason and the key that would try the continuation.
      first.sol.skipped.push_back("continuation: not run after the exact solver's start was not certified "
                                  "(solver.exact.fallback = false; true tries it, as does solver.exact.start = never)");
      log_info() << "exact solver from the start: not certified (" << first.sol.message
                 << "); the continuation is not tried (solver.exact.fallback = false)";
      return done(std::move(first.sol), why + "; the exact solver's answer was not certified and "
                                              "solver.exact.fallback = false");
    }
    first_note = "the exact solver from the start was not certified (" + first.sol.message +
                 "), so the continuation ran; ";
    log_info() << "exact solver from the start: not certified (" << first.sol.message
               << "); the continuation runs from the same start";
  }
  Solution sol = I.continuation(z0, t_start);
  if (!first_note.empty()) sol.handover.note = first_note + sol.handover.note;
  // The last resort, where the exact solver was not tried from the start: the continuation's
  // neighbourhood can lead the coupled fixed point astray when Φ_λ is not strongly convex (several
  // stationary points), while a start from scratch is certified. Only a certified answer replaces
  // the continuation's, and it says so; otherwise the continuation's answer and verdict stand.
  if (!sol.ok() && first_note.empty() && I.exact_available() && I.opt.exact_start != "never") {
    Impl::Run last = I.start(z0);
    last.sol.start_energy = sol.start_energy;
    I.exact_solve(last, -1, "the continuation's answer was not certified (" + sol.message + ")");
    I.certify(last, t_start);
    if (last.sol.ok()) {
      last.sol.skipped.push_back("continuation: its answer was not certified; the exact solver's from the start was");
      // The backend did run, in the discarded attempt: its minimizations stay in the record, first.
      const int shift = static_cast<int>(sol.history.size());
      for (auto& h : last.sol.history) h.k += shift;
      last.sol.history.insert(last.sol.history.begin(), sol.history.begin(), sol.history.end());
      return done(std::move(last.sol));
    }
    log_info() << "exact solver from the start: not certified either (" << last.sol.message << ")";
    sol.timings["solve_total"] = last.sol.timings["solve_total"];  // the time both took
  }
  return done(std::move(sol));
}

// The CHOLMOD engine's steps of the outer algorithm (outer_loop.hpp): the backend's minimizations
// on the condensed or full problem, the exact solver behind them, the polish on a copy.
struct ContactSolver::Impl::Stepper final : OuterStepper {
  Impl& I;
  Run& run;
  clk::time_point t_start;
  Stepper(Impl& impl, Run& r, clk::time_point t) : I(impl), run(r), t_start(t) {}
  Solution& solution() override { return run.sol; }
  size_t stage_count() const override { return I.schedule.size(); }
  bool lagged() const override { return I.lagged; }
  std::string backend_name() const override { return I.backend->name(); }
  void set_smoothing(size_t stage) override {
    I.set_smoothing(stage);
    if (stage == 0) run.sol.start_energy = I.F.energy->value(I.U_s * run.zs);
  }
  OuterIteration minimize(size_t stage) override { return I.minimize(run, stage); }
  LambdaChange relax_lambda() override { return I.relax_lambda(run); }
  bool polish_exists() const override { return I.F.cond != nullptr; }
  std::optional<Solution> certified_copy() override {
    Run trial = run;
    I.polish(trial);
    I.certify(trial, t_start);
    if (!(trial.sol.certificate.passed && trial.sol.polish.accepted)) return std::nullopt;
    return std::move(trial.sol);
  }
  Solution finish() override {
    I.polish(run);
    I.certify(run, t_start);
    return std::move(run.sol);
  }
  void check_interrupt() override { hemicontact::check_interrupt(); }
  bool exact_available() const override { return I.exact_available(); }
  std::string exact_due(size_t stage, bool backend_failed) override { return I.exact_due(run, stage, backend_failed); }
  Solution exact_finish(size_t stage, const std::string& why) override {
    I.exact_solve(run, static_cast<int>(stage), why);
    I.certify(run, t_start);
    return std::move(run.sol);
  }
};

// The continuation (solve.hpp's pseudo-code) from @p z0, with the hand-over to the exact solver.
Solution ContactSolver::Impl::continuation(const Vec* z0, clk::time_point t_start) {
  Run run = start(z0);
  Stepper steps(*this, run, t_start);
  return run_outer(steps, opt);
}

// What every answer carries from the set-up.
Solution ContactSolver::Impl::header() const {
  Solution sol;
  sol.backend = backend ? backend->name() : opt.backend;
  sol.backend_use.requested = requested_backend;
  sol.skipped = skipped;
  sol.smallness = smallness;
  sol.inner_convexity = convexity;
  sol.method_choice = F.choice;
  sol.timings = setup_timings;
  return sol;
}

Solution ContactSolver::Impl::linear_answer(clk::time_point t_start) const {
  Solution sol = header();
  sol.backend = "none (CHOLMOD linear solve)";
  sol.backend_use.not_run = "linear elasticity without contact: one sparse Cholesky solve is the answer";
  sol.x = x_linear;
  sol.u = model->dofs.to_full(sol.x);
  evaluate_solution(*model, opt, sol);
  sol.timings["solve_total"] = since(t_start) + setup_timings.at("setup_total");
  sol.message = sol.certificate.passed ? "linear solve; certificate passed" : "linear solve; certificate failed";
  return sol;
}

// Backend ssn: the exact solver of the full space (solver/ssn.hpp) from @p z0 (full unknowns), no
// smoothing and no outer loop; judged by the certificate as every answer is.
Solution ContactSolver::Impl::ssn_answer(const Vec* z0, clk::time_point t_start) {
  Run run;
  Solution& sol = run.sol;
  sol = header();
  sol.formulation = F.name;
  sol.backend = "ssn (semismooth Newton, CHOLMOD)";
  sol.skipped.push_back("continuation: ssn solves the unsmoothed problem (no eps stages)");
  sol.skipped.push_back("polish: ssn's steps are the polish's, with statuses updated");
  if (lagged) sol.skipped.push_back("fixed_point: lambda = F_b(u_nu) is read at every Newton step (no outer loop)");
  // No stop before a step at round-off (tol 0, unlike the petsc engine's solver.ssn.tol): here a step
  // whose statuses held is one CG iteration on the last factor, and the answer is then as exact as
  // the condensed solver's (1e-14 U, not the 1e-12 F of a residual test).
  const SsnOutcome o = ssn_full(*model, SsnLimits{opt.ssn.max_iters, 0.0, opt.petsc.ksp_rtol, opt.ordering}, z0);
  OuterIteration rec;
  rec.solver = sol.backend;
  rec.backend.iterations = o.steps;
  rec.backend.seconds = o.seconds;
  rec.backend.status = o.converged ? SolveStatus::CONVERGED : SolveStatus::MAX_ITERATIONS;
  rec.backend.message = o.converged ? "ssn converged in " + std::to_string(o.steps) + " Newton steps" : o.message;
  sol.history.push_back(rec);
  sol.backend_use.ran = true;
  sol.backend_ok = o.converged;
  if (!o.converged) sol.message = o.message;
  sol.x = o.x;
  sol.u = model->dofs.to_full(sol.x);
  certify(run, t_start);
  return std::move(run.sol);
}

// ssn did not certify: it stops where its Newton matrix is not positive definite or the statuses
// still change at its step cap (a nonconvex inner problem: 148 of the 1000 random scenes). The engine's default NLP
// backend then runs the design's path from the same start, as a named backend (its first ε-stage,
// then the exact solver's hand-over and the polish), and the answer says that ssn ran first.
Solution ContactSolver::Impl::ssn_handover(Solution failed, const Vec* z0) const {
  SolveOptions o = opt;
  o.backend = make_backend(AUTO_BACKEND)->name();
  log_info() << "ssn: not certified (" << failed.message << "); handing over to " << o.backend;
  ContactSolver next(*model, o);
  // ssn's start is in the full unknowns; a condensed hand-over starts from zero as the default does.
  const bool same_unknowns = z0 && next.m->F.name == "full";
  Solution s = next.solve(same_unknowns ? z0 : nullptr);
  s.history.insert(s.history.begin(), failed.history.begin(), failed.history.end());
  s.message = "ssn did not certify (" + failed.message + "); handed over to " + o.backend + ": " + s.message;
  s.backend_use.requested = requested_backend;
  s.timings["ssn"] = failed.timings.count("solve_total") ? failed.timings.at("solve_total") : 0.0;
  return s;
}

// The start z0 (zero by default) in scaled unknowns, projected onto the bounds, with λ frozen there.
ContactSolver::Impl::Run ContactSolver::Impl::start(const Vec* z0) {
  Run run;
  run.sol = header();
  run.sol.formulation = F.name;
  run.sol.x_scale = U_s;
  run.sol.f_scale = F_s * U_s;
  run.zs = z0 ? Vec(*z0 / U_s) : Vec::Zero(F.energy->size());
  if (run.zs.size() != F.energy->size()) throw Error("solve: start vector of the wrong size", EXIT_INTERNAL);
  run.zs = run.zs.cwiseMax(prob.lower).cwiseMin(prob.upper);
  if (F.friction) F.friction->set_lambda(friction_bounds(run.zs));
  run.prev_c = gamma3(run.zs);
  run.sol.fixed_point_converged = true;
  return run;
}

// The smoothing widths of a stage (absolute: relative widths × U_s).
void ContactSolver::Impl::set_smoothing(size_t stage) {
  const auto [et, en] = schedule[stage];
  if (F.normal) F.normal->set_eps(en * U_s, "solver.eps_nu");
  if (F.friction) F.friction->set_eps(et * U_s);
}

// x ← argmin Π_λ,ε (warm start), recorded with the change on Γ3 and the first-order residual.
OuterIteration ContactSolver::Impl::minimize(Run& run, size_t stage) {
  OuterIteration rec;
  rec.k = run.k_total++;
  rec.stage = static_cast<int>(stage);
  rec.eps_tau = schedule[stage].first * U_s;
  rec.eps_nu = schedule[stage].second * U_s;
  BackendOptions bo = opt.backend_options;
  // With the exact solver behind it, a stage that needs more than exact_stage_max_iter iterations
  // has stalled: it hands over instead of grinding.
  if (exact_available() && opt.exact_stage_max_iter > 0) bo.max_iter = std::min(bo.max_iter, opt.exact_stage_max_iter);
  // ... and stops at the statuses' neighbourhood (solver.exact.stage_tol), not at round-off.
  if (exact_available() && opt.exact_stage_tol > 0) bo.tol = std::max(bo.tol, opt.exact_stage_tol);
  rec.backend = backend->minimize(prob, run.zs, bo);
  rec.solver = backend->name();
  const Vec c = gamma3(run.zs);
  rec.change_u = rel_change(c, run.prev_c);
  run.prev_c = c;
  // The backend's kkt_norm is nlp's first_order_residual at zs, on the same scaled problem.
  rec.grad_norm = rec.backend.kkt_norm;
  return rec;
}

// λ ← (1−θ)λ + θ F_b(u_ν), with the change and (when @p measure_contraction) the contraction ρ_k.
LambdaChange ContactSolver::Impl::relax_lambda(Run& run) {
  const Vec lam_old = F.friction->lambda();
  const Vec lam = (1 - opt.relaxation) * lam_old + opt.relaxation * friction_bounds(run.zs);
  const LambdaChange c{(lam - lam_old).cwiseAbs().maxCoeff(),
                       std::max(lam.cwiseAbs().maxCoeff(), lam_old.cwiseAbs().maxCoeff())};
  F.friction->set_lambda(lam);
  return c;
}

// The exact polish on the identified statuses (solver/polish.hpp), then x and u. Polished even
// after a backend failure: the certificate, not the backend's word, decides.
void ContactSolver::Impl::polish(Run& run, bool attempt) {
  Solution& sol = run.sol;
  sol.contraction_estimate = contraction_estimate(sol.history);
  Vec z = U_s * run.zs;
  if (F.cond && opt.polish && attempt && sol.fixed_point_converged && all_separated(z)) {
    // Every Γ3 node off the layer with no friction bound: Γ3 carries no traction, so the answer is
    // the linear elastic solution, which the smoothed energy's minimizer already is to round-off
    // (p_ν = 0 and λ = 0 there: nothing was smoothed). A polish could only be rejected.
    sol.skipped.push_back("polish: every gamma3 node is separated with F_b = 0 (no contact traction to polish)");
    attempt = false;
  }
  if (F.cond && opt.polish && attempt && sol.fixed_point_converged) {
    const auto t1 = clk::now();
    sol.polish = polish_condensed(*model, *F.cond, opt, z, F.load_scale);
    sol.timings["polish"] = since(t1);
    log_info() << "polish: " << (sol.polish.accepted ? "accepted" : "rejected") << ", certificate " << sol.polish.before
               << " -> " << sol.polish.after << " in " << sol.polish.iterations
               << (model->dim() == 3 ? " Newton iterations" : " lambda iterations")
               << (sol.polish.note.empty() ? "" : " (" + sol.polish.note + ")");
  } else if (!F.cond) {
    sol.skipped.push_back("polish: needs the condensed formulation");
  }
  sol.x = F.to_x(z);
  sol.u = model->dofs.to_full(sol.x);
}

// Every Γ3 node strictly below the layer (u_ν < −status_tol·U_s, where p_ν = 0) with F_b(u_ν) = 0.
bool ContactSolver::Impl::all_separated(const Vec& z) const {
  const Model& md = *model;
  if (md.contact.size() == 0) return false;
  for (Index k = 0; k < md.contact.size(); ++k) {
    const double un = z[F.nd.first[k]];
    if (!(un < -opt.status_tol * U_s)) return false;
    if (md.friction && md.friction->F(un) != 0) return false;
  }
  return true;
}

// The certificate of the answer (docs/model.md §4), the timings and the verdict.
void ContactSolver::Impl::certify(Run& run, clk::time_point t_start) const {
  Solution& sol = run.sol;
  auto t1 = clk::now();
  evaluate_solution(*model, opt, sol);
  sol.timings["certificate"] = since(t1);
  // The backend's own minimizations (the exact solver's inner solves are under "exact").
  sol.timings["backend"] = sol.work_of(sol.backend).seconds;
  sol.timings["solve_total"] = since(t_start) + setup_timings.at("setup_total");
  state_verdict(sol);
  if (!sol.fixed_point_converged) log_warn() << sol.message;
}

// Each node's statuses after @p stage, read at that stage's smoothing scale (10 ε, at least
// check.status_tol): the normal one (separated, the piece of p_ν, contact) and the tangential one
// (stick, slip±; 3D slip). Two stages that agree have most likely identified the final statuses.
std::vector<int> ContactSolver::Impl::status_signature(const Run& run, size_t stage) const {
  const Index nc = model->contact.size();
  const int d = model->dim();
  const double t = U_s * std::max(opt.status_tol, 10 * std::max(schedule[stage].first, schedule[stage].second));
  std::vector<int> sig(static_cast<size_t>(nc));
  for (Index k = 0; k < nc; ++k) {
    const double un = U_s * run.zs[F.nd.first[k]];
    int normal = 0;
    if (un >= model->contact.g[k] - t)
      normal = 1000;
    else if (un > t && model->normal_law)
      for (double b : model->normal_law->breakpoints()) normal += un > b;
    const Vec ut = U_s * run.zs.segment(F.nd.first[k] + 1, d - 1);
    const int tang = ut.norm() <= t ? 0 : d == 2 ? (ut[0] > 0 ? 1 : 2) : 1;
    sig[static_cast<size_t>(k)] = 4 * normal + tang;
  }
  return sig;
}

// Why the exact solver starts before any continuation stage (solver.exact.start), or "" (it does not).
std::string ContactSolver::Impl::exact_first() const {
  if (!exact_available() || opt.exact_start == "never") return "";
  if (opt.exact_start == "always") return "solver.exact.start = always";
  // A backend the user named runs at least its first stage (solver.exact.start = auto): the user
  // asked for that solver's answer, on a strongly convex scene too.
  if (opt.exact_start == "auto" && backend_named(opt)) return "";
  // The backend's stage is skipped only where it cannot change the answer: Φ_λ strongly convex has
  // one minimizer, which the exact solver's monotone sweeps reach from any start.
  if (convexity.checked && convexity.strongly_convex)
    return std::string("the inner problem is strongly convex (") +
           (dense_checks_too_large() ? "k_1nu - alpha, Lanczos, " : "smallest eigenvalue of S - alpha W_nu ") +
           fmt(convexity.min_eigenvalue, 3) + " > 0): its minimizer is unique and the exact solver "
           "reaches it from any start";
  return "";
}

// Why the exact solver should take over after @p stage, or "" (not yet).
std::string ContactSolver::Impl::exact_due(Run& run, size_t stage, bool backend_failed) {
  std::vector<int> sig = status_signature(run, stage);
  const bool same = !run.prev_status.empty() && sig == run.prev_status;
  run.prev_status = std::move(sig);
  const OuterIteration& last = run.sol.history.back();
  if (backend_failed)
    return last.backend.status == SolveStatus::MAX_ITERATIONS
               ? "backend " + backend->name() + " stalled (" + std::to_string(last.backend.iterations) +
                     " iterations, the cap is min(solver.max_iter, solver.exact.stage_max_iter))"
               : "backend " + backend->name() + " failed: " + to_string(last.backend.status) + " (" +
                     last.backend.message + ")";
  if (!run.sol.fixed_point_converged) return "the fixed point with the backend did not converge: " + run.sol.message;
  if (same) return "statuses unchanged since stage " + std::to_string(stage - 1);
  if (stage + 1 == schedule.size()) return "last continuation stage";
  if (static_cast<int>(stage) >= opt.exact_after_stage)
    return "the smoothed neighbourhood of stage " + std::to_string(stage) + " (solver.exact.after_stage)";
  return "";
}

namespace {

// The exact solver's two maps of the Γ3 unknowns x (d per node): the bounds λ = F_b(u_ν), and the
// certificate's traction scale (check/certificate.cpp): max(|f|∞/w̄, max λ, max |p_ν|).
struct ExactCoupling {
  const Model& md;
  int d;
  Index nc;
  double f_trac;
  explicit ExactCoupling(const Model& m)
      : md(m),
        d(m.dim()),
        nc(m.contact.size()),
        f_trac((m.f.size() ? m.f.cwiseAbs().maxCoeff() : 0.0) / (nc ? m.contact.w.mean() : 1.0)) {}
  Vec bounds(const Vec& x) const {
    Vec l = Vec::Zero(nc);
    if (md.friction)
      for (Index k = 0; k < nc; ++k) l[k] = md.friction->F(x[d * k]);
    return l;
  }
  double scale(const Vec& x, const Vec& lam) const {
    double s = std::max(f_trac, nc ? lam.cwiseAbs().maxCoeff() : 0.0);
    if (md.normal_law)
      for (Index k = 0; k < nc; ++k) s = std::max(s, std::abs(md.normal_law->p(x[d * k])));
    return s > 0 ? s : 1.0;
  }
};

// The inner problem with λ frozen (solver/exact_inner.hpp), λ and the traction scale still unset.
ExactInnerProblem exact_inner_problem(const Model& md, const Formulation& F) {
  ExactInnerProblem P;
  P.S = &F.cond->S();
  P.y = F.load_scale * F.cond->y_C();
  P.d = md.dim();
  P.w = md.contact.w;
  P.g = md.contact.g;
  P.law = md.normal_law.get();
  P.fixed.assign(md.contact.fixed_local.begin(), md.contact.fixed_local.end());
  return P;
}

// One inner solve's work in the handover report, and its record as an outer iteration.
OuterIteration inner_solve_record(HandoverReport& H, const ExactInnerResult& R, int k, int stage, double seconds) {
  H.inner_rounds += R.rounds;
  H.newton_steps += R.newton_steps;
  H.factorizations += R.factorizations;
  H.inner_converged = R.converged;
  H.note = R.note;
  OuterIteration rec;
  rec.k = k;
  rec.stage = stage;
  rec.backend.status = R.converged ? SolveStatus::CONVERGED : SolveStatus::FAILED;
  rec.backend.iterations = R.rounds;
  rec.backend.f = R.energy;
  rec.backend.kkt_norm = R.residual;
  rec.backend.seconds = seconds;
  rec.backend.message = "exact inner solver" + (R.note.empty() ? std::string() : ": " + R.note);
  rec.solver = EXACT_SOLVER;
  rec.grad_norm = R.residual;
  return rec;
}

// The exact solver's stop test after update @p it: the coupled residual at solver.exact.tol, or
// at its round-off floor below check.certificate_tol (@p floor_ref: the residual 5 updates ago).
bool exact_converged(HandoverReport& H, const ExactInnerResult& R, int it, double floor_ref, const SolveOptions& opt) {
  if (H.residual <= opt.exact_inner.tol) {
    H.fixed_point_converged = true;
    return true;
  }
  // The round-off floor: the coupled residual has not halved in 5 updates but is already below
  // the user's acceptance tolerance (check.certificate_tol). Further updates only stir round-off;
  // the certificate, computed from u alone, decides.
  if (R.converged && it >= 5 && H.residual <= opt.certificate_tol && !(H.residual < 0.5 * floor_ref)) {
    H.fixed_point_converged = true;
    H.note = "coupled residual " + fmt(H.residual, 3) +
             " below check.certificate_tol but at its round-off floor above solver.exact.tol";
    return true;
  }
  return false;
}

// The cap (solver.fixed_point.max_iters) reached while still converging, with the coupled residual
// already below the user's acceptance tolerance (check.certificate_tol): as at the round-off floor
// (exact_converged), the certificate, computed from u alone, decides (the sliding scene at c_i × 10,
// μ = 12 of docs/stress/theta.md: 2.9e-10 after 50 updates, converged at 51).
void accept_at_cap(HandoverReport& H, const SolveOptions& opt) {
  if (!H.fixed_point_converged && H.inner_converged && H.outer_iterations >= opt.max_outer &&
      H.residual <= opt.certificate_tol) {
    H.fixed_point_converged = true;
    H.note = "coupled residual " + fmt(H.residual, 3) + " after " + std::to_string(H.outer_iterations) +
             " updates (solver.fixed_point.max_iters): below check.certificate_tol, above solver.exact.tol";
  }
}

// Anderson relaxation of λ = F_b(u_ν): the next λ from the frozen @p lam and its image @p G.
Vec anderson_relax(Anderson& aa, const Vec& lam, const Vec& G, double delta_lambda, double& best) {
  Vec next = aa.next(lam, G);
  // A safeguard: an accelerated step that made the update grow tenfold restarts the history.
  if (delta_lambda > 10 * best) aa.reset();
  best = std::min(best, delta_lambda);
  return next;
}

// The exact solver's verdict in the answer (@p when: where it started, for the message; @p theta:
// the mixing it ran with, whose half the message offers).
void exact_verdict(Solution& sol, const std::string& when, double theta) {
  const HandoverReport& H = sol.handover;
  sol.backend_ok = true;
  sol.message.clear();
  sol.fixed_point_converged = H.fixed_point_converged;
  if (!H.fixed_point_converged) {
    if (!H.inner_converged)
      sol.message = "backend exact (inner solver " + when + ") did not converge: " + H.note;
    else
      sol.message = "fixed point lambda = F_b(u_nu) did not converge in the exact solver: " +
                    std::to_string(H.outer_iterations) + " Anderson iterations (solver.fixed_point.max_iters), " +
                    "coupled residual " + fmt(H.residual, 3) + "; a smaller solver.fixed_point.relaxation (" +
                    fmt(theta, 3) + " now), e.g. " + fmt(0.5 * theta, 3) + ", damps its updates";
  }
}

}  // namespace

// The exact solver from the current iterate: the inner problem with λ frozen solved exactly
// (solver/exact_inner.hpp), λ = F_b(u_ν) by Anderson acceleration, until the coupled stationarity
// residual (the certificate's terms with λ = F_b(u_ν), λ not frozen) is at most solver.exact.tol;
// then the exact polish. Only the condensed formulation has it.
void ContactSolver::Impl::exact_solve(Run& run, int stage, const std::string& reason) {
  const auto t0 = clk::now();
  const Model& md = *model;
  const Index nc = md.contact.size();
  HandoverReport& H = run.sol.handover;
  H.used = true;
  H.after_stage = stage;
  H.reason = reason;
  const std::string when = stage < 0 ? "from the start, no eps-stage" : "after stage " + std::to_string(stage);
  log_info() << "exact solver " << (stage < 0 ? "runs " : "takes over ") << when << ": " << reason;

  ExactInnerProblem P = exact_inner_problem(md, F);
  const ExactCoupling coupling(md);
  Vec x = U_s * run.zs, x_prev = x;
  P.lambda = coupling.bounds(x);
  Anderson aa(opt.anderson_memory, opt.relaxation);
  double best = INF, floor_ref = INF;
  ExactInnerFactor factor;  // kept across the λ updates (2D: where the statuses stay, no refactorization)
  for (int it = 0; it < opt.max_outer; ++it) {
    check_interrupt();
    P.traction_scale = coupling.scale(x, P.lambda);
    const auto ti = clk::now();
    const ExactInnerResult R = exact_inner_solve(P, x, opt.exact_inner, &factor);
    OuterIteration rec = inner_solve_record(H, R, run.k_total++, stage, since(ti));
    rec.change_u = rel_change(x, x_prev);
    x_prev = x;
    const Vec lam = P.lambda, G = coupling.bounds(x);
    rec.change_lambda = rel_change(G, lam);
    rec.delta_lambda = nc ? (G - lam).cwiseAbs().maxCoeff() : 0.0;
    // The coupled residual: stationarity with λ = F_b(u_ν) itself.
    P.lambda = G;
    P.traction_scale = coupling.scale(x, G);
    H.residual = exact_inner_residual(P, x);
    run.sol.history.push_back(rec);
    H.outer_iterations = it + 1;
    log_info() << "exact " << it << ": inner " << (R.converged ? "converged" : "not converged") << " in " << R.rounds
               << " rounds (" << R.newton_steps << " Newton steps), residual " << R.residual
               << "; |dlambda|/|lambda| = " << rec.change_lambda << ", coupled residual " << H.residual;
    if (exact_converged(H, R, it, floor_ref, opt)) break;
    if (it % 5 == 0) floor_ref = H.residual;
    if (!lagged) break;  // λ does not depend on u: the inner answer is the answer
    P.lambda = anderson_relax(aa, lam, G, rec.delta_lambda, best);
  }
  accept_at_cap(H, opt);
  run.zs = x / U_s;
  if (F.friction) F.friction->set_lambda(P.lambda);
  exact_verdict(run.sol, when, opt.relaxation);
  H.seconds = since(t0);
  run.sol.timings["exact"] = H.seconds;
  // The polish on the exact answer's statuses: kept only if the certificate improves, it takes the
  // answer from solver.exact.tol to round-off (the paper scenes agree with the reference to 1e-12).
  // An answer already at round-off (solver.exact.polish_above) does not need it.
  if (H.fixed_point_converged && H.residual <= opt.exact_inner.polish_above) {
    polish(run, false);  // x, u and the rest of the answer, without the polish itself
    run.sol.skipped.push_back("polish: the exact solver's coupled residual " + fmt(H.residual, 3) +
                              " is at round-off already (solver.exact.polish_above)");
    return;
  }
  polish(run);
}

// The Γ3 unknowns (d per node, node order) of solver unknowns z.
Vec ContactSolver::Impl::gamma3(const Vec& z) const {
  const Index nc = model->contact.size();
  const int d = model->dim();
  Vec c(nc * d);
  for (Index k = 0; k < nc; ++k) c.segment(d * k, d) = z.segment(F.nd.first[k], d);
  return c;
}

// λ_i = F_b(u_ν,i) at scaled unknowns zs.
Vec ContactSolver::Impl::friction_bounds(const Vec& zs) const {
  Vec l(model->contact.size());
  for (Index k = 0; k < model->contact.size(); ++k) l[k] = model->friction->F(U_s * zs[F.nd.first[k]]);
  return l;
}

Solution solve(const Model& md, const SolveOptions& opt) {
  ContactSolver solver(md, opt);
  return solver.solve();
}

}  // namespace hemicontact
