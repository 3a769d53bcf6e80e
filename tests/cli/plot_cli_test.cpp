// `hemicontact solve ... --plot`: the Fig. 2 picture (scripts/plot_fig2.py) is drawn next to the
// results; without python3/matplotlib the solve still succeeds and warns.
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

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using PlotOutcome = hemicontact::test::CliOutcome;
using hemicontact::test::lines_of;
using hemicontact::test::matplotlib_available;
using hemicontact::test::slurp;

class PlotCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() /
          ("hemicontact_plot_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ifstream in(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json");
    json s = json::parse(in);
    s["mesh"]["n"] = 8;  // small: 9 Γ3 nodes
    scene = (dir / "fig2.json").string();
    std::ofstream(scene) << s.dump(2);
  }
  void TearDown() override { fs::remove_all(dir); }

  PlotOutcome cli(const std::string& args, const std::string& env = "") const {
    return hemicontact::test::run_cli(dir, args, env);
  }

  fs::path dir;
  std::string scene;
};

}  // namespace

TEST_F(PlotCli, SolvePlotWritesFig2) {
  if (!matplotlib_available()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  const fs::path out = dir / "res";
  const PlotOutcome r = cli("solve " + scene + " --quiet --plot --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(out / "fig2.png")) << r.out << r.err;
  EXPECT_GT(fs::file_size(out / "fig2.png"), 20000u);
  EXPECT_EQ(r.err.find("--plot"), std::string::npos) << r.err;
  // A given magnification is used; output.plot = true asks for the picture too.
  const PlotOutcome m =
      cli("solve " + scene + " --quiet --force --set output.plot=true --magnification 2 --out " + out.string());
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_TRUE(fs::exists(out / "fig2.png"));
}

TEST_F(PlotCli, BadMagnificationIsAUsageError) {
  const PlotOutcome r = cli("solve " + scene + " --plot --magnification -1 --out " + (dir / "res").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("--magnification"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "res" / "report.json"));
}

TEST_F(PlotCli, MissingPythonWarnsButTheSolveSucceeds) {
  const fs::path out = dir / "res";
  const PlotOutcome r = cli("solve " + scene + " --quiet --plot --out " + out.string(),
                            "HEMICONTACT_PYTHON=" + (dir / "no-python3").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "report.json"));
  EXPECT_FALSE(fs::exists(out / "fig2.png"));
  EXPECT_NE(r.err.find("matplotlib"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fig2.png"), std::string::npos) << r.err;
}

TEST_F(PlotCli, ScriptsAreFoundThroughHemicontactScripts) {
  const fs::path out = dir / "res";
  const PlotOutcome r = cli("solve " + scene + " --quiet --plot --out " + out.string(),
                            "HEMICONTACT_SCRIPTS=" + (dir / "nowhere").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("plot_fig2.py not found"), std::string::npos) << r.err;
}
