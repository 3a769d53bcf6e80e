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

#include <gtest/gtest.h>

#include <cmath>
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

TEST(Adapt, ThreeDimensionalMeshIsRefused) {
  const json scene = load_scene(PROBLEMS + "/sofonea2017-3d.json", {"mesh.n=2"});
  try {
    AdaptOptions a;
    run_adaptive(scene, build_mesh(scene, PROBLEMS), a, solve_options_from_scene(scene));
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT);
    EXPECT_NE(std::string(e.what()).find("adapt"), std::string::npos) << e.what();
  }
}
