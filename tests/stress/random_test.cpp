// Randomized stress scenes with fixed seeds, fast part: each drawn scene either converges with its
// certificate below tolerance or says it did not (a non-empty message and a reason: the fixed
// point, the backend or the certificate) — never NaN, never a crash, never an uncertified answer
// presented as converged. The full part (300 seeds, finer meshes) is bench/stress_report.cpp. A
// failing seed prints the command line that reruns it.
#include <hemicontact/studies/random_scenes.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

using namespace hemicontact;

namespace {

/// One drawn scene: certified, or honestly not (see the file comment). Returns whether the answer
/// was certified; an input error (an inverted perturbed cell) counts as not certified.
bool certified_or_honestly_not(unsigned seed) {
  const stress::RandomScene rs = stress::draw_scene(seed, 4, 8);
  SCOPED_TRACE("seed " + std::to_string(seed) + ", rerun: " + rs.command());
  std::vector<std::string> o = rs.overrides;
  // CI budget: a hard draw stops early and must then say so (the bench runs the full budgets).
  o.insert(o.end(), {"solver.max_iter=300", "solver.fixed_point.max_iters=20"});
  const nlohmann::json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", o);
  Model md;
  try {
    md = build_model(scene, ".");
  } catch (const Error& e) {
    // A perturbed mesh with an inverted cell (possible on crossed meshes and boxes; right/left/
    // symmetric rectangles only beyond perturb 0.35) is an input error naming it: the honest outcome.
    EXPECT_EQ(e.code(), EXIT_INPUT);
    EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos) << e.what();
    return false;
  }
  const SolveOptions opt = solve_options_from_scene(scene);
  const Solution s = solve(md, opt);
  if (!s.u.allFinite()) {
    ADD_FAILURE() << "non-finite u";
    return false;
  }
  EXPECT_TRUE(std::isfinite(s.energy));
  EXPECT_FALSE(s.message.empty());
  for (const auto& h : s.history)
    if (!std::isnan(h.contraction)) {
      EXPECT_GE(h.contraction, 0.0);
    }
  if (s.ok()) {
    EXPECT_LE(s.certificate.max_residual, s.certificate.tol) << s.message;
  } else {
    // A reason: the fixed point, the backend or the certificate said no, and the message says which.
    EXPECT_TRUE(!s.fixed_point_converged || !s.backend_ok || !s.certificate.passed);
    const bool named = s.message.find("fixed point") != std::string::npos ||
                       s.message.find("backend") != std::string::npos ||
                       s.message.find("certificate failed") != std::string::npos;
    EXPECT_TRUE(named) << s.message;
  }
  // The verdict is not the solver's word: the certificate of the returned u, recomputed here,
  // agrees with the one the solution carries.
  Solution again;
  again.u = s.u;
  evaluate_solution(md, opt, again);
  EXPECT_EQ(again.certificate.passed, s.certificate.passed);
  EXPECT_NEAR(again.certificate.max_residual, s.certificate.max_residual, 1e-12 + 1e-9 * s.certificate.max_residual);
  return s.ok();
}

}  // namespace

// Honest failures alone would let this pass with every seed failing, so it also has a floor: the
// number of certified seeds among 1..24 measured when the floor was set (CERTIFIED_MEASURED) less
// a margin of 2 for machines whose rounding tips a borderline draw (the draws themselves are
// portable: studies/random_scenes.hpp). Raise the floor when the solver gets better.
TEST(RandomScenes, CertifiedOrHonestlyNotConvergedWithAFloor) {
  constexpr int CERTIFIED_MEASURED = 21, MARGIN = 2;
  int certified = 0;
  std::string failed;
  for (unsigned seed = 1; seed <= 24; ++seed) {
    if (certified_or_honestly_not(seed))
      ++certified;
    else
      failed += " " + std::to_string(seed);
  }
  std::printf("[ random   ] %d of 24 seeds certified; not certified:%s\n", certified, failed.c_str());
  EXPECT_GE(certified, CERTIFIED_MEASURED - MARGIN) << "not certified:" << failed;
}

// Seed 40 of the full report (n = 8..16): final ε = 1.8e-7 ≫ check.status_tol = 1e-8, so the
// smoothed answer shows |u_τ| ~ ε U on sticking nodes and reads 28 of them as slipping; the status
// system built on those statuses is inconsistent (certificate 0.34, slip_direction). The polish
// reads the statuses again at the smoothing scale and certifies the answer to round-off.
TEST(RandomScenesPolish, StatusesReadAtTheSmoothingScale) {
  const stress::RandomScene rs = stress::draw_scene(40, 8, 16);
  SCOPED_TRACE("rerun: " + rs.command());
  std::vector<std::string> o = rs.overrides;
  o.push_back("solver.max_iter=500");
  // The polish of the continuation's final answer is the subject: without the exact solver, which
  // would take over after stage 0.
  o.push_back("solver.exact.enabled=false");
  const nlohmann::json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", o);
  const Model md = build_model(scene, ".");
  SolveOptions opt = solve_options_from_scene(scene);
  ASSERT_GT(opt.eps_tau, 10 * opt.status_tol);  // the premise of this case
  const Solution s = solve(md, opt);
  EXPECT_TRUE(s.ok()) << s.message << " / polish: " << s.polish.note;
  EXPECT_TRUE(s.polish.accepted);
  EXPECT_NE(s.polish.note.find("10 eps"), std::string::npos) << s.polish.note;
  EXPECT_GT(s.polish.before, 1e-2);
  EXPECT_LT(s.certificate.max_residual, 1e-12);
}

// The default-settings study in CI: seeds 1..48 of draw_default_scene (n = 4..8) with DEFAULT
// solver settings. Each is certified or honestly not (as above), every strongly convex inner
// problem is certified (a solution exists there, so a failure would be the solver's), and a floor
// on the count: CERTIFIED_MEASURED when it was set, less a margin of 1 for a machine whose rounding
// tips a borderline draw. The 1000-seed study is bench/random_study.cpp.
TEST(RandomScenesDefault, CertifiedWithDefaultSettingsWithAFloor) {
#if defined(HEMICONTACT_SANITIZED)
  // Under the sanitizers the first 16 seeds (all 16 certified when measured): the same solver paths
  // for their memory use, at a third of the time (16 s for 48 seeds there).
  constexpr int SEEDS = 16, CERTIFIED_MEASURED = 16, MARGIN = 1;
#else
  constexpr int SEEDS = 48, CERTIFIED_MEASURED = 48, MARGIN = 1;
#endif
  int certified = 0, solved = 0;
  std::string failed;
  for (unsigned seed = 1; seed <= SEEDS; ++seed) {
    const stress::RandomScene rs = stress::draw_default_scene(seed, 4, 8);
    SCOPED_TRACE("seed " + std::to_string(seed) + ", rerun: " + rs.command());
    std::vector<std::string> o = rs.overrides;
    const nlohmann::json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", o);
    Model md;
    try {
      md = build_model(scene, ".");
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), EXIT_INPUT) << e.what();
      continue;
    }
    ++solved;
    const Solution s = solve(md, solve_options_from_scene(scene));
    ASSERT_TRUE(s.u.allFinite());
    if (s.ok()) {
      ++certified;
      EXPECT_LE(s.certificate.max_residual, s.certificate.tol);
    } else {
      failed += " " + std::to_string(seed);
      EXPECT_FALSE(s.message.empty());
      EXPECT_FALSE(s.inner_convexity.checked && s.inner_convexity.strongly_convex)
          << "strongly convex inner problem not certified: " << s.message;
    }
  }
  std::printf("[ random   ] default settings: %d of %d solved seeds certified; not certified:%s\n", certified, solved,
              failed.c_str());
  EXPECT_GE(certified, std::min(solved, CERTIFIED_MEASURED) - MARGIN) << "not certified:" << failed;
}

// Seed 947 of the 1000-seed study (bench/random_study.cpp, n = 8..16): the inner problem is not
// strongly convex, and from the neighbourhood of the continuation's stage 0 the Anderson fixed
// point stalls at a coupled residual of 3e-6 (50 iterations). The last resort — the exact solver
// from the start — is certified, and the answer says which path produced it.
TEST(RandomScenesDefault, LastResortFromTheStartCertifiesSeed947) {
  const stress::RandomScene rs = stress::draw_default_scene(947, 8, 16);
  SCOPED_TRACE("rerun: " + rs.command());
  // The default (start = auto): the backend's stage 0 runs first on this not strongly convex scene,
  // the answer after the hand-over is not certified, and the last resort from the start is.
  std::vector<std::string> o = rs.overrides;
  const nlohmann::json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", o);
  const Model md = build_model(scene, ".");
  const Solution s = solve(md, solve_options_from_scene(scene));
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_TRUE(s.handover.used);
  EXPECT_EQ(s.handover.after_stage, -1);
  bool said = false;
  for (const auto& k : s.skipped) said = said || k.rfind("continuation: its answer was not certified", 0) == 0;
  EXPECT_TRUE(said) << "expected the last resort (the continuation's answer was not certified)";
  // The backend's work in the discarded attempt stays in the record: it ran.
  EXPECT_TRUE(s.backend_use.ran);
  EXPECT_GT(s.work_of(s.backend).iterations, 0);
  // solver.exact.start = always certifies it from the start, no stage run, with the same answer: u to
  // the certificate's scale.
  std::vector<std::string> o_always = rs.overrides;
  o_always.push_back("solver.exact.start=\"always\"");
  const nlohmann::json scene_default = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", o_always);
  const Solution a = solve(md, solve_options_from_scene(scene_default));
  ASSERT_TRUE(a.ok()) << a.message;
  for (const auto& h : a.history) EXPECT_EQ(h.stage, -1);
  ASSERT_EQ(a.u.size(), s.u.size());
  EXPECT_LE((a.u - s.u).norm(), 1e-8 * s.u.norm());
}
