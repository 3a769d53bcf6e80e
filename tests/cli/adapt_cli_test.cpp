// `hemicontact solve SCENE --set adapt.target_error=…` end to end: report.json gets adapt.history
// and the final estimate, the VTU the cell field error_indicator; bad adapt keys exit 2 naming them.
#include <hemicontact/core/error.hpp>

#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using json = nlohmann::json;
using hemicontact::test::slurp;

namespace {

class AdaptCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() / ("hemicontact_adapt_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    scene = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json";
  }
  void TearDown() override { fs::remove_all(dir); }
  hemicontact::test::CliOutcome cli(const std::string& args) const { return hemicontact::test::run_cli(dir, args); }
  fs::path dir;
  std::string scene;
};

}  // namespace

TEST_F(AdaptCli, ReportCarriesTheHistoryAndVtuTheIndicators) {
  const fs::path out = dir / "a";
  const auto r = cli("solve " + scene + " --set mesh.n=8 --set adapt.target_error=0.1 --set check.smallness=false " +
                     "--set output.vtu_format='\"ascii\"' --out " + out.string() + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const json rep = json::parse(slurp(out / "report.json"));
  ASSERT_TRUE(rep.contains("adapt"));
  const json& a = rep.at("adapt");
  EXPECT_TRUE(a.at("reached").get<bool>());
  EXPECT_LE(a.at("final_estimate").get<double>(), 0.1);
  ASSERT_GE(a.at("history").size(), 2u);
  for (const json& L : a.at("history")) {
    EXPECT_TRUE(L.at("ok").get<bool>());
    EXPECT_LE(L.at("certificate").get<double>(), 1e-8);
    EXPECT_GT(L.at("dofs").get<long long>(), 0);
  }
  EXPECT_EQ(a.at("history").back().at("estimate"), a.at("final_estimate"));
  const std::string vtu = slurp(out / "solution.vtu");
  EXPECT_NE(vtu.find("Name=\"error_indicator\""), std::string::npos);
  EXPECT_NE(r.out.find("adapt:"), std::string::npos) << r.out;
}

TEST_F(AdaptCli, BadAdaptKeysNameTheKey) {
  for (const std::string bad : {"adapt.theta=0", "adapt.estimator='\"kelly\"'", "adapt.target_error=2",
                                 "adapt.bisection='\"red\"'", "mesh.grading.power=0.5"}) {
    const auto r = cli("solve " + scene + " --set mesh.n=4 --set adapt.target_error=0.1 --set " + bad + " --out " +
                       (dir / "b").string() + " --quiet");
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find(bad.substr(0, bad.find('='))), std::string::npos) << r.err;
  }
}

// The 3D scene end to end: the adaptive solve (cholmod engine: auto sends adaptive scenes there)
// reports the estimate and, from the scene's adapt.reference_energy, the error per level and at the
// end; converge --adaptive runs the uniform and adaptive families on boxes (no graded family).
TEST_F(AdaptCli, ThreeDimensionalSceneReportsTheReferenceError) {
  const std::string scene3d = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json";
  const fs::path out = dir / "s";
  auto r = cli("solve " + scene3d + " --set mesh.n=4 --set adapt.target_error=0.3 --set check.smallness=false --out " +
               out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const json a = json::parse(slurp(out / "report.json")).at("adapt");
  EXPECT_TRUE(a.at("reached").get<bool>());
  EXPECT_EQ(a.at("history").back().at("reference_error"), a.at("final_reference_error"));
  EXPECT_GT(a.at("final_reference_error").get<double>(), 0);
  EXPECT_NE(r.out.find("error against the reference energy"), std::string::npos) << r.out;
  EXPECT_EQ(json::parse(slurp(out / "report.json")).at("engine_choice").at("engine"), "cholmod");
  const fs::path conv = dir / "c";
  r = cli("converge " + scene3d + " --adaptive --set mesh.n=2 --levels 2,4 --reference adaptive:0.2 " +
          "--set adapt.target_error=0.3 --quiet --out " + conv.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const json wp = json::parse(slurp(conv / "work_precision.json"));
  int uniform = 0, adaptive = 0, graded = 0;
  for (const json& p : wp.at("points")) {
    uniform += p.at("family") == "uniform";
    adaptive += p.at("family") == "adaptive";
    graded += p.at("family") == "graded";
  }
  EXPECT_EQ(uniform, 2);
  EXPECT_GE(adaptive, 1);
  EXPECT_EQ(graded, 0);
}
