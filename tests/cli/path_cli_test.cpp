// `hemicontact path` end to end on the one-cell scene: the summary, CSV, JSON, one VTU per state
// with the PVD, the picture; --help; bad options; refusal to overwrite; a linear scene refused.
#include <hemicontact/core/error.hpp>

#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using hemicontact::test::CliOutcome;
using hemicontact::test::lines_of;
using hemicontact::test::slurp;

class PathCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() /
          ("hemicontact_path_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    scene = std::string(HEMICONTACT_SOURCE_DIR) + "/problems/minima-one-node.json";
  }
  void TearDown() override { fs::remove_all(dir); }
  CliOutcome cli(const std::string& args, const std::string& env = "") const {
    return hemicontact::test::run_cli(dir, args, env);
  }
  fs::path dir;
  std::string scene;
};

TEST_F(PathCli, WritesCsvJsonVtusAndPicture) {
  const fs::path out = dir / "p";
  const CliOutcome r = cli("path " + scene + " --load 0,2,0 --steps 10 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 jump(s)"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("path: state 0 (start)"), std::string::npos) << "progress on stderr";
  const json js = json::parse(slurp(out / "path.json"));
  EXPECT_TRUE(js["complete"].get<bool>());
  const size_t n = js["states"].size();
  EXPECT_EQ(js["certified_states"].get<size_t>(), n);
  ASSERT_EQ(js["jumps"].size(), 2u);
  EXPECT_EQ(js["jumps"][0]["direction"], "loading");
  EXPECT_EQ(js["jumps"][1]["direction"], "unloading");
  EXPECT_FALSE(js["jumps"][0]["switched"].empty());
  const auto rows = lines_of(slurp(out / "path.csv"));
  ASSERT_EQ(rows.size(), n + 1);
  EXPECT_EQ(rows[0].rfind("k,segment,kind,load,energy,reaction,mean_u_nu,max_u_nu,certificate,certified,type", 0), 0u);
  std::vector<std::string> vtus;
  for (size_t k = 0; k < n; ++k) vtus.push_back("state_" + std::to_string(k) + ".vtu");
  EXPECT_EQ(hemicontact::test::pvd_files(out / "path.pvd"), vtus);
  if (hemicontact::test::matplotlib_available()) {
    EXPECT_TRUE(fs::exists(out / "path.png")) << r.err;
  }
  const CliOutcome again = cli("path " + scene + " --load 0,1 --steps 2 --out " + out.string() + " --quiet");
  EXPECT_EQ(again.code, hemicontact::EXIT_INPUT);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  EXPECT_EQ(cli("path " + scene + " --load 0,1 --steps 2 --out " + out.string() + " --quiet --force").code, 0);
  EXPECT_FALSE(fs::exists(out / ("state_" + std::to_string(n - 1) + ".vtu"))) << "--force removed the old states";
}

TEST_F(PathCli, HelpAndBadOptions) {
  const CliOutcome help = cli("path --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--bisection-tol"), std::string::npos) << help.out;
  struct Case {
    std::string args;
    int code;
    std::string what;
  };
  const std::string out = " --out " + (dir / "bad").string();
  std::ofstream(dir / "linear.json") << R"({"mesh": {"type": "rectangle", "n": 2}, "material": {"E": 1000, "nu": 0.3},
      "boundary": {"gamma1": [{"side": "top"}]}, "loads": {"body_force": [0, -1]}})";
  for (const Case& c : std::vector<Case>{
           {scene + " --load 1", hemicontact::EXIT_USAGE, "--load"},
           {scene + " --load 0,,2", hemicontact::EXIT_USAGE, "--load"},
           {scene + " --load 0,x", hemicontact::EXIT_USAGE, "--load"},
           {scene + " --load 0,1,", hemicontact::EXIT_USAGE, "--load"},
           {scene + " --load 0,0", hemicontact::EXIT_USAGE, "differ"},
           {scene + " --steps 0", hemicontact::EXIT_USAGE, "--steps"},
           {scene + " --bisection-tol -1", hemicontact::EXIT_USAGE, "--bisection-tol"},
           {(dir / "linear.json").string(), hemicontact::EXIT_INPUT, "condensed"},
       }) {
    SCOPED_TRACE(c.args);
    const CliOutcome r = cli("path " + c.args + out + " --quiet");
    EXPECT_EQ(r.code, c.code) << r.err;
    EXPECT_NE(r.err.find(c.what), std::string::npos) << r.err;
  }
}

}  // namespace
