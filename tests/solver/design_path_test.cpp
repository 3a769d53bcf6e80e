// The design's path is what a solve runs, and every report says what ran: the backend's smoothed
// ε-stage inside the outer fixed point, then the exact solver; the backend's stage skipped only
// where the inner problem is strongly convex (unique minimizer), and then said so with the
// eigenvalue; a named backend always runs; reports count a backend's own work, not the exact
// solver's.
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace hemicontact;

namespace {

struct DesignRun {
  Model md;
  SolveOptions opt;
  Solution sol;
};

DesignRun design_solve(const std::string& file, const std::vector<std::string>& o) {
  DesignRun r;
  const nlohmann::json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/" + file, o);
  r.md = build_model(s, ".");
  r.opt = solve_options_from_scene(s);
  r.sol = solve(r.md, r.opt);
  return r;
}

bool has_backend(const std::string& name) {
  for (const auto& [n, doc] : available_backends())
    if (n == name) return true;
  return false;
}

// The relative max-norm distance of two displacements.
double u_distance(const Solution& a, const Solution& b) {
  return (a.u - b.u).cwiseAbs().maxCoeff() / std::max(a.u.cwiseAbs().maxCoeff(), 1e-300);
}

}  // namespace

// fig2 is strongly convex: under solver.backend = auto the backend's stage cannot change the answer
// and is skipped; the summary, the report and `skipped` say so, with the eigenvalue, and no
// iteration is charged to a backend that did not run.
TEST(DesignPath, StronglyConvexSceneSkipsTheBackendAndSaysWhy) {
  const DesignRun r = design_solve("sofonea2017-fig2.json", {"mesh.n=8"});
  const Solution& s = r.sol;
  ASSERT_TRUE(s.ok()) << s.message;
  ASSERT_TRUE(s.inner_convexity.checked && s.inner_convexity.strongly_convex);
  EXPECT_EQ(s.backend_use.requested, "auto");
  EXPECT_FALSE(s.backend_use.ran);
  EXPECT_NE(s.backend_use.not_run.find("strongly convex"), std::string::npos) << s.backend_use.not_run;
  EXPECT_EQ(s.work_of(s.backend).minimizations, 0);
  EXPECT_TRUE(s.handover.used);
  EXPECT_EQ(s.solved_by(), "exact");
  const nlohmann::json rep = make_report(r.md, s, r.opt);
  EXPECT_EQ(rep["backend"]["ran"], false);
  EXPECT_EQ(rep["backend"]["iterations"], 0);
  EXPECT_EQ(rep["backend"]["evaluations"], 0);
  EXPECT_NE(rep["backend"]["not_run"].get<std::string>().find("smallest eigenvalue"), std::string::npos);
  EXPECT_EQ(rep["solved_by"], "exact");
  EXPECT_EQ(rep["phases"][0]["phase"], "backend");
  EXPECT_EQ(rep["phases"][1]["phase"], "exact");
  EXPECT_EQ(rep["phases"][1]["ran"], true);
  const std::string summary = summary_table(r.md, s);
  EXPECT_NE(summary.find("not run: the inner problem is strongly convex"), std::string::npos) << summary;
  EXPECT_NE(summary.find("solved by     exact"), std::string::npos) << summary;
}

// A named backend runs its first stage on a strongly convex scene too, then hands over; the answer
// is the unique minimizer, the same as the default's to the certificate's scale.
TEST(DesignPath, NamedBackendRunsOnAStronglyConvexScene) {
  const DesignRun def = design_solve("sofonea2017-fig2.json", {"mesh.n=8"});
  std::vector<std::string> names = {"newton"};
  for (const char* b : {"ipopt", "nlopt:LD_MMA"})
    if (has_backend(b)) names.push_back(b);
  for (const std::string& b : names) {
    SCOPED_TRACE(b);
    const DesignRun r = design_solve("sofonea2017-fig2.json", {"mesh.n=8", "solver.backend=\"" + b + "\""});
    const Solution& s = r.sol;
    ASSERT_TRUE(s.ok()) << s.message;
    EXPECT_TRUE(s.backend_use.ran);
    EXPECT_EQ(s.backend, b);
    const SolverWork w = s.work_of(b);
    EXPECT_GE(w.minimizations, 1);
    EXPECT_GT(w.iterations + w.evaluations, 0);
    // The backend's stage 0 ran first; the exact solver finished from its answer.
    ASSERT_FALSE(s.history.empty());
    EXPECT_EQ(s.history.front().solver, b);
    EXPECT_EQ(s.history.front().stage, 0);
    EXPECT_LT(u_distance(s, def.sol), 1e-8);
    const nlohmann::json rep = make_report(r.md, s, r.opt);
    EXPECT_EQ(rep["backend"]["requested"], b);
    EXPECT_EQ(rep["backend"]["ran"], true);
    EXPECT_EQ(rep["backend"]["iterations"].get<long long>(), w.iterations);
    EXPECT_TRUE(rep["backend"]["not_run"].is_null());
  }
}

// Scenes whose inner problem is not strongly convex: the default runs Ipopt's ε-stage, then hands
// over — to the exact solver (minima-laminate) or, where the polish on Ipopt's statuses is already
// certified, to the polish (minima-softening); the report shows each phase and who did it.
TEST(DesignPath, NotStronglyConvexSceneRunsTheBackendThenHandsOver) {
  if (!has_backend("ipopt")) GTEST_SKIP() << "Ipopt not compiled in";
  for (const auto& [file, by] : std::vector<std::pair<std::string, std::string>>{
           {"minima-laminate.json", "ipopt+exact"}, {"minima-softening.json", "ipopt+polish"}}) {
    SCOPED_TRACE(file);
    const DesignRun r = design_solve(file, {"check.smallness=false"});
    const Solution& s = r.sol;
    ASSERT_TRUE(s.inner_convexity.checked);
    ASSERT_FALSE(s.inner_convexity.strongly_convex);
    ASSERT_TRUE(s.ok()) << s.message;
    EXPECT_EQ(s.backend, "ipopt");
    EXPECT_TRUE(s.backend_use.ran);
    EXPECT_GT(s.work_of("ipopt").iterations, 0);
    EXPECT_EQ(s.solved_by(), by);
    // The exact solver's inner solves are not the backend's: the two counts partition the history.
    EXPECT_EQ(s.work_of("ipopt").minimizations + s.work_of(EXACT_SOLVER).minimizations,
              static_cast<int>(s.history.size()));
    const std::string summary = summary_table(r.md, s);
    EXPECT_NE(summary.find("ipopt (solver.backend = auto): 1 minimization"), std::string::npos) << summary;
    const nlohmann::json rep = make_report(r.md, s, r.opt);
    EXPECT_EQ(rep["phases"][0]["ran"], true);
    if (by == "ipopt+exact") {
      EXPECT_TRUE(s.handover.used);
      EXPECT_EQ(s.handover.after_stage, 0);
      EXPECT_NE(summary.find("exact solver  took over after stage 0"), std::string::npos) << summary;
      EXPECT_EQ(rep["phases"][1]["ran"], true);
    } else {
      EXPECT_TRUE(s.polish.accepted);
      EXPECT_NE(summary.find("polish        accepted"), std::string::npos) << summary;
    }
  }
}

// solver.exact.start = always keeps the exact solver's own path as an explicit choice: no backend
// stage, and the report says which key decided it.
TEST(DesignPath, ExactStartAlwaysIsAnExplicitChoice) {
  const DesignRun r = design_solve("minima-softening.json", {"check.smallness=false", "solver.exact.start=\"always\""});
  ASSERT_TRUE(r.sol.ok()) << r.sol.message;
  EXPECT_FALSE(r.sol.backend_use.ran);
  EXPECT_NE(r.sol.backend_use.not_run.find("solver.exact.start = always"), std::string::npos)
      << r.sol.backend_use.not_run;
  EXPECT_EQ(r.sol.solved_by(), "exact");
}

// A scene whose Γ3 nodes all end separated (the load lifts the body off the layer): Γ3 carries no
// traction, the answer is the linear elastic one, and the polish is skipped with its reason.
TEST(DesignPath, AllSeparatedSkipsThePolish) {
  const DesignRun r = design_solve("sofonea2017-fig2.json",
                                   {"mesh.n=8", "solver.backend=\"newton\"", "loads.body_force=[0,500]",
                                    "boundary.gamma2=[]", "solver.exact.enabled=false"});
  const Solution& s = r.sol;
  ASSERT_TRUE(s.ok()) << s.message;
  for (const auto& st : s.status) ASSERT_EQ(st.normal, NormalStatus::SEPARATED);
  EXPECT_FALSE(s.polish.attempted);
  bool said = false;
  for (const auto& k : s.skipped) said = said || k.rfind("polish: every gamma3 node is separated", 0) == 0;
  EXPECT_TRUE(said);
}

// Backend names as users write them: NLopt's algorithms case-insensitive, with or without the family
// prefix; the backend's name (and so every report) is NLopt's canonical spelling; a template such as
// "+LOCAL" is not listed as a name; auto is listed first.
TEST(BackendNames, NloptAliasesAndCaseResolveToOneCanonicalName) {
  if (!has_backend("nlopt:LD_MMA")) GTEST_SKIP() << "NLopt not compiled in";
  for (const auto& [asked, canonical] : std::vector<std::pair<std::string, std::string>>{
           {"nlopt:mma", "nlopt:LD_MMA"},
           {"NLOPT:ld_mma", "nlopt:LD_MMA"},
           {"nlopt:ccsaq", "nlopt:LD_CCSAQ"},
           {"nlopt:slsqp", "nlopt:LD_SLSQP"},
           {"nlopt:lbfgs", "nlopt:LD_LBFGS"},
           {"nlopt:mlsl_lds+mma", "nlopt:G_MLSL_LDS+LD_MMA"},
           {"IPOPT", "ipopt"}}) {
    SCOPED_TRACE(asked);
    if (canonical == "ipopt" && !has_backend("ipopt")) continue;
    EXPECT_EQ(make_backend(asked)->name(), canonical);
  }
  const auto list = available_backends();
  ASSERT_FALSE(list.empty());
  EXPECT_EQ(list.front().first, "auto");
  for (const auto& [name, doc] : list) EXPECT_EQ(name.find("LOCAL"), std::string::npos) << name;
  bool alias_shown = false;
  for (const auto& [name, doc] : list) alias_shown = alias_shown || (name == "nlopt:LD_MMA" && doc.find("nlopt:mma") != std::string::npos);
  EXPECT_TRUE(alias_shown);
}
