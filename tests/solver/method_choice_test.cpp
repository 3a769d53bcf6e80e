// solver.formulation = auto chooses the method from the scene's numbers (solver/method_choice.hpp),
// and the checks above check.dense_max_unknowns take their eigenvalues from Lanczos on the solve's
// own factor (solver/sparse_checks.hpp) instead of a dense Γ3 matrix.
#include <hemicontact/check/smallness.hpp>
#include <hemicontact/config.hpp>
#include <hemicontact/fem/condensation.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/method_choice.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/solver/sparse_checks.hpp>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace hemicontact;
using json = nlohmann::json;

namespace method_choice_test {

struct Solved {
  Model md;
  SolveOptions opt;
  Solution sol;
};

Solved run(const std::string& scene, const std::vector<std::string>& overrides) {
  const json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/" + scene + ".json", overrides);
  Solved r{build_model(s, HEMICONTACT_SOURCE_DIR "/problems"), solve_options_from_scene(s), {}};
  r.sol = solve(r.md, r.opt);
  return r;
}

// fig2's conditions on the strip [0, 300] × [0, 1], 600 × 2 cells: 601 Γ3 nodes over 1 803 nodes.
std::vector<std::string> strip(std::vector<std::string> more = {}) {
  std::vector<std::string> o = {"mesh.n=null", "mesh.x=[0,300]", "mesh.nx=600", "mesh.ny=2"};
  o.insert(o.end(), more.begin(), more.end());
  return o;
}

Model model_of(const std::string& scene, const std::vector<std::string>& overrides) {
  const json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/" + scene + ".json", overrides);
  return build_model(s, HEMICONTACT_SOURCE_DIR "/problems");
}

// k_1, k_1ν of a dense S (sparse_checks.hpp), by Eigen's dense solver: the reference.
std::pair<double, double> dense_k(const Mat& S, const Vec& w, int d) {
  const Index nc = w.size();
  Vec s(d * nc);
  for (Index k = 0; k < nc; ++k) s.segment(d * k, d).setConstant(1 / std::sqrt(w[k]));
  const Mat A = s.asDiagonal() * S * s.asDiagonal();
  const double k1 = Eigen::SelfAdjointEigenSolver<Mat>(A, Eigen::EigenvaluesOnly).eigenvalues().minCoeff();
  // S_ν⁻¹ = (S⁻¹)_νν, and (W^-1/2 S_ν W^-1/2)⁻¹ = W^1/2 S_ν⁻¹ W^1/2.
  const Mat Si = S.inverse();
  Mat Sn_inv(nc, nc);
  for (Index i = 0; i < nc; ++i)
    for (Index j = 0; j < nc; ++j) Sn_inv(i, j) = Si(d * i, d * j) * std::sqrt(w[i] * w[j]);
  const double top = Eigen::SelfAdjointEigenSolver<Mat>(Sn_inv, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  return {k1, 1 / top};
}

}  // namespace method_choice_test

namespace mct = method_choice_test;

// A long strip: Γ3 is a third of the nodes and its dense work (m³) dwarfs the sparse factorization,
// so auto takes the full formulation with its exact solver ssn, and says why with its numbers.
TEST(MethodChoice, LongStripPicksFull) {
  const mct::Solved r = mct::run("sofonea2017-fig2", mct::strip());
  const MethodChoice& c = r.sol.method_choice;
  EXPECT_EQ(c.chosen, "full");
  EXPECT_EQ(r.sol.formulation, "full");
  EXPECT_TRUE(c.automatic);
  EXPECT_EQ(c.backend, "ssn");
  EXPECT_NE(r.sol.backend.find("ssn"), std::string::npos) << r.sol.backend;
  EXPECT_EQ(r.sol.backend_use.requested, "auto");
  EXPECT_EQ(c.numbers.at("gamma3_unknowns"), 1202);
  ASSERT_GT(c.numbers.at("factor_flops"), 0);
  EXPECT_GT(c.numbers.at("condensed_flops"), c.numbers.at("full_flops"));
  EXPECT_NE(c.reason.find(" > "), std::string::npos) << c.reason;
  EXPECT_TRUE(r.sol.ok()) << r.sol.message;
  // ssn factorizes only its own Newton matrices: no elastic factorization for the checks alone
  // (nor a Gram matrix's), so (21) is not evaluated, and the report says why and how to ask.
  EXPECT_FALSE(r.sol.smallness.computed);
  EXPECT_NE(r.sol.smallness.note.find("no factor at hand"), std::string::npos) << r.sol.smallness.note;
  EXPECT_NE(r.sol.smallness.note.find("check.smallness_method = exact"), std::string::npos) << r.sol.smallness.note;
  EXPECT_EQ(r.sol.timings.count("linear_elastic_factor"), 0u);
  // Asked for, (21) is evaluated exactly: one factorization of the Gram matrix.
  const mct::Solved e = mct::run("sofonea2017-fig2", mct::strip({"check.smallness_method=exact"}));
  EXPECT_EQ(e.sol.backend_use.requested, "auto");
  EXPECT_TRUE(e.sol.smallness.computed) << e.sol.smallness.note;
  EXPECT_EQ(e.sol.smallness.method, "exact");
}

// The paper's square: few Γ3 unknowns against a large interior, condensed as before.
TEST(MethodChoice, Fig2PicksCondensed) {
  const mct::Solved r = mct::run("sofonea2017-fig2", {"mesh.n=32"});
  const MethodChoice& c = r.sol.method_choice;
  EXPECT_EQ(c.chosen, "condensed");
  EXPECT_EQ(r.sol.formulation, "condensed");
  EXPECT_TRUE(c.automatic);
  EXPECT_TRUE(c.backend.empty()) << c.backend;
  EXPECT_LE(c.numbers.at("dense_flops"), 0.1 * c.numbers.at("factor_flops"));
  EXPECT_NE(c.reason.find(" <= "), std::string::npos) << c.reason;
  EXPECT_TRUE(r.sol.ok()) << r.sol.message;
}

// Every explicit setting wins: a condensed strip stays condensed, a named backend stays named.
TEST(MethodChoice, ExplicitSettingsWin) {
  const mct::Solved c = mct::run("sofonea2017-fig2", mct::strip({"solver.formulation=condensed"}));
  EXPECT_EQ(c.sol.formulation, "condensed");
  EXPECT_FALSE(c.sol.method_choice.automatic);
  EXPECT_NE(c.sol.method_choice.reason.find("set explicitly"), std::string::npos);
  // A named backend (newton: built in every configuration, where ipopt is optional) is kept.
  const mct::Solved b = mct::run("sofonea2017-fig2", mct::strip({"solver.backend=newton"}));
  EXPECT_EQ(b.sol.formulation, "full");
  EXPECT_EQ(b.sol.backend, "newton");
  const mct::Solved f = mct::run("sofonea2017-fig2", {"mesh.n=8", "solver.formulation=full"});
  EXPECT_EQ(f.sol.formulation, "full");
  EXPECT_EQ(f.sol.backend, c.sol.backend);  // the engine's default, as before the choice existed
}

// A stricter cost model moves the same scene: the numbers, not the scene's name, decide.
TEST(MethodChoice, TheCostModelDecides) {
  SceneNumbers n;
  n.dim = 2;
  n.dofs = 10000;
  n.gamma3_unknowns = 100;  // dense work 1e6 flops
  n.factor_flops = 2e6;
  n.memory_bytes = 1e10;
  SolveOptions opt;
  int analyses = 0;
  const auto full = [&] { return ++analyses, 1e6; };
  EXPECT_EQ(choose_method(n, opt, full).chosen, "condensed");  // 3e6 ≤ condensed_below, and ≤ 100 · 1e7
  EXPECT_EQ(analyses, 1);
  opt.method_choice.condensed_below = 0;
  EXPECT_EQ(choose_method(n, opt, full).chosen, "condensed");  // 2e6 + 1e6 ≤ 10 · 1e6
  EXPECT_EQ(analyses, 2);
  opt.method_choice.full_factorizations = 2;
  EXPECT_EQ(choose_method(n, opt, full).chosen, "full");  // 3e6 > 2 · 1e6
  // A long strip: below condensed_below, but the full path 150x cheaper (3e6 against 2 · 1e4).
  opt.method_choice.condensed_below = 1e9;
  const auto strip_full = [&] { return ++analyses, 1e4; };
  const MethodChoice strip = choose_method(n, opt, strip_full);
  EXPECT_EQ(strip.chosen, "full");
  EXPECT_NE(strip.reason.find(" > full work"), std::string::npos) << strip.reason;
  opt.method_choice.full_cheaper_by = 200;  // a laxer margin keeps the exact path
  EXPECT_EQ(choose_method(n, opt, strip_full).chosen, "condensed");
  EXPECT_EQ(analyses, 5);
  n.factor_flops = 2e7;  // dense work ≤ 0.1 × the factorization: condensed, no second analysis
  EXPECT_EQ(choose_method(n, opt, full).chosen, "condensed");
  EXPECT_EQ(analyses, 5);
  n.memory_bytes = 1e6;  // 7 · 8 · 100² = 5.6e5 bytes > 0.5 · 1e6
  const MethodChoice c = choose_method(n, opt, full);
  EXPECT_EQ(c.chosen, "full");
  EXPECT_NE(c.reason.find("memory"), std::string::npos) << c.reason;
  n.linear_material = false;
  EXPECT_EQ(choose_method(n, opt, full).chosen, "full");
  // K's pattern bound of fl_F decides without the analysis where it can (3e6 ≤ 100 · 10 · 1e4),
  // and says so; a bound too low to decide leaves the analysis to decide.
  n = SceneNumbers{};
  n.dofs = 10000;
  n.gamma3_unknowns = 100;
  n.factor_flops = 2e6;
  n.full_factor_flops_low = 1e4;
  opt = SolveOptions{};
  const MethodChoice b = choose_method(n, opt, full);
  EXPECT_EQ(b.chosen, "condensed");
  EXPECT_EQ(analyses, 5);
  EXPECT_NE(b.reason.find("no analysis needed"), std::string::npos) << b.reason;
  EXPECT_EQ(b.numbers.at("full_flops_low"), 1e5);
  n.full_factor_flops_low = 1e3;  // 3e6 > 100 · 10 · 1e3: the analysis (fl_F = 1e6) decides
  EXPECT_EQ(choose_method(n, opt, full).chosen, "condensed");
  EXPECT_EQ(analyses, 6);
}

// The pattern bound nnz(K)²/n never exceeds what CHOLMOD's analysis predicts for the full
// formulation's factorization (2D and 3D, squares and strips), whatever the ordering.
TEST(MethodChoice, PatternBoundIsBelowTheAnalysedFlops) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> scenes = {
      {"sofonea2017-fig2", {"mesh.n=16"}}, {"sofonea2017-fig2", mct::strip()}, {"sofonea2017-3d", {"mesh.n=4"}}};
  for (const auto& [scene, o] : scenes)
    for (const std::string ordering : {"amd", "metis", "nesdis"}) {
      const Model md = mct::model_of(scene, o);
      const double low = factor_flops_lower_bound(md.Kx.lower());
      const double fl = Condensation(md.Kx.lower(), 0, ordering).predicted_flops();
      EXPECT_GT(low, 0);
      EXPECT_LE(low, fl) << scene << " " << ordering;
    }
}

// report.json carries the choice, its reason and the numbers it decided on.
TEST(MethodChoice, ReportCarriesTheReason) {
  const mct::Solved r = mct::run("sofonea2017-fig2", mct::strip());
  const json j = solve_records(r.sol, r.opt, true);
  ASSERT_TRUE(j.contains("method_choice"));
  EXPECT_EQ(j["method_choice"]["chosen"], "full");
  EXPECT_EQ(j["method_choice"]["backend"], "ssn");
  EXPECT_EQ(j["method_choice"]["reason"], r.sol.method_choice.reason);
  EXPECT_EQ(j["method_choice"]["numbers"]["gamma3_unknowns"], 1202);
  EXPECT_TRUE(j.contains("formulation") && j.contains("smallness") && j.contains("inner_convexity"));
  EXPECT_NE(summary_table(r.md, r.sol).find("method        full (auto)"), std::string::npos);
}

// The strip solved by auto (full, ssn) and by the condensed path: both certified, same energy.
TEST(MethodChoice, AutoStripCertifiesWithTheCondensedEnergy) {
  const mct::Solved a = mct::run("sofonea2017-fig2", mct::strip());
  const mct::Solved c = mct::run("sofonea2017-fig2", mct::strip({"solver.formulation=condensed"}));
  ASSERT_TRUE(a.sol.ok()) << a.sol.message;
  ASSERT_TRUE(c.sol.ok()) << c.sol.message;
  EXPECT_EQ(a.sol.formulation, "full");
  EXPECT_NEAR(a.sol.energy, c.sol.energy, 1e-10 * std::abs(c.sol.energy));
  ASSERT_EQ(a.sol.status.size(), c.sol.status.size());
  for (size_t k = 0; k < a.sol.status.size(); ++k) EXPECT_EQ(a.sol.status[k].str(), c.sol.status[k].str()) << k;
}

// Lanczos on a random SPD matrix: the largest eigenvalue to the relative tolerance it was asked for.
TEST(SparseChecks, LanczosFindsTheLargestEigenvalue) {
  const Index n = 150;
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  Mat B(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) B(i, j) = g(rng);
  const Mat A = B * B.transpose() / n + Mat::Identity(n, n);
  const double top = Eigen::SelfAdjointEigenSolver<Mat>(A, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  const double tol = 1e-10;
  const LanczosResult r = lanczos_largest([&](const Vec& v) { return Vec(A * v); }, n, tol, 150);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.theta, top * (1 + 1e-14));
  EXPECT_NEAR(r.theta, top, 2 * tol * top);
}

// k_1 and k_1ν by Lanczos through the condensation's L_CC and through solves with a factor of the
// whole K agree with the dense eigenvalues to the Lanczos tolerance, and bracket them.
TEST(SparseChecks, SpectrumAgreesWithTheDenseOne) {
  const Model md = mct::model_of("sofonea2017-fig2", {"mesh.n=16"});
  const int d = md.dim();
  const Index m = d * md.contact.size(), n = md.dofs.n_free();
  const Condensation cond(md.Kx.lower(), md.fx, m);
  const auto [k1, k1nu] = mct::dense_k(cond.S(), md.contact.w, d);
  SolveOptions opt;
  const double tol = opt.lanczos_tol;
  const Gamma3Spectrum a = gamma3_spectrum([&](const Vec& b) { return cond.solve_schur(b); }, md.contact.w, d, opt, "L_CC");
  SparseCholesky chol;
  chol.compute(md.Kx.lower());
  const auto full = [&](const Vec& b) {
    Vec x = Vec::Zero(n);
    x.tail(m) = b;
    return Vec(chol.solve(x).tail(m));
  };
  const Gamma3Spectrum f = gamma3_spectrum(full, md.contact.w, d, opt, "K");
  for (const Gamma3Spectrum* s : {&a, &f}) {
    ASSERT_TRUE(s->converged) << s->how;
    EXPECT_NEAR(s->k1, k1, 10 * tol * k1) << s->how;
    EXPECT_NEAR(s->k1nu, k1nu, 10 * tol * k1nu) << s->how;
    EXPECT_LE(s->k1_low, k1 * (1 + 1e-12));
    EXPECT_LE(s->k1nu_low, k1nu * (1 + 1e-12));
  }
}

// (21) and the inner-convexity test with check.dense_max_unknowns = 0 (Lanczos) decide as the dense
// ones do, with the same numbers to the Lanczos tolerance, and say how.
TEST(SparseChecks, SmallnessAndConvexityAgreeWithTheDenseChecks) {
  const mct::Solved dense = mct::run("sofonea2017-fig2", {"mesh.n=16"});
  const mct::Solved sparse = mct::run("sofonea2017-fig2", {"mesh.n=16", "check.dense_max_unknowns=0"});
  const SmallnessReport &p = dense.sol.smallness, &q = sparse.sol.smallness;
  ASSERT_EQ(p.method, "bound");
  ASSERT_TRUE(p.computed && q.computed) << q.note;
  EXPECT_EQ(q.method, "bound");
  EXPECT_EQ(p.holds, q.holds);
  // The runs stop once the brackets decide (sparse_checks.hpp): the Lanczos bracket holds the
  // dense one (Ritz values from below, widened by the residual), never narrows it.
  EXPECT_LE(q.lhs_lower, p.lhs_lower * (1 + 1e-13));
  EXPECT_GE(q.lhs_upper, p.lhs_upper * (1 - 1e-13));
  EXPECT_NE(q.note.find("Lanczos"), std::string::npos) << q.note;
  EXPECT_TRUE(p.note.empty()) << p.note;
  const InnerConvexity &cd = dense.sol.inner_convexity, &cs = sparse.sol.inner_convexity;
  ASSERT_TRUE(cd.checked && cs.checked) << cs.note;
  EXPECT_EQ(cd.strongly_convex, cs.strongly_convex);
  EXPECT_EQ(cd.min_eigenvalue > 0, cs.min_eigenvalue > 0);
  EXPECT_NEAR(sparse.sol.energy, dense.sol.energy, 1e-12 * std::abs(dense.sol.energy));
}

// check.smallness = false asks the inner convexity alone: the spectrum then runs k_1ν's Lanczos
// only (half the S⁻¹ applications), decides as the run with (21) does, and (21) asked afterwards
// (the adaptive loop's final mesh) gets k_1 then, from the factor the solver keeps: the same
// bracket as the solve that asked it.
TEST(SparseChecks, ConvexityAloneRunsTheKOneNuLanczosOnly) {
  const std::vector<std::string> o = {"mesh.n=16", "check.dense_max_unknowns=0"};
  const mct::Solved both = mct::run("sofonea2017-fig2", o);
  std::vector<std::string> off = o;
  off.push_back("check.smallness=false");
  const json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", off);
  const Model md = build_model(scene, HEMICONTACT_SOURCE_DIR "/problems");
  ContactSolver solver(md, solve_options_from_scene(scene));
  const Solution sol = solver.solve();
  const InnerConvexity &c = sol.inner_convexity, &cb = both.sol.inner_convexity;
  ASSERT_TRUE(c.checked && cb.checked) << c.note;
  EXPECT_EQ(c.strongly_convex, cb.strongly_convex);
  EXPECT_NE(c.note.find("k_1nu alone"), std::string::npos) << c.note;
  EXPECT_EQ(cb.note.find("k_1nu alone"), std::string::npos) << cb.note;
  EXPECT_FALSE(sol.smallness.computed);
  EXPECT_NEAR(sol.energy, both.sol.energy, 1e-12 * std::abs(both.sol.energy));
  const SmallnessReport later = solver.smallness(), &asked = both.sol.smallness;
  ASSERT_TRUE(later.computed && asked.computed) << later.note;
  EXPECT_EQ(later.holds, asked.holds);
  EXPECT_NEAR(later.lhs_lower, asked.lhs_lower, 1e-12 * asked.lhs_upper);
  EXPECT_NEAR(later.lhs_upper, asked.lhs_upper, 1e-12 * asked.lhs_upper);
}

// The spectrum on a known operator: to check.lanczos_tol without a question, and stopped early,
// with a bracket that holds the exact values, where the question is decided.
TEST(SparseChecks, SpectrumRunsToTheToleranceOrUntilTheQuestionIsDecided) {
  const int d = 2;
  const Index nc = 40, m = d * nc;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  Mat B(m, m);
  for (Index i = 0; i < m; ++i)
    for (Index j = 0; j < m; ++j) B(i, j) = u(rng) - 1.25;
  const Mat S = B * B.transpose() + 5.0 * Mat::Identity(m, m);  // SPD, well separated from 0
  Vec w(nc);
  for (Index k = 0; k < nc; ++k) w[k] = u(rng);
  const Eigen::LLT<Mat> llt(S);
  const auto apply = [&](const Vec& b) { return Vec(llt.solve(b)); };
  // Exact k_1 = λ_min(W^-1/2 S W^-1/2) and k_1ν = λ_min of the same for S_ν = ((S⁻¹)_νν)⁻¹.
  Vec s_inv(m);
  for (Index k = 0; k < nc; ++k) s_inv.segment(d * k, d).setConstant(1 / std::sqrt(w[k]));
  const double k1 = Eigen::SelfAdjointEigenSolver<Mat>(s_inv.asDiagonal() * S * s_inv.asDiagonal()).eigenvalues()[0];
  const Mat Sinv = S.inverse();
  Mat Snu_inv(nc, nc);
  for (Index a = 0; a < nc; ++a)
    for (Index b = 0; b < nc; ++b) Snu_inv(a, b) = std::sqrt(w[a] * w[b]) * Sinv(d * a, d * b);
  const double k1nu = 1 / Eigen::SelfAdjointEigenSolver<Mat>(Snu_inv).eigenvalues()[nc - 1];
  SolveOptions opt;
  const Gamma3Spectrum full = gamma3_spectrum(apply, w, d, opt, "dense S");
  ASSERT_TRUE(full.converged);
  EXPECT_FALSE(full.decided);
  EXPECT_NEAR(full.k1, k1, 10 * opt.lanczos_tol * k1);
  EXPECT_NEAR(full.k1nu, k1nu, 10 * opt.lanczos_tol * k1nu);
  // A question the first readings decide: is k_1 above half its value?
  const Gamma3Spectrum early = gamma3_spectrum(apply, w, d, opt, "dense S", [&](const Gamma3Spectrum& g) {
    return g.k1_low > 0.5 * k1;
  });
  EXPECT_TRUE(early.decided);
  EXPECT_LT(early.iterations, full.iterations);
  EXPECT_LE(early.k1_low, k1 * (1 + 1e-12));  // the bracket holds the exact value
  EXPECT_GE(early.k1, k1 * (1 - 1e-12));
  EXPECT_LE(early.k1nu_low, k1nu * (1 + 1e-12));
  EXPECT_GE(early.k1nu, k1nu * (1 - 1e-12));
  EXPECT_NE(early.how.find("stopped once the brackets decided"), std::string::npos) << early.how;
  // k_1ν alone: its run is the same run (the same start), to the tolerance, without k_1's steps;
  // (21) is not decided from it.
  const Gamma3Spectrum nu = gamma3_spectrum(apply, w, d, opt, "dense S", {}, false);
  ASSERT_TRUE(nu.converged);
  EXPECT_FALSE(nu.has_k1);
  EXPECT_TRUE(std::isnan(nu.k1) && std::isnan(nu.k1_low));
  EXPECT_NEAR(nu.k1nu, k1nu, 10 * opt.lanczos_tol * k1nu);
  EXPECT_LT(nu.iterations, full.iterations);
  EXPECT_NE(nu.how.find("k_1nu alone"), std::string::npos) << nu.how;
  const Model md = mct::model_of("sofonea2017-fig2", {"mesh.n=4"});
  EXPECT_THROW(smallness_from_spectrum(md, nu), Error);
}

// A softening law whose inner problem is not strongly convex: Lanczos says so too.
TEST(SparseChecks, NotConvexIsFoundByLanczosToo) {
  const mct::Solved dense = mct::run("minima-softening", {});
  const mct::Solved sparse = mct::run("minima-softening", {"check.dense_max_unknowns=0"});
  const InnerConvexity &cd = dense.sol.inner_convexity, &cs = sparse.sol.inner_convexity;
  ASSERT_TRUE(cd.checked);
  ASSERT_FALSE(cd.strongly_convex);  // λ_min(S − αW_ν) = −6083 at α = 1e5
  EXPECT_EQ(cd.checked, cs.checked) << cs.note;
  EXPECT_EQ(cd.strongly_convex, cs.strongly_convex) << cs.note;
  EXPECT_EQ(cd.min_eigenvalue > 0, cs.min_eigenvalue > 0);
}

// Above the threshold in 3D, (21) costs no extra factorization: decided by the bracket or reported
// undecided with its reason, never the exact evaluation (whose method is "exact").
TEST(SparseChecks, Large3DSmallnessNeedsNoFactorization) {
  const mct::Solved r = mct::run("sofonea2017-3d", {"mesh.n=4", "check.dense_max_unknowns=0"});
  const SmallnessReport& q = r.sol.smallness;
  EXPECT_EQ(q.method, "bound");
  EXPECT_NE(q.note.find("Lanczos"), std::string::npos) << q.note;
  if (!q.computed) {
    EXPECT_NE(q.note.find("not decided"), std::string::npos) << q.note;
  }
  EXPECT_TRUE(r.sol.ok()) << r.sol.message;
}

// A caller that asks for (21) after the solve (the adaptive loop's final mesh: check.smallness off
// during the solve) under an automatic full gets it from the spectrum read at set-up where the
// set-up had the elastic factor (a backend that needs its scales: here the engine's default,
// kept because solver.options are passed to it), and the reason where ssn answers.
TEST(SparseChecks, SmallnessAfterTheSolveUnderAnAutomaticFull) {
  const auto smallness_after = [](const std::vector<std::string>& extra) {
    std::vector<std::string> sets = mct::strip({"check.smallness=false"});
    sets.insert(sets.end(), extra.begin(), extra.end());
    const json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", sets);
    const Model md = build_model(s, HEMICONTACT_SOURCE_DIR "/problems");
    ContactSolver solver(md, solve_options_from_scene(s));
    EXPECT_EQ(solver.formulation(), "full");
    return solver.smallness();
  };
  const SmallnessReport ssn = smallness_after({});
  EXPECT_FALSE(ssn.computed);
  EXPECT_NE(ssn.note.find("no factor at hand"), std::string::npos) << ssn.note;
  // An option of the engine's default backend (ipopt where built, else newton).
  const std::string option = HEMICONTACT_HAS_IPOPT ? "solver.options.mu_strategy=\"adaptive\""
                                                   : "solver.options.hessian=\"exact_first\"";
  const SmallnessReport kept = smallness_after({option});
  EXPECT_TRUE(kept.computed) << kept.note;
  EXPECT_EQ(kept.method, "bound");
  EXPECT_NE(kept.note.find("elastic factor"), std::string::npos) << kept.note;
}
