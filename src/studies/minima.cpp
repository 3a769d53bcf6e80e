// Many starts → certified results → distinct solutions → local minimum or saddle (minima.hpp).
//
// Why a search at all: when (21) fails, Π_λ is nonconvex and every backend here is a local
// method, so which solution a solve returns depends on where it starts. Nothing below changes the
// solver: it only chooses starts, and checks and sorts what comes back.

#include <hemicontact/studies/minima.hpp>

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/energy/energy_term.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/solver/sparse_checks.hpp>
#include <hemicontact/solver/ssn.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <sstream>

namespace hemicontact {
namespace {
using json = nlohmann::json;


// ‖a − b‖_E = sqrt(a(a − b, a − b)).
double energy_distance(const Model& md, const Vec& a, const Vec& b) {
  const Vec d = a - b;
  return std::sqrt(std::max(0.0, md.a(d, d)));
}

// A start in solver unknowns from Γ3 values (ν, τ[, τ2]) node after node; interior unknowns 0.
Vec from_gamma3(const ContactSolver& s, const Vec& c) {
  const NodalDofs& nd = s.contact_dofs();
  Vec z = Vec::Zero(s.size());
  for (Index k = 0; k < nd.size(); ++k) z.segment(nd.first[k], nd.dim) = c.segment(nd.dim * k, nd.dim);
  return z;
}

// A caller's start in solver unknowns (sizes checked in the order documented in MinimaOptions).
Vec user_start(const ContactSolver& s, const Model& md, const Vec& v, const std::string& label) {
  const Index nc = md.contact.size(), d = md.dim();
  if (v.size() == md.dofs.n_full()) return s.to_unknowns(md.dofs.to_reduced(v));
  if (v.size() == d * nc) return from_gamma3(s, v);
  if (v.size() == s.size()) return v;
  input_error("minima: start '" + label + "' has " + std::to_string(v.size()) + " values; expected " +
              std::to_string(md.dofs.n_full()) + " (full u), " + std::to_string(d * nc) +
              " (u_nu, u_tau per Gamma3 node) or " + std::to_string(s.size()) + " (solver unknowns)");
}

// A model with every load multiplied by @p s (exact: u_D = 0, so the loads are f and f_x only).
Model scaled_model(const Model& md, double s) {
  Model m = md;
  m.f *= s;
  m.fx *= s;
  return m;
}

struct Candidate {
  int run = -1;
  Solution sol;
};

// The reduced Hessian: H's rows and columns @p idx (ascending), its lower triangle (H's own).
SpMat reduced_lower(const SpMat& H, const std::vector<Index>& idx, Index n) {
  std::vector<Index> pos(static_cast<size_t>(n), -1);
  for (size_t i = 0; i < idx.size(); ++i) pos[static_cast<size_t>(idx[i])] = static_cast<Index>(i);
  std::vector<Eigen::Triplet<double>> t;
  for (Index j = 0; j < H.outerSize(); ++j)
    for (SpMat::InnerIterator it(H, j); it; ++it) {
      const Index a = pos[static_cast<size_t>(it.row())], b = pos[static_cast<size_t>(it.col())];
      if (a >= 0 && b >= 0) t.emplace_back(std::max(a, b), std::min(a, b), it.value());
    }
  const Index k = static_cast<Index>(idx.size());
  SpMat R(k, k);
  R.setFromTriplets(t.begin(), t.end());
  return R;
}

// λ_min of the reduced Hessian H_r without a dense matrix: H_r + σI is positive definite for
// σ > α · max w, α the normal law's softening (one-sided Lipschitz constant of p_ν, (21)'s α_jν):
// the only part of H_r below the elastic stiffness is w_k j_ν'' ≥ −α w_k (friction's is ≥ 0).
// One sparse Cholesky of H_r + σI (σ times 4 where round-off or the smoothing still leave it
// indefinite) and Lanczos on its inverse, whose largest eigenvalue is 1/(λ_min + σ).
// False with @p note where it cannot say.
bool sparse_lambda_min(const SpMat& Hr, const Model& md, double tau, const SolveOptions& opt, double& lambda_min,
                       std::string& note) {
  const double alpha = md.normal_law ? md.normal_law->one_sided_lipschitz() : 0.0;
  if (!std::isfinite(alpha)) {
    note = "p_nu jumps downward: no shift makes the Hessian definite";
    return false;
  }
  const double w_max = md.contact.size() ? md.contact.w.maxCoeff() : 0.0;
  SpMat I(Hr.rows(), Hr.cols());
  I.setIdentity();
  double sigma = 2 * alpha * w_max + tau;
  for (int attempt = 0; attempt < 8; ++attempt, sigma *= 4) {
    SparseCholesky chol;
    try {
      chol.compute(SpMat(Hr + sigma * I));
    } catch (const Error&) {
      continue;  // not positive definite yet
    }
    const LanczosResult r = lanczos_largest([&](const Vec& v) { return chol.solve(v); }, Hr.rows(), opt.lanczos_tol,
                                            opt.lanczos_max_iter);
    if (!r.converged) {
      note = "sparse check: Lanczos did not converge in check.lanczos_max_iter steps";
      return false;
    }
    lambda_min = 1 / r.theta - sigma;
    note = "sparse check (" + std::to_string(Hr.rows()) + " unknowns > max_dense): Cholesky of H + " + fmt(sigma, 3) +
           " I and Lanczos, " + std::to_string(r.iterations) + " steps";
    return true;
  }
  note = "sparse check: H + sigma I not positive definite for any tried sigma";
  return false;
}

// The verdict from c.lambda_min, dense or sparse alike: a local minimum where λ_min ≥ −tol · scale.
SecondOrderCheck second_order_verdict(SecondOrderCheck c, const MinimaOptions& mopt, const std::string& how) {
  c.verdict = c.lambda_min >= -mopt.second_order_tol * c.scale ? "local minimum" : "saddle";
  if (std::abs(c.lambda_min) <= mopt.second_order_tol * c.scale)
    c.note = "lambda_min ~ 0: second-order test inconclusive (degenerate)";
  else if (c.degenerate > 0)
    c.note = std::to_string(c.degenerate) + " contact node(s) with zero rigid reaction: necessary condition only";
  if (!how.empty()) c.note = c.note.empty() ? how : how + "; " + c.note;
  return c;
}
}  // namespace

SecondOrderCheck second_order_check(ContactSolver& solver, const Model& md, const SolveOptions& opt,
                                    const Solution& sol, const MinimaOptions& mopt) {
  SecondOrderCheck c;
  if (!md.Kx.empty() && md.Kx.rows() > 0) c.scale = std::max(c.scale, md.Kx.diagonal().maxCoeff());
  if (solver.formulation().empty()) {
    c.verdict = "local minimum";
    c.note = "linear elasticity: the energy is a convex quadratic";
    return c;
  }
  // The energy of the lagged problem at the solution: final widths, λ frozen there.
  const ContactSolver::LaggedEnergy lagged = solver.lagged_energy(sol);
  const NlpObjective& f = lagged.f;
  const NodalDofs& nd = lagged.nd;
  const Vec& z = lagged.z;
  const Index n = f.size();
  std::vector<bool> keep(static_cast<size_t>(n), true);
  Vec grad;
  f.gradient(z, grad);
  // A rigid reaction is a nodal force; below this it counts as zero (degenerate contact).
  const double force_tol = opt.certificate_tol * std::max(sol.certificate.force_scale, 1e-300);
  for (Index k = 0; k < nd.size(); ++k) {
    const NodeStatus& st = sol.status[static_cast<size_t>(k)];
    if (st.normal == NormalStatus::CONTACT) {
      keep[static_cast<size_t>(nd.first[k])] = false;
      ++c.removed_contact;
      // KKT of min Π s.t. z_ν ≤ g: ∇_ν Π + R = 0 with the rigid reaction R ≥ 0.
      if (-grad[nd.first[k]] <= force_tol) ++c.degenerate;
    }
    if (st.tangential == TangentialStatus::STICK && sol.state.lambda[k] > 0)
      for (int a = 1; a < nd.dim; ++a) {
        keep[static_cast<size_t>(nd.first[k] + a)] = false;
        ++c.removed_stick;
      }
  }
  std::vector<Index> idx;
  for (Index i = 0; i < n; ++i)
    if (keep[static_cast<size_t>(i)]) idx.push_back(i);
  c.kept = static_cast<Index>(idx.size());
  if (c.kept == 0) {
    c.verdict = "local minimum";
    c.note = "no free direction: every unknown is at the bound or sticking";
    return c;
  }
  SpMat H = f.hessian_pattern();
  f.hessian(z, H, Psd::NONE);
  if (c.kept > mopt.max_dense) {
    std::string how;
    if (!sparse_lambda_min(reduced_lower(H, idx, n), md, mopt.second_order_tol * c.scale, opt, c.lambda_min, how)) {
      c.note = "free subspace of " + std::to_string(c.kept) + " unknowns > max_dense = " +
               std::to_string(mopt.max_dense) + ": " + how;
      return c;
    }
    return second_order_verdict(c, mopt, how);
  }
  std::vector<Index> pos(static_cast<size_t>(n), -1);
  for (Index i = 0; i < c.kept; ++i) pos[static_cast<size_t>(idx[static_cast<size_t>(i)])] = i;
  Mat Hr = Mat::Zero(c.kept, c.kept);
  for (Index j = 0; j < H.outerSize(); ++j)
    for (SpMat::InnerIterator it(H, j); it; ++it) {
      const Index a = pos[static_cast<size_t>(it.row())], b = pos[static_cast<size_t>(it.col())];
      if (a < 0 || b < 0) continue;
      Hr(a, b) = it.value();  // lower triangle stored: mirror it
      Hr(b, a) = it.value();
    }
  Eigen::SelfAdjointEigenSolver<Mat> es(Hr, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) {
    c.note = "eigenvalue solver failed";
    return c;
  }
  c.lambda_min = es.eigenvalues().minCoeff();
  return second_order_verdict(c, mopt, "");
}

namespace {
// 2D: Γ3 node k's mirror partner about the midpoint of Γ3's x-range (−1 where none lies within a
// relative 1e-9 of the range), or an empty map when Γ3 is not mirror-symmetric.
std::vector<Index> gamma3_mirror(const Model& md) {
  const Index nc = md.contact.size();
  if (md.dim() != 2 || nc == 0) return {};
  double lo = INF, hi = -INF;
  for (Index k = 0; k < nc; ++k) {
    const double x = md.mesh.points(md.contact.node[static_cast<size_t>(k)], 0);
    lo = std::min(lo, x), hi = std::max(hi, x);
  }
  const double tol = 1e-9 * std::max(hi - lo, 1e-300);
  std::vector<Index> m(static_cast<size_t>(nc), -1);
  for (Index k = 0; k < nc; ++k) {
    const double xm = lo + hi - md.mesh.points(md.contact.node[static_cast<size_t>(k)], 0);
    for (Index q = 0; q < nc && m[static_cast<size_t>(k)] < 0; ++q)
      if (std::abs(md.mesh.points(md.contact.node[static_cast<size_t>(q)], 0) - xm) <= tol) m[static_cast<size_t>(k)] = q;
    if (m[static_cast<size_t>(k)] < 0) return {};
  }
  return m;
}
}  // namespace

void pair_mirror_images(const Model& md, MinimaReport& R, double group_tol) {
  const std::vector<Index> m = gamma3_mirror(md);
  if (m.empty()) return;
  for (size_t a = 0; a < R.solutions.size(); ++a)
    for (size_t b = a + 1; b < R.solutions.size(); ++b) {
      DistinctSolution &A = R.solutions[a], &B = R.solutions[b];
      if (A.mirror_of >= 0 || B.mirror_of >= 0) continue;
      const ContactState &sa = A.solution.state, &sb = B.solution.state;
      const double Es = std::max({std::abs(A.solution.energy), std::abs(B.solution.energy), 1e-300});
      if (std::abs(A.solution.energy - B.solution.energy) > group_tol * Es) continue;
      // Γ3 values of B reflected: u_ν at the partner node, u_τ reversed (the tangent flips).
      double diff = 0, scale = 0;
      for (size_t k = 0; k < m.size(); ++k) {
        const Index q = m[k];
        diff = std::max({diff, std::abs(sa.u_nu[Index(k)] - sb.u_nu[q]), std::abs(sa.u_tau[Index(k)] + sb.u_tau[q])});
        scale = std::max({scale, std::abs(sa.u_nu[Index(k)]), std::abs(sa.u_tau[Index(k)])});
      }
      // A symmetric solution is its own mirror image: it pairs with none.
      double self = 0;
      for (size_t k = 0; k < m.size(); ++k)
        self = std::max({self, std::abs(sa.u_nu[Index(k)] - sa.u_nu[m[k]]), std::abs(sa.u_tau[Index(k)] + sa.u_tau[m[k]])});
      if (diff <= group_tol * scale && self > group_tol * scale) {
        A.mirror_of = static_cast<int>(b);
        B.mirror_of = static_cast<int>(a);
      }
    }
}

namespace {
/// One find_minima search in progress: the report so far and the certified runs (candidates).
struct MinimaSearch {
  const Model& md;
  MinimaReport& R;
  std::vector<Candidate> cands;

  // @p started: when the run began. Its seconds are taken here, once @p sol exists: a since(t)
  // beside S.solve() in one call's arguments may be evaluated first (the order is unspecified),
  // which once timed every start but zero at 0 s.
  void record(const std::string& start, const std::string& backend, Solution sol, clk::time_point started);
  void run_backend(std::unique_ptr<ContactSolver>& solver, const SolveOptions& opt, const std::string& name);
  void run_engine(std::unique_ptr<ContactSolver>& checks, const SolveOptions& opt);
  /// One solve from solver unknowns z0 (the in-process solver's, or the check solver's on an engine).
  using SolveFrom = std::function<Solution(const Vec& z0)>;
  void gamma3_starts(const ContactSolver& S, const std::string& name, double Us, const SolveFrom& solve_from);
  void load_path(ContactSolver& S, const std::string& name);
  void engine_load_path(const std::string& name);
  void load_path_legs(const std::string& name, const std::function<Solution(double)>& solve_at);
  void group();
  std::vector<int> random_abundances() const;
};

bool is_random_start(const std::string& label) { return label.rfind("random-", 0) == 0; }

// How many certified random-start runs reached each distinct solution so far, grouped as group()
// groups (greedy against each group's first member): the provisional counts of until_complete.
std::vector<int> MinimaSearch::random_abundances() const {
  double scale = 0;
  for (const auto& cd : cands) scale = std::max(scale, cd.sol.energy_norm);
  std::vector<const Solution*> anchors;
  std::vector<int> count;
  for (const auto& cd : cands) {
    if (!is_random_start(R.runs[static_cast<size_t>(cd.run)].start)) continue;
    size_t q = 0;
    while (q < anchors.size() && energy_distance(md, cd.sol.u, anchors[q]->u) > R.options.group_tol * scale) ++q;
    if (q == anchors.size()) anchors.push_back(&cd.sol), count.push_back(0);
    ++count[q];
  }
  return count;
}

void MinimaSearch::record(const std::string& start, const std::string& backend, Solution sol,
                          clk::time_point started) {
  const double secs = since(started);
  const MinimaOptions& mopt = R.options;
  MinimaRun r;
  r.start = start;
  r.backend = backend;
  r.solved_by = sol.solved_by();
  r.converged = sol.backend_ok && sol.fixed_point_converged;
  // The certificate is the judge (docs/model.md §4): a backend that stopped short of its own
  // tolerance may still have delivered a solution of (22), and a converged one may not.
  r.certified = sol.certificate.passed;
  r.energy = sol.energy;
  r.certificate = sol.certificate.max_residual;
  r.seconds = secs;
  r.message = sol.message;
  log_info() << "minima: " << backend << " from " << start << ": energy " << fmt(sol.energy, 10) << ", certificate "
             << fmt(sol.certificate.max_residual, 3) << (r.certified ? "" : " (NOT certified)");
  R.runs.push_back(r);
  if (r.certified) cands.push_back({static_cast<int>(R.runs.size()) - 1, std::move(sol)});
  if (mopt.on_run) mopt.on_run(R.runs);
}

// The largest |u_ν|, |u_τ| of @p s over Γ3: the search's length U_s (the random box, the second-order
// check's smoothing widths) where the solver has none of its own (ContactSolver::length_scale).
double gamma3_extent(const Model& md, const Solution& s) {
  double U = 0;
  for (Index k = 0; k < md.contact.size(); ++k) U = std::max({U, std::abs(s.state.u_nu[k]), std::abs(s.state.u_tau[k])});
  return U;
}

// Every start with backend @p name on the one solver (made by the first backend: factored, and
// condensed, once for every backend, start and load step).
void MinimaSearch::run_backend(std::unique_ptr<ContactSolver>& solver, const SolveOptions& opt,
                               const std::string& name) {
  const MinimaOptions& mopt = R.options;
  SolveOptions o = opt;
  o.backend = name;
  // solver.exact.start = auto: the continuation's neighbourhoods for the starts whose inner problem
  // is not strongly convex, since reaching different stationary points is what minima is for
  // (solve_options.hpp; minima-softening: 6 distinct minima this way, 3 with "always").
  if (o.exact_start == "auto") o.exact_start = "convex";
  const bool first = !solver;
  if (first)
    solver = std::make_unique<ContactSolver>(md, o);
  else
    solver->set_backend(name);
  auto t = clk::now();
  Solution zero = solver->solve(nullptr);
  double Us = zero.x_scale;
  // ssn in the full space runs without a U_s (1 m: the random box ±1 m, the check's widths ε m
  // whatever the loads); its zero answer's extent on Γ3 is the scale, as on the petsc engine
  // (run_engine), and the solver is set up again with it (ssn's set-up factorizes nothing).
  if (const double extent = gamma3_extent(md, zero); first && solver->length_scale() == 0 && extent > 0) {
    Us = o.x_scale = extent;
    solver = std::make_unique<ContactSolver>(md, o);
  }
  ContactSolver& S = *solver;
  R.x_scale = Us;
  if (first) R.smallness = zero.smallness;
  record("zero", name, std::move(zero), t);
  if (S.formulation().empty()) {  // linear: the solution is unique, one solve says it all
    log_info() << "minima: linear problem, one solution; no further starts";
    return;
  }
  // The exact solver's own path from zero (solver.exact.start = always), once: a solve that
  // chooses it must find its answer among these (it can be another stationary point than the
  // backend's neighbourhood leads to when Φ_λ is not strongly convex).
  if (first && opt.exact) {
    S.set_exact_start("always");
    const auto t1 = clk::now();
    record("exact-from-zero", name, S.solve(nullptr), t1);
    S.set_exact_start(o.exact_start);
  }
  gamma3_starts(S, name, Us, [&](const Vec& z0) { return S.solve(&z0); });
  if (mopt.load_path_steps > 0) load_path(S, name);
  for (size_t i = 0; i < mopt.user_starts.size(); ++i) {
    const std::string label = "user-" + std::to_string(i + 1);
    const Vec z0 = user_start(S, md, mopt.user_starts[i], label);
    const auto t1 = clk::now();
    record(label, name, S.solve(&z0), t1);
  }
}

// Every start on the caller's engine (MinimaOptions::engine): zero (the engine's own start), the
// Γ3 starts, the load path, the caller's starts; no "exact-from-zero", the in-process exact
// solver's own path. The starts are u = T z from the check solver's unknowns: the full
// formulation with ssn, which factorizes nothing at its set-up and serves the second-order check
// (lagged_energy). Its U_s, which sets the random box and the check's smoothing widths, is the
// zero start's largest |u| on Γ3 (the unconstrained elastic solution would be a solve of its own).
void MinimaSearch::run_engine(std::unique_ptr<ContactSolver>& checks, const SolveOptions& opt) {
  const MinimaOptions& mopt = R.options;
  const std::string& name = mopt.engine_name;
  auto t = clk::now();
  Solution zero = mopt.engine(md, 1.0, nullptr);
  const double Us = gamma3_extent(md, zero);
  R.x_scale = Us > 0 ? Us : 1.0;
  R.smallness = zero.smallness;
  record("zero", name, std::move(zero), t);
  SolveOptions o = opt;
  o.engine = "cholmod";  // this process's solver, for the checks only
  o.formulation = "full";
  if (md.material->is_linear()) o.backend = SSN_BACKEND;
  o.smallness = false;
  o.x_scale = R.x_scale;
  checks = std::make_unique<ContactSolver>(md, o);
  const ContactSolver& S = *checks;
  if (S.formulation().empty()) {
    log_info() << "minima: linear problem, one solution; no further starts";
    return;
  }
  const SolveFrom solve_from = [&](const Vec& z0) {
    const Vec u = md.dofs.to_full(z0);
    return mopt.engine(md, 1.0, &u);
  };
  gamma3_starts(S, name, R.x_scale, solve_from);
  if (mopt.load_path_steps > 0) engine_load_path(name);
  for (size_t i = 0; i < mopt.user_starts.size(); ++i) {
    const std::string label = "user-" + std::to_string(i + 1);
    const Vec z0 = user_start(S, md, mopt.user_starts[i], label);
    const auto t1 = clk::now();
    record(label, name, solve_from(z0), t1);
  }
}

// The load path on the engine: each load's model to judge on, u carried from step to step.
void MinimaSearch::engine_load_path(const std::string& name) {
  Vec u = Vec::Zero(md.dofs.n_full());
  load_path_legs(name, [&](double scale) {
    Solution s = scale == 1 ? R.options.engine(md, 1.0, &u) : R.options.engine(scaled_model(md, scale), scale, &u);
    u = s.u;
    return s;
  });
}

// Γ3 starts: at the gap, separated, random in the box.
void MinimaSearch::gamma3_starts(const ContactSolver& S, const std::string& name, double Us,
                                 const SolveFrom& solve_from) {
  const MinimaOptions& mopt = R.options;
  const Index nc = md.contact.size();
  const int d = md.dim();
  const auto run_from = [&](const std::string& label, const Vec& z0) {
    const auto t1 = clk::now();
    record(label, name, solve_from(z0), t1);
  };
  Vec c(d * nc);
  c.setZero();
  for (Index k = 0; k < nc; ++k) c[d * k] = std::isfinite(md.contact.g[k]) ? md.contact.g[k] : Us;
  run_from("at-gap", from_gamma3(S, c));
  c.setZero();
  for (Index k = 0; k < nc; ++k) c[d * k] = -Us;
  run_from("separated", from_gamma3(S, c));
  std::mt19937 rng(mopt.seed);
  const double B = mopt.box * Us;
  // Batches of `starts` random starts; with until_complete, until fewer than one distinct solution
  // is estimated unreached (chao1_estimate) or max_starts have run.
  int done = 0;
  while (true) {
    for (int i = 0; i < mopt.starts && (!mopt.until_complete || done < mopt.max_starts); ++i) {
      for (Index k = 0; k < nc; ++k) {
        const double hi = std::min(B, md.contact.g[k]);
        c[d * k] = std::uniform_real_distribution<double>(-B, std::max(-B, hi))(rng);
        for (int a = 1; a < d; ++a) c[d * k + a] = std::uniform_real_distribution<double>(-B, B)(rng);
      }
      run_from("random-" + std::to_string(++done), from_gamma3(S, c));
    }
    if (!mopt.until_complete) break;
    const UnseenEstimate e = chao1_estimate(random_abundances());
    log_info() << "minima: " << done << " random starts: " << e.observed << " distinct, f1 = " << e.f1 << ", f2 = " << e.f2
               << ", Chao1 " << fmt(e.chao1, 4) << " (unseen " << fmt(e.unseen, 3) << ")";
    if (e.samples > 0 && e.unseen < 1) {
      R.unseen.complete = true;
      break;
    }
    if (done >= mopt.max_starts) break;
  }
  R.unseen.random_starts = done;
}

// Load path up (1/N … 1), then on to 2 and back down to 1; warm starts all the way.
void MinimaSearch::load_path(ContactSolver& S, const std::string& name) {
  Vec z = Vec::Zero(S.size());
  load_path_legs(name, [&](double scale) {  // from z, at loads × scale (1: the model itself)
    std::optional<Model> scaled;  // outlives the solve: set_loads keeps a reference
    if (scale != 1) {
      scaled = scaled_model(md, scale);
      S.set_loads(*scaled, scale);  // same factorization, scaled loads
    }
    Solution s = S.solve(&z);
    if (scale != 1) S.set_loads(md, 1.0);
    z = S.to_unknowns(s.x);
    return s;
  });
}

// The load path's schedule, one definition for both: up (1/N … 1), then on to 2 and back down to
// 1, recorded at 1 on the way up and on the way down; @p solve_at(scale) solves at loads × scale
// from the previous step's answer.
void MinimaSearch::load_path_legs(const std::string& name, const std::function<Solution(double)>& solve_at) {
  const int N = R.options.load_path_steps;
  bool ok = true;
  const auto step = [&](int i) {
    Solution s = solve_at(static_cast<double>(i) / N);
    if (i != N && (!s.backend_ok || !s.fixed_point_converged)) ok = false;
    return s;
  };
  const auto leg_end = [&](const std::string& label, clk::time_point t) {
    Solution end = step(N);
    if (!ok) end.message = "load path: an intermediate solve did not converge; " + end.message;
    record(label, name, std::move(end), t);
    ok = true;
  };
  const auto t1 = clk::now();
  for (int i = 1; i < N; ++i) step(i);
  leg_end("load-up", t1);
  const auto t2 = clk::now();
  for (int i = N + 1; i <= 2 * N; ++i) step(i);
  for (int i = 2 * N - 1; i > N; --i) step(i);
  leg_end("load-down", t2);
}

// Group: greedy, against each group's first member (its anchor), in run order; each group's
// representative is its member with the smallest certificate residual. Sorted by energy.
void MinimaSearch::group() {
  for (const auto& cd : cands) R.norm_scale = std::max(R.norm_scale, cd.sol.energy_norm);
  const double thr = R.options.group_tol * R.norm_scale;
  std::vector<std::vector<int>> groups;  // indices into cands
  for (int i = 0; i < static_cast<int>(cands.size()); ++i) {
    int g = -1;
    for (int q = 0; q < static_cast<int>(groups.size()) && g < 0; ++q)
      if (energy_distance(md, cands[static_cast<size_t>(i)].sol.u, cands[static_cast<size_t>(groups[q][0])].sol.u) <=
          thr)
        g = q;
    if (g < 0)
      groups.push_back({i});
    else
      groups[static_cast<size_t>(g)].push_back(i);
  }
  for (const auto& members : groups) {
    int best = members[0];
    for (int i : members)
      if (cands[static_cast<size_t>(i)].sol.certificate.max_residual <
          cands[static_cast<size_t>(best)].sol.certificate.max_residual)
        best = i;
    DistinctSolution ds;
    ds.solution = cands[static_cast<size_t>(best)].sol;
    for (int i : members) {
      const int run = cands[static_cast<size_t>(i)].run;
      ds.runs.push_back(run);
      ds.starts.push_back(R.runs[static_cast<size_t>(run)].start);
      ++ds.backends[R.runs[static_cast<size_t>(run)].solved_by];
      if (R.norm_scale > 0)
        ds.spread =
            std::max(ds.spread, energy_distance(md, cands[static_cast<size_t>(i)].sol.u, ds.solution.u) / R.norm_scale);
    }
    R.solutions.push_back(std::move(ds));
  }
  std::stable_sort(R.solutions.begin(), R.solutions.end(), [](const DistinctSolution& a, const DistinctSolution& b) {
    return a.solution.energy < b.solution.energy;
  });
}
}  // namespace

MinimaReport find_minima(const Model& md, const SolveOptions& opt, const MinimaOptions& mopt_in) {
  const auto t0 = clk::now();
  MinimaReport R;
  R.options = mopt_in;
  MinimaOptions& mopt = R.options;
  if (mopt.backends.empty()) mopt.backends = {opt.backend};
  if (mopt.starts < 0) input_error("minima: --starts must be >= 0");
  if (!(mopt.group_tol > 0)) input_error("minima: group_tol must be > 0");
  if (!(mopt.box > 0)) input_error("minima: box must be > 0");
  if (mopt.load_path_steps < 0) input_error("minima: load_path_steps must be >= 0");
  if (mopt.until_complete && (mopt.starts < 1 || mopt.max_starts < mopt.starts))
    input_error("minima: --until-complete needs --starts >= 1 (the batch) and --max-starts >= --starts");

  MinimaSearch search{md, R, {}};
  // One solver for every backend, start and load step: factored (and condensed) once.
  std::unique_ptr<ContactSolver> solver;
  if (mopt.engine)
    search.run_engine(solver, opt);
  else
    for (const std::string& name : mopt.backends) search.run_backend(solver, opt, name);
  search.group();
  pair_mirror_images(md, R, mopt.group_tol);
  std::vector<int> abundance;
  for (const DistinctSolution& ds : R.solutions)
    abundance.push_back(static_cast<int>(std::count_if(ds.starts.begin(), ds.starts.end(), is_random_start)));
  const UnseenEstimate so_far = R.unseen;
  R.unseen = chao1_estimate(abundance);
  R.unseen.random_starts = so_far.random_starts;
  R.unseen.complete = so_far.complete;
  for (size_t k = 0; k < R.solutions.size(); ++k) {
    DistinctSolution& ds = R.solutions[k];
    for (int run : ds.runs) R.runs[static_cast<size_t>(run)].group = static_cast<int>(k);
    ds.second_order = second_order_check(*solver, md, opt, ds.solution, mopt);
    log_info() << "minima: solution " << k << ": energy " << fmt(ds.solution.energy, 10) << ", "
               << ds.second_order.verdict << " (lambda_min " << fmt(ds.second_order.lambda_min, 4) << "), "
               << ds.runs.size() << " start(s)";
  }
  R.seconds = since(t0);
  return R;
}

UnseenEstimate chao1_estimate(const std::vector<int>& abundances) {
  UnseenEstimate e;
  for (int a : abundances) {
    if (a <= 0) continue;
    e.samples += a;
    ++e.observed;
    e.f1 += a == 1;
    e.f2 += a == 2;
  }
  if (e.samples == 0) return e;
  const double n = e.samples, S = e.observed, f1 = e.f1, f2 = e.f2, c = (n - 1) / n;
  double var = 0;
  if (f2 > 0) {
    const double r = f1 / f2;
    e.chao1 = S + c * f1 * f1 / (2 * f2);
    var = f2 * (0.5 * c * r * r + c * c * r * r * r + 0.25 * c * c * r * r * r * r);
  } else {
    e.chao1 = S + c * f1 * (f1 - 1) / 2;
    var = c * f1 * (f1 - 1) / 2 + c * c * f1 * (2 * f1 - 1) * (2 * f1 - 1) / 4 - c * c * f1 * f1 * f1 * f1 / (4 * e.chao1);
  }
  e.unseen = e.chao1 - S;
  e.lo = e.hi = S;
  if (e.unseen > 0) {
    const double K = std::exp(1.96 * std::sqrt(std::log(1 + std::max(var, 0.0) / (e.unseen * e.unseen))));
    e.lo = S + e.unseen / K;
    e.hi = S + e.unseen * K;
  }
  return e;
}

std::vector<Vec> read_gamma3_starts(const json& js, const Model& md, const std::string& context) {
  const Index nc = md.contact.size();
  const int d = md.dim();
  const auto one = [&](const json& s, const std::string& where) -> Vec {
    Vec v(d * nc);
    if (s.is_object()) {
      if (!s.contains("nodes") || !s.at("nodes").is_array())
        input_error(context + where + ": expected an array of [u_nu, u_tau] or a report.json with \"nodes\"");
      if (d != 2) input_error(context + where + ": report.json starts are 2D only (3D u_tau is a magnitude)");
      const json& nodes = s.at("nodes");
      if (static_cast<Index>(nodes.size()) != nc)
        input_error(context + where + ": " + std::to_string(nodes.size()) + " nodes, the scene has " +
                    std::to_string(nc) + " Gamma3 nodes");
      for (Index k = 0; k < nc; ++k) {
        const json& n = nodes[static_cast<size_t>(k)];
        if (!n.contains("u_nu") || !n.contains("u_tau") || !n.at("u_nu").is_number() || !n.at("u_tau").is_number())
          input_error(context + where + ".nodes[" + std::to_string(k) + "]: needs numbers u_nu and u_tau");
        v[d * k] = n.at("u_nu").get<double>();
        v[d * k + 1] = n.at("u_tau").get<double>();
      }
      return v;
    }
    if (!s.is_array() || static_cast<Index>(s.size()) != nc)
      input_error(context + where + ": expected " + std::to_string(nc) +
                  " entries [u_nu, u_tau] (one per Gamma3 node)");
    for (Index k = 0; k < nc; ++k) {
      const json& e = s[static_cast<size_t>(k)];
      if (!e.is_array() || static_cast<int>(e.size()) != d)
        input_error(context + where + "[" + std::to_string(k) + "]: expected " + std::to_string(d) + " numbers");
      for (int a = 0; a < d; ++a) {
        if (!e[static_cast<size_t>(a)].is_number())
          input_error(context + where + "[" + std::to_string(k) + "]: expected numbers");
        v[d * k + a] = e[static_cast<size_t>(a)].get<double>();
      }
    }
    return v;
  };
  // Several starts: an array whose elements are starts themselves (objects, or arrays of arrays).
  const bool several = js.is_array() && !js.empty() &&
                       (js[0].is_object() || (js[0].is_array() && !js[0].empty() && js[0][0].is_array()));
  std::vector<Vec> r;
  if (several)
    for (size_t i = 0; i < js.size(); ++i) r.push_back(one(js[i], "[" + std::to_string(i) + "]"));
  else
    r.push_back(one(js, ""));
  return r;
}

}  // namespace hemicontact
