// NodalTerm and NodalLayout (nodal_term.hpp), the base of the nodal contact terms: the global value,
// gradient and Hessian of a sum of nodal terms (normal compliance + lagged friction sharing one
// layout) against finite differences on a small problem whose Γ3 nodes are mixed — free, at the
// rigid obstacle (x_ν = g), held by a roller (x_τ = 0), with and without friction — in 2D and 3D;
// the Hessian scattered through the layout's cached positions equals a triplet assembly of the same
// kernels, on K's pattern and on a blocks-only one; positions, absent entries and a foreign pattern.
//
// Tolerances: central differences with h = 1e-6·max(1, |x_i|) (tests/support/fd_check.hpp). Every
// point keeps each ν component ≥ 5e-3 from the window edges r_k ± ε and each |x_τ| either 0 or
// ≥ 0.1ε and ≥ 5e-3 from ε, so no step crosses a kink. Truncation ≤ h²/6·sup|f‴|: p_ε″ ≤
// Σ|Δs_k|/(2ε) = 1.5e4, ∇f0's third derivatives ≲ 3/(ε²|x_τ|) ≤ 4e6, so ≤ 1e-6 absolute against
// gradients and Hessians of size ≳ 1: 1e-6 relative for the gradient and 1e-5 for the Hessian. At
// x_τ = 0 exactly ∇f0(|u|) = (2/ε − |u|/ε²)u is only C¹ and the difference of the gradient errs by
// wλh/ε² = 2.5e-3·wλ against a τ-diagonal of 2wλ/ε = 100·wλ: 2.5e-5 relative, hence 1e-4 there.

#include <hemicontact/contact/mollified_law.hpp>
#include <hemicontact/contact/piecewise_linear_law.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/energy/contact_energy.hpp>
#include <hemicontact/energy/nodal_term.hpp>
#include <hemicontact/energy/total_energy.hpp>

#include "support/fd_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

constexpr double EPS = 0.02;  // ε_ν = ε_τ (absolute); windows [−ε, ε], [0.1 ± ε], [0.15 ± ε]

/// n_int interior dofs, then nc Γ3 nodes of d components. Node roles (k mod 5):
///   0 free, in contact with the layer   1 at its obstacle x_ν = g = 0.125 (between two windows)
///   2 roller (x_τ = 0) inside a window  3 free, separated (x_ν < 0)      4 at g = 0.06, λ = 0
struct Scene {
  int dim = 2;
  Index n_int = 3, nc = 7, n = 0;
  NodalDofs nodes;
  Vec g, lambda;
  std::vector<bool> roller;
  SpMat K_pattern;  ///< lower: tridiagonal couplings + full nodal blocks (like K's)
  SpMat blocks;     ///< lower: the nodal blocks only
  std::shared_ptr<const MollifiedLaw> law;
  Index nu(Index k) const { return nodes.first[k]; }
};

Scene make_scene(int dim) {
  Scene s;
  s.dim = dim;
  s.n = s.n_int + s.nc * dim;
  s.nodes.dim = dim;
  s.nodes.w.resize(s.nc);
  s.g = Vec::Constant(s.nc, INF);
  s.lambda.resize(s.nc);
  s.roller.assign(static_cast<size_t>(s.nc), false);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (Index k = 0; k < s.nc; ++k) {
    s.nodes.first.push_back(s.n_int + dim * k);
    s.nodes.w[k] = 0.2 + 0.8 * u01(rng);
    s.lambda[k] = 0.5 + u01(rng);
    if (k % 5 == 1) s.g[k] = 0.125;
    if (k % 5 == 4) s.g[k] = 0.06, s.lambda[k] = 0.0;
    s.roller[static_cast<size_t>(k)] = k % 5 == 2;
  }
  Triplets t, tb;
  for (Index i = 0; i < s.n; ++i) t.emplace_back(i, i, 0.0);
  for (Index i = 0; i + 1 < s.n; ++i) t.emplace_back(i + 1, i, 0.0);
  for (Index k = 0; k < s.nc; ++k)
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b <= a; ++b) {
        t.emplace_back(s.nu(k) + a, s.nu(k) + b, 0.0);
        tb.emplace_back(s.nu(k) + a, s.nu(k) + b, 0.0);
      }
  s.K_pattern.resize(s.n, s.n);
  s.K_pattern.setFromTriplets(t.begin(), t.end());
  s.K_pattern.makeCompressed();
  s.blocks.resize(s.n, s.n);
  s.blocks.setFromTriplets(tb.begin(), tb.end());
  s.blocks.makeCompressed();
  s.law = std::make_shared<const MollifiedLaw>(
      std::make_shared<const PiecewiseLinearLaw>(PiecewiseLinearLaw::paper(100, -100, 400, 0.1, 0.15)), EPS);
  return s;
}

/// A point with every node in its role; interior and free components random.
Vec make_point(const Scene& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Vec x(s.n);
  for (Index i = 0; i < s.n_int; ++i) x[i] = 0.4 * u01(rng) - 0.2;
  const double r_free[] = {0.05, 0.2, 0.1 + 0.007, -0.03};  // inside (0.02, 0.08), beyond 0.17, a window, < −ε
  for (Index k = 0; k < s.nc; ++k) {
    const int role = static_cast<int>(k % 5);
    double r = role == 0 ? r_free[k % 2] + 0.01 * u01(rng) : role == 2 ? r_free[2] : role == 3 ? r_free[3] : s.g[k];
    x[s.nu(k)] = r;
    // |x_τ| log-uniform in [0.1ε, 10ε], redrawn within 5e-3 of ε; exactly 0 on a roller.
    double y;
    do y = EPS * std::pow(10.0, -1.0 + 2.0 * u01(rng));
    while (std::abs(y - EPS) < 5e-3);
    Vec dir(s.dim - 1);
    do
      for (int a = 0; a + 1 < s.dim; ++a) dir[a] = 2 * u01(rng) - 1;
    while (dir.norm() < 0.1);
    x.segment(s.nu(k) + 1, s.dim - 1) =
        s.roller[static_cast<size_t>(k)] ? Vec(Vec::Zero(s.dim - 1)) : Vec(y * dir.normalized());
  }
  return x;
}

/// Lower bounds −∞, upper g on ν and 0 ≤ x_τ ≤ 0 on rollers, as the driver sets them: the point
/// must be feasible, with the bounded nodes active.
void expect_feasible_with_active_bounds(const Scene& s, const Vec& x) {
  int active = 0, held = 0;
  for (Index k = 0; k < s.nc; ++k) {
    EXPECT_LE(x[s.nu(k)], s.g[k]);
    active += x[s.nu(k)] == s.g[k];
    if (s.roller[static_cast<size_t>(k)]) held += x.segment(s.nu(k) + 1, s.dim - 1).norm() == 0;
  }
  EXPECT_GE(active, 2);
  EXPECT_GE(held, 1);
}

/// Dense symmetric matrix from a lower triangle.
Mat dense(const SpMat& L) { return Mat(Mat(L).selfadjointView<Eigen::Lower>()); }

/// The sum of the two nodal terms on @p pattern, one layout shared.
struct Sum {
  std::shared_ptr<const NodalLayout> layout;
  std::shared_ptr<NormalComplianceEnergy> normal;
  std::shared_ptr<FrictionEnergy> friction;
  std::unique_ptr<TotalEnergy> total;
  Sum(const Scene& s, const SpMat& pattern)
      : layout(std::make_shared<const NodalLayout>(s.nodes, pattern)),
        normal(std::make_shared<NormalComplianceEnergy>(layout, s.law)),
        friction(std::make_shared<FrictionEnergy>(layout, EPS, s.lambda)),
        total(std::make_unique<TotalEnergy>(s.n, pattern)) {
    total->add(normal);
    total->add(friction);
  }
};

class NodalTermEnergy : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override { s_ = make_scene(GetParam()); }
  Scene s_;
};

TEST_P(NodalTermEnergy, SumOfNodalTermsAgainstFiniteDifferences) {
  const Sum sum(s_, s_.K_pattern);
  ASSERT_EQ(&sum.normal->layout(), &sum.friction->layout());  // one cache for both terms
  const TotalEnergy& f = *sum.total;
  const auto value = [&](const Vec& y) { return f.value(y); };
  const auto gradient = [&](const Vec& y) {
    Vec g;
    f.gradient(y, g);
    return g;
  };
  std::mt19937 rng(21);
  for (int i = 0; i < 10; ++i) {
    SCOPED_TRACE("point " + std::to_string(i));
    const Vec x = make_point(s_, rng);
    expect_feasible_with_active_bounds(s_, x);
    const Vec g = gradient(x);
    EXPECT_TRUE(test::near_rel(g, test::fd_gradient(value, x), 1e-6, 0));
    SpMat H;
    f.hessian(x, H, Psd::NONE);
    const Mat fd_H = test::fd_jacobian(gradient, x);
    // Roller rows (x_τ = 0, only C¹ there): their own tolerance (file comment).
    Mat Hd = dense(H);
    for (Index k = 0; k < s_.nc; ++k)
      if (s_.roller[static_cast<size_t>(k)])
        for (int a = 1; a < s_.dim; ++a) {
          const Index r = s_.nu(k) + a;
          EXPECT_NEAR(Hd(r, r), fd_H(r, r), 1e-4 * std::abs(Hd(r, r)));
          EXPECT_GT(Hd(r, r), 0.0);  // the stick stiffness 2wλ/ε
          Hd(r, r) = fd_H(r, r);
        }
    EXPECT_TRUE(test::near_rel(Hd, fd_H, 1e-5, 0));
    // Interior unknowns see nothing; the λ = 0 node's τ components see nothing.
    EXPECT_EQ(g.head(s_.n_int).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(g.segment(s_.nu(4) + 1, s_.dim - 1).cwiseAbs().maxCoeff(), 0.0);
    // The value is the sum of the kernels.
    double v = 0;
    for (Index k = 0; k < s_.nc; ++k)
      v += sum.normal->node_value(k, sum.normal->local(x, k)) + sum.friction->node_value(k, sum.friction->local(x, k));
    EXPECT_NEAR(f.value(x), v, 1e-14 * std::abs(v));
  }
}

TEST_P(NodalTermEnergy, PatternCacheEqualsTripletAssembly) {
  std::mt19937 rng(22);
  for (const SpMat* pattern : {&s_.K_pattern, &s_.blocks}) {
    const Sum sum(s_, *pattern);
    for (int i = 0; i < 5; ++i) {
      const Vec x = make_point(s_, rng);
      for (Psd psd : {Psd::NONE, Psd::CLAMP}) {
        SCOPED_TRACE("point " + std::to_string(i) + (psd == Psd::CLAMP ? " clamp" : " none") +
                     (pattern == &s_.blocks ? " (blocks pattern)" : " (K pattern)"));
        Triplets t;
        sum.normal->add_hessian_triplets(x, t, psd);
        sum.friction->add_hessian_triplets(x, t, psd);
        for (const Triplet& e : t) EXPECT_GE(e.row(), e.col());
        SpMat T(s_.n, s_.n);
        T.setFromTriplets(t.begin(), t.end());
        SpMat H;
        sum.total->hessian(x, H, psd);
        // Each entry is 0 + the same kernel values in the same order both ways: equal exactly.
        EXPECT_EQ(dense(H), dense(T));
        // Each term alone, too.
        for (const NodalTerm* term :
             {static_cast<const NodalTerm*>(sum.normal.get()), static_cast<const NodalTerm*>(sum.friction.get())}) {
          Triplets tt;
          term->add_hessian_triplets(x, tt, psd);
          SpMat Tt(s_.n, s_.n);
          Tt.setFromTriplets(tt.begin(), tt.end());
          SpMat Ht = *pattern;
          Ht.coeffs().setZero();
          term->add_hessian(x, Ht, psd);
          EXPECT_EQ(dense(Ht), dense(Tt)) << term->name();
        }
      }
    }
  }
}

TEST_P(NodalTermEnergy, LayoutPositions) {
  const NodalLayout L(s_.nodes, s_.K_pattern);
  EXPECT_EQ(L.size(), s_.nc);
  EXPECT_EQ(L.dim(), s_.dim);
  EXPECT_EQ(L.n(), s_.n);
  for (Index k = 0; k < s_.nc; ++k)
    for (int a = 0; a < s_.dim; ++a)
      for (int b = 0; b <= a; ++b) {
        const Index pos = L.position(k, a, b);
        ASSERT_GE(pos, 0);
        EXPECT_EQ(pos, pattern_position(s_.K_pattern, s_.nu(k) + a, s_.nu(k) + b));
      }
  EXPECT_TRUE(L.matches(s_.K_pattern));
  EXPECT_FALSE(L.matches(s_.blocks));  // another pattern: the positions would be wrong
  // A Hessian of another pattern is refused, not silently mis-scattered.
  const auto layout = std::make_shared<const NodalLayout>(s_.nodes, s_.K_pattern);
  const NormalComplianceEnergy normal(layout, s_.law);
  SpMat H = s_.blocks;
  std::mt19937 rng(23);
  EXPECT_THROW(normal.add_hessian(make_point(s_, rng), H, Psd::NONE), Error);
}

// A pattern without the (ν, τ) couplings (and, in 3D, without (τ2, τ1)): those positions are −1.
// The normal term never adds there, so it assembles; friction at a 3D slip with both tangential
// components adds a nonzero (τ2, τ1) and is refused.
TEST_P(NodalTermEnergy, AbsentEntries) {
  Triplets t;
  for (Index i = 0; i < s_.n; ++i) t.emplace_back(i, i, 0.0);
  SpMat diag(s_.n, s_.n);
  diag.setFromTriplets(t.begin(), t.end());
  diag.makeCompressed();
  const auto layout = std::make_shared<const NodalLayout>(s_.nodes, diag);
  for (Index k = 0; k < s_.nc; ++k) {
    EXPECT_GE(layout->position(k, 0, 0), 0);
    EXPECT_EQ(layout->position(k, 1, 0), -1);
  }
  const NormalComplianceEnergy normal(layout, s_.law);
  const FrictionEnergy friction(layout, EPS, s_.lambda);
  std::mt19937 rng(24);
  const Vec x = make_point(s_, rng);
  SpMat H = diag;
  H.coeffs().setZero();
  normal.add_hessian(x, H, Psd::NONE);
  Triplets tn;
  normal.add_hessian_triplets(x, tn, Psd::NONE);
  SpMat T(s_.n, s_.n);
  T.setFromTriplets(tn.begin(), tn.end());
  EXPECT_EQ(dense(H), dense(T));
  if (s_.dim == 2) {
    friction.add_hessian(x, H, Psd::NONE);  // τ-block is one diagonal entry
  } else {
    EXPECT_THROW(friction.add_hessian(x, H, Psd::NONE), Error);
  }
}

TEST_P(NodalTermEnergy, LayoutRejectsInconsistentInput) {
  NodalDofs bad = s_.nodes;
  bad.w.resize(s_.nc - 1);
  EXPECT_THROW((void)NodalLayout(bad, s_.K_pattern), Error);
  bad = s_.nodes;
  bad.first.back() = s_.n - 1;  // components beyond the last unknown
  EXPECT_THROW((void)NodalLayout(bad, s_.K_pattern), Error);
  bad = s_.nodes;
  bad.dim = 4;
  EXPECT_THROW((void)NodalLayout(bad, s_.K_pattern), Error);
  EXPECT_THROW((void)NormalComplianceEnergy(nullptr, s_.law), Error);
}

INSTANTIATE_TEST_SUITE_P(Dim, NodalTermEnergy, ::testing::Values(2, 3),
                         [](const ::testing::TestParamInfo<int>& info) { return "d" + std::to_string(info.param); });

}  // namespace
}  // namespace hemicontact
