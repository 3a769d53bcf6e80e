// The "newton" backend: a projected Newton method with an active (binding) set for
//   min f(x)  subject to  l <= x <= u,
// after Bertsekas, "Projected Newton methods for optimization problems with simple constraints",
// SIAM J. Control Optim. 20 (1982), in the form of Kelley, "Iterative Methods for Optimization"
// (SIAM 1999), §5.5 (projected Armijo rule on the arc x(α) = P[x + α d]).
//
// One iteration at x, with g = ∇f(x):
//  1. Binding set B = {i: x_i <= l_i + ε_b, g_i > 0} ∪ {i: x_i >= u_i − ε_b, g_i < 0}, the bounds
//     that the gradient presses on; F is the rest (free).
//     ε_b = 10·tol (EPS_BINDING_PER_TOL): the problem is O(1)-scaled (ScaledObjective), so this
//     is an absolute distance well below any physical one. Bertsekas' theory only needs ε_b > 0;
//     in practice iterates reach a bound exactly through the projection, so a small ε_b only
//     catches round-off. Bertsekas' adaptive ε_b = min(ε, r) measured no better on the paper
//     scenes (fig2 and frictionless, mesh.n = 16 and 64, both formulations): identical iteration
//     counts for ε <= 1e-3, and for ε = 0.1 the first stage of fig2 at n = 64 (full) took 11
//     iterations instead of 6 (nodes just below the obstacle were pinned, then released).
//  2. H = ∇²f(x), exact (Psd::NONE) when its H_FF is positive definite, else with Psd::CLAMP
//     (nonconvex nodal curvatures clamped to 0; the elastic part is SPD, so the clamped H_FF is
//     SPD in the contact problems). Solve H_FF d_F = −g_F.
//     Why exact first (option "hessian": "exact_first", the default, or "clamp" for CLAMP only):
//     with CLAMP, Newton converges only linearly once compliance nodes sit on the softening
//     branch (c2 < 0 clamped to 0): the rate is ≈ |w c2| / stiffness, measured 1e-2 per
//     iteration on fig2, so every continuation stage costs 2-5 factorizations instead of 1.
//     fig2 at mesh.n = 64 took 20 (full) / 18 (condensed) iterations in all with CLAMP, 10 / 9
//     exact-first; the exact H_FF was positive definite in every iteration of the paper scenes
//     (mesh.n = 2 ... 256), the elastic stiffness outweighing w·|c2|. When it is not (coarse
//     meshes, steep softening, mollified jumps of p_ν), the failed factorization costs one
//     extra Cholesky and the clamped Hessian takes over for that iteration.
//     For i ∈ B, d_i = (bound − x_i): zero for the usual binding unknown that sits exactly on its
//     bound (the textbook d_B = 0), and for one within ε_b of it the step lands it on the bound at
//     α = 1, so r_i = min(|g_i|, distance) cannot stall at ≈ ε_b > tol.
//     - sparse pattern: the rows and columns of B are replaced by those of the identity in a matrix
//       with H's pattern (plus the diagonal), so the pattern never changes during a run and
//       CHOLMOD's symbolic analysis is done once; it is kept across minimize() calls while the
//       pattern is the same (same object, size, nnz, and index arrays, compared in O(nnz) — the
//       driver's warm-started continuation calls this backend tens of times on one pattern).
//     - dense pattern (nnz == n(n+1)/2, the condensed formulation): Eigen's dense LLᵀ of the
//       compact H_FF.
//     - not positive definite, or numerically singular (‖d_F‖∞·max|H_ii| > ‖g_F‖∞/(100 ε_mach),
//       i.e. cond(H_FF) beyond round-off; e.g. a clamped curvature that leaves a null direction
//       "factors" with a pivot ~1e-16 and gives a step ~1e16): H_FF + δ·max|diag H_FF|·I with
//       δ = 1e-10, ×10 per failure up to 1e10, starting at a tenth of the previous iteration's δ
//       (logged at debug level, counted in the message). The contact problems never needed it:
//       their elastic part is SPD and CLAMP keeps the rest PSD.
//  3. Projected backtracking: α = 1, 1/2, ... (at most MAX_HALVINGS) until
//       f(x(α)) <= f(x) + σ·min(0, gᵀ(x(α) − x)),   σ = 1e-4.
//     min(0, ·) keeps a projected step that is not first-order descent from being accepted for
//     increasing f. Round-off: the full step (α = 1) is also accepted when its predicted change
//     |gᵀ(x(1) − x)| and the actual increase are both below the noise of f, 64·ε_mach·(1 + |f|);
//     near the solution the true decrease (~r²/‖H‖) is far below what f can resolve, and
//     without this the last Newton step would be rejected on noise. Only α = 1 gets this
//     allowance, so a bad direction (e.g. an inconsistent gradient) cannot creep along on noise.
//     Where f's error is not that small (a 3D body's energy sums 10⁴ cell energies; 3D Hencky at
//     mesh.n = 16 rose by 2.6e-12 along a step predicted to lower it by 1.5e-16, and r stalled at
//     1e-8), α = 1 is also accepted by Hager and Zhang's approximate Armijo test, which reads the
//     decrease from the gradients at both ends (approximate_armijo below).
//     No acceptable α (or x(α) = x bitwise): FAILED, x left at the last accepted iterate.
// Stopping (checked before each iteration, so a warm start at the answer takes 0 iterations):
//  - CONVERGED when r = max_i min(|g_i|, distance to the bound that −g_i points to) <= tol,
//    the driver's first-order residual (src/solver/solve.cpp) in the O(1)-scaled unknowns.
//  - CONVERGED ("round-off floor") when the Newton correction on the free set is tiny,
//    ‖d_F‖∞ <= tol·max(1, ‖x‖∞), no binding unknown is off its bound, and r <= 10·tol: another
//    step cannot change x, so r is then limited by the accuracy of the gradient itself
//    (cancellation in K x − f), not by the method.
//  - MAX_ITERATIONS after max_iter Newton steps.
// Options (BackendOptions::extra, anything else is an Error): "linear_solver" = auto (dense LLᵀ
// iff the pattern is dense) | cholmod | dense; "hessian" = exact_first (default) | clamp.

#include "nlp/backend_factories.hpp"

#include <hemicontact/core/clock.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/core/log.hpp>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

constexpr double EPS_BINDING_PER_TOL = 10.0;  // ε_b = 10·tol (see the top of the file)
constexpr double ARMIJO_SIGMA = 1e-4;
constexpr int MAX_HALVINGS = 50;       // α >= 2^-50 ≈ 1e-15
constexpr double SHIFT_FIRST = 1e-10;  // δ of the first shifted factorization
constexpr double SHIFT_LAST = 1e10;    // give up beyond this δ
constexpr double EPS = std::numeric_limits<double>::epsilon();
constexpr double F_NOISE = 64 * EPS;          // relative round-off of f(x) in the Armijo test
// The approximate Armijo test's allowance ε_HZ|f| for f's own error: Hager and Zhang take 1e-6
// for any f; here f is a sum of at most ~10⁶ cell and node terms, whose round-off is below
// 10⁶ ε_mach ≈ 2e-10 relative, so 1e-10 covers it (the 3D Hencky stall: 2.3e-14) while a full
// step that raises f by more, e.g. across a barrier of a nonconvex law, is still refused.
constexpr double HZ_EPS = 1e-10;
constexpr double COND_MAX = 1 / (100 * EPS);  // a step implying cond(H_FF) above this is noise

enum class LinearSolver { AUTO, CHOLMOD, DENSE };

/// Solves H_FF d_F = −g_F for the free unknowns, d_B = 0, by CHOLMOD on a fixed pattern or by a
/// dense LLᵀ. Keeps CHOLMOD's symbolic analysis while the pattern does not change.
class FreeSetSolver {
 public:
  // Silent CHOLMOD: "not positive definite" is expected and handled here (shift), other failures
  // are thrown as Errors with CHOLMOD's status.
  FreeSetSolver() { m_llt.cholmod().print = 0; }

  /// Prepare for @p pattern (lower triangle); a no-op, keeping the analysis, if it is the same
  /// object with the same index arrays as last time. @param dense use the dense LLᵀ.
  void set_pattern(const SpMat& pattern, bool dense) {
    const bool same = &pattern == m_key && pattern.rows() == m_H.rows() && pattern.nonZeros() == m_H.nonZeros() &&
                      dense == m_dense && same_indices(pattern, m_H);
    if (same) return;
    m_key = &pattern;
    m_dense = dense;
    m_H = pattern;
    m_H.makeCompressed();
    m_analyzed = false;
    const Index n = m_H.rows();
    // Lower triangle only (CHOLMOD reads the lower part; an upper entry would be dropped silently).
    for (Index j = 0; j < m_H.outerSize(); ++j)
      for (SpMat::InnerIterator it(m_H, j); it; ++it)
        if (it.row() < it.col())
          throw Error("newton: the Hessian pattern has an entry above the diagonal (" + std::to_string(it.row()) +
                          ", " + std::to_string(it.col()) + ")",
                      EXIT_INTERNAL);
    if (m_dense) return;
    // A = H's pattern ∪ the diagonal (the identity rows and the shift need every (i, i)).
    Triplets t;
    t.reserve(size_t(m_H.nonZeros() + n));
    for (Index j = 0; j < n; ++j) t.emplace_back(int(j), int(j), 0.0);
    for (Index j = 0; j < m_H.outerSize(); ++j)
      for (SpMat::InnerIterator it(m_H, j); it; ++it) t.emplace_back(int(it.row()), int(it.col()), 0.0);
    m_A.resize(int(n), int(n));
    m_A.setFromTriplets(t.begin(), t.end());
    m_A.makeCompressed();
    m_pos.resize(size_t(m_H.nonZeros()));
    m_diag.resize(size_t(n));
    for (Index j = 0; j < n; ++j) {
      const int* b = m_A.innerIndexPtr() + m_A.outerIndexPtr()[j];
      const int* e = m_A.innerIndexPtr() + m_A.outerIndexPtr()[j + 1];
      m_diag[size_t(j)] = int(std::lower_bound(b, e, int(j)) - m_A.innerIndexPtr());
      for (int k = m_H.outerIndexPtr()[j]; k < m_H.outerIndexPtr()[j + 1]; ++k)
        m_pos[size_t(k)] = int(std::lower_bound(b, e, m_H.innerIndexPtr()[k]) - m_A.innerIndexPtr());
    }
  }

  /// The Hessian storage handed to NlpObjective::hessian(); kept so that the objective's cached
  /// pattern positions (keyed on the index arrays) stay valid across iterations and calls.
  SpMat& hessian() { return m_H; }

  /// Factor H_FF + shift·I. @return false if it is not (numerically) positive definite.
  bool factor(const std::vector<char>& binding, double shift) {
    const auto t0 = clk::now();
    const bool ok = m_dense ? factor_dense(binding, shift) : factor_sparse(binding, shift);
    m_seconds += since(t0);
    ++m_factorizations;
    return ok;
  }

  /// @return d with d_F = −(H_FF + shift·I)⁻¹ g_F and d_B = 0 (after a successful factor()).
  Vec solve(const Vec& g, const std::vector<char>& binding) const {
    const Index n = g.size();
    Vec d = Vec::Zero(n);
    if (m_dense) {
      Vec gF(Index(m_free.size()));
      for (Index a = 0; a < gF.size(); ++a) gF[a] = g[m_free[size_t(a)]];
      const Vec dF = m_dllt.solve(gF);
      for (Index a = 0; a < gF.size(); ++a) d[m_free[size_t(a)]] = -dF[a];
      return d;
    }
    Vec b(n);
    for (Index i = 0; i < n; ++i) b[i] = binding[size_t(i)] ? 0.0 : -g[i];
    d = m_llt.solve(b);
    for (Index i = 0; i < n; ++i)
      if (binding[size_t(i)]) d[i] = 0.0;
    return d;
  }

  /// @return max |diagonal| of the free block last passed to factor() (shift included), or 1
  /// if that is 0 or not finite: the scale of the shift and of the singularity test.
  double free_diagonal_max(const std::vector<char>& binding) const {
    double s = 0;
    if (m_dense) {
      if (m_HFF.size()) s = m_HFF.diagonal().cwiseAbs().maxCoeff();
    } else {
      for (size_t i = 0; i < m_diag.size(); ++i)
        if (!binding[i]) s = std::max(s, std::abs(m_A.valuePtr()[m_diag[i]]));
    }
    return s > 0 && std::isfinite(s) ? s : 1.0;
  }

  bool dense() const { return m_dense; }
  int analyses() const { return m_analyses; }
  int factorizations() const { return m_factorizations; }
  double seconds() const { return m_seconds; }
  void reset_counters() { m_analyses = m_factorizations = 0, m_seconds = 0; }

 private:
  static bool same_indices(const SpMat& a, const SpMat& b) {
    if (!a.isCompressed()) return false;  // m_H is compressed; make a fresh copy rather than guess
    return std::memcmp(a.outerIndexPtr(), b.outerIndexPtr(), sizeof(int) * size_t(a.outerSize() + 1)) == 0 &&
           std::memcmp(a.innerIndexPtr(), b.innerIndexPtr(), sizeof(int) * size_t(a.nonZeros())) == 0;
  }

  bool factor_sparse(const std::vector<char>& binding, double shift) {
    // A = H scattered onto the fixed pattern, B's rows/columns replaced by the identity's.
    double* a = m_A.valuePtr();
    std::fill(a, a + m_A.nonZeros(), 0.0);
    const double* h = m_H.valuePtr();
    for (size_t k = 0; k < m_pos.size(); ++k) a[m_pos[k]] += h[k];
    const int* outer = m_A.outerIndexPtr();
    const int* inner = m_A.innerIndexPtr();
    for (Index j = 0; j < m_A.outerSize(); ++j) {
      if (binding[size_t(j)]) {
        for (int k = outer[j]; k < outer[j + 1]; ++k) a[k] = 0.0;
        continue;
      }
      for (int k = outer[j]; k < outer[j + 1]; ++k)
        if (binding[size_t(inner[k])]) a[k] = 0.0;
    }
    for (size_t i = 0; i < m_diag.size(); ++i) a[m_diag[i]] = binding[i] ? 1.0 : a[m_diag[i]] + shift;
    if (!m_analyzed) {
      const auto t0 = clk::now();
      m_llt.analyzePattern(m_A);
      log_debug() << "newton: CHOLMOD analysis of n = " << m_A.rows() << ", nnz = " << m_A.nonZeros() << " (lower) in "
                  << since(t0) << " s";
      m_analyzed = true;
      ++m_analyses;
    }
    m_llt.factorize(m_A);
    if (m_llt.info() != Eigen::Success) {
      const int status = m_llt.cholmod().status;
      if (status != CHOLMOD_NOT_POSDEF && status != CHOLMOD_OK)
        throw Error("newton: CHOLMOD factorization failed with status " + std::to_string(status) +
                        (status == CHOLMOD_OUT_OF_MEMORY ? " (out of memory)" : ""),
                    EXIT_INTERNAL);
      return false;
    }
    return true;
  }

  bool factor_dense(const std::vector<char>& binding, double shift) {
    const Index n = m_H.rows();
    m_free.clear();
    m_where.assign(size_t(n), -1);
    for (Index i = 0; i < n; ++i)
      if (!binding[size_t(i)]) {
        m_where[size_t(i)] = int(m_free.size());
        m_free.push_back(i);
      }
    const Index nf = Index(m_free.size());
    m_HFF.setZero(nf, nf);
    for (Index j = 0; j < m_H.outerSize(); ++j) {
      const int b = m_where[size_t(j)];
      if (b < 0) continue;
      for (SpMat::InnerIterator it(m_H, j); it; ++it) {
        const int a = m_where[size_t(it.row())];
        if (a >= 0) m_HFF(a, b) = it.value();  // lower: row >= col in both numberings
      }
    }
    m_HFF.diagonal().array() += shift;
    m_dllt.compute(m_HFF);
    return m_dllt.info() == Eigen::Success;
  }

  const SpMat* m_key = nullptr;  // the pattern object the cached analysis belongs to
  bool m_dense = false;
  bool m_analyzed = false;
  SpMat m_H;  // Hessian values, on the objective's pattern
  // sparse
  SpMat m_A;                // H's pattern ∪ diagonal: the matrix CHOLMOD factors
  std::vector<int> m_pos;   // H value k → A value m_pos[k]
  std::vector<int> m_diag;  // A value index of (i, i)
  Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> m_llt;
  // dense
  std::vector<Index> m_free;  // free unknowns in order
  std::vector<int> m_where;   // unknown → position in m_free, −1 if binding
  Mat m_HFF;
  Eigen::LLT<Mat, Eigen::Lower> m_dllt;
  // statistics (per minimize())
  int m_analyses = 0, m_factorizations = 0;
  double m_seconds = 0;
};

/// The backend's own options (BackendOptions::extra); see the top of the file.
struct NewtonOptions {
  LinearSolver linear_solver = LinearSolver::AUTO;  ///< "linear_solver": auto | cholmod | dense
  bool exact_first = true;                          ///< "hessian": exact_first | clamp
};

NewtonOptions parse_options(const BackendOptions& options) {
  NewtonOptions o;
  const auto bad = [](const std::string& key, const std::string& allowed, const std::string& value) {
    return Error("newton: option '" + key + "' must be " + allowed + ", got '" + value + "'", EXIT_INPUT);
  };
  for (const auto& [key, value] : options.extra) {
    if (key == "linear_solver") {
      if (value == "auto")
        o.linear_solver = LinearSolver::AUTO;
      else if (value == "cholmod")
        o.linear_solver = LinearSolver::CHOLMOD;
      else if (value == "dense")
        o.linear_solver = LinearSolver::DENSE;
      else
        throw bad(key, "\"auto\", \"cholmod\" or \"dense\"", value);
    } else if (key == "hessian") {
      if (value == "exact_first")
        o.exact_first = true;
      else if (value == "clamp")
        o.exact_first = false;
      else
        throw bad(key, "\"exact_first\" or \"clamp\"", value);
    } else {
      throw Error("newton: unknown option '" + key + "' (value '" + value +
                      "'); the newton backend takes 'linear_solver' (auto | cholmod | dense) and "
                      "'hessian' (exact_first | clamp)",
                  EXIT_INPUT);
    }
  }
  return o;
}

/// Counts for the closing message of NewtonBackend::do_minimize.
struct NewtonStats {
  int exact_steps = 0, shifted = 0, halvings = 0;
  double r = 0;  // the last first-order residual computed (0 before the first)
};

/// A Newton direction on the free set: which Hessian gave it and the diagonal shift it needed.
struct NewtonDirection {
  bool found = false;
  bool exact = false;  // the exact Hessian (else the clamped one)
  double delta = 0;    // shift / max|diag| (0: none)
};

/// The outcome of the projected backtracking line search.
struct LineSearch {
  bool accepted = false;
  bool gradient_at_xt = false;  // the approximate Armijo test computed ∇f(xt)
  double alpha = 1, ft = 0;
  int halvings = 0;
};

/// Marks the binding unknowns: on (within eps_b of) a bound with the gradient pointing out of the
/// box. Returns their number.
Index mark_binding(const Vec& x, const Vec& g, const Vec& lo, const Vec& up, double eps_b, std::vector<char>& binding) {
  Index nb = 0;
  for (Index i = 0; i < x.size(); ++i) {
    const bool b = (x[i] <= lo[i] + eps_b && g[i] > 0) || (x[i] >= up[i] - eps_b && g[i] < 0);
    binding[size_t(i)] = b;
    nb += b;
  }
  return nb;
}

/// Hager and Zhang's approximate Armijo test for the full step x(1) (the first of their
/// "approximate Wolfe conditions", SIAM J. Optim. 16 (2005) 170-192, §4): on φ(α) = f(x(α)),
/// φ(1) − φ(0) ≈ (φ'(0) + φ'(1))/2, exact for a quadratic, so φ'(1) <= (2σ − 1)φ'(0) with
/// φ'(0) < 0 is the Armijo test computed from gradients, which keep their accuracy where the
/// difference of two values of f is round-off (a 3D Hencky body's f sums 10⁴ cell energies: its
/// noise, ~1e-11|f|, hid a predicted decrease of 1e-16 and stalled Newton at r = 1e-8). As theirs,
/// it also asks φ(1) <= φ(0) + ε_HZ|φ(0)| (ε_HZ above). Tried only where the exact test failed at α = 1;
/// @p gt receives ∇f(x(1)).
bool approximate_armijo(const NlpObjective& f, const Vec& x, const Vec& g, const Vec& xt, double fx, double ft,
                        Vec& gt) {
  const double slope0 = g.dot(xt - x);
  if (!(slope0 < 0) || ft > fx + HZ_EPS * std::abs(fx)) return false;
  f.gradient(xt, gt);
  return gt.dot(xt - x) <= (2 * ARMIJO_SIGMA - 1) * slope0;
}

/// Projected backtracking (Armijo along the projection arc) from x along d; xt is the accepted
/// point. Counts the evaluations in @p evaluations. Where the full step was accepted by the
/// approximate Armijo test, @p gt holds ∇f(xt) and ls.gradient_at_xt is set.
LineSearch projected_line_search(const NlpObjective& f, const Vec& x, const Vec& g, const Vec& d, double fx,
                                 const Vec& lo, const Vec& up, Vec& xt, Vec& gt, int& evaluations) {
  const double noise = F_NOISE * (1 + std::abs(fx));
  LineSearch ls;
  for (; ls.halvings <= MAX_HALVINGS; ++ls.halvings, ls.alpha *= 0.5) {
    xt = (x + ls.alpha * d).cwiseMax(lo).cwiseMin(up);
    // x(α) = x in every bit: no step left to try. (Component-wise on purpose: near a stick node
    // the Newton step is ~1e-20 against a curvature ~2λw/ε_τ ~ 1e10, tiny next to ‖x‖∞ but
    // not next to that node's u_τ ≈ 0, and it does reduce the residual.)
    if ((xt.array() == x.array()).all()) break;
    ls.ft = f.value(xt);
    ++evaluations;
    const double slope = g.dot(xt - x);
    if (ls.ft <= fx + ARMIJO_SIGMA * std::min(0.0, slope) ||
        (ls.halvings == 0 && -slope <= noise && ls.ft <= fx + noise)) {
      ls.accepted = true;
      break;
    }
    if (ls.halvings == 0 && approximate_armijo(f, x, g, xt, fx, ls.ft, gt)) {
      ls.accepted = ls.gradient_at_xt = true;
      break;
    }
  }
  return ls;
}

/// d_B = (the bound the gradient presses on) − x_B for the binding unknowns (see the top of the
/// file); @return whether one of them is off its bound.
bool snap_binding(const Vec& x, const Vec& g, const Vec& lo, const Vec& up, const std::vector<char>& binding, Vec& d) {
  bool snap = false;
  for (Index i = 0; i < x.size(); ++i)
    if (binding[size_t(i)]) {
      d[i] = (g[i] > 0 ? lo[i] : up[i]) - x[i];
      snap |= d[i] != 0;
    }
  return snap;
}

std::string no_shift_helps() {
  return "H_FF not positive definite even with a diagonal shift of " + std::to_string(SHIFT_LAST) + "·max|diag|";
}

std::string line_search_failure(int k, int halvings, double r) {
  std::ostringstream why;
  why << "line search failed at iteration " << k << ": no decrease along the projected Newton step after "
      << halvings << " halvings (first-order residual " << r << ")";
  return why.str();
}

/// Per-iteration progress: debug level, or info with solver.print_level > 0.
void log_iteration(int print_level, int k, double fx, const LineSearch& ls, double r, Index nb, double dF_norm,
                   const NewtonDirection& dir) {
  LogStream(print_level > 0 ? LogLevel::INFO : LogLevel::DEBUG)
      << "newton " << k << ": f " << fx << " -> " << ls.ft << ", r " << r << ", |B| " << nb << ", |d_F| " << dF_norm
      << ", alpha " << ls.alpha << ", H " << (dir.exact ? "exact" : "clamped")
      << (dir.delta > 0 ? ", shift " + std::to_string(dir.delta) : std::string());
}

/// See the top of this file for the method and the reasons behind each constant.
class NewtonBackend final : public NlpBackend {
 public:
  std::string name() const override { return "newton"; }
  bool uses_hessian() const override { return true; }
  void check_options(const BackendOptions& options) const override { (void)parse_options(options); }

 protected:
  SolveResult do_minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options) override;

 private:
  void set_pattern(const NlpObjective& f, LinearSolver ls);
  NewtonDirection direction(const NlpObjective& f, const Vec& x, const Vec& g, const std::vector<char>& binding,
                            bool exact_first, double shift_last, int k, Vec& d);
  SolveResult& finish(SolveResult& result, const NewtonStats& stats, SolveStatus status, const std::string& why);

  FreeSetSolver m_solver;  // keeps CHOLMOD's analysis across calls on the same pattern
};

SolveResult& NewtonBackend::finish(SolveResult& result, const NewtonStats& stats, SolveStatus status,
                                   const std::string& why) {
  result.status = status;
  std::ostringstream m;
  m << "newton: " << why << " (" << m_solver.factorizations() << " factorizations ["
    << (m_solver.dense() ? "dense" : "cholmod") << ", " << m_solver.seconds() << " s], " << m_solver.analyses()
    << " analyses; Hessian exact " << stats.exact_steps << ", clamped " << result.iterations - stats.exact_steps
    << ", shifted " << stats.shifted << "; " << stats.halvings << " halvings)";
  result.message = m.str();
  log_debug() << result.message << "; " << result.iterations << " iterations, " << result.evaluations
              << " evaluations, f = " << result.f << ", r = " << stats.r;
  return result;
}

void NewtonBackend::set_pattern(const NlpObjective& f, LinearSolver ls) {
  const Index n = f.size();
  const SpMat& pattern = f.hessian_pattern();
  if (pattern.rows() != n || pattern.cols() != n)
    throw Error("newton: Hessian pattern is " + std::to_string(pattern.rows()) + "×" + std::to_string(pattern.cols()) +
                    " for n = " + std::to_string(n),
                EXIT_INTERNAL);
  const bool dense_pattern = pattern.nonZeros() == n * (n + 1) / 2;
  m_solver.set_pattern(pattern, ls == LinearSolver::DENSE || (ls == LinearSolver::AUTO && dense_pattern));
}

// Newton direction on the free set: the exact Hessian if H_FF is positive definite, else the
// clamped one, shifting its diagonal until the factorization succeeds.
NewtonDirection NewtonBackend::direction(const NlpObjective& f, const Vec& x, const Vec& g,
                                         const std::vector<char>& binding, bool exact_first, double shift_last, int k,
                                         Vec& d) {
  const Index n = f.size();
  double gF_norm = 0;
  for (Index i = 0; i < n; ++i)
    if (!binding[size_t(i)]) gF_norm = std::max(gF_norm, std::abs(g[i]));
  // Factor and solve; false if not positive definite or numerically singular: ‖d_F‖∞·max|H_ii|
  // / ‖g_F‖∞ is a lower bound on cond∞(H_FF), and beyond 1/(100 ε_mach) d_F is round-off (a
  // clamped curvature that leaves a null direction "factors" with a pivot ~1e-16 and gives a
  // step ~1e16). Unlike a pivot ratio, this is not fooled by a stiff but well-resolved
  // direction (a stick node's 2λw/ε_τ ~ 1e10 next to O(1) elastic entries).
  const auto solve = [&](double shift) {
    if (!m_solver.factor(binding, shift)) return false;
    d = m_solver.solve(g, binding);
    const double dn = d.cwiseAbs().maxCoeff();
    return std::isfinite(dn) && dn * m_solver.free_diagonal_max(binding) <= COND_MAX * gF_norm;
  };
  NewtonDirection out;
  out.exact = exact_first;
  f.hessian(x, m_solver.hessian(), out.exact ? Psd::NONE : Psd::CLAMP);
  out.found = solve(0.0);
  if (!out.found && out.exact) {
    out.exact = false;
    f.hessian(x, m_solver.hessian(), Psd::CLAMP);
    out.found = solve(0.0);
  }
  if (!out.found) {
    const double scale = m_solver.free_diagonal_max(binding);
    for (out.delta = std::max(SHIFT_FIRST, shift_last / 10); out.delta <= SHIFT_LAST; out.delta *= 10) {
      log_debug() << "newton: iteration " << k << ": H_FF is not (numerically) positive definite; shift " << out.delta
                  << "·" << scale;
      if ((out.found = solve(out.delta * scale))) break;
    }
  }
  return out;
}

// The problem is checked, x is inside the bounds and n ≥ 1 (NlpBackend::minimize, which also sets
// the result's kkt_norm and seconds).
SolveResult NewtonBackend::do_minimize(const NlpProblem& problem, Vec& x, const BackendOptions& options) {
  const NlpObjective& f = *problem.f;
  const Index n = f.size();
  const NewtonOptions opt = parse_options(options);
  const Vec& lo = problem.lower;
  const Vec& up = problem.upper;

  SolveResult result;
  NewtonStats stats;  // statistics for the message
  m_solver.reset_counters();
  set_pattern(f, opt.linear_solver);

  const double tol = options.tol;
  const double eps_b = EPS_BINDING_PER_TOL * tol;
  double fx = f.value(x);
  result.evaluations = 1;
  result.f = fx;
  if (!std::isfinite(fx)) return finish(result, stats, SolveStatus::FAILED, "f is not finite at the start");
  Vec g, d, xt, gt;
  f.gradient(x, g);
  std::vector<char> binding(size_t(n), 0);
  double shift_last = 0;  // δ of the previous iteration (0: none needed)

  for (int k = 0;; ++k) {
    check_interrupt();
    const double r = first_order_residual(x, g, lo, up);
    stats.r = r;
    if (!std::isfinite(r)) return finish(result, stats, SolveStatus::FAILED, "the gradient is not finite");
    if (r <= tol) return finish(result, stats, SolveStatus::CONVERGED, "converged: first-order residual <= tol");
    if (k >= options.max_iter) return finish(result, stats, SolveStatus::MAX_ITERATIONS, "iteration limit reached");

    const Index nb = mark_binding(x, g, lo, up, eps_b, binding);
    const NewtonDirection dir = direction(f, x, g, binding, opt.exact_first, shift_last, k, d);
    if (!dir.found) return finish(result, stats, SolveStatus::FAILED, no_shift_helps());
    shift_last = dir.delta;
    const double dF_norm = d.cwiseAbs().maxCoeff();  // d_B = 0 here
    const bool snap = snap_binding(x, g, lo, up, binding, d);
    if (!snap && dF_norm <= tol * std::max(1.0, x.cwiseAbs().maxCoeff()) && r <= 10 * tol)
      return finish(result, stats, SolveStatus::CONVERGED,
                    "converged: Newton step below tol and first-order residual <= 10·tol (round-off floor)");

    const LineSearch ls = projected_line_search(f, x, g, d, fx, lo, up, xt, gt, result.evaluations);
    stats.halvings += ls.halvings;
    if (!ls.accepted) return finish(result, stats, SolveStatus::FAILED, line_search_failure(k, ls.halvings, r));
    log_iteration(options.print_level, k, fx, ls, r, nb, dF_norm, dir);
    x.swap(xt);
    fx = ls.ft;
    result.f = fx;
    result.iterations = k + 1;
    stats.exact_steps += dir.exact;
    stats.shifted += dir.delta > 0;
    if (ls.gradient_at_xt)
      g.swap(gt);
    else
      f.gradient(x, g);
  }
}

}  // namespace

std::unique_ptr<NlpBackend> make_newton_backend() { return std::make_unique<NewtonBackend>(); }

}  // namespace hemicontact
