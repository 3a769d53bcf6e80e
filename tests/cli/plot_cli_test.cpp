// `hemicontact solve ... --plot`: the Fig. 2 picture (scripts/plot_fig2.py) is drawn next to the
// results; without python3/matplotlib the solve still succeeds and warns.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

struct PlotOutcome {
  int code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool matplotlib_available() { return std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") == 0; }

class PlotCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() / ("hemicontact_plot_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
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
    const std::string cmd = env + " " + std::string(HEMICONTACT_CLI_PATH) + " " + args + " >" +
                            (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string();
    const int status = std::system(cmd.c_str());
    PlotOutcome r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir / "out.txt");
    r.err = slurp(dir / "err.txt");
    return r;
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
  const PlotOutcome m = cli("solve " + scene + " --quiet --force --set output.plot=true --magnification 2 --out " +
                            out.string());
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
  const PlotOutcome r =
      cli("solve " + scene + " --quiet --plot --out " + out.string(), "HEMICONTACT_PYTHON=" + (dir / "no-python3").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "report.json"));
  EXPECT_FALSE(fs::exists(out / "fig2.png"));
  EXPECT_NE(r.err.find("matplotlib"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fig2.png"), std::string::npos) << r.err;
}

TEST_F(PlotCli, ScriptsAreFoundThroughHemicontactScripts) {
  const fs::path out = dir / "res";
  const PlotOutcome r =
      cli("solve " + scene + " --quiet --plot --out " + out.string(), "HEMICONTACT_SCRIPTS=" + (dir / "nowhere").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("plot_fig2.py not found"), std::string::npos) << r.err;
}
