// solver.engine = auto for the adaptive loop's levels (solver/engine_choice.hpp,
// choose_level_engine): the first level as `solve` decides its mesh, later 3D levels by whether
// the factorization predicted from the previous level's fits solver.method_choice.memory_fraction
// of the memory, once on the petsc engine always there, and every given or cholmod-only setting
// kept. The engine's availability is passed in: these rules hold whether or not it is built.
#include <hemicontact/solver/engine_choice.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/config.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace hemicontact {
namespace {

nlohmann::json box_scene(const std::string& extra = "") {
  std::vector<std::string> sets{"mesh.n=8"};
  if (!extra.empty()) sets.push_back(extra);
  return load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-3d.json", sets);
}

LevelNumbers later_level(double previous_nnz, double memory_bytes) {
  LevelNumbers n;
  n.dim = 3;
  n.unknowns = 8e5;
  n.previous_unknowns = 1e5;
  n.previous_factor_nnz = previous_nnz;
  n.memory_bytes = memory_bytes;
  return n;
}

TEST(LevelEngine, TheFirstLevelIsDecidedAsSolveDecidesItsMesh) {
  LevelNumbers n;
  n.dim = 3;
  n.unknowns = 5e3;
  EXPECT_EQ(choose_level_engine(box_scene(), n, true).engine, "cholmod");
  n.unknowns = 5e4;  // above petsc_above (1e4)
  const EngineChoice big = choose_level_engine(box_scene(), n, true);
  EXPECT_EQ(big.engine, "petsc");
  EXPECT_NE(big.reason.find("petsc_above"), std::string::npos) << big.reason;
}

TEST(LevelEngine, LaterLevelsGoWhereThePredictedFactorizationDoesNotFit) {
  // 8x the unknowns: (8)^(4/3) = 16x the previous level's entries, 8 bytes each.
  const double predicted = 8 * 1e7 * std::pow(8.0, 4.0 / 3.0);  // 1.28 GB
  const double fraction = 0.5;  // the scene's default solver.method_choice.memory_fraction
  const EngineChoice fits = choose_level_engine(box_scene(), later_level(1e7, 1.01 * predicted / fraction), true);
  EXPECT_EQ(fits.engine, "cholmod");
  EXPECT_NE(fits.reason.find("(1.28 GB) <="), std::string::npos) << fits.reason;
  const EngineChoice over = choose_level_engine(box_scene(), later_level(1e7, 0.99 * predicted / fraction), true);
  EXPECT_EQ(over.engine, "petsc");
  EXPECT_TRUE(over.automatic);
  EXPECT_NE(over.reason.find("(1.28 GB) >"), std::string::npos) << over.reason;
  // Once there, always there: the petsc engine made no factorization to go by.
  LevelNumbers after = later_level(0, 1e12);
  after.previous_petsc = true;
  EXPECT_EQ(choose_level_engine(box_scene(), after, true).engine, "petsc");
  // A large level whose predicted factorization fits stays here whatever its size.
  EXPECT_EQ(choose_level_engine(box_scene(), later_level(1e7, 1e12), true).engine, "cholmod");
}

TEST(LevelEngine, GivenOrCholmodOnlySettingsAndAMissingEngineKeepTheirEngine) {
  const LevelNumbers over = later_level(1e9, 1e9);  // far over any budget
  EXPECT_EQ(choose_level_engine(box_scene(), over, true).engine, "petsc");
  const EngineChoice given = choose_level_engine(box_scene("solver.engine=\"cholmod\""), over, true);
  EXPECT_EQ(given.engine, "cholmod");
  EXPECT_FALSE(given.automatic);
  const EngineChoice ipopt = choose_level_engine(box_scene("solver.backend=\"ipopt\""), over, true);
  EXPECT_EQ(ipopt.engine, "cholmod");
  EXPECT_NE(ipopt.reason.find("solver.backend = ipopt"), std::string::npos) << ipopt.reason;
  EXPECT_EQ(choose_level_engine(box_scene(), over, false).engine, "cholmod");
  LevelNumbers flat = over;
  flat.dim = 2;
  EXPECT_EQ(choose_level_engine(box_scene(), flat, true).engine, "cholmod");
}

// minima's engine: choose_engine's rule at petsc_restarts_above (a search restarts one solver
// many times: the in-process factorization serves every start), the cholmod engine where
// --backends or --barriers need the in-process solver, and a given petsc with either refused.
TEST(MinimaEngine, RestartsHaveTheirOwnThresholdAndInProcessNeedsKeepCholmod) {
  // n = 8: 2 187 unknowns. solve's threshold 1 000 would take the petsc engine; minima's 80 000 not.
  const nlohmann::json s = box_scene("solver.method_choice.petsc_above=1000");
  EXPECT_EQ(choose_engine(s, ".", true, false).engine, "petsc");
  const EngineChoice low = minima_engine(s, ".", true, false, false);
  EXPECT_EQ(low.engine, "cholmod");
  EXPECT_NE(low.reason.find("< solver.method_choice.petsc_restarts_above = 8e+04"), std::string::npos) << low.reason;
  const nlohmann::json big = box_scene("solver.method_choice.petsc_restarts_above=1000");
  const EngineChoice p = minima_engine(big, ".", true, false, false);
  EXPECT_EQ(p.engine, "petsc");
  EXPECT_TRUE(p.automatic);
  EXPECT_EQ(minima_engine(big, ".", false, false, false).engine, "cholmod");  // not built
  for (const bool backends : {true, false}) {
    const EngineChoice here = minima_engine(big, ".", true, backends, !backends);
    EXPECT_EQ(here.engine, "cholmod");
    EXPECT_NE(here.reason.find(backends ? "--backends" : "--barriers"), std::string::npos) << here.reason;
    EXPECT_NE(here.reason.find("petsc_restarts_above"), std::string::npos) << here.reason;
  }
  const nlohmann::json given = box_scene("solver.engine=\"petsc\"");
  EXPECT_EQ(minima_engine(given, ".", true, false, false).engine, "petsc");
  EXPECT_THROW(minima_engine(given, ".", true, true, false), Error);
  EXPECT_THROW(minima_engine(given, ".", true, false, true), Error);
  EXPECT_THROW(minima_engine(given, ".", false, false, false), Error);  // given, not built
}

}  // namespace
}  // namespace hemicontact
