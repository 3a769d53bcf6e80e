// The adaptive loop (solver/adapt.hpp).
//
// Corner problem: the paper's body without contact (problems/elasticity-square.json): clamped top,
// loaded sides; at the clamped–free corners u ~ r^0.72 (scripts/corner_exponent.py), so uniform
// meshes converge like N^(−0.36). Adaptive meshes must restore N^(−1/2): the true errors against
// the last (finest) level of the same sequence — nested, so the prolongation is exact and
// ‖u_ref − u_L‖² = ‖u − u_L‖² − ‖u − u_ref‖² (Galerkin orthogonality) — are fitted over the levels
// with at most 1/8 of the reference's unknowns, where the subtracted part is below 1/8 of the
// error² for a rate ≥ 1/2: the bias of the fitted slope is below 0.03.
//
// Contact problem: the Fig. 2 scene adapts from n = 8 with every level certified, Γ3 weights
// summing to |Γ3| = 1 on every mesh, and the estimate going down.
#include <hemicontact/check/smallness.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/prolongation.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/adapt.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <cstdlib>

#include <dlfcn.h>

using namespace hemicontact;
using json = nlohmann::json;

namespace {
const std::string PROBLEMS = HEMICONTACT_SOURCE_DIR "/problems";

struct Kept {
  Mesh mesh;
  Vec u;
  Index dofs;
  double estimate;
};
}  // namespace

TEST(Adapt, CornerProblemRestoresTheOptimalRate) {
#if defined(HEMICONTACT_SANITIZED)
  // The rate needs levels up to 60 000 unknowns (17 s under the sanitizers); the adaptive loop's
  // memory use is watched there by the smaller cases below, and the rate is asserted in the
  // regular build.
  GTEST_SKIP() << "the observed rate needs 60 000 unknowns: asserted in the regular build";
#endif
  const json scene = load_scene(PROBLEMS + "/elasticity-square.json",
                                {"mesh.n=4", "mesh.diagonal=\"symmetric\"", "check.smallness=false"});
  AdaptOptions a;
  a.target_error = 0.01;
  a.max_dofs = 60000;
  a.theta = 0.5;
  std::vector<Kept> levels;
  const AdaptResult r = run_adaptive(scene, build_mesh(scene, PROBLEMS), a, solve_options_from_scene(scene),
                                     [&](const AdaptLevel& L, const Model& md, const Solution& sol, const ErrorEstimate&) {
                                       levels.push_back({md.mesh, sol.u, L.dofs, L.estimate});
                                     });
  ASSERT_GE(levels.size(), 6u);
  const Kept& ref = levels.back();
  const Model ref_model = build_model(scene, ref.mesh);
  const double norm_ref = std::sqrt(ref_model.a(ref.u, ref.u));
  std::vector<double> lx, ly;
  for (const Kept& k : levels) {
    if (8 * k.dofs > ref.dofs) break;
    const Vec diff = ref.u - prolongate(k.mesh, k.u, ref.mesh);  // nested: vanishes on Γ1
    const double e = std::sqrt(ref_model.a(diff, diff)) / norm_ref;
    lx.push_back(std::log(static_cast<double>(k.dofs)));
    ly.push_back(std::log(e));
    // ZZ efficiency against the true error, in the band [0.5, 3].
    EXPECT_GE(k.estimate / e, 0.5) << k.dofs;
    EXPECT_LE(k.estimate / e, 3.0) << k.dofs;
  }
  ASSERT_GE(lx.size(), 4u);
  // Least-squares slope of log e against log N over the last four qualifying levels.
  const size_t n = 4, s0 = lx.size() - n;
  double mx = 0, my = 0;
  for (size_t i = s0; i < lx.size(); ++i) mx += lx[i] / n, my += ly[i] / n;
  double sxy = 0, sxx = 0;
  for (size_t i = s0; i < lx.size(); ++i) sxy += (lx[i] - mx) * (ly[i] - my), sxx += (lx[i] - mx) * (lx[i] - mx);
  const double slope = sxy / sxx;
  RecordProperty("slope", std::to_string(slope));
  EXPECT_LT(slope, -0.45) << "uniform meshes give -0.36";
}

TEST(Adapt, Fig2SceneEveryLevelCertified) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-fig2.json",
                                {"mesh.n=8", "adapt.target_error=0.08", "check.smallness=false"});
  ASSERT_TRUE(adapt_requested(scene));
  const AdaptOptions a = adapt_options_from_scene(scene);
  std::vector<double> weight_sums;
  const AdaptResult r = run_adaptive(scene, build_mesh(scene, PROBLEMS), a, solve_options_from_scene(scene),
                                     [&](const AdaptLevel&, const Model& md, const Solution&, const ErrorEstimate&) {
                                       weight_sums.push_back(md.contact.w.sum());
                                     });
  EXPECT_TRUE(r.reached) << r.stop_reason;
  ASSERT_GE(r.history.size(), 3u);
  for (const AdaptLevel& L : r.history) {
    SCOPED_TRACE("level " + std::to_string(L.level));
    EXPECT_TRUE(L.ok);
    EXPECT_LE(L.certificate, 1e-8);
    // The phases are disjoint parts of the level (the log line and bookkeeping are outside them).
    for (double t : {L.build_seconds, L.setup_seconds, L.contact_seconds, L.estimate_seconds, L.refine_seconds})
      EXPECT_GE(t, 0.0);
    EXPECT_LE(L.build_seconds + L.setup_seconds + L.contact_seconds + L.estimate_seconds + L.refine_seconds,
              L.seconds);
    EXPECT_NEAR(L.setup_seconds + L.contact_seconds, L.solve_seconds, 1e-12);
  }
  for (double w : weight_sums) EXPECT_NEAR(w, 1.0, 1e-13);
  EXPECT_LT(r.history.back().estimate, r.history.front().estimate);
  EXPECT_LE(r.history.back().estimate, 0.08);
  EXPECT_EQ(r.estimate.eta.size(), r.model.mesh.num_cells());
  const json rep = adapt_report(r, a);
  EXPECT_EQ(rep.at("history").size(), r.history.size());
  EXPECT_EQ(rep.at("final_estimate").get<double>(), r.history.back().estimate);
}

// (21) on the final mesh comes from that mesh's condensation (the bracket, no factorization); the
// exact evaluation on the same mesh must lie inside the bracket, and both must agree on the verdict.
TEST(Adapt, SmallnessOnTheFinalMeshFromItsCondensation) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-fig2.json", {"mesh.n=8", "adapt.target_error=0.08"});
  const SolveOptions sopt = solve_options_from_scene(scene);
  ASSERT_TRUE(sopt.smallness);
  const AdaptResult r = run_adaptive(scene, build_mesh(scene, PROBLEMS), adapt_options_from_scene(scene), sopt);
  ASSERT_TRUE(r.reached) << r.stop_reason;
  const SmallnessReport& q = r.solution.smallness;
  ASSERT_TRUE(q.computed);
  EXPECT_EQ(q.method, "bound");
  EXPECT_TRUE(q.holds);
  EXPECT_EQ(r.solution.timings.count("smallness"), 1u);
  const SmallnessReport exact = evaluate_smallness(r.model);
  EXPECT_TRUE(exact.holds);
  // Round-off of two different eigenvalue computations: relative 1e-10 on each end.
  EXPECT_LE(q.lhs_lower, exact.lhs * (1 + 1e-10));
  EXPECT_GE(q.lhs_upper, exact.lhs * (1 - 1e-10));
  EXPECT_LT(q.lhs, q.m_F);
}

// Landing: from n = 8 the fig2 estimates are 0.0957 (1276 unknowns), 0.0687 (2556), 0.0499 (4824).
// For a target of 0.06 the need predicted at 2556 unknowns, 1.1 × (0.0687/0.06)² × 1339 nodes ≈ 1930,
// is below Dörfler's next mesh (2499 nodes): the marking is cut, and the cut step must still reach
// the target (no extra level) on a smaller mesh than Dörfler's.
TEST(Adapt, LandingCutsTheLastStepToThePredictedNeed) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-fig2.json",
                                {"mesh.n=8", "adapt.target_error=0.06", "check.smallness=false"});
  AdaptOptions a = adapt_options_from_scene(scene);
  ASSERT_DOUBLE_EQ(a.landing, 1.1);
  a.lookahead = 1;  // a solve after every step: the landing alone (the lookahead needs it on)
  const SolveOptions sopt = solve_options_from_scene(scene);
  const AdaptResult landed = run_adaptive(scene, build_mesh(scene, PROBLEMS), a, sopt);
  a.landing = 0;
  const AdaptResult plain = run_adaptive(scene, build_mesh(scene, PROBLEMS), a, sopt);
  ASSERT_TRUE(landed.reached) << landed.stop_reason;
  ASSERT_TRUE(plain.reached) << plain.stop_reason;
  ASSERT_EQ(landed.history.size(), plain.history.size());
  const size_t last = landed.history.size() - 1;
  for (size_t i = 0; i + 1 < last; ++i) {
    EXPECT_FALSE(landed.history[i].landed) << i;
    EXPECT_EQ(landed.history[i].nodes, plain.history[i].nodes) << i;  // the same sequence up to there
  }
  const AdaptLevel& before = landed.history[last - 1];
  EXPECT_TRUE(before.landed);
  EXPECT_FALSE(plain.history[last - 1].landed);
  EXPECT_LE(landed.history[last].estimate, 0.06);
  EXPECT_LT(landed.history[last].nodes, plain.history[last].nodes);
  // Near the prediction: the node count of a cut marking is approximate (closure), within 25 %.
  const double r = before.estimate / 0.06, need = 1.1 * r * r * static_cast<double>(before.nodes);
  EXPECT_NEAR(static_cast<double>(landed.history[last].nodes), need, 0.25 * need);
  EXPECT_TRUE(adapt_report(landed, adapt_options_from_scene(scene)).at("history")[last - 1].at("landed").get<bool>());
}

// Two steps per solve (lookahead 2, the default) against a solve after every step, to 2 % on the
// Fig. 2 scene: fewer levels, the target reached, and meshes as good for the error: adaptive P1
// meshes follow η ≈ C N^(−1/2), and the final C = η√N of the predicted steps is within 5 % of the
// one-step sequence's (the ±1 % spread of η√N over the fine levels, the landing's 10 % margin).
TEST(Adapt, LookaheadSkipsSolvesOnMeshesAsGood) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-fig2.json",
                                {"mesh.n=8", "adapt.target_error=0.02", "check.smallness=false"});
  AdaptOptions a = adapt_options_from_scene(scene);
  ASSERT_EQ(a.lookahead, 2);
  const SolveOptions sopt = solve_options_from_scene(scene);
  const AdaptResult two = run_adaptive(scene, build_mesh(scene, PROBLEMS), a, sopt);
  a.lookahead = 1;
  const AdaptResult one = run_adaptive(scene, build_mesh(scene, PROBLEMS), a, sopt);
  ASSERT_TRUE(two.reached) << two.stop_reason;
  ASSERT_TRUE(one.reached) << one.stop_reason;
  EXPECT_LT(two.history.size(), one.history.size());
  int predicted = 0;
  for (const AdaptLevel& L : two.history) predicted += L.steps > 1;
  EXPECT_GE(predicted, 1);
  for (const AdaptLevel& L : one.history) EXPECT_LE(L.steps, 1);
  const auto C = [](const AdaptLevel& L) { return L.estimate * std::sqrt(static_cast<double>(L.dofs)); };
  EXPECT_NEAR(C(two.history.back()) / C(one.history.back()), 1.0, 0.05);
  EXPECT_LE(two.history.back().estimate, 0.02);
}

TEST(Adapt, LandingBelowOneIsRefused) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-fig2.json", {"adapt.target_error=0.06", "adapt.landing=0.5"});
  EXPECT_THROW(adapt_options_from_scene(scene), Error);
}

// adapt.blas_threads: OpenBLAS runs that many threads during the loop and its own count after it.
TEST(Adapt, BlasThreadsDuringTheLoopOnly) {
  auto* get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  auto* set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!get || !set || std::getenv("OPENBLAS_NUM_THREADS")) GTEST_SKIP() << "not OpenBLAS, or its count set by the environment";
  const int before = get();
  set(2);  // whatever the machine: a count that the loop must change and restore
  const json scene = load_scene(PROBLEMS + "/sofonea2017-fig2.json",
                                {"mesh.n=8", "adapt.target_error=0.2", "check.smallness=false"});
  const AdaptOptions a = adapt_options_from_scene(scene);
  ASSERT_EQ(a.blas_threads, 1);
  std::vector<int> during;
  run_adaptive(scene, build_mesh(scene, PROBLEMS), a, solve_options_from_scene(scene),
               [&](const AdaptLevel&, const Model&, const Solution&, const ErrorEstimate&) { during.push_back(get()); });
  const int after = get();
  set(before);
  ASSERT_FALSE(during.empty());
  for (int n : during) EXPECT_EQ(n, 1);
  EXPECT_EQ(after, 2);
}

TEST(Adapt, StopsBeforeMaxDofs) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-fig2.json",
                                {"mesh.n=8", "adapt.target_error=0.001", "adapt.max_dofs=600", "check.smallness=false"});
  const AdaptResult r = run_adaptive(scene, build_mesh(scene, PROBLEMS), adapt_options_from_scene(scene),
                                     solve_options_from_scene(scene));
  EXPECT_EQ(r.stop_reason, "max_dofs");
  EXPECT_FALSE(r.reached);
  for (const AdaptLevel& L : r.history) EXPECT_LE(L.dofs, 600);
}

// The same loop in 3D (tagged tetrahedra, the estimator over the dimension): the paper's 3D scene
// from the box n = 4 to a 25 % estimate. Every level certified, Σ w_i = |Γ3| = 1 on every level
// (Γ3 carried to the children), the estimate decreasing, the stop rule "target reached".
TEST(Adapt3d, TargetReachedEveryLevelCertified) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-3d.json",
                                {"mesh.n=4", "adapt.target_error=0.25", "check.smallness=false"});
  const AdaptOptions a = adapt_options_from_scene(scene);
  std::vector<double> weight_sums;
  const AdaptResult r = run_adaptive(scene, build_mesh(scene, PROBLEMS), a, solve_options_from_scene(scene),
                                     [&](const AdaptLevel&, const Model& md, const Solution&, const ErrorEstimate&) {
                                       weight_sums.push_back(md.contact.w.sum());
                                     });
  EXPECT_TRUE(r.reached) << r.stop_reason;
  EXPECT_EQ(r.stop_reason, "target reached");
  ASSERT_GE(r.history.size(), 2u);
  for (const AdaptLevel& L : r.history) {
    SCOPED_TRACE("level " + std::to_string(L.level));
    EXPECT_TRUE(L.ok);
    EXPECT_LE(L.certificate, 1e-8);
    // Each level's method is its own model's choice: a plain solve of that mesh picks the same.
    EXPECT_TRUE(L.method == "condensed" || L.method == "full") << L.method;
  }
  for (size_t k = 1; k < r.history.size(); ++k) {
    EXPECT_GT(r.history[k].dofs, r.history[k - 1].dofs);
    EXPECT_LT(r.history[k].estimate, r.history[k - 1].estimate);
  }
  for (double w : weight_sums) EXPECT_NEAR(w, 1.0, 1e-12);
  EXPECT_LE(r.history.back().estimate, 0.25);
  // The scene's reference energy gives each level its error: ZZ's efficiency index within the 3D
  // target's band [0.5, 2] (measured 0.61 on the uniform n = 4 start, then 0.77).
  ASSERT_TRUE(std::isfinite(a.reference_energy));
  for (const AdaptLevel& L : r.history) {
    ASSERT_TRUE(std::isfinite(L.reference_error)) << L.level;
    EXPECT_GE(L.estimate / L.reference_error, 0.5) << L.level;
    EXPECT_LE(L.estimate / L.reference_error, 2.0) << L.level;
  }
  EXPECT_EQ(r.estimate.eta.size(), r.model.mesh.num_cells());
  EXPECT_EQ(r.model.mesh.dim, 3);
  EXPECT_EQ(solve(r.model, solve_options_from_scene(scene)).method_choice.chosen, r.history.back().method);
}

// A mesh whose longest edges are not a compatible labelling (the 3D scene's box perturbed by 0.3 h,
// handed over as a mesh of its own: the scene says nothing of a lattice) is refined as marked
// tetrahedra (AMP), as it is: every level certified and conforming (bisect checks), Γ3's weights
// summing to its area, the estimate decreasing to the target, and the marking said in the mesh's
// origin. Before 3D bisection of any mesh this ended with an input error at the first refinement.
TEST(Adapt3d, AMeshThatIsNotKuhnIsRefinedAsMarkedTetrahedra) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-3d.json",
                                {"mesh.n=4", "adapt.target_error=0.3", "check.smallness=false"});
  json perturbed = scene;
  perturbed["mesh"]["perturb"] = 0.3;
  const Mesh coarse = build_mesh(perturbed, PROBLEMS);
  std::vector<double> weight_sums;
  const AdaptResult r = run_adaptive(scene, coarse, adapt_options_from_scene(scene), solve_options_from_scene(scene),
                                     [&](const AdaptLevel&, const Model& md, const Solution&, const ErrorEstimate&) {
                                       weight_sums.push_back(md.contact.w.sum());
                                     });
  EXPECT_TRUE(r.reached) << r.stop_reason;
  ASSERT_GE(r.history.size(), 2u);
  EXPECT_EQ(r.history.front().cells, coarse.num_cells());
  for (const AdaptLevel& L : r.history) {
    EXPECT_TRUE(L.ok) << L.level;
    EXPECT_LE(L.certificate, 1e-8) << L.level;
  }
  for (size_t k = 1; k < r.history.size(); ++k) EXPECT_LT(r.history[k].estimate, r.history[k - 1].estimate);
  for (double w : weight_sums) EXPECT_NEAR(w, 1.0, 1e-12);
  EXPECT_NE(r.model.mesh.origin.find("marked tetrahedra (AMP)"), std::string::npos) << r.model.mesh.origin;
}

// The scene's own perturbed box is labelled on its unperturbed lattice (the same cells: Kuhn
// paths), Maubach's tags: the first level is the scene's mesh, every level certified.
TEST(Adapt3d, APerturbedBoxIsLabelledOnItsLattice) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-3d.json",
                                {"mesh.n=4", "mesh.perturb=0.3", "adapt.target_error=0.3", "check.smallness=false"});
  const Mesh coarse = build_mesh(scene, PROBLEMS);
  const AdaptResult r = run_adaptive(scene, coarse, adapt_options_from_scene(scene), solve_options_from_scene(scene));
  EXPECT_TRUE(r.reached) << r.stop_reason;
  ASSERT_GE(r.history.size(), 2u);
  EXPECT_EQ(r.history.front().cells, coarse.num_cells());
  for (const AdaptLevel& L : r.history) EXPECT_LE(L.certificate, 1e-8) << L.level;
  EXPECT_EQ(r.model.mesh.origin.find("marked"), std::string::npos) << r.model.mesh.origin;
}

// The stored references (tests/data/<scene>-reference.json, bench/reference3d.py) belong to this
// code and their scenes (the 3D scene, and its frictionless Signorini variant): the scene carries
// the energy, the n = 8 level is reproduced to the certificate's accuracy (Π is stationary at the
// solution: an O(tol) error in u is O(tol²) in Π, so 1e-9 relative is loose), every stored level
// lies above the reference and the energies decrease towards it, and the fit's own residual is far
// below the stated uncertainty.
TEST(Adapt3d, ReferenceEnergyBelongsToTheScene) {
  for (const std::string name : {"sofonea2017-3d", "sofonea2017-3d-signorini"}) {
    SCOPED_TRACE(name);
    std::ifstream in(std::string(HEMICONTACT_SOURCE_DIR) + "/tests/data/" + name + "-reference.json");
    ASSERT_TRUE(in.good());
    const json ref = json::parse(in);
    const json scene = load_scene(PROBLEMS + "/" + name + ".json", {"mesh.n=8", "check.smallness=false"});
    const double pi_ref = ref.at("energy").get<double>(), tol = ref.at("energy_uncertainty").get<double>();
    EXPECT_NEAR(scene.at("adapt").at("reference_energy").get<double>(), pi_ref, 1e-3);
    double previous = INFINITY;
    for (const json& level : ref.at("levels")) {
      const double e = level.at("energy").get<double>();
      EXPECT_GT(e, pi_ref + tol) << level.at("n");
      EXPECT_LT(e, previous) << level.at("n");
      previous = e;
      if (level.at("n").get<int>() == 8) {
        const Model md = build_model(scene, PROBLEMS);
        const Solution sol = solve(md, solve_options_from_scene(scene));
        ASSERT_TRUE(sol.ok());
        EXPECT_NEAR(sol.energy, e, 1e-9 * std::abs(e));
      }
    }
    EXPECT_LT(ref.at("fit").at("residual_rms").get<double>(), 0.1 * tol);
  }
}

// The caps in 3D: max_dofs refuses the mesh that would exceed it (at most 3 unknowns per node),
// max_levels ends after that many solves; both stop above the target.
TEST(Adapt3d, StopRules) {
  json scene = load_scene(PROBLEMS + "/sofonea2017-3d.json",
                          {"mesh.n=2", "adapt.target_error=0.001", "adapt.max_dofs=1500", "check.smallness=false"});
  AdaptResult r = run_adaptive(scene, build_mesh(scene, PROBLEMS), adapt_options_from_scene(scene),
                               solve_options_from_scene(scene));
  EXPECT_EQ(r.stop_reason, "max_dofs");
  EXPECT_FALSE(r.reached);
  ASSERT_GE(r.history.size(), 2u);
  for (const AdaptLevel& L : r.history) EXPECT_LE(L.dofs, 1500);
  scene = load_scene(PROBLEMS + "/sofonea2017-3d.json",
                     {"mesh.n=2", "adapt.target_error=0.001", "adapt.max_levels=2", "check.smallness=false"});
  r = run_adaptive(scene, build_mesh(scene, PROBLEMS), adapt_options_from_scene(scene), solve_options_from_scene(scene));
  EXPECT_EQ(r.stop_reason, "max_levels");
  EXPECT_EQ(r.history.size(), 2u);
  EXPECT_FALSE(r.reached);
}

