// The paper's scene with the nonlinear Hencky law (problems/sofonea2017-fig2-hencky.json): solved
// and certified in the full space by both backends, condensation refused, and — with a constant
// shear modulus (μ_∞ = μ_0) — the same solution as the linear plane-strain law.

#include <hemicontact/driver/model.hpp>
#include <hemicontact/driver/solve.hpp>
#include <hemicontact/io/config.hpp>

#include "support/expect_error.hpp"

#include <gtest/gtest.h>

#include <algorithm>

using namespace hemicontact;
using json = nlohmann::json;

namespace {

constexpr const char* kScene = HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2-hencky.json";

Solution solve_scene(const std::vector<std::string>& overrides) {
  const json s = load_scene(kScene, overrides);
  const Model md = build_model(s, HEMICONTACT_SOURCE_DIR "/problems");
  return solve(md, solve_options_from_scene(s));
}

bool skipped_starts_with(const Solution& s, const std::string& prefix) {
  return std::any_of(s.skipped.begin(), s.skipped.end(), [&](const std::string& k) { return k.rfind(prefix, 0) == 0; });
}

}  // namespace

// Certificate ≤ 1e-8 (the acceptance level) with ipopt and newton; both minimize the same
// strongly convex-in-the-interior energy to the backend tolerance (1e-12, scaled) and the same
// ε-smoothing (1e-10·U_s), so they agree to ~1e-9 relative in u and energy.
TEST(HenckyScene, SolvesCertifiedWithBothBackends) {
  const Solution a = solve_scene({"mesh.n=16", "solver.backend=ipopt"});
  const Solution b = solve_scene({"mesh.n=16", "solver.backend=newton"});
  for (const Solution* s : {&a, &b}) {
    EXPECT_TRUE(s->ok()) << s->message;
    EXPECT_LE(s->certificate.max_residual, 1e-8);
    EXPECT_EQ(s->formulation, "full");
    EXPECT_TRUE(skipped_starts_with(*s, "condensation: nonlinear material"));
    EXPECT_TRUE(skipped_starts_with(*s, "polish:"));
  }
  const double U = a.u.cwiseAbs().maxCoeff();
  EXPECT_LE((a.u - b.u).cwiseAbs().maxCoeff(), 1e-9 * U);
  EXPECT_NEAR(a.energy, b.energy, 1e-9 * std::abs(a.energy));
  ASSERT_EQ(a.status.size(), b.status.size());
  for (size_t k = 0; k < a.status.size(); ++k) EXPECT_EQ(a.status[k].str(), b.status[k].str()) << k;
}

// μ_∞ = μ_0 makes W exactly the linear plane-strain energy (hencky.hpp), so the same backend on the
// same full-space problem must give the same u up to the rounding differences between the two
// assemblies (the tangent C(ε) = κ m mᵀ + 2μ(I − m mᵀ/3) vs λ, λ + 2μ entries: ~1e-16 relative),
// amplified by the conditioning of the solve; the tolerances of the backend and continuation are
// common to both and cancel (measured: 3e-15 relative in u at n = 16). 1e-12 leaves room for that
// amplification while a wrong factor anywhere in the law (O(1)) or a missed ε33 term (O(ν)) fails.
TEST(HenckyScene, ConstantShearModulusReproducesLinearPlaneStrain) {
  const Solution h = solve_scene({"mesh.n=16", "solver.backend=newton", "material.shear_ratio=1"});
  const Solution l = solve_scene({"mesh.n=16", "solver.backend=newton", "solver.formulation=full",
                                  "material.model=linear_elastic", "material.shear_ratio=null",
                                  "material.eps_ref=null"});
  ASSERT_TRUE(h.ok()) << h.message;
  ASSERT_TRUE(l.ok()) << l.message;
  const double U = l.u.cwiseAbs().maxCoeff();
  const double du = (h.u - l.u).cwiseAbs().maxCoeff();
  std::printf("[ hencky   ] mu constant vs linear plane strain: max|du|/max|u| = %.3e, energies %.12g, %.12g\n",
              du / U, h.energy, l.energy);
  EXPECT_LE(du, 1e-12 * U);
  EXPECT_NEAR(h.energy, l.energy, 1e-12 * std::abs(l.energy));
  EXPECT_NEAR(h.elastic_energy, 0.5 * l.a_uu, 1e-12 * l.a_uu);
  for (size_t k = 0; k < h.status.size(); ++k) EXPECT_EQ(h.status[k].str(), l.status[k].str()) << k;
}

TEST(HenckyScene, CondensationAndPlaneStressAreRefused) {
  const json s = load_scene(kScene, {"mesh.n=4", "solver.formulation=condensed"});
  const Model md = build_model(s, HEMICONTACT_SOURCE_DIR "/problems");
  test::expect_input_error([&] { solve(md, solve_options_from_scene(s)); }, {"solver.formulation", "linear material"});
  const json p = load_scene(kScene, {"mesh.n=4", "material.plane=stress"});
  test::expect_input_error([&] { build_model(p, HEMICONTACT_SOURCE_DIR "/problems"); }, {"material.plane"});
}
