// find_barriers (studies/barriers.hpp) against the exact enumeration and a brute-force scan of the
// one-cell scene, and the verified saddles of the softening scene.
//
// One cell (support/one_cell_scan.hpp): every stationary point is known exactly from the branch
// choices. A barrier's saddle must be one of the enumerated index-1 points (to 1e-8), and the
// barriers the differences to the minima's energies. The brute-force scan: on a grid over
// (ν0, ν1), τ minimized out exactly (the energy is quadratic in τ), the level at which a flood from
// the lowest point first joins the two minima's cells (union-find, points added in order of energy)
// is the grid's mountain-pass level, within ½ λ_max(H) (h/√2)² of the true lowest pass (H the
// piecewise Hessian). The string's path is one path between the two, so its saddle is at least
// that level; it is equal where the lowest path is the direct one (0–2), and above it where the
// lowest path runs through a further minimum (0–1: the string finds a minimum-energy path near its
// straight start, not the lowest of all).

#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/studies/barriers.hpp>
#include <hemicontact/studies/minima.hpp>

#include "support/one_cell_scan.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

namespace hemicontact {
namespace barrier_scan {

struct Loaded {
  Model md;
  SolveOptions opt;
};

Loaded load(const std::string& name) {
  const std::string path = std::string(HEMICONTACT_SOURCE_DIR) + "/problems/" + name;
  const nlohmann::json scene = load_scene(path, {});
  return {build_model(scene, scene_directory(path)), solve_options_from_scene(scene)};
}

// The reduced energy E(ν0, ν1) = min over τ of Π (frictionless: τ enters quadratically).
struct Reduced {
  const Model& md;
  Mat K;
  Vec f;
  std::vector<Index> nu, tau;
  explicit Reduced(const Model& m) : md(m), K(Mat(m.Kx.full())), f(m.fx) {
    for (Index k = 0; k < 2; ++k) nu.push_back(m.dofs.contact_dof(k, 0)), tau.push_back(m.dofs.contact_dof(k, 1));
  }
  double operator()(double v0, double v1) const {
    Vec x = Vec::Zero(K.rows());
    x[nu[0]] = v0, x[nu[1]] = v1;
    Mat Ktt(2, 2);
    Vec r(2);
    for (int a = 0; a < 2; ++a) {
      r[a] = f[tau[static_cast<size_t>(a)]];
      for (int b = 0; b < 2; ++b) Ktt(a, b) = K(tau[static_cast<size_t>(a)], tau[static_cast<size_t>(b)]);
      r[a] -= K(tau[static_cast<size_t>(a)], nu[0]) * v0 + K(tau[static_cast<size_t>(a)], nu[1]) * v1;
    }
    const Vec t = Ktt.llt().solve(r);
    x[tau[0]] = t[0], x[tau[1]] = t[1];
    double E = 0.5 * x.dot(K * x) - f.dot(x);
    for (Index k = 0; k < 2; ++k) E += md.contact.w[k] * md.normal_law->j(x[nu[static_cast<size_t>(k)]]);
    return E;
  }
};

// The grid's mountain-pass level between the cells nearest (a0, a1) and (b0, b1).
double pass_level(const Reduced& E, double lo, double hi, int n, double a0, double a1, double b0, double b1) {
  const double h = (hi - lo) / (n - 1);
  std::vector<double> val(static_cast<size_t>(n * n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) val[static_cast<size_t>(i * n + j)] = E(lo + i * h, lo + j * h);
  std::vector<int> order(val.size()), parent(val.size());
  std::iota(order.begin(), order.end(), 0);
  std::iota(parent.begin(), parent.end(), 0);
  std::sort(order.begin(), order.end(), [&](int p, int q) { return val[static_cast<size_t>(p)] < val[static_cast<size_t>(q)]; });
  std::vector<bool> in(val.size(), false);
  const auto find = [&](int p) {
    while (parent[static_cast<size_t>(p)] != p) p = parent[static_cast<size_t>(p)] = parent[static_cast<size_t>(parent[static_cast<size_t>(p)])];
    return p;
  };
  const auto cell = [&](double v0, double v1) {
    return static_cast<int>(std::lround((v0 - lo) / h)) * n + static_cast<int>(std::lround((v1 - lo) / h));
  };
  const int A = cell(a0, a1), B = cell(b0, b1);
  for (int p : order) {
    in[static_cast<size_t>(p)] = true;
    const int i = p / n, j = p % n;
    for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const int ii = i + di, jj = j + dj;
      if (ii < 0 || jj < 0 || ii >= n || jj >= n || !in[static_cast<size_t>(ii * n + jj)]) continue;
      parent[static_cast<size_t>(find(ii * n + jj))] = find(p);
    }
    if (in[static_cast<size_t>(A)] && in[static_cast<size_t>(B)] && find(A) == find(B)) return val[static_cast<size_t>(p)];
  }
  return NaN;
}

// λ_max of the piecewise Hessian K_x + diag(w p_ν') over every piece: λ_max(K_x) + max w max|p_ν'|.
double curvature_bound(const Model& md) {
  double smax = 0;
  for (double sl : md.normal_law->slopes()) smax = std::max(smax, std::abs(sl));
  return Eigen::SelfAdjointEigenSolver<Mat>(Mat(md.Kx.full())).eigenvalues().maxCoeff() + md.contact.w.maxCoeff() * smax;
}

TEST(Barriers, OneNodeSaddlesAreTheEnumerationsAndNotBelowTheGridsPass) {
  const Loaded L = load("minima-one-node.json");
  const Model& md = L.md;
  MinimaOptions mo;
  mo.starts = 8;
  const MinimaReport R = find_minima(md, L.opt, mo);
  BarrierOptions bo;
  const std::vector<Barrier> B = find_barriers(md, L.opt, R, bo);
  ASSERT_EQ(B.size(), 3u) << "every pair of the lowest three minima";
  const auto P = one_cell::pieces_below_gap(*md.normal_law, md.contact.g[0]);
  const int nb = static_cast<int>(P.size()) + 1;
  std::vector<one_cell::Branch> saddles;
  for (int c = 0; c < nb * nb; ++c) {
    const one_cell::Branch b = one_cell::on_branch(md, P, {c % nb, c / nb}, 1.0);
    if (b.valid && b.negative == 1) saddles.push_back(b);
  }
  const Reduced E(md);
  int neighbours = 0;
  for (const Barrier& b : B) {
    SCOPED_TRACE("barrier " + std::to_string(b.a) + " - " + std::to_string(b.b));
    const BarrierSide& s = b.from_a;
    if (!s.neighbours) {
      std::printf("minima %d - %d: through %d intermediate minima, saddles", b.a, b.b, s.intermediate);
      for (double e : s.saddles) std::printf(" %.12g", e);
      std::printf(", %s\n", s.verified ? "all verified" : "NOT all verified");
      EXPECT_TRUE(s.verified) << s.note;
      for (double e : s.saddles)
        EXPECT_TRUE(std::any_of(saddles.begin(), saddles.end(),
                                [&](const one_cell::Branch& q) { return std::abs(q.energy - e) <= 1e-8 * std::abs(e); }))
            << "saddle " << e << " is none of the enumerated index-1 points";
      continue;
    }
    ++neighbours;
    ASSERT_TRUE(s.verified) << s.note;
    EXPECT_EQ(s.negative, 1);
    const Vec& xs = s.saddle;
    const auto match = std::find_if(saddles.begin(), saddles.end(), [&](const one_cell::Branch& e) {
      return std::abs(e.x[md.dofs.contact_dof(0, 0)] - xs[0]) <= 1e-8 && std::abs(e.x[md.dofs.contact_dof(1, 0)] - xs[2]) <= 1e-8;
    });
    ASSERT_NE(match, saddles.end()) << "the saddle is none of the enumerated index-1 points";
    EXPECT_NEAR(s.energy_saddle, match->energy, 1e-8 * std::abs(match->energy));
    const double Ea = R.solutions[static_cast<size_t>(b.a)].solution.energy, Eb = R.solutions[static_cast<size_t>(b.b)].solution.energy;
    EXPECT_NEAR(b.from_a.barrier, match->energy - Ea, 1e-8 * std::abs(match->energy));
    EXPECT_NEAR(b.from_b.barrier, match->energy - Eb, 1e-8 * std::abs(match->energy));
    // The lowest pass on a grid over [−0.02, 0.32]² with h = 0.34/680 (under the sanitizers
    // h = 0.34/170: the grid's 463 761 energies, in test code at -O0 there, took 27 s of the
    // sanitized suite; the bound below scales with h²).
#if defined(HEMICONTACT_SANITIZED)
    const int n = 171;
#else
    const int n = 681;
#endif
    const double lo = -0.02, hi = 0.32, h = (hi - lo) / (n - 1);
    const Vec &xa = R.solutions[static_cast<size_t>(b.a)].solution.x, &xb = R.solutions[static_cast<size_t>(b.b)].solution.x;
    const double level = pass_level(E, lo, hi, n, xa[md.dofs.contact_dof(0, 0)], xa[md.dofs.contact_dof(1, 0)],
                                    xb[md.dofs.contact_dof(0, 0)], xb[md.dofs.contact_dof(1, 0)]);
    // The string's path is one path between the two: the grid's lowest pass is at most its saddle
    // (up to the grid error), and lower where the lowest path runs through a third minimum.
    EXPECT_LE(level, s.energy_saddle + 0.5 * curvature_bound(md) * h * h / 2);
    std::printf("minima %d - %d: saddle %.12g (enumeration %.12g, grid pass %.8g), barriers %.10g / %.10g, %d string steps\n",
                b.a, b.b, s.energy_saddle, match->energy, level, b.from_a.barrier, b.from_b.barrier, s.steps);
  }
  EXPECT_GE(neighbours, 2);
}

// minima-softening (Coulomb-type friction: each side on its own minimum's λ): the barriers between
// its lowest three minima, every saddle on every path verified (stationary to round-off, exactly one
// negative eigenvalue on the free subspace), every barrier positive.
TEST(Barriers, SofteningSaddlesAreVerified) {
  const Loaded L = load("minima-softening.json");
  MinimaOptions mo;
  mo.starts = 16;
  mo.seed = 3;
  const MinimaReport R = find_minima(L.md, L.opt, mo);
  ASSERT_GE(R.local_minima(), 3);
  BarrierOptions bo;
#if defined(HEMICONTACT_SANITIZED)
  // One pair, 0 - 1 (its paths pass an intermediate minimum, as the others'): the three pairs'
  // 45 000 string steps took 80 s under the sanitizers, the longest test there by far.
  bo.minima = 2;
#endif
  const std::vector<Barrier> B = find_barriers(L.md, L.opt, R, bo);
  ASSERT_EQ(B.size(), static_cast<size_t>(bo.minima * (bo.minima - 1) / 2));
  for (const Barrier& b : B)
    for (const BarrierSide* s : {&b.from_a, &b.from_b}) {
      SCOPED_TRACE("barrier " + std::to_string(b.a) + " - " + std::to_string(b.b) + " from " + std::to_string(s->minimum));
      EXPECT_TRUE(s->verified) << s->note;
      EXPECT_EQ(s->negative, 1);
      EXPECT_LE(s->residual, bo.saddle_tol);
      EXPECT_GT(s->barrier, 0.0);
      EXPECT_NE(s->lambda.find("frozen at minimum"), std::string::npos) << "the Coulomb-type bound says which lambda";
      std::printf("%d - %d from %d: saddle %.10g, barrier %.6g, %d intermediate minima, %d string steps\n", b.a, b.b,
                  s->minimum, s->energy_saddle, s->barrier, s->intermediate, s->steps);
    }
}

}  // namespace barrier_scan
}  // namespace hemicontact
