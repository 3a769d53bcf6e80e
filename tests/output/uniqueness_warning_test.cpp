// A plain solve warns where other certified solutions may exist: (21) fails and the inner problem
// is not convex. Every shipped nonconvex scene gets the warning (and the summary's row), none of
// the paper's scenes, whose (21) holds.
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <string>

namespace hemicontact {
namespace {

struct Solved {
  Model md;
  Solution sol;
};

Solved solve_shipped(const std::string& name) {
  const nlohmann::json scene = load_scene(std::string(HEMICONTACT_SOURCE_DIR) + "/problems/" + name + ".json");
  Solved s;
  s.md = build_model(scene, std::string(HEMICONTACT_SOURCE_DIR) + "/problems");
  s.sol = solve(s.md, solve_options_from_scene(scene));
  return s;
}

TEST(UniquenessWarning, EveryShippedNonconvexSceneWarns) {
  for (const char* name : {"minima-softening", "minima-laminate", "minima-one-node"}) {
    const Solved s = solve_shipped(name);
    ASSERT_TRUE(s.sol.smallness.computed) << name;
    EXPECT_FALSE(s.sol.smallness.holds) << name;
    const std::string w = uniqueness_warning(s.sol);
    EXPECT_NE(w.find("other certified solutions may exist"), std::string::npos) << name << ": " << w;
    EXPECT_NE(w.find("hemicontact minima"), std::string::npos) << name;
    EXPECT_NE(w.find("hemicontact path"), std::string::npos) << name;
    EXPECT_NE(summary_table(s.md, s.sol).find("uniqueness    NOT guaranteed"), std::string::npos) << name;
  }
}

TEST(UniquenessWarning, ThePapersScenesDoNot) {
  for (const char* name : {"sofonea2017-fig2", "sofonea2017-printed", "sofonea2017-frictionless"}) {
    const Solved s = solve_shipped(name);
    ASSERT_TRUE(s.sol.smallness.computed && s.sol.smallness.holds) << name;
    EXPECT_EQ(uniqueness_warning(s.sol), "") << name;
    EXPECT_EQ(summary_table(s.md, s.sol).find("NOT guaranteed"), std::string::npos) << name;
  }
}

}  // namespace
}  // namespace hemicontact
