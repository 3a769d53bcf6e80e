// The mesh-convergence study (studies/convergence.hpp) on the paper's two scenes: errors against a
// finer reference decrease at a positive observed order (the paper reports ≈ 1, Fig. 3); the request is
// checked before any solve; the reference measured against itself has no error.
#include <hemicontact/core/error.hpp>
#include <hemicontact/output/study_writers.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/studies/convergence.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

using namespace hemicontact;
using json = nlohmann::json;

namespace {

const std::string PROBLEMS_DIR = HEMICONTACT_SOURCE_DIR "/problems";

json scene_of(const std::string& name) { return load_scene(PROBLEMS_DIR + "/sofonea2017-" + name + ".json"); }

// Each scene's study (levels 4, 8, 16 against 32) is run once and shared by the tests.
const ConvergenceStudy& study_of(const std::string& name) {
  static std::map<std::string, ConvergenceStudy> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, run_convergence(scene_of(name), PROBLEMS_DIR, {16, 4, 8}, 32)).first;
  return it->second;
}

}  // namespace

class ConvergenceStudyScenes : public ::testing::TestWithParam<std::string> {};

// Measured (ipopt, Release), levels 4, 8, 16 against 32:
//   printed: e = 0.552, 0.343, 0.185   orders 0.69, 0.89
//   fig2:    e = 0.565, 0.364, 0.201   orders 0.64, 0.86
// and levels 4..64 against 128 (`hemicontact converge`):
//   printed: orders 0.62, 0.69, 0.77, 0.94;   fig2: orders 0.57, 0.65, 0.75, 0.93;
//   the same body without contact (problems/elasticity-square.json): 0.62, 0.69, 0.77, 0.94.
// So the contact does not limit the rate: the elastic solution does, through the corners where
// the clamped top meets the loaded sides. Its true order is ≈ 0.7: with E_L = C h^α and Galerkin
// orthogonality the measured e_L = (E_L² − E_R²)^{1/2} gives orders 0.71, 0.73, 0.77, 0.93 for
// α = 0.7 — the last pair is inflated by the reference being only 2× finer, and the paper's "≈ 1"
// is what the finest pairs show. Hence the band [0.5, 1.6] on the finest pair.
TEST_P(ConvergenceStudyScenes, ErrorsDecreaseAtAnObservedOrderInBand) {
  const ConvergenceStudy& st = study_of(GetParam());
  ASSERT_EQ(st.levels.size(), 3u);
  EXPECT_TRUE(st.ok()) << "failed levels: " << st.failed().size();
  EXPECT_EQ(st.reference.n, 32);
  EXPECT_EQ(st.reference.error, 0.0);
  EXPECT_TRUE(std::isnan(st.levels[0].order));
  for (size_t i = 0; i < st.levels.size(); ++i) {
    const ConvergenceLevel& l = st.levels[i];
    SCOPED_TRACE("n = " + std::to_string(l.n));
    EXPECT_EQ(l.n, 4 << i);  // sorted coarse to fine
    EXPECT_DOUBLE_EQ(l.h, 1.0 / l.n);
    EXPECT_TRUE(l.ok) << l.message;
    EXPECT_TRUE(l.nested);
    EXPECT_GT(l.error, 0.0);
    EXPECT_LT(l.error, 1.0);
    EXPECT_GT(l.energy_norm, 0.0);
    EXPECT_LT(l.dofs, st.reference.dofs);
    if (i > 0) {
      EXPECT_LT(l.error, st.levels[i - 1].error);
      EXPECT_GT(l.order, 0.0);
    }
  }
  const double finest = st.levels.back().order;
  EXPECT_GE(finest, 0.5);
  EXPECT_LE(finest, 1.6);
  // The table and the CSV row count follow the study.
  const std::string table = convergence_table(st);
  EXPECT_NE(table.find("(reference)"), std::string::npos);
  EXPECT_NE(table.find("converged and certified"), std::string::npos);
  const json js = convergence_json(st);
  EXPECT_EQ(js["levels"].size(), 3u);
  EXPECT_TRUE(js["levels"][0]["order"].is_null());
  EXPECT_TRUE(js["ok"].get<bool>());
}

INSTANTIATE_TEST_SUITE_P(PaperScenes, ConvergenceStudyScenes, ::testing::Values("printed", "fig2"));

TEST(ConvergenceStudy, ReferenceAgainstItselfHasNoError) {
  const ConvergenceStudy st = run_convergence(scene_of("fig2"), PROBLEMS_DIR, {4, 8}, 8);
  ASSERT_EQ(st.levels.size(), 2u);
  EXPECT_GT(st.levels[0].error, 0.0);
  EXPECT_EQ(st.levels[1].n, 8);
  EXPECT_EQ(st.levels[1].error, 0.0);
  EXPECT_EQ(st.levels[1].dofs, st.reference.dofs);
  EXPECT_TRUE(std::isnan(st.levels[1].order));  // log of e/0 is no order
}

// The callback sees each solved mesh once, the reference first, then each level other than the
// reference with its error already in so_far (what the CLI keeps as it comes, so that an interrupt
// loses no finished level); the study so far agrees with the finished study.
TEST(ConvergenceStudy, EachLevelIsAnnouncedWithItsErrorAsItEnds) {
  std::vector<int> seen;
  std::vector<size_t> levels_so_far;
  std::vector<double> errors;
  const ConvergenceStudy st = run_convergence(
      scene_of("fig2"), PROBLEMS_DIR, {8, 4, 16}, 16,
      [&](const ConvergenceStudy& so_far, int n, const Model& md, const Solution& sol) {
        seen.push_back(n);
        levels_so_far.push_back(so_far.levels.size());
        EXPECT_EQ(md.dofs.n_full(), sol.u.size());
        if (!so_far.levels.empty()) {
          EXPECT_EQ(so_far.levels.back().n, n);
          errors.push_back(so_far.levels.back().error);
        }
      });
  EXPECT_EQ(seen, (std::vector<int>{16, 4, 8}));  // 16 = the reference: solved once
  EXPECT_EQ(levels_so_far, (std::vector<size_t>{0, 1, 2}));
  ASSERT_EQ(st.levels.size(), 3u);
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0], st.levels[0].error);
  EXPECT_EQ(errors[1], st.levels[1].error);
  EXPECT_GT(errors[0], errors[1]);
}

TEST(ConvergenceStudy, LevelsMustDivideTheReference) {
  try {
    run_convergence(scene_of("fig2"), PROBLEMS_DIR, {4, 6, 12, 5}, 32);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.code(), EXIT_INPUT);
    EXPECT_NE(msg.find("5, 6, 12"), std::string::npos) << msg;  // every offender, sorted
    EXPECT_NE(msg.find("32"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("4,"), std::string::npos) << msg;
  }
  EXPECT_THROW(run_convergence(scene_of("fig2"), PROBLEMS_DIR, {}, 32), Error);
  EXPECT_THROW(run_convergence(scene_of("fig2"), PROBLEMS_DIR, {0, 4}, 32), Error);
  EXPECT_THROW(run_convergence(scene_of("fig2"), PROBLEMS_DIR, {64}, 32), Error);  // finer than the reference
}

TEST(ConvergenceStudy, NonNestedMeshesAreFlagged) {
  // A perturbed mesh is not a refinement of another: still measured, but flagged.
  const json scene = load_scene(PROBLEMS_DIR + "/sofonea2017-printed.json", {"mesh.perturb=0.2"});
  const ConvergenceStudy st = run_convergence(scene, PROBLEMS_DIR, {4}, 8);
  ASSERT_EQ(st.levels.size(), 1u);
  EXPECT_FALSE(st.levels[0].nested);
  EXPECT_GT(st.levels[0].error, 0.0);
}

TEST(ConvergenceStudy, ParseLevels) {
  EXPECT_EQ(parse_levels("4,8,...,64"), (std::vector<int>{4, 8, 16, 32, 64}));
  EXPECT_EQ(parse_levels("3,9,...,81"), (std::vector<int>{3, 9, 27, 81}));
  EXPECT_EQ(parse_levels("16,4,8,4"), (std::vector<int>{4, 8, 16}));
  for (const char* bad : {"", "4,x", "4,-8", "4,0", "4,...,8", "4,8,...", "4,6,...,36", "8,4,...,64"}) {
    SCOPED_TRACE(bad);
    try {
      parse_levels(bad);
      FAIL() << "expected an Error";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), EXIT_USAGE);
      EXPECT_NE(std::string(e.what()).find("--levels"), std::string::npos) << e.what();
    }
  }
}

namespace {

// A study whose errors follow e = C sqrt(h^{2α} − h_R^{2α}) exactly (nested levels 4..64, R = 256).
ConvergenceStudy synthetic_study(double C, double alpha, double perturb = 0) {
  ConvergenceStudy st;
  st.reference.n = 256;
  st.reference.h = 1.0 / 256;
  int i = 0;
  for (int n : {4, 8, 16, 32, 64}) {
    ConvergenceLevel l;
    l.n = n;
    l.h = 1.0 / n;
    l.error = C * std::sqrt(std::pow(l.h, 2 * alpha) - std::pow(st.reference.h, 2 * alpha)) *
              (1 + perturb * ((i++ % 2) ? 1 : -1));
    st.levels.push_back(l);
  }
  return st;
}

}  // namespace

// The reference-corrected fit recovers α and C from data that follow its model exactly, although
// the naive orders of the same data are biased upwards: for the finest pair (h = 1/32, 1/64 against
// 1/256) by ½ log2((1 − 8^{−2α})/(1 − 4^{−2α})) = 0.068 at α = 0.72, and against a 2× reference by
// ½ log2((1 − 4^{−2α})/(1 − 2^{−2α})) = 0.23: the reason the fit exists.
TEST(ConvergenceRateFit, RecoversTheModelsRate) {
  for (double alpha : {0.5, 0.72, 1.0, 2.0}) {
    SCOPED_TRACE("alpha = " + std::to_string(alpha));
    const ConvergenceStudy st = synthetic_study(1.7, alpha);
    const RateFit f = fit_rate(st);
    ASSERT_TRUE(f.valid);
    EXPECT_EQ(f.levels_used, 4);
    EXPECT_NEAR(f.alpha, alpha, 1e-6);
    EXPECT_NEAR(f.C, 1.7, 1e-5);
    EXPECT_LT(f.max_rel_residual, 1e-6);
    const double naive = std::log2(st.levels[3].error / st.levels[4].error);
    const double bias = 0.5 * std::log2((1 - std::pow(8.0, -2 * alpha)) / (1 - std::pow(4.0, -2 * alpha)));
    EXPECT_GT(bias, 0.0);
    EXPECT_NEAR(naive - alpha, bias, 1e-9);  // the bias the fit removes
  }
}

// Alternating ±1 % noise moves α by at most O(noise / log(h range)) and is reported as residual.
TEST(ConvergenceRateFit, NoiseShowsInTheResidual) {
  const RateFit f = fit_rate(synthetic_study(1.0, 0.72, 0.01));
  ASSERT_TRUE(f.valid);
  EXPECT_NEAR(f.alpha, 0.72, 0.02);
  EXPECT_GT(f.max_rel_residual, 0.005);
  EXPECT_LT(f.max_rel_residual, 0.03);
}

TEST(ConvergenceRateFit, NeedsTwoLevelsCoarserThanTheReference) {
  ConvergenceStudy st = synthetic_study(1.0, 1.0);
  st.levels.erase(st.levels.begin(), st.levels.end() - 1);
  EXPECT_FALSE(fit_rate(st).valid);
  EXPECT_TRUE(convergence_json(st)["rate_fit"].is_null());
  EXPECT_TRUE(convergence_json(synthetic_study(1.0, 1.0))["rate_fit"].is_object());
}

// A level on another branch of a nonconvex law: its error is off the others' curve. Flagged (and
// left out of the fit, which then recovers the others' rate) only where uniqueness is in doubt;
// the others, with ±10 % noise, are not flagged.
TEST(ConvergenceRateFit, ALevelOnAnotherBranchIsLeftOutWhereUniquenessIsInDoubt) {
  ConvergenceStudy st = synthetic_study(1.0, 0.72, 0.1);
  st.levels[3].error *= 5;  // n = 32 jumped to another branch
  ConvergenceStudy sure = st;
  EXPECT_TRUE(flag_other_branches(sure).empty());  // (21) holds or convex: one solution, no flag
  const RateFit biased = fit_rate(sure);
  st.levels[2].unique_in_doubt = true;
  EXPECT_EQ(flag_other_branches(st), std::vector<int>{32});
  EXPECT_NE(st.levels[3].other_branch.find("another branch"), std::string::npos) << st.levels[3].other_branch;
  const RateFit f = fit_rate(st);
  ASSERT_TRUE(f.valid);
  EXPECT_NEAR(f.alpha, 0.72, 0.15);
  EXPECT_GT(std::abs(biased.alpha - 0.72), std::abs(f.alpha - 0.72));
  const json j = convergence_json(st);
  EXPECT_EQ(j.at("rate_fit").at("left_out"), json::array({32}));
  EXPECT_TRUE(j.at("levels")[3].at("other_branch").is_string());
  EXPECT_TRUE(j.at("levels")[2].at("other_branch").is_null());
  // The paper's scenes: one solution, nothing flagged on a real study.
  ConvergenceStudy real = run_convergence(scene_of("fig2"), PROBLEMS_DIR, {4, 8}, 16);
  for (const auto& l : real.levels) EXPECT_FALSE(l.unique_in_doubt) << l.n;
  EXPECT_TRUE(flag_other_branches(real).empty());
}

// A 3D study (box meshes, Kuhn/symmetric tetrahedra): the levels are nested in the reference
// (the Kuhn split of a cube is a union of Kuhn splits of its 8 sub-cubes), every solve is
// certified, and the error decreases from level to level.
TEST(ConvergenceStudy3D, BoxLevelsAreNestedAndConverge) {
  const ConvergenceStudy st = run_convergence(scene_of("3d"), PROBLEMS_DIR, {2, 4}, 8);
  ASSERT_EQ(st.levels.size(), 2u);
  EXPECT_TRUE(st.ok());
  for (const auto& l : st.levels) {
    EXPECT_TRUE(l.nested) << "n = " << l.n;
    EXPECT_GT(l.error, 0.0);
    EXPECT_LT(l.error, 1.0);
  }
  EXPECT_LT(st.levels[1].error, st.levels[0].error);
  EXPECT_GT(st.levels[1].order, 0.3);  // measured in the comment of the 2D scenes: orders 0.6-0.9
  EXPECT_DOUBLE_EQ(st.levels[0].h, 0.5);
}

TEST(ConvergenceStudy, GmshMeshesAreRefused) {
  json s = scene_of("fig2");
  s["mesh"]["type"] = "gmsh";
  s["mesh"]["file"] = "x.msh";
  try {
    run_convergence(s, PROBLEMS_DIR, {4}, 8);
    ADD_FAILURE() << "a gmsh scene was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT);
    EXPECT_NE(std::string(e.what()).find("mesh.type is 'gmsh'"), std::string::npos) << e.what();
  }
}
