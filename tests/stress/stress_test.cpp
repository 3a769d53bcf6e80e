// Fast part of the numerical stress tests: each case either converges with a passing certificate or
// reports non-convergence — never NaN, never a crash, never an uncertified answer presented as
// converged.
#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace hemicontact;
using json = nlohmann::json;

namespace {

Solution run(const std::vector<std::string>& overrides, Model* keep = nullptr) {
  std::vector<std::string> o{"mesh.n=16", "check.smallness=false"};
  o.insert(o.end(), overrides.begin(), overrides.end());
  const json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", o);
  Model md = build_model(s, ".");
  Solution sol = solve(md, solve_options_from_scene(s));
  if (keep) *keep = std::move(md);
  return sol;
}

// The contract every stress case must keep.
void expect_honest(const Solution& s) {
  EXPECT_TRUE(s.u.allFinite());
  EXPECT_TRUE(std::isfinite(s.energy));
  if (s.ok())
    EXPECT_LE(s.certificate.max_residual, s.certificate.tol);
  else
    EXPECT_FALSE(s.message.empty());
}

}  // namespace

struct StressCase {
  std::string name;
  std::vector<std::string> overrides;
};

class Stress : public ::testing::TestWithParam<StressCase> {};

// Every case here is expected to solve and be certified (measured); a regression shows as a failure.
TEST_P(Stress, SolvesAndCertifies) {
  const Solution s = run(GetParam().overrides);
  expect_honest(s);
  EXPECT_TRUE(s.ok()) << s.message << " (certificate " << s.certificate.max_residual << ")";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, Stress,
    ::testing::Values(StressCase{"g0", {"contact.gap=0"}}, StressCase{"gLarge", {"contact.gap=1e6"}},
                      StressCase{"noObstacle", {"contact.gap=null"}}, StressCase{"mu0", {"contact.friction.mu=0"}},
                      StressCase{"mu5", {"contact.friction.mu=5"}},
                      StressCase{"allSeparated", {"loads.body_force=[0,500]", "boundary.gamma2=[]"}},
                      StressCase{"stiffLayer", {"contact.normal_law.c1=1e8"}},
                      StressCase{
                          "softLayer",
                          {"contact.normal_law.c1=1e-2", "contact.normal_law.c2=-1e-2", "contact.normal_law.c3=4e-2"}},
                      StressCase{"nearlyIncompressible", {"material.plane=strain", "material.nu=0.499"}},
                      StressCase{"E1e9", {"material.E=1e9"}}, StressCase{"E1em3", {"material.E=1e-3"}},
                      StressCase{"epsLarge", {"solver.eps_tau=1e-2", "solver.eps_nu=1e-2"}},
                      StressCase{"epsTiny", {"solver.eps_tau=1e-12", "solver.eps_nu=1e-12"}},
                      StressCase{"distorted", {"mesh.perturb=0.3", "mesh.seed=7"}},
                      StressCase{"thinStrip", {"mesh.x=[0,100]", "mesh.nx=200", "mesh.ny=2", "mesh.n=null"}},
                      StressCase{"newtonFull", {"solver.backend=newton", "solver.formulation=full"}}),
    [](const ::testing::TestParamInfo<StressCase>& i) { return i.param.name; });

// Scale invariance: loads × s with E and the layer's c_i × s gives the same u (units never matter).
TEST(StressScale, LoadsAndModuliScaledTogether) {
  const Solution a = run({});
  for (double s : {1e-6, 1e4}) {
    SCOPED_TRACE("s = " + std::to_string(s));
    const std::string ss = std::to_string(s);
    const Solution b =
        run({"loads.scale=" + ss, "material.E=" + std::to_string(2000 * s),
             "contact.normal_law.c1=" + std::to_string(100 * s), "contact.normal_law.c2=" + std::to_string(-100 * s),
             "contact.normal_law.c3=" + std::to_string(400 * s)});
    ASSERT_TRUE(b.ok()) << b.message;
    // Both exact to the certificate (1e-8 relative): u agrees to that level.
    EXPECT_LE((a.u - b.u).cwiseAbs().maxCoeff(), 1e-8 * a.u.cwiseAbs().maxCoeff());
    for (size_t k = 0; k < a.status.size(); ++k) EXPECT_EQ(a.status[k].str(), b.status[k].str());
  }
}

// A stiff layer (c1 → ∞) without obstacle approaches Signorini contact with zero gap: the layer's
// penetration is O(σ/c1). Frictionless in both, since with F_b = μ p_ν the Signorini limit (u_ν = 0,
// p_ν(0) = 0) would have no friction while the stiff layer has.
TEST(StressLimits, StiffLayerApproachesSignorini) {
  const std::string none = R"(contact.friction={"type":"none"})";
  const Solution sig = run({"contact.gap=0", none});
  const Solution stiff = run({"contact.gap=null", none, "contact.normal_law.c1=1e7", "contact.normal_law.r1=1e3",
                              "contact.normal_law.r2=2e3", "contact.normal_law.c2=0", "contact.normal_law.c3=1e7"});
  ASSERT_TRUE(sig.ok() && stiff.ok()) << sig.message << " / " << stiff.message;
  const double U = sig.u.cwiseAbs().maxCoeff();
  // Penetration of the stiff layer is σ/c1 ~ 2000/1e7 = 2e-4 ≪ U ~ 1: the fields agree to ~1e-3 U.
  EXPECT_LE((sig.u - stiff.u).cwiseAbs().maxCoeff(), 1e-3 * U);
}

// A layer whose softening branch drives p_ν below zero makes F_b = μ p_ν negative: (15c) rejects it
// with a message naming the key instead of solving a meaningless problem.
TEST(StressLimits, NegativeFrictionBoundIsRejected) {
  try {
    run({"contact.normal_law.c1=1e-2"});
    FAIL() << "expected an input error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT);
    EXPECT_NE(std::string(e.what()).find("contact.friction"), std::string::npos) << e.what();
  }
}
