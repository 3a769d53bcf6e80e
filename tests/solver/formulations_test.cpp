// Fast path (static condensation onto Γ3 + exact polish) against the full-space formulation, and
// skipping of what a scene does not need.
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>
#include "support/polish_check.hpp"

#include <gtest/gtest.h>

using namespace hemicontact;
using json = nlohmann::json;

namespace {
Solution run(const std::string& scene, const std::vector<std::string>& overrides, Model* keep = nullptr) {
  const json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/" + scene + ".json", overrides);
  Model md = build_model(s, HEMICONTACT_SOURCE_DIR "/problems");
  Solution sol = solve(md, solve_options_from_scene(s));
  if (keep) *keep = std::move(md);
  return sol;
}
}  // namespace

class Formulations : public ::testing::TestWithParam<std::string> {};

// Both formulations minimize the same energy; the condensed one is then polished to the exact
// unsmoothed solution, the full one carries Ipopt's tolerance (1e-12 on the scaled problem) and the
// smoothing error O(ε_τ) = 1e-10·U_s. So they agree to ~1e-9 relative in u.
TEST_P(Formulations, CondensedAndFullAgree) {
  const std::string scene = GetParam();
  const Solution c = run(scene, {"mesh.n=32", "solver.formulation=condensed"});
  const Solution f = run(scene, {"mesh.n=32", "solver.formulation=full"});
  ASSERT_TRUE(c.backend_ok && c.fixed_point_converged) << c.message;
  ASSERT_TRUE(f.backend_ok && f.fixed_point_converged) << f.message;
  EXPECT_EQ(c.formulation, "condensed");
  EXPECT_EQ(f.formulation, "full");
  const double U = c.u.cwiseAbs().maxCoeff();
  EXPECT_LE((c.u - f.u).cwiseAbs().maxCoeff(), 1e-9 * U);
  EXPECT_NEAR(c.energy, f.energy, 1e-9 * std::abs(c.energy));
  ASSERT_EQ(c.status.size(), f.status.size());
  for (size_t k = 0; k < c.status.size(); ++k) EXPECT_EQ(c.status[k].str(), f.status[k].str()) << k;
  // The exact solver and its polish leave no smoothing error: the certificate is at round-off.
  EXPECT_TRUE(hemicontact::test::polished_or_at_roundoff(c));
  EXPECT_LE(c.certificate.max_residual, 1e-10);
  EXPECT_LE(f.certificate.max_residual, 1e-8);
}

INSTANTIATE_TEST_SUITE_P(PaperScenes, Formulations,
                         ::testing::Values("sofonea2017-fig2", "sofonea2017-printed", "sofonea2017-frictionless"));

// No soft layer: no j_ν term is assembled (and said so); a pure Signorini problem with friction.
TEST(Skipping, NoLayerNoNormalComplianceTerm) {
  const Solution s =
      run("sofonea2017-fig2",
          {"mesh.n=8", "contact.normal_law.type=none", "contact.normal_law.c1=null", "contact.normal_law.c2=null",
           "contact.normal_law.c3=null", "contact.normal_law.r1=null", "contact.normal_law.r2=null",
           "contact.friction.type=tresca", "contact.friction.mu=null", "contact.friction.bound=1"});
  ASSERT_TRUE(s.backend_ok) << s.message;
  EXPECT_TRUE(s.certificate.passed) << s.certificate.max_residual;
  bool no_j = false, no_loop = false;
  for (const auto& m : s.skipped) {
    no_j |= m.rfind("normal_compliance", 0) == 0;
    no_loop |= m.rfind("fixed_point", 0) == 0;
  }
  EXPECT_TRUE(no_j);
  EXPECT_TRUE(no_loop);  // Tresca: F_b does not depend on u_ν
  EXPECT_EQ(s.j_term, 0.0);
}

// Linear elasticity only: no backend, one factorization, exact.
TEST(Skipping, PureElasticityNeedsNoBackend) {
  const Solution s = run("elasticity-square", {"mesh.n=16"});
  EXPECT_TRUE(s.history.empty());
  EXPECT_LE(s.certificate.max_residual, 1e-12);
  EXPECT_FALSE(s.skipped.empty());
}
