// find_minima (studies/minima.hpp) on the nonconvex scenes of problems/ and on the paper's scene.
//
// ---------------------------------------------------------------- the closed form of (c)
// problems/minima-one-node.json is one square cell with its top clamped: the free unknowns are
// exactly the two bottom (Γ3) nodes' (ν, τ), so x = (ν0, τ0, ν1, τ1) and the discrete energy is
//   Π(x) = ½ xᵀK_x x − f_xᵀx + Σ_k w_k j(x_ν,k),   x_ν,k ≤ g   (frictionless),
// with a piecewise-linear p = j′. On a choice of branch per node — a linear piece of p, or the
// bound x_ν,k = g — the stationarity conditions are LINEAR:
//   piece i (p = a_i + s_i r on [lo_i, hi_i]):  (K_x x − f_x)_ν,k + w_k (a_i + s_i x_ν,k) = 0,
//   contact:                                     x_ν,k = g,
//   every τ row:                                 (K_x x − f_x)_τ,k = 0.
// Enumerating all (pieces + 1)² choices, solving each system and keeping the solutions that lie on
// their pieces (and have a rigid reaction R = −(K_x x − f_x)_ν,k − w_k p(g) ≥ 0 at contact nodes)
// gives every solution of (22), exactly; the Hessian K_x + diag(w_k s_i) restricted to the
// non-contact unknowns decides minimum (positive definite) or saddle. This brute-force enumeration
// of the exact conditions is the independent "closed form" the search is checked against: 4 minima
// and 5 saddles (see the scene's description).

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/studies/minima.hpp>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

using json = nlohmann::json;

std::string problem(const std::string& name) { return std::string(HEMICONTACT_SOURCE_DIR) + "/problems/" + name; }

struct Loaded {
  json scene;
  Model md;
  SolveOptions opt;
};

Loaded load(const std::string& name, const std::vector<std::string>& overrides = {}) {
  const std::string path = problem(name);
  json scene = load_scene(path, overrides);
  Model md = build_model(scene, scene_directory(path));
  SolveOptions opt = solve_options_from_scene(scene);
  return {std::move(scene), std::move(md), std::move(opt)};
}

// ---------------------------------------------------------------- enumeration of (c)

struct Piece {
  double lo, hi, a, s;  // p = a + s r on [lo, hi]
};

struct Stationary {
  Vec x;                 // (ν0, τ0, ν1, τ1)
  double energy = 0;     // Π(x), exact
  bool minimum = false;  // reduced Hessian positive definite
  double lambda_min = 0;
  std::vector<int> branch;  // per node: piece index, or -1 for contact
};

std::vector<Piece> pieces_of(const PiecewiseLinearLaw& law, double g) {
  const auto& r = law.breakpoints();
  const auto& s = law.slopes();  // size r.size() + 1
  std::vector<Piece> P;
  const size_t m = r.size();
  // Left of the first breakpoint: through p(r_0⁻).
  P.push_back({-INF, r[0], law.values_left()[0] - s[0] * r[0], s[0]});
  for (size_t i = 1; i < m; ++i) P.push_back({r[i - 1], r[i], law.values_right()[i - 1] - s[i] * r[i - 1], s[i]});
  P.push_back({r[m - 1], INF, law.values_right()[m - 1] - s[m] * r[m - 1], s[m]});
  for (auto& p : P) p.hi = std::min(p.hi, g);
  P.erase(std::remove_if(P.begin(), P.end(), [](const Piece& p) { return p.lo > p.hi; }), P.end());
  return P;
}

std::vector<Stationary> enumerate_one_cell(const Model& md) {
  const Mat K = Mat(md.Kx.full());
  const Vec& f = md.fx;
  const int d = 2;
  const Index nc = md.contact.size();
  const auto P = pieces_of(*md.normal_law, md.contact.g[0]);
  const int nb = static_cast<int>(P.size()) + 1;  // pieces + contact
  std::vector<Stationary> out;
  std::vector<int> choice(static_cast<size_t>(nc), 0);
  for (int code = 0; code < nb * nb; ++code) {
    choice = {code % nb, code / nb};
    Mat A = K;
    Vec b = f;
    for (Index k = 0; k < nc; ++k) {
      const Index i = md.dofs.contact_dof(k, 0);
      const int c = choice[static_cast<size_t>(k)];
      if (c == nb - 1) {
        A.row(i).setZero();
        A(i, i) = 1;
        b[i] = md.contact.g[k];
      } else {
        A(i, i) += md.contact.w[k] * P[static_cast<size_t>(c)].s;
        b[i] -= md.contact.w[k] * P[static_cast<size_t>(c)].a;
      }
    }
    Eigen::FullPivLU<Mat> lu(A);
    if (!lu.isInvertible()) continue;
    const Vec x = lu.solve(b);
    const Vec res = K * x - f;
    bool ok = true;
    Mat H = K;
    std::vector<Index> keep;
    for (Index k = 0; k < nc; ++k) {
      const Index i = md.dofs.contact_dof(k, 0);
      const int c = choice[static_cast<size_t>(k)];
      const double tol = 1e-12 * std::max(1.0, std::abs(x[i]));
      if (c == nb - 1) {
        const double R = -res[i] - md.contact.w[k] * md.normal_law->p(md.contact.g[k]);
        if (R < -1e-10) ok = false;
      } else {
        const Piece& p = P[static_cast<size_t>(c)];
        if (x[i] < p.lo - tol || x[i] > p.hi + tol) ok = false;
        // A point on the bound belongs to the contact choice (counted once).
        if (std::abs(x[i] - md.contact.g[k]) <= tol) ok = false;
        H(i, i) += md.contact.w[k] * p.s;
        keep.push_back(i);
      }
      keep.push_back(md.dofs.contact_dof(k, 1));
    }
    if (!ok) continue;
    std::sort(keep.begin(), keep.end());
    Mat Hr(static_cast<Index>(keep.size()), static_cast<Index>(keep.size()));
    for (size_t a = 0; a < keep.size(); ++a)
      for (size_t c = 0; c < keep.size(); ++c) Hr(static_cast<Index>(a), static_cast<Index>(c)) = H(keep[a], keep[c]);
    Stationary st;
    st.x = x;
    st.lambda_min = Eigen::SelfAdjointEigenSolver<Mat>(Hr).eigenvalues().minCoeff();
    st.minimum = st.lambda_min > 0;
    st.energy = 0.5 * x.dot(K * x) - f.dot(x);
    for (Index k = 0; k < nc; ++k) st.energy += md.contact.w[k] * md.normal_law->j(x[md.dofs.contact_dof(k, 0)]);
    for (int c : choice) st.branch.push_back(c == nb - 1 ? -1 : c);
    out.push_back(st);
  }
  (void)d;
  return out;
}

double rel_dist(const Vec& a, const Vec& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

// ---------------------------------------------------------------- (c): exactly the known minima

TEST(Minima, OneNodeSceneIsWhatTheEnumerationSays) {
  const Loaded L = load("minima-one-node.json");
  const Model& md = L.md;
  ASSERT_EQ(md.dofs.n_interior(), 0) << "the closed form assumes the Γ3 unknowns are all the unknowns";
  ASSERT_EQ(md.contact.size(), 2);
  ASSERT_TRUE(md.normal_law);
  ASSERT_FALSE(md.friction);
  const auto st = enumerate_one_cell(md);
  const auto n_min = std::count_if(st.begin(), st.end(), [](const Stationary& s) { return s.minimum; });
  EXPECT_EQ(n_min, 4);
  EXPECT_EQ(static_cast<long>(st.size()) - n_min, 5);
  // Each enumerated point is a solution of (22): the certificate says so independently.
  for (const auto& s : st) {
    Solution sol;
    sol.x = s.x;
    sol.u = md.dofs.to_full(sol.x);
    evaluate_solution(md, L.opt, sol);
    EXPECT_TRUE(sol.certificate.passed) << "residual " << sol.certificate.max_residual;
    EXPECT_NEAR(sol.energy, s.energy, 1e-12 * std::abs(s.energy) + 1e-12);
  }
}

TEST(Minima, OneNodeFindsExactlyTheKnownMinima) {
  const Loaded L = load("minima-one-node.json");
  const Model& md = L.md;
  const auto exact = enumerate_one_cell(md);
  MinimaOptions mo;  // the documented defaults: 8 random starts, seed 1, load path of 10 steps
  const MinimaReport r = find_minima(md, L.opt, mo);
  EXPECT_TRUE(r.smallness.computed);
  EXPECT_FALSE(r.smallness.holds);
  EXPECT_EQ(r.local_minima(), 4);
  std::vector<int> found(exact.size(), 0);
  for (const auto& ds : r.solutions) {
    EXPECT_TRUE(ds.solution.certificate.passed);
    int match = -1;
    for (size_t i = 0; i < exact.size(); ++i)
      if (rel_dist(ds.solution.x, exact[i].x) <= 1e-7) match = static_cast<int>(i);
    ASSERT_GE(match, 0) << "solution with energy " << ds.solution.energy
                        << " is not a stationary point of the enumeration";
    ++found[static_cast<size_t>(match)];
    const Stationary& e = exact[static_cast<size_t>(match)];
    EXPECT_NEAR(ds.solution.energy, e.energy, 1e-9 * std::abs(e.energy) + 1e-9);
    EXPECT_EQ(ds.second_order.verdict, e.minimum ? "local minimum" : "saddle") << "energy " << e.energy;
    if (e.minimum) {
      EXPECT_NEAR(ds.second_order.lambda_min, e.lambda_min, 1e-6 * e.lambda_min);
    }
  }
  for (size_t i = 0; i < exact.size(); ++i) {
    EXPECT_LE(found[i], 1) << "two groups for one solution";
    if (exact[i].minimum) {
      EXPECT_EQ(found[i], 1) << "minimum with energy " << exact[i].energy << " not found";
    }
  }
  // Sorted by energy; every run certified, and accounted for in exactly one group.
  for (size_t k = 1; k < r.solutions.size(); ++k)
    EXPECT_LE(r.solutions[k - 1].solution.energy, r.solutions[k].solution.energy);
  size_t grouped = 0;
  for (const auto& ds : r.solutions) grouped += ds.runs.size();
  EXPECT_EQ(grouped, static_cast<size_t>(r.certified_runs()));
  // zero, the exact solver's own path from zero, at-gap, separated, the random starts, the load path.
  EXPECT_EQ(r.runs.size(), static_cast<size_t>(4 + mo.starts + 2));
}

TEST(Minima, SecondOrderCheckAtTheExactStationaryPoints) {
  const Loaded L = load("minima-one-node.json");
  const Model& md = L.md;
  ContactSolver solver(md, L.opt);
  for (const auto& s : enumerate_one_cell(md)) {
    Solution sol;
    sol.x = s.x;
    sol.u = md.dofs.to_full(sol.x);
    evaluate_solution(md, L.opt, sol);
    const SecondOrderCheck c = second_order_check(solver, md, L.opt, sol, MinimaOptions{});
    EXPECT_EQ(c.verdict, s.minimum ? "local minimum" : "saddle") << "branches " << s.branch[0] << "," << s.branch[1];
    // Off the law's kinks the mollified Hessian is the exact one.
    EXPECT_NEAR(c.lambda_min, s.lambda_min, 1e-6 * std::abs(s.lambda_min));
    const long contacts = std::count(s.branch.begin(), s.branch.end(), -1);
    EXPECT_EQ(c.removed_contact, contacts);
    EXPECT_EQ(c.kept, 4 - contacts);
    // Above max_dense, no dense matrix: the shifted sparse Cholesky and Lanczos on its inverse give
    // the same λ_min (to Lanczos's tolerance on 1/(λ_min + σ)) and verdict, minima and saddles alike.
    MinimaOptions sparse;
    sparse.max_dense = 0;
    const SecondOrderCheck q = second_order_check(solver, md, L.opt, sol, sparse);
    if (c.kept == 0) continue;
    EXPECT_EQ(q.verdict, c.verdict) << q.note;
    EXPECT_NEAR(q.lambda_min, c.lambda_min, 1e-8 * q.scale) << q.note;
    EXPECT_NE(q.note.find("sparse check"), std::string::npos) << q.note;
  }
}

TEST(Minima, UserStartReachesItsMinimumAndSameSeedSameStarts) {
  const Loaded L = load("minima-one-node.json");
  const Model& md = L.md;
  const auto exact = enumerate_one_cell(md);
  // The highest-energy minimum: reached from a start next to it (Γ3 pairs, 0.9 of the way).
  const Stationary* target = nullptr;
  for (const auto& s : exact)
    if (s.minimum && (!target || s.energy > target->energy)) target = &s;
  ASSERT_TRUE(target);
  MinimaOptions mo;
  mo.starts = 2;
  mo.seed = 7;
  mo.load_path_steps = 0;
  mo.user_starts = {Vec(0.9 * target->x), md.dofs.to_full(Vec(0.9 * target->x))};  // Γ3 pairs, then a full u
  const MinimaReport r = find_minima(md, L.opt, mo);
  ASSERT_EQ(r.runs.size(), 4u + 2u + 2u);  // zero, exact-from-zero, at-gap, separated; 2 random; 2 user
  for (const std::string label : {"user-1", "user-2"}) {
    const auto it = std::find_if(r.runs.begin(), r.runs.end(), [&](const MinimaRun& m) { return m.start == label; });
    ASSERT_NE(it, r.runs.end());
    ASSERT_TRUE(it->certified);
    EXPECT_LT(rel_dist(r.solutions[static_cast<size_t>(it->group)].solution.x, target->x), 1e-7) << label;
  }
  const MinimaReport again = find_minima(md, L.opt, mo);
  ASSERT_EQ(again.runs.size(), r.runs.size());
  for (size_t i = 0; i < r.runs.size(); ++i) EXPECT_EQ(again.runs[i].energy, r.runs[i].energy) << r.runs[i].start;
  mo.user_starts = {Vec::Zero(3)};
  EXPECT_THROW(find_minima(md, L.opt, mo), Error);
}

TEST(Minima, ReadGamma3Starts) {
  const Loaded L = load("minima-one-node.json");
  const auto one = read_gamma3_starts(json::parse("[[0.1, 0.2], [0.3, -0.4]]"), L.md, "f");
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], (Vec(4) << 0.1, 0.2, 0.3, -0.4).finished());
  const auto rep = read_gamma3_starts(
      json::parse(R"({"nodes": [{"u_nu": 1, "u_tau": 2, "x": 0}, {"u_nu": 3, "u_tau": 4}]})"), L.md, "f");
  EXPECT_EQ(rep[0], (Vec(4) << 1, 2, 3, 4).finished());
  const auto two = read_gamma3_starts(json::parse("[[[0, 0], [0, 0]], [[1, 1], [1, 1]]]"), L.md, "f");
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[1], Vec::Ones(4));
  EXPECT_THROW(read_gamma3_starts(json::parse("[[0.1, 0.2]]"), L.md, "f"), Error);
  EXPECT_THROW(read_gamma3_starts(json::parse("[[0.1], [0.2]]"), L.md, "f"), Error);
  EXPECT_THROW(read_gamma3_starts(json::parse(R"({"nodes": [{"u_nu": 1}]})"), L.md, "f"), Error);
  EXPECT_THROW(read_gamma3_starts(json::parse("3"), L.md, "f"), Error);
}

// ---------------------------------------------------------------- (a), (b) and the paper's scene

TEST(Minima, SofteningSceneHasTwoCertifiedLocalMinima) {
  if (!HEMICONTACT_HAS_IPOPT) GTEST_SKIP() << "built without Ipopt (coinor-libipopt-dev): which minimum each start reaches, recorded here, is the default backend's (Ipopt)";
  const Loaded L = load("minima-softening.json");
  MinimaOptions mo;
  mo.starts = 2;
  mo.load_path_steps = 0;
  const MinimaReport r = find_minima(L.md, L.opt, mo);
  EXPECT_TRUE(r.smallness.computed);
  EXPECT_FALSE(r.smallness.holds);
  EXPECT_GE(r.local_minima(), 2);
  // The two stable states of the scene's description: u = 0 leads to the layer's first branch
  // everywhere, the start at g to the middle of Γ3 on the foundation, at a lower energy.
  const auto group_of = [&](const std::string& start) {
    for (const auto& m : r.runs)
      if (m.start == start) return m.certified ? m.group : -1;
    return -1;
  };
  const int gz = group_of("zero"), gg = group_of("at-gap");
  ASSERT_GE(gz, 0);
  ASSERT_GE(gg, 0);
  ASSERT_NE(gz, gg);
  const auto& z = r.solutions[static_cast<size_t>(gz)];
  const auto& a = r.solutions[static_cast<size_t>(gg)];
  EXPECT_EQ(z.second_order.verdict, "local minimum");
  EXPECT_EQ(a.second_order.verdict, "local minimum");
  EXPECT_EQ(z.solution.status_counts().at("compliance"), L.md.contact.size());
  EXPECT_GE(a.solution.status_counts().at("contact"), 5);
  EXPECT_LT(a.solution.energy, z.solution.energy);
  // Every run's seconds are its own solve's: at least one linear solve of the scene, far above
  // 10 µs (a since(t) evaluated before the solve, as one call's arguments once allowed, reads
  // the ~0.1 µs between two clock reads).
  for (const auto& m : r.runs) EXPECT_GT(m.seconds, 1e-5) << m.start;
}

// solver.exact.start = auto means "convex" in minima: where the inner problem is not strongly
// convex (this scene), each start goes through the continuation's neighbourhood (ε-stages run),
// which is what gives the search its variety; "always" sends every start to the exact solver at
// once and, from the same starts, finds no more distinct solutions (6 against 3 when measured).
TEST(Minima, AutoStartKeepsTheContinuationForTheStarts) {
  const Loaded L = load("minima-softening.json");
  ASSERT_EQ(L.opt.exact_start, "auto");
  MinimaOptions mo;
  mo.load_path_steps = 0;
  const MinimaReport r = find_minima(L.md, L.opt, mo);
  bool stage_ran = false;
  for (const auto& d : r.solutions)
    for (const auto& h : d.solution.history) stage_ran = stage_ran || h.stage >= 0;
  EXPECT_TRUE(stage_ran) << "with start = auto, minima's starts should run the continuation";
  SolveOptions always = L.opt;
  always.exact_start = "always";
  const MinimaReport a = find_minima(L.md, always, mo);
  for (const auto& d : a.solutions)
    for (const auto& h : d.solution.history) EXPECT_EQ(h.stage, -1);
  EXPECT_GE(r.solutions.size(), a.solutions.size());
}

TEST(Minima, LaminateSceneHasSeveralMinimaAndZeroIsNotTheLowest) {
  if (!HEMICONTACT_HAS_IPOPT) GTEST_SKIP() << "built without Ipopt (coinor-libipopt-dev): which minimum each start reaches, recorded here, is the default backend's (Ipopt)";
  const Loaded L = load("minima-laminate.json");
  MinimaOptions mo;
  mo.starts = 4;
  mo.load_path_steps = 0;
  const MinimaReport r = find_minima(L.md, L.opt, mo);
  EXPECT_FALSE(r.smallness.holds);
  EXPECT_GE(r.local_minima(), 2);
  const auto it = std::find_if(r.runs.begin(), r.runs.end(), [](const MinimaRun& m) { return m.start == "zero"; });
  ASSERT_NE(it, r.runs.end());
  ASSERT_TRUE(it->certified);
  EXPECT_GT(it->group, 0) << "the local method from u = 0 should stall above the lowest energy";
}

TEST(Minima, PaperSceneWhereSmallnessHoldsHasOneSolution) {
  const Loaded L = load("sofonea2017-fig2.json", {"mesh.n=8"});
  MinimaOptions mo;
  mo.starts = 4;
  const MinimaReport r = find_minima(L.md, L.opt, mo);
  EXPECT_TRUE(r.smallness.computed);
  EXPECT_TRUE(r.smallness.holds);
  EXPECT_EQ(r.certified_runs(), static_cast<int>(r.runs.size()));
  ASSERT_EQ(r.solutions.size(), 1u);
  EXPECT_EQ(r.solutions[0].second_order.verdict, "local minimum");
  EXPECT_EQ(r.solutions[0].runs.size(), r.runs.size());
  EXPECT_GT(r.solutions[0].second_order.removed_contact, 0);
}

// The full formulation's ssn has no U_s of its own (it factorizes no elastic solution): the search
// takes its zero answer's extent on Γ3, as on the petsc engine, not 1 m. The printed loads (u ~
// 1e-7, problems/sofonea2017-printed.json) would otherwise draw random starts from a ±1 m box and
// smooth the second-order check over ε · 1 m.
TEST(Minima, FullSsnTakesItsScaleFromTheZeroAnswer) {
  Loaded L = load("sofonea2017-printed.json", {"mesh.n=8", "solver.formulation=\"full\""});
  L.opt.backend = "ssn";
  MinimaOptions mo;
  mo.starts = 2;
  mo.load_path_steps = 0;
  const MinimaReport r = find_minima(L.md, L.opt, mo);
  EXPECT_EQ(r.certified_runs(), static_cast<int>(r.runs.size()));
  ASSERT_EQ(r.solutions.size(), 1u);  // the printed loads: (21) holds, one solution
  const ContactState& st = r.solutions[0].solution.state;
  const double extent = std::max(st.u_nu.cwiseAbs().maxCoeff(), st.u_tau.cwiseAbs().maxCoeff());
  EXPECT_GT(extent, 0.0);
  EXPECT_NEAR(r.x_scale, extent, 1e-9 * extent);
  EXPECT_EQ(r.solutions[0].second_order.verdict, "local minimum");
}

// minima finds what a solve finds: the default solve's answer and the exact solver's own path from
// zero (solver.exact.start = always) are both among its runs, on every nonconvex scene shipped
// (minima-laminate: the exact path's −0.0758 was missed before it was a start).
TEST(Minima, FindsTheDefaultSolvesAndTheExactPathsAnswers) {
  for (const char* file : {"minima-laminate.json", "minima-softening.json", "minima-one-node.json"}) {
    SCOPED_TRACE(file);
    const Loaded L = load(file);
    MinimaOptions mo;
    mo.starts = 2;
    mo.load_path_steps = 0;
    const MinimaReport r = find_minima(L.md, L.opt, mo);
    const Solution def = solve(L.md, L.opt);
    SolveOptions always = L.opt;
    always.exact_start = "always";
    const Solution ex = solve(L.md, always);
    for (const Solution* s : {&def, &ex}) {
      if (!s->ok()) continue;
      bool found = false;
      for (const auto& d : r.solutions)
        found = found || (d.solution.u - s->u).cwiseAbs().maxCoeff() <=
                             mo.group_tol * std::max(1.0, s->u.cwiseAbs().maxCoeff()) * 10;
      EXPECT_TRUE(found) << "energy " << s->energy << " (" << s->solved_by() << ") not among the minima";
    }
    const auto it = std::find_if(r.runs.begin(), r.runs.end(), [](const MinimaRun& m) { return m.start == "exact-from-zero"; });
    ASSERT_NE(it, r.runs.end());
    EXPECT_EQ(it->solved_by, "exact");
  }
}

// Mirror images of a symmetric scene are one pair, not two unrelated solutions: minima-softening is
// symmetric about x = 1/2; each pair has equal energies and Γ3 values reflected (u_τ reversed).
TEST(Minima, MirrorImagesArePaired) {
  const Loaded L = load("minima-softening.json");
  MinimaOptions mo;
  mo.starts = 8;
  mo.load_path_steps = 0;
  const MinimaReport r = find_minima(L.md, L.opt, mo);
  int paired = 0;
  for (size_t k = 0; k < r.solutions.size(); ++k) {
    const DistinctSolution& d = r.solutions[k];
    if (d.mirror_of < 0) continue;
    ++paired;
    const DistinctSolution& e = r.solutions[static_cast<size_t>(d.mirror_of)];
    EXPECT_EQ(e.mirror_of, static_cast<int>(k));
    EXPECT_NEAR(d.solution.energy, e.solution.energy, 1e-6 * std::abs(d.solution.energy));
    EXPECT_NE(d.solution.state.u_tau.cwiseAbs().maxCoeff(), 0.0);
  }
  EXPECT_GE(paired, 2) << "minima-softening's asymmetric minima come in mirror pairs";
  // A symmetric solution (the one from u = 0: every node in compliance) pairs with none.
  for (const auto& m : r.runs)
    if (m.start == "zero" && m.certified) {
      EXPECT_EQ(r.solutions[static_cast<size_t>(m.group)].mirror_of, -1);
    }
}

}  // namespace
}  // namespace hemicontact

namespace hemicontact {
namespace {

// ---------------------------------------------------------------- the unseen-solutions estimate
// chao1_estimate against its closed form on small abundance lists, and as an estimator: sampling
// n = 60 from 30 equally likely classes (about 26 seen, several unseen), its mean over many
// replicates is within 10 % of 30 (Chao1 is nearly unbiased for equal class probabilities; a
// Python simulation of the same formulas gives 31.06) and its interval covers 30 in at least 80 %
// of them (the log-normal interval under-covers its nominal 95 % at such small samples: 89.7 %).
TEST(Minima, Chao1ClosedFormsAndCoverage) {
  UnseenEstimate e = chao1_estimate({1, 2, 3});  // n = 6, S_obs = 3, f1 = f2 = 1, c = 5/6
  EXPECT_EQ(e.samples, 6);
  EXPECT_EQ(e.observed, 3);
  EXPECT_NEAR(e.chao1, 3 + 5.0 / 12, 1e-14);
  EXPECT_LT(e.lo, e.chao1);
  EXPECT_GT(e.hi, e.chao1);
  EXPECT_GE(e.lo, 3.0);
  e = chao1_estimate({1, 1, 1, 3});  // f2 = 0: S_obs + c f1 (f1 − 1)/2 = 4 + (5/6)·3
  EXPECT_NEAR(e.chao1, 6.5, 1e-14);
  e = chao1_estimate({2, 3, 5});  // nothing seen once: nothing unseen
  EXPECT_EQ(e.unseen, 0.0);
  EXPECT_EQ(e.lo, 3.0);
  EXPECT_EQ(e.hi, 3.0);
  EXPECT_EQ(chao1_estimate({}).samples, 0);
  std::mt19937 rng(7);
  const int K = 30, n = 60;
  std::uniform_int_distribution<int> cls(0, K - 1);
  const int reps = 2000;
  double mean = 0;
  int covered = 0;
  for (int r = 0; r < reps; ++r) {
    std::vector<int> count(K, 0);
    for (int i = 0; i < n; ++i) ++count[static_cast<size_t>(cls(rng))];
    const UnseenEstimate u = chao1_estimate(count);
    mean += u.chao1 / reps;
    covered += u.lo <= K && K <= u.hi;
  }
  EXPECT_NEAR(mean, K, 0.1 * K);
  EXPECT_GE(covered, static_cast<int>(0.8 * reps));
  std::printf("Chao1 over %d replicates of n = %d from %d classes: mean %.3f, 95%% interval covers %d in %.1f%%\n",
              reps, n, K, mean, K, 100.0 * covered / reps);
}

// --until-complete on the one-cell scene: its few basins are each reached many times, so the first
// batch already leaves less than one solution unseen, and the search stops there.
TEST(Minima, UntilCompleteStopsWhenNothingIsLeftUnseen) {
  const Loaded L = load("minima-one-node.json");
  MinimaOptions mo;
  mo.starts = 16;
  mo.until_complete = true;
  mo.max_starts = 64;
  mo.load_path_steps = 0;
  const MinimaReport R = find_minima(L.md, L.opt, mo);
  EXPECT_TRUE(R.unseen.complete);
  EXPECT_LT(R.unseen.unseen, 1.0);
  EXPECT_EQ(R.unseen.random_starts % mo.starts, 0);
  EXPECT_LE(R.unseen.random_starts, mo.max_starts);
  EXPECT_GT(R.unseen.samples, 0);
  EXPECT_LE(R.unseen.observed, static_cast<int>(R.solutions.size()));
  mo.max_starts = 8;  // below the batch
  EXPECT_THROW(find_minima(L.md, L.opt, mo), Error);
}

}  // namespace
}  // namespace hemicontact
