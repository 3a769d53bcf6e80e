#pragma once
/// @file test_problems.hpp  Small NlpObjective implementations with known minimizers, for the
/// backend tests (every backend should pass the same problems, so that backends that disagree show
/// up here rather than in a scene).
///
/// Each objective derives from DenseObjective, which turns a dense lower-triangle Hessian into the
/// fixed sparse pattern NlpObjective promises (explicit zeros kept, values written in place).

#include <hemicontact/core/types.hpp>
#include <hemicontact/nlp/nlp_problem.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hemicontact::test {

/// @return the bound-constrained problem min @p f subject to @p lower ≤ x ≤ @p upper (@p f must
/// outlive it), as every backend test builds it.
inline NlpProblem make_problem(const NlpObjective& f, const Vec& lower, const Vec& upper) {
  NlpProblem p;
  p.f = &f;
  p.lower = lower;
  p.upper = upper;
  return p;
}

/// @return the lower-triangular pattern (explicit zeros) of the entries (i, j), i >= j, where
/// @p mask is nonzero: a structural Hessian pattern chosen once.
inline SpMat lower_pattern_from_mask(const Mat& mask) {
  Triplets t;
  for (Index j = 0; j < mask.cols(); ++j)
    for (Index i = j; i < mask.rows(); ++i)
      if (mask(i, j) != 0.0) t.emplace_back(int(i), int(j), 0.0);
  SpMat p(int(mask.rows()), int(mask.cols()));
  p.setFromTriplets(t.begin(), t.end());
  p.makeCompressed();
  return p;
}

/// @brief Base for small test objectives: the Hessian is given densely and scattered onto a fixed
/// lower-triangular pattern chosen once (a structural mask), as hessian_pattern() requires.
class DenseObjective : public NlpObjective {
 public:
  /// @param mask n×n; entry (i, j), i >= j, is in the pattern when mask(i, j) != 0.
  explicit DenseObjective(const Mat& mask) : m_pattern(lower_pattern_from_mask(mask)) {}
  Index size() const override { return m_pattern.rows(); }
  const SpMat& hessian_pattern() const override { return m_pattern; }
  /// Writes the lower triangle of dense_hessian(x) on the pattern, keeping explicit zeros.
  void hessian(const Vec& x, SpMat& H, Psd /*psd*/) const override {
    if (H.rows() != m_pattern.rows() || H.nonZeros() != m_pattern.nonZeros()) H = m_pattern;
    const Mat D = dense_hessian(x);
    for (int k = 0; k < H.outerSize(); ++k)
      for (SpMat::InnerIterator it(H, k); it; ++it) it.valueRef() = D(it.row(), it.col());
  }
  /// @return the full symmetric ∇²f(x) (only its lower triangle inside the mask is used).
  virtual Mat dense_hessian(const Vec& x) const = 0;

 private:
  SpMat m_pattern;
};

/// @brief f(x) = ½ xᵀ A x − bᵀ x with A symmetric positive definite (dense pattern).
class QuadraticObjective : public DenseObjective {
 public:
  /// @param A SPD matrix; @param b linear term.
  QuadraticObjective(Mat A, Vec b)
      : DenseObjective(Mat::Ones(A.rows(), A.cols())), m_A(std::move(A)), m_b(std::move(b)) {}
  double value(const Vec& x) const override { return 0.5 * x.dot(m_A * x) - m_b.dot(x); }
  void gradient(const Vec& x, Vec& g) const override { g = m_A * x - m_b; }
  Mat dense_hessian(const Vec&) const override { return m_A; }
  /// @return A.
  const Mat& A() const { return m_A; }
  /// @return b.
  const Vec& b() const { return m_b; }

 private:
  Mat m_A;
  Vec m_b;
};

/// @brief Exact minimizer of ½xᵀAx − bᵀx on [l, u] for SPD A by enumerating active sets.
///
/// Each unknown is at its lower bound, its upper bound or free (3^n sets, so keep n small). For a
/// set, the free block solves A_FF x_F = b_F − A_FB x_B; the set is the answer when x is feasible
/// and the KKT signs hold: g = A x − b >= 0 where x_i = l_i, <= 0 where x_i = u_i. SPD makes the
/// minimizer unique, so the first verified set is it.
/// @param active_lower, active_upper outputs: which bounds are active at the answer.
inline Vec solve_box_qp_by_enumeration(const Mat& A, const Vec& b, const Vec& l, const Vec& u,
                                       std::vector<bool>* active_lower = nullptr,
                                       std::vector<bool>* active_upper = nullptr) {
  const Index n = b.size();
  long combos = 1;
  for (Index i = 0; i < n; ++i) combos *= 3;
  for (long c = 0; c < combos; ++c) {
    std::vector<int> state(n);  // 0 free, 1 at lower, 2 at upper
    bool possible = true;
    long code = c;
    for (Index i = 0; i < n; ++i, code /= 3) {
      state[i] = int(code % 3);
      if ((state[i] == 1 && std::isinf(l[i])) || (state[i] == 2 && std::isinf(u[i]))) possible = false;
    }
    if (!possible) continue;
    Vec x = Vec::Zero(n);
    std::vector<Index> free;
    for (Index i = 0; i < n; ++i) {
      if (state[i] == 1)
        x[i] = l[i];
      else if (state[i] == 2)
        x[i] = u[i];
      else
        free.push_back(i);
    }
    if (!free.empty()) {
      const Index k = Index(free.size());
      Mat AFF(k, k);
      Vec rhs(k);
      for (Index a = 0; a < k; ++a) {
        rhs[a] = b[free[a]];
        for (Index j = 0; j < n; ++j)
          if (state[j] != 0) rhs[a] -= A(free[a], j) * x[j];
        for (Index c2 = 0; c2 < k; ++c2) AFF(a, c2) = A(free[a], free[c2]);
      }
      const Vec xF = AFF.llt().solve(rhs);
      for (Index a = 0; a < k; ++a) x[free[a]] = xF[a];
    }
    const Vec g = A * x - b;
    const double eps = 1e-12 * (1.0 + b.cwiseAbs().maxCoeff());
    bool kkt = true;
    for (Index i = 0; i < n && kkt; ++i) {
      if (state[i] == 0)
        kkt = x[i] >= l[i] - eps && x[i] <= u[i] + eps;
      else if (state[i] == 1)
        kkt = g[i] >= -eps;
      else
        kkt = g[i] <= eps;
    }
    if (!kkt) continue;
    if (active_lower) {
      active_lower->assign(n, false);
      for (Index i = 0; i < n; ++i) (*active_lower)[i] = state[i] == 1;
    }
    if (active_upper) {
      active_upper->assign(n, false);
      for (Index i = 0; i < n; ++i) (*active_upper)[i] = state[i] == 2;
    }
    return x;
  }
  throw std::logic_error("solve_box_qp_by_enumeration: no active set satisfies KKT (A not SPD?)");
}

/// @brief The nonconvex double well f(x, y) = (x² − 1)² + (y − x/2)².
///
/// Unconstrained minimizers (±1, ±1/2), f = 0; a local maximum in x at x = 0. With the bound
/// x <= 1/2, a start with 0 < x0 <= 1/2 descends to the bound: ∂f/∂x = 4x(x² − 1) − (y − x/2)
/// is −3/2 < 0 at (1/2, 1/4), so (1/2, 1/4) is a KKT point with multiplier 3/2 and f = 9/16.
class DoubleWellObjective : public DenseObjective {
 public:
  DoubleWellObjective() : DenseObjective(Mat::Ones(2, 2)) {}
  double value(const Vec& v) const override {
    const double x = v[0], y = v[1];
    return std::pow(x * x - 1.0, 2) + std::pow(y - 0.5 * x, 2);
  }
  void gradient(const Vec& v, Vec& g) const override {
    const double x = v[0], y = v[1];
    g.resize(2);
    g[0] = 4.0 * x * (x * x - 1.0) - (y - 0.5 * x);
    g[1] = 2.0 * (y - 0.5 * x);
  }
  Mat dense_hessian(const Vec& v) const override {
    const double x = v[0];
    Mat H(2, 2);
    H << 12.0 * x * x - 4.0 + 0.5, -1.0, -1.0, 2.0;
    return H;
  }
};

/// @brief Chained Rosenbrock f(x) = Σ_{i<n−1} 100 (x_{i+1} − x_i²)² + (1 − x_i)² (tridiagonal
/// Hessian).
///
/// Minimizer x = (1, …, 1), f = 0. For n = 2 with x_0 <= 1/2: f >= (1 − x_0)² >= 1/4 with equality
/// only at (1/2, 1/4), which is therefore the bound-constrained minimizer (multiplier 1).
class RosenbrockObjective : public DenseObjective {
 public:
  /// @param n number of unknowns (>= 2).
  explicit RosenbrockObjective(Index n) : DenseObjective(tridiagonal_mask(n)) {}
  double value(const Vec& x) const override {
    double f = 0.0;
    for (Index i = 0; i + 1 < x.size(); ++i) f += 100.0 * std::pow(x[i + 1] - x[i] * x[i], 2) + std::pow(1.0 - x[i], 2);
    return f;
  }
  void gradient(const Vec& x, Vec& g) const override {
    g = Vec::Zero(x.size());
    for (Index i = 0; i + 1 < x.size(); ++i) {
      const double r = x[i + 1] - x[i] * x[i];
      g[i] += -400.0 * x[i] * r - 2.0 * (1.0 - x[i]);
      g[i + 1] += 200.0 * r;
    }
  }
  Mat dense_hessian(const Vec& x) const override {
    Mat H = Mat::Zero(x.size(), x.size());
    for (Index i = 0; i + 1 < x.size(); ++i) {
      H(i, i) += 1200.0 * x[i] * x[i] - 400.0 * x[i + 1] + 2.0;
      H(i + 1, i + 1) += 200.0;
      H(i, i + 1) += -400.0 * x[i];
      H(i + 1, i) += -400.0 * x[i];
    }
    return H;
  }

 private:
  static Mat tridiagonal_mask(Index n) {
    Mat m = Mat::Zero(n, n);
    for (Index i = 0; i < n; ++i) {
      m(i, i) = 1.0;
      if (i + 1 < n) m(i + 1, i) = 1.0;
    }
    return m;
  }
};

/// @brief Wraps an objective and corrupts its gradient (adds @p error to component 0), to show
/// that a derivative check catches a wrong gradient.
class WrongGradientObjective : public NlpObjective {
 public:
  /// @param inner the correct objective (referenced); @param error added to ∂f/∂x_0.
  WrongGradientObjective(const NlpObjective& inner, double error) : m_inner(inner), m_error(error) {}
  Index size() const override { return m_inner.size(); }
  double value(const Vec& x) const override { return m_inner.value(x); }
  void gradient(const Vec& x, Vec& g) const override {
    m_inner.gradient(x, g);
    g[0] += m_error;
  }
  const SpMat& hessian_pattern() const override { return m_inner.hessian_pattern(); }
  void hessian(const Vec& x, SpMat& H, Psd psd) const override { m_inner.hessian(x, H, psd); }

 private:
  const NlpObjective& m_inner;
  double m_error;
};

/// @brief An objective whose value() throws after @p calls evaluations (exception propagation).
class ThrowingObjective : public NlpObjective {
 public:
  /// @param inner the objective to forward to; @param calls successful value() calls before
  /// throwing.
  ThrowingObjective(const NlpObjective& inner, int calls) : m_inner(inner), m_left(calls) {}
  Index size() const override { return m_inner.size(); }
  double value(const Vec& x) const override {
    if (m_left-- <= 0) throw std::runtime_error("ThrowingObjective: evaluation failed on purpose");
    return m_inner.value(x);
  }
  void gradient(const Vec& x, Vec& g) const override { m_inner.gradient(x, g); }
  const SpMat& hessian_pattern() const override { return m_inner.hessian_pattern(); }
  void hessian(const Vec& x, SpMat& H, Psd psd) const override { m_inner.hessian(x, H, psd); }

 private:
  const NlpObjective& m_inner;
  mutable int m_left;
};

/// @return the full symmetric Hessian of @p f at @p x, expanded from its lower-triangle pattern.
inline Mat full_hessian(const NlpObjective& f, const Vec& x) {
  SpMat H = f.hessian_pattern();
  f.hessian(x, H, Psd::NONE);
  Mat D = Mat(H);
  Mat full = D + D.transpose();
  full.diagonal() = D.diagonal();
  return full;
}

/// A 6-unknown SPD box QP ½xᵀAx − bᵀx whose solution has lower, upper and inactive bounds, and some
/// infinite bounds (unknown 3 has no lower bound, unknown 5 none at all). Shared by the backend tests.
struct BoxQp {
  Mat A;
  Vec b, lower, upper;
};
inline BoxQp make_box_qp() {
  const Index n = 6;
  BoxQp q;
  q.A.resize(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) q.A(i, j) = 1.0 / (1.0 + std::abs(double(i - j))) + (i == j ? 2.0 : 0.0);
  Vec x_unconstrained(n);
  x_unconstrained << 2.0, -2.0, 0.3, -3.0, 1.5, 0.1;
  q.b = q.A * x_unconstrained;
  q.lower = Vec::Constant(n, -1.0);
  q.upper = Vec::Constant(n, 1.0);
  q.lower[3] = -INF;
  q.lower[5] = -INF;
  q.upper[5] = INF;
  return q;
}

/// A start, bounds on x and the closed-form answer of DoubleWellObjective (shared by the backends).
struct DoubleWellCase {
  const char* name;
  double x0, y0;  // start
  double lower_x, upper_x;
  double x_star, y_star;  // closed-form answer
};
inline void PrintTo(const DoubleWellCase& c, std::ostream* os) {
  *os << c.name << ": start (" << c.x0 << ", " << c.y0 << "), " << c.lower_x << " <= x <= " << c.upper_x << ", answer ("
      << c.x_star << ", " << c.y_star << ")";
}
/// The three cases every backend is run on:
/// - upper_bound_active: start between the local maximum x = 0 and the bound, which is active
///   (multiplier 3/2); the start has negative curvature f_xx = 12·0.09 − 3.5 < 0;
/// - left_well: same bound, start in the left well: the interior minimizer (−1, −1/2);
/// - lower_bound_inactive: x >= 1/2 inactive: the interior minimizer (1, 1/2).
inline std::vector<DoubleWellCase> double_well_cases() {
  return {{"upper_bound_active", 0.3, 0.0, -INF, 0.5, 0.5, 0.25},
          {"left_well", -0.4, 0.0, -INF, 0.5, -1.0, -0.5},
          {"lower_bound_inactive", 2.0, -3.0, 0.5, INF, 1.0, 0.5}};
}

}  // namespace hemicontact::test
