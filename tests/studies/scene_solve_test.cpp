// The one "scene → solve → files" sequence (studies/scene_solve.hpp) that the CLI and the Python
// module run: it must be exactly build_model + the engine, write
// the solve's files with report.json last, run the adaptive loop where the scene asks (handing each
// certified level on), refuse adaptivity where the engine is not the cholmod one, and turn a
// solution into the documented exit code.
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/solve_files.hpp>
#include <hemicontact/studies/minima.hpp>
#include <hemicontact/studies/scene_solve.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include "../support/expect_error.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace hemicontact {
namespace {

namespace fs = std::filesystem;

const std::string PROBLEMS = std::string(HEMICONTACT_SOURCE_DIR) + "/problems";

// fig2 at n = 8 with the newton backend (built in every configuration).
nlohmann::json fig2(std::vector<std::string> extra = {}) {
  extra.insert(extra.begin(), {"mesh.n=8", "solver.backend=\"newton\""});
  return load_scene(PROBLEMS + "/sofonea2017-fig2.json", extra);
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream f(p);
  return nlohmann::json::parse(f);
}

TEST(SceneSolve, OneSolveIsBuildModelThenTheEngine) {
  const nlohmann::json scene = fig2();
  const SceneSolve r = solve_scene(scene, PROBLEMS);
  const Model md = build_model(scene, PROBLEMS);
  const Solution direct = solve(md, solve_options_from_scene(scene));
  EXPECT_EQ(r.solution.energy, direct.energy);  // the same deterministic computation
  EXPECT_EQ(r.solution.certificate.max_residual, direct.certificate.max_residual);
  EXPECT_TRUE(r.solution.certificate.passed);
  EXPECT_GT(r.solution.timings.at("wall_total"), 0.0);
  EXPECT_FALSE(r.adapt.has_value());
  EXPECT_TRUE(r.adapt_levels_file.is_null());
  EXPECT_EQ(solve_exit_code(r), EXIT_OK);
  // The engine is the caller's: solve_scene_with hands it the built model and the scene's options.
  int calls = 0;
  const SceneSolve w = solve_scene_with(scene, PROBLEMS, [&](const Model& m, const SolveOptions& o) {
    ++calls;
    EXPECT_EQ(m.contact.size(), md.contact.size());
    return solve(m, o);
  });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(w.solution.energy, direct.energy);
}

TEST(SceneSolve, WritesTheSolveFilesWithTheReportLast) {
  const SceneSolve r = solve_scene(fig2(), PROBLEMS);
  const fs::path dir = fs::temp_directory_path() / ("hemicontact_scene_solve_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  {
    const OutputLock lock = prepare_output_dir(dir.string(), false, solve_output_names());
    bool report_absent_before = false;
    write_scene_solve(dir.string(), r, scene_solve_report(r),
                      [&] { report_absent_before = !fs::exists(dir / "report.json"); });
    EXPECT_TRUE(report_absent_before);
  }
  const nlohmann::json rep = read_json(dir / "report.json");
  EXPECT_EQ(rep.at("energy").get<double>(), r.solution.energy);
  EXPECT_TRUE(fs::exists(dir / "solution.vtu"));
  EXPECT_TRUE(fs::exists(dir / "gamma3.csv"));
  EXPECT_FALSE(fs::exists(dir / ADAPT_LEVELS_FILE));  // not adaptive: no levels file
  fs::remove_all(dir);
}

TEST(SceneSolve, AdaptiveSceneRunsTheLoopAndHandsOnEachLevel) {
  const nlohmann::json scene = fig2({"adapt.target_error=0.05", "adapt.max_levels=4"});
  std::vector<size_t> seen;
  const SceneSolve r = solve_scene(scene, PROBLEMS, [&](const std::vector<AdaptLevel>& L) { seen.push_back(L.size()); });
  ASSERT_TRUE(r.adapt.has_value());
  ASSERT_FALSE(r.adapt_levels.empty());
  EXPECT_EQ(seen.size(), r.adapt_levels.size());  // every level handed on as it ended, in order
  for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], i + 1);
  EXPECT_EQ(r.adapt_levels_file.at("partial"), false);
  EXPECT_EQ(r.indicators->size(), r.model->mesh.num_cells());
  EXPECT_FALSE(r.stop_reason.empty());
  // Only the cholmod engine refines: another engine refuses the key rather than drop it.
  test::expect_input_error(
      [&] { (void)solve_scene_with(scene, PROBLEMS, [](const Model& m, const SolveOptions& o) { return solve(m, o); }); },
      {"adapt.target_error", "cholmod"});
}

// Where other certified solutions may exist, a plain solve says which kind the one found is (the
// second-order check of `minima`, on the same solution): in the warning, the summary and
// report.json; where uniqueness holds, nothing is checked.
TEST(SceneSolve, APlainSolveNamesTheKindOfSolutionItFoundWhereOthersMayExist) {
  for (const char* name : {"minima-softening", "minima-one-node"}) {
    const SceneSolve r = solve_scene(load_scene(PROBLEMS + "/" + name + ".json"), PROBLEMS);
    const SecondOrderCheck& c = r.solution.second_order;
    ASSERT_TRUE(c.verdict == "local minimum" || c.verdict == "saddle") << name << ": " << c.verdict << " " << c.note;
    if (c.verdict == "saddle")
      EXPECT_LT(c.lambda_min, 0.0) << name;
    else
      EXPECT_GE(c.lambda_min, -MinimaOptions{}.second_order_tol * c.scale) << name;
    const std::string w = uniqueness_warning(r.solution);
    EXPECT_NE(w.find("the solution found is a " + c.verdict), std::string::npos) << w;
    const nlohmann::json rep = scene_solve_report(r);
    EXPECT_EQ(rep.at("uniqueness").at("second_order").at("verdict"), c.verdict);
  }
  const SceneSolve paper = solve_scene(fig2(), PROBLEMS);
  EXPECT_EQ(paper.solution.second_order.verdict, "unchecked");
}

TEST(SceneSolve, ExitCodeIsTheCertificatesVerdict) {
  const SceneSolve r = solve_scene(fig2(), PROBLEMS);
  ASSERT_EQ(solve_exit_code(r), EXIT_OK);
  Solution s = r.solution;
  s.certificate.passed = false;
  EXPECT_EQ(solve_exit_code(s, r.opt), EXIT_CERTIFICATE);
  s.backend_ok = false;  // the backend said so too: not converged
  EXPECT_EQ(solve_exit_code(s, r.opt), EXIT_NOT_CONVERGED);
  s = r.solution;
  s.fixed_point_converged = false;
  EXPECT_EQ(solve_exit_code(s, r.opt), EXIT_NOT_CONVERGED);
  SolveOptions lenient = r.opt;
  lenient.allow_not_converged = true;  // accepted only because the certificate passed
  EXPECT_EQ(solve_exit_code(s, lenient), EXIT_OK);
  EXPECT_EQ(solve_exit_code(r.solution, r.opt, "adapt: max_levels stopped the loop above the target"),
            EXIT_NOT_CONVERGED);
}

}  // namespace
}  // namespace hemicontact
