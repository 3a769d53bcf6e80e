// `hemicontact converge` end to end: the CSV/JSON files and the table of a small study, bad
// level lists, refusal to overwrite, and --plot without matplotlib (the CSV is still written).
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

using ConvergeOutcome = hemicontact::test::CliOutcome;
using hemicontact::test::lines_of;
using hemicontact::test::matplotlib_available;
using hemicontact::test::slurp;

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> r;
  std::stringstream ss(s);
  for (std::string t; std::getline(ss, t, sep);) r.push_back(t);
  if (!s.empty() && s.back() == sep) r.emplace_back();
  return r;
}

// Runs the CLI with stdout/stderr captured in files of a per-test scratch directory.
class ConvergeCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() /
          ("hemicontact_converge_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ifstream in(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json");
    scene = (dir / "fig2.json").string();
    std::ofstream(scene) << json::parse(in).dump(2);
  }
  void TearDown() override { fs::remove_all(dir); }

  ConvergeOutcome cli(const std::string& args, const std::string& env = "") const {
    return hemicontact::test::run_cli(dir, args, env);
  }

  fs::path dir;
  std::string scene;
};

}  // namespace

TEST_F(ConvergeCli, WritesCsvJsonAndTable) {
  const fs::path out = dir / "conv";
  const ConvergeOutcome r =
      cli("converge " + scene + " --levels 4,8 --reference 16 --out " + out.string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  // CSV: a header and one row per level, coarse to fine; errors decrease; the first order is empty.
  const auto rows = lines_of(slurp(out / "convergence.csv"));
  ASSERT_EQ(rows.size(), 3u) << slurp(out / "convergence.csv");
  const auto head = split(rows[0], ',');
  ASSERT_GE(head.size(), 8u);
  EXPECT_EQ(head[0], "n");
  EXPECT_EQ(head[5], "error");
  EXPECT_EQ(head[6], "order");
  EXPECT_EQ(head.back(), "ok");
  const auto r4 = split(rows[1], ','), r8 = split(rows[2], ',');
  ASSERT_EQ(r4.size(), head.size());
  ASSERT_EQ(r8.size(), head.size());
  EXPECT_EQ(r4[0], "4");
  EXPECT_EQ(r8[0], "8");
  EXPECT_DOUBLE_EQ(std::stod(r4[1]), 0.25);
  EXPECT_GT(std::stod(r4[5]), std::stod(r8[5]));
  EXPECT_GT(std::stod(r8[5]), 0.0);
  EXPECT_EQ(r4[6], "");
  EXPECT_GT(std::stod(r8[6]), 0.0);
  EXPECT_EQ(r4.back(), "1");
  // One VTU per level (the reference too) and a collection that steps through them, coarse first.
  EXPECT_EQ(hemicontact::test::pvd_files(out / "convergence.pvd"),
            (std::vector<std::string>{"level_4.vtu", "level_8.vtu", "level_16.vtu"}));
  for (const auto& f : hemicontact::test::pvd_files(out / "convergence.pvd")) EXPECT_TRUE(fs::exists(out / f)) << f;
  // JSON: the same levels, the reference and the verdict.
  const json js = json::parse(slurp(out / "convergence.json"));
  EXPECT_EQ(js["reference"]["n"], 16);
  EXPECT_EQ(js["levels"].size(), 2u);
  EXPECT_EQ(js["name"], "fig2");
  EXPECT_TRUE(js["ok"].get<bool>());
  // stdout: the table with the reference row.
  EXPECT_NE(r.out.find("(reference)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rel.error"), std::string::npos) << r.out;
  // No overwrite without --force.
  const ConvergeOutcome again =
      cli("converge " + scene + " --levels 4,8 --reference 16 --out " + out.string() + " --quiet");
  EXPECT_EQ(again.code, hemicontact::EXIT_INPUT);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
}

TEST_F(ConvergeCli, BadLevelsAreRejectedWithAMessage) {
  const std::string out = " --out " + (dir / "bad").string();
  struct Case {
    std::string args;
    int code;
    std::string what;
  };
  for (const Case& c : std::vector<Case>{
           {"--levels 4,abc --reference 16", hemicontact::EXIT_USAGE, "--levels"},
           {"--levels 4,...,16 --reference 16", hemicontact::EXIT_USAGE, "'...'"},
           {"--levels 4,6 --reference 16", hemicontact::EXIT_INPUT, "level(s) 6 do not divide the reference level 16"},
           {"--levels 4,8 --reference 0", hemicontact::EXIT_USAGE, "--reference"},
           {"--levels 4,8 --reference 16,32", hemicontact::EXIT_USAGE, "--reference"},
           {"--levels", hemicontact::EXIT_USAGE, "--levels needs a value"},
       }) {
    SCOPED_TRACE(c.args);
    const ConvergeOutcome r = cli("converge " + scene + out + " " + c.args);
    EXPECT_EQ(r.code, c.code) << r.err;
    EXPECT_NE(r.err.find(c.what), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad" / "convergence.csv"));
  }
}

TEST_F(ConvergeCli, PlotWithoutMatplotlibStillWritesTheCsv) {
  // A python3 that does not exist stands for a machine without python3-matplotlib.
  const fs::path out = dir / "noplot";
  const ConvergeOutcome r = cli("converge " + scene + " --levels 4 --reference 8 --quiet --plot --out " + out.string(),
                                "HEMICONTACT_PYTHON=" + (dir / "no-python3").string());
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("matplotlib"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "convergence.csv"));
  EXPECT_FALSE(fs::exists(out / "convergence.png"));
}

TEST_F(ConvergeCli, PlotDrawsTheFigure) {
  if (!matplotlib_available()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  const fs::path out = dir / "plot";
  const ConvergeOutcome r =
      cli("converge " + scene + " --levels 4,8 --reference 16 --quiet --plot --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(out / "convergence.png")) << r.out << r.err;
  EXPECT_GT(fs::file_size(out / "convergence.png"), 10000u);
}
