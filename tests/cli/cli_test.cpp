// The command-line program end to end: every bad input gets a one-line message naming the problem
// and a non-zero exit code; good runs write their files.
#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>

#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using CliRun = hemicontact::test::CliOutcome;
using hemicontact::test::lines_of;
using hemicontact::test::matplotlib_available;
using hemicontact::test::slurp;

// Runs the CLI with stdout/stderr captured in files of a per-test scratch directory.
class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir =
        fs::temp_directory_path() / ("hemicontact_cli_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  CliRun run(const std::string& args) const { return hemicontact::test::run_cli(dir, args); }

  // A small valid scene (the paper's, n = 4), as JSON to be modified by each test.
  static json scene() {
    std::ifstream in(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json");
    json s = json::parse(in);
    s["mesh"]["n"] = 4;
    return s;
  }

  std::string write(const json& s, const std::string& name = "scene.json") const {
    const fs::path p = dir / name;
    std::ofstream(p) << s.dump(2);
    return p.string();
  }

  fs::path dir;
};

// The error is one line on stderr ("hemicontact: error: ..."), containing @p what.
void expect_error(const CliRun& r, int code, const std::string& what) {
  EXPECT_EQ(r.code, code) << r.err;
  EXPECT_NE(r.err.find("hemicontact: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << "stderr: " << r.err;
  EXPECT_EQ(r.err.find("terminate"), std::string::npos) << "crashed: " << r.err;
}

}  // namespace

TEST_F(Cli, HelpBackendsAndUsage) {
  const CliRun h = run("--help");
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.out.find("hemicontact solve SCENE.json"), std::string::npos);
  const CliRun b = run("backends");
  EXPECT_EQ(b.code, 0);
#if HEMICONTACT_HAS_IPOPT
  EXPECT_NE(b.out.find("ipopt"), std::string::npos);
#endif
  expect_error(run("frobnicate"), hemicontact::EXIT_USAGE, "unknown command 'frobnicate'");
  expect_error(run("solve"), hemicontact::EXIT_USAGE, "missing SCENE.json");
  expect_error(run("solve x.json --bogus"), hemicontact::EXIT_USAGE, "unknown option --bogus");
}

// Every command answers -h and --help with its own help on stdout (usage, options with their
// defaults, an example) and exit 0, wherever the flag stands; a value that reads "-h" is a value.
TEST_F(Cli, EveryCommandHasHelp) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> commands = {
      {"solve", {"usage: hemicontact solve SCENE.json", "--set path=value", "--plot", "--magnification", "example:"}},
      {"converge", {"usage: hemicontact converge", "default 4,8,...,128", "default 256", "example:"}},
      {"minima", {"usage: hemicontact minima", "default 8", "default 1e-6", "default 10", "example:"}},
      {"backends", {"usage: hemicontact backends", "example:"}}};
  for (const auto& [cmd, parts] : commands)
    for (const std::string flag : {"-h", "--help"}) {
      SCOPED_TRACE(cmd + " " + flag);
      const CliRun r = run(cmd + " " + flag);
      EXPECT_EQ(r.code, 0) << r.err;
      EXPECT_TRUE(r.err.empty()) << r.err;
      for (const auto& p : parts) EXPECT_NE(r.out.find(p), std::string::npos) << p << "\n" << r.out;
    }
  const CliRun after = run("solve x.json --quiet --help");
  EXPECT_EQ(after.code, 0);
  EXPECT_NE(after.out.find("usage: hemicontact solve"), std::string::npos);
  // --out -h names a folder called "-h": not help, so the missing scene is the error.
  expect_error(run("solve missing.json --out -h"), hemicontact::EXIT_INPUT, "missing.json");
  const CliRun overview = run("--help");
  EXPECT_NE(overview.out.find("hemicontact COMMAND --help"), std::string::npos);
}

// --force replaces the previous result set as a whole: an n = 8 run without VTU after one with it
// leaves no stale solution.vtu, keeps the user's notes.txt, and report.json lists the new set.
TEST_F(Cli, ForceReplacesThePreviousResultSet) {
  const std::string out = (dir / "res").string();
  const std::string scene_file = write(scene());
  ASSERT_EQ(run("solve " + scene_file + " --out " + out + " --quiet").code, 0);
  ASSERT_TRUE(fs::exists(fs::path(out) / "solution.vtu"));
  std::ofstream(fs::path(out) / "notes.txt") << "mine\n";
  const CliRun again = run("solve " + scene_file + " --out " + out + " --quiet");
  EXPECT_EQ(again.code, hemicontact::EXIT_INPUT);
  EXPECT_NE(again.err.find("already holds results"), std::string::npos) << again.err;
  const CliRun r = run("solve " + scene_file + " --out " + out + " --quiet --force --set output.vtu=false");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(fs::path(out) / "solution.vtu"));
  EXPECT_EQ(slurp(fs::path(out) / "notes.txt"), "mine\n");
  const json rep = json::parse(slurp(fs::path(out) / "report.json"));
  EXPECT_EQ(rep["files"], json({"gamma3.csv", "report.json"}));
}

// A folder holding the user's own gamma3.csv and solution.vtu but no report.json
// used to have both overwritten without --force; now the run is refused before any work, and
// --force does not change that (it replaces only files the tool wrote).
TEST_F(Cli, UsersFilesInTheOutputFolderAreNeverOverwritten) {
  const fs::path out = dir / "mine";
  fs::create_directories(out);
  std::ofstream(out / "gamma3.csv") << "my table\n";
  std::ofstream(out / "solution.vtu") << "my mesh\n";
  for (const std::string force : {"", " --force"}) {
    const CliRun r = run("solve " + write(scene()) + " --out " + out.string() + " --quiet" + force);
    expect_error(r, hemicontact::EXIT_INPUT, "exists and was not written by hemicontact");
    EXPECT_EQ(slurp(out / "gamma3.csv"), "my table\n");
    EXPECT_EQ(slurp(out / "solution.vtu"), "my mesh\n");
    EXPECT_FALSE(fs::exists(out / "report.json"));
  }
}

TEST_F(Cli, SolveWritesResults) {
  const std::string out = (dir / "res").string();
  const CliRun r = run("solve " + write(scene()) + " --out " + out + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("certificate"), std::string::npos);
  for (const char* f : {"report.json", "solution.vtu", "gamma3.csv"}) EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  const json rep = json::parse(slurp(fs::path(out) / "report.json"));
  for (const char* k : {"energy", "energy_norm", "status_counts", "nodes", "certificate", "timings", "scene"})
    EXPECT_TRUE(rep.contains(k)) << k;
  EXPECT_EQ(rep["scene"]["mesh"]["nx"], 4);  // the effective scene is echoed
  EXPECT_TRUE(rep["ok"].get<bool>());
  // Results are not overwritten without asking...
  const CliRun again = run("solve " + write(scene()) + " --out " + out + " --quiet");
  expect_error(again, hemicontact::EXIT_INPUT, "--force");
  // ...and are with --force; --set and --backend reach the scene.
  const CliRun forced = run("solve " + write(scene()) + " --out " + out + " --quiet --force --set mesh.n=6");
  ASSERT_EQ(forced.code, 0) << forced.err;
  EXPECT_EQ(json::parse(slurp(fs::path(out) / "report.json"))["scene"]["mesh"]["nx"], 6);
}

TEST_F(Cli, MissingAndMalformedSceneFiles) {
  expect_error(run("solve " + (dir / "nope.json").string()), hemicontact::EXIT_INPUT, "not found");
  std::ofstream(dir / "bad.json") << "{ \"mesh\": { \"n\": 4, }\n";
  expect_error(run("solve " + (dir / "bad.json").string()), hemicontact::EXIT_INPUT, "line 1");
}

TEST_F(Cli, UnknownKeyWrongTypeAndBadOverride) {
  json s = scene();
  s["mesh"]["nn"] = 4;
  expect_error(run("solve " + write(s)), hemicontact::EXIT_INPUT, "mesh.nn");
  s = scene();
  s["mesh"]["n"] = "four";
  expect_error(run("solve " + write(s)), hemicontact::EXIT_INPUT, "mesh.n");
  expect_error(run("solve " + write(scene()) + " --set mesh.nope=3"), hemicontact::EXIT_INPUT, "mesh.nope");
  expect_error(run("solve " + write(scene()) + " --set meshn"), hemicontact::EXIT_INPUT, "meshn");
}

TEST_F(Cli, MeshWithoutGamma1) {
  json s = scene();
  s["boundary"]["gamma1"] = json::array();
  expect_error(run("solve " + write(s)), hemicontact::EXIT_INPUT, "Γ1");
}

TEST_F(Cli, Gamma3ThatIsNotABoundary) {
#if HEMICONTACT_HAS_GMSH
  json s = scene();
  s["mesh"] = {{"type", "gmsh"}, {"file", HEMICONTACT_SOURCE_DIR "/tests/data/unit_square_3x3_interior_contact.msh"}};
  s["boundary"] = {{"gamma1", {{{"physical", "clamped"}}}}, {"gamma3", {{{"physical", "contact"}}}}};
  expect_error(run("solve " + write(s)), hemicontact::EXIT_INPUT, "not on the boundary");
  // The same file's good sibling solves.
  s["mesh"]["file"] = HEMICONTACT_SOURCE_DIR "/tests/data/unit_square_3x3.msh";
  const CliRun ok = run("solve " + write(s) + " --out " + (dir / "g").string() + " --quiet");
  EXPECT_EQ(ok.code, 0) << ok.err;
#else
  GTEST_SKIP() << "built without Gmsh";
#endif
}

TEST_F(Cli, SelectorThatSelectsNothing) {
  json s = scene();
  s["boundary"]["gamma3"] = {{{"side", "bottom"}, {"from", 2.0}, {"to", 3.0}}};
  expect_error(run("solve " + write(s)), hemicontact::EXIT_INPUT, "boundary.gamma3[0]");
}

TEST_F(Cli, NegativeThickness) {
  json s = scene();
  s["contact"]["gap"] = -0.1;
  expect_error(run("solve " + write(s)), hemicontact::EXIT_INPUT, "negative thickness");
  s["contact"]["gap"] = {{"along", "x"}, {"points", {{0.0, 0.1}, {1.0, -0.2}}}};
  expect_error(run("solve " + write(s)), hemicontact::EXIT_INPUT, "negative thickness");
}

TEST_F(Cli, PoissonRatioInPlaneStrain) {
  json s = scene();
  s["material"]["plane"] = "strain";
  s["material"]["nu"] = 0.5;
  expect_error(run("solve " + write(s)), hemicontact::EXIT_INPUT, "material.nu");
}

TEST_F(Cli, OutputDirThatIsAFile) {
  std::ofstream(dir / "afile") << "x";
  expect_error(run("solve " + write(scene()) + " --out " + (dir / "afile").string()), hemicontact::EXIT_INPUT,
               "not a directory");
}

TEST_F(Cli, UnknownBackend) {
  expect_error(run("solve " + write(scene()) + " --backend nope"), hemicontact::EXIT_INPUT, "nope");
}

TEST_F(Cli, NonConvergenceIsLoud) {
  // One Ipopt iteration cannot solve the contact problem: exit 3 and a warning, unless allowed.
  // The continuation's own exit (solver.exact.enabled = false: with the exact inner solver behind
  // it, a stalled backend hands over instead, see NonConvergenceOfTheExactSolverIsLoud). Without
  // the polish: its active-set rounds can turn even such a rough iterate into a certified answer,
  // which is then rightly accepted.
  json s = scene();
  s["solver"] = {{"max_iter", 1}, {"polish", false}, {"exact", {{"enabled", false}}}};
  const CliRun r = run("solve " + write(s) + " --out " + (dir / "nc").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_NOT_CONVERGED) << r.err;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  const json rep = json::parse(slurp(dir / "nc" / "report.json"));
  EXPECT_FALSE(rep["ok"].get<bool>());
}

TEST_F(Cli, NonConvergenceOfTheExactSolverIsLoud) {
  // The default path (the exact inner solver takes over after stage 0 or a stall) has its own ways
  // to fail, and they are as loud. One Ipopt iteration stalls stage 0 far from the answer (λ frozen
  // at F_b of a rough u_ν), the exact solver takes over, and with one outer iteration allowed
  // (solver.fixed_point.max_iters = 1) its λ = F_b(u_ν) has moved by O(1) relative: the fixed
  // point did not converge. Exit 3, a warning, ok = false in report.json, the hand-over recorded
  // there. Without the polish, whose own λ iteration would otherwise certify the answer (rightly).
  json s = scene();
  s["solver"] = {{"max_iter", 1}, {"polish", false}, {"fixed_point", {{"max_iters", 1}}}};
  const CliRun r = run("solve " + write(s) + " --out " + (dir / "nc").string());
  EXPECT_EQ(r.code, hemicontact::EXIT_NOT_CONVERGED) << r.err;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("exact solver"), std::string::npos) << r.err;
  const json rep = json::parse(slurp(dir / "nc" / "report.json"));
  EXPECT_FALSE(rep["ok"].get<bool>());
  EXPECT_TRUE(rep["inner"]["handover"]["used"].get<bool>()) << rep["inner"].dump();
}
