// `hemicontact minima` end to end on the one-cell scene (c): the table, CSV, JSON, one VTU per
// distinct solution and the picture; --start files (an array of [u_nu, u_tau] and a report-like
// object with "nodes"); bad options; refusal to overwrite; a missing matplotlib is a warning only.
#include <hemicontact/core/error.hpp>

#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using MinimaOutcome = hemicontact::test::CliOutcome;
using hemicontact::test::lines_of;
using hemicontact::test::matplotlib_available;
using hemicontact::test::slurp;

class MinimaCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() /
          ("hemicontact_minima_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    scene = std::string(HEMICONTACT_SOURCE_DIR) + "/problems/minima-one-node.json";
  }
  void TearDown() override { fs::remove_all(dir); }

  MinimaOutcome cli(const std::string& args, const std::string& env = "") const {
    return hemicontact::test::run_cli(dir, args, env);
  }

  fs::path dir;
  std::string scene;
};

TEST_F(MinimaCli, WritesTableCsvJsonVtuAndPicture) {
  const fs::path out = dir / "m";
  const MinimaOutcome r = cli("minima " + scene + " --starts 8 --seed 1 --out " + out.string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("4 distinct solution(s), 4 local minima"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("uniqueness guaranteed: no"), std::string::npos) << r.out;
  // CSV: header + one row per distinct solution, lowest energy first.
  const auto rows = lines_of(slurp(out / "minima.csv"));
  ASSERT_EQ(rows.size(), 5u) << slurp(out / "minima.csv");
  EXPECT_EQ(rows[0].rfind("k,energy,energy_norm,type,lambda_min,certificate,n_starts,backends,starts", 0), 0u)
      << rows[0];
  for (size_t k = 1; k < rows.size(); ++k) EXPECT_NE(rows[k].find(",local minimum,"), std::string::npos) << rows[k];
  // JSON: the solutions with their Γ3 nodes, the runs, the smallness verdict.
  const json js = json::parse(slurp(out / "minima.json"));
  ASSERT_EQ(js["solutions"].size(), 4u);
  EXPECT_FALSE(js["smallness"]["uniqueness_guaranteed"].get<bool>());
  EXPECT_EQ(js["runs"].size(), 14u);  // zero, exact-from-zero, at-gap, separated, 8 random, load up, load down
  double prev = -1e300;
  for (const auto& s : js["solutions"]) {
    EXPECT_GE(s["energy"].get<double>(), prev);
    prev = s["energy"].get<double>();
    EXPECT_EQ(s["nodes"].size(), 2u);
    EXPECT_TRUE(s["certificate"]["passed"].get<bool>());
    EXPECT_EQ(s["type"], "local minimum");
  }
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(fs::exists(out / ("solution_" + std::to_string(k) + ".vtu"))) << k;
  EXPECT_FALSE(fs::exists(out / "solution_4.vtu"));
  EXPECT_EQ(hemicontact::test::pvd_files(out / "minima.pvd"),
            (std::vector<std::string>{"solution_0.vtu", "solution_1.vtu", "solution_2.vtu", "solution_3.vtu"}));
  if (matplotlib_available()) {
    EXPECT_TRUE(fs::exists(out / "minima.png")) << r.err;
  }
  // No overwrite without --force; with it, fine.
  const MinimaOutcome again = cli("minima " + scene + " --starts 0 --out " + out.string() + " --quiet");
  EXPECT_EQ(again.code, hemicontact::EXIT_INPUT);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  EXPECT_EQ(cli("minima " + scene + " --starts 0 --out " + out.string() + " --quiet --force").code, 0);
}

TEST_F(MinimaCli, StartFilesAndReportNodes) {
  // First run: no random starts, no load path; take its highest-energy solution's nodes as a start.
  const fs::path out1 = dir / "a";
  ASSERT_EQ(cli("minima " + scene + " --starts 0 --load-path-steps 0 --out " + out1.string() + " --quiet").code, 0);
  const json first = json::parse(slurp(out1 / "minima.json"));
  const json& last = first["solutions"].back();
  json pairs = json::array();
  for (const auto& n : last["nodes"]) pairs.push_back({n["u_nu"], n["u_tau"]});
  std::ofstream(dir / "pairs.json") << pairs.dump();
  std::ofstream(dir / "report.json") << json{{"nodes", last["nodes"]}}.dump();
  const fs::path out2 = dir / "b";
  const MinimaOutcome r =
      cli("minima " + scene + " --starts 0 --load-path-steps 0 --start " + (dir / "pairs.json").string() + " --start " +
          (dir / "report.json").string() + " --out " + out2.string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json js = json::parse(slurp(out2 / "minima.json"));
  int users = 0;
  for (const auto& run : js["runs"])
    if (run["start"].get<std::string>().rfind("user-", 0) == 0) {
      ++users;
      ASSERT_TRUE(run["certified"].get<bool>());
      EXPECT_NEAR(run["energy"].get<double>(), last["energy"].get<double>(),
                  1e-9 * std::abs(last["energy"].get<double>()));
    }
  EXPECT_EQ(users, 2);
}

TEST_F(MinimaCli, BadOptionsAndStarts) {
  const std::string out = " --out " + (dir / "bad").string();
  std::ofstream(dir / "short.json") << "[[0, 0]]";
  struct Case {
    std::string args;
    int code;
    std::string what;
  };
  for (const Case& c : std::vector<Case>{
           {"--starts -1", hemicontact::EXIT_USAGE, "--starts"},
           {"--starts x", hemicontact::EXIT_USAGE, "--starts"},
           {"--group-tol 0", hemicontact::EXIT_USAGE, "--group-tol"},
           {"--backends ,", hemicontact::EXIT_USAGE, "--backends"},
           {"--backends nosuch", hemicontact::EXIT_INPUT, "nosuch"},
           {"--start " + (dir / "short.json").string(), hemicontact::EXIT_INPUT, "Gamma3"},
           {"--start " + (dir / "missing.json").string(), hemicontact::EXIT_INPUT, "cannot read"},
       }) {
    SCOPED_TRACE(c.args);
    const MinimaOutcome r = cli("minima " + scene + " " + c.args + out + " --quiet");
    EXPECT_EQ(r.code, c.code) << r.err;
    EXPECT_NE(r.err.find(c.what), std::string::npos) << r.err;
  }
}

TEST_F(MinimaCli, MissingMatplotlibIsAWarningOnly) {
  const fs::path out = dir / "np";
  const MinimaOutcome r = cli("minima " + scene + " --starts 0 --load-path-steps 0 --out " + out.string() + " --quiet",
                              "HEMICONTACT_PYTHON=" + (dir / "no-python3").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "minima.csv"));
  EXPECT_TRUE(fs::exists(out / "solution_0.vtu"));
  EXPECT_FALSE(fs::exists(out / "minima.png"));
  EXPECT_NE(r.err.find("matplotlib"), std::string::npos) << r.err;
}

// A scene without Γ3 is linear elasticity: one solution and no Γ3 profile to draw. It used to end
// in a Python traceback that blamed a missing matplotlib; now it says why there is no picture.
TEST_F(MinimaCli, SceneWithoutGamma3DrawsNothingAndSaysWhy) {
  const fs::path file = dir / "no_gamma3.json";
  std::ofstream(file) << R"({"mesh": {"type": "rectangle", "n": 4}, "material": {"E": 1000, "nu": 0.3},
                             "boundary": {"gamma1": [{"side": "top"}]}, "loads": {"body_force": [0, -1]}})";
  const fs::path out = dir / "ng3";
  const MinimaOutcome r = cli("minima " + file.string() + " --starts 0 --load-path-steps 0 --out " + out.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "minima.csv"));
  EXPECT_FALSE(fs::exists(out / "minima.png"));
  EXPECT_NE(r.err.find("no Gamma3 nodes"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("Traceback"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("matplotlib"), std::string::npos) << r.err;
}

}  // namespace

namespace {

// --barriers and --until-complete end to end on the one-cell scene: the barrier table, the unseen
// estimate, barriers.csv, a saddle VTU per verified saddle; a law with downward jumps is refused
// before any solve.
TEST_F(MinimaCli, BarriersAndUnseenEstimate) {
  const fs::path out = dir / "b";
  const MinimaOutcome r =
      cli("minima " + scene + " --starts 8 --until-complete --max-starts 32 --barriers --out " + out.string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("barriers (string method"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Chao1 estimate"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--until-complete: fewer than one unseen solution estimated"), std::string::npos) << r.out;
  const json js = json::parse(slurp(out / "minima.json"));
  ASSERT_EQ(js["barriers"].size(), 3u);
  EXPECT_TRUE(js["barriers"][0]["from_a"]["verified"].get<bool>());
  EXPECT_TRUE(js["unseen"]["complete"].get<bool>());
  EXPECT_EQ(lines_of(slurp(out / "barriers.csv")).size(), 7u);  // header + two sides per pair
  EXPECT_TRUE(fs::exists(out / "saddle_0.vtu"));
  const std::string laminate = std::string(HEMICONTACT_SOURCE_DIR) + "/problems/minima-laminate.json";
  const MinimaOutcome refused = cli("minima " + laminate + " --barriers --out " + (dir / "l").string() + " --quiet");
  EXPECT_EQ(refused.code, hemicontact::EXIT_INPUT);
  EXPECT_NE(refused.err.find("jumps downward"), std::string::npos) << refused.err;
  const MinimaOutcome cap = cli("minima " + scene + " --starts 8 --until-complete --max-starts 4 --out " +
                                (dir / "c").string() + " --quiet");
  EXPECT_EQ(cap.code, hemicontact::EXIT_USAGE) << cap.err;
}

}  // namespace
