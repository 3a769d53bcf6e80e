// Manufactured solution for the nonlinear (Hencky) law: u* of support/manufactured.hpp (zero on
// the whole boundary, clamped there), f0 = −div F(ε(u*)), solved by the full-space path of the
// contact solver (no contact: NonlinearElasticEnergy + LoadEnergy, newton backend) on nested
// meshes. The P1 error in the energy norm must decrease at the a-priori rate O(h): Galerkin
// orthogonality (F(ε(u)) − F(ε(u_h)), ε(w_h)) = 0 and (12) give, for every v_h,
//   m_F‖ε(u − u_h)‖² ≤ (F(ε u) − F(ε u_h), ε(u − v_h)) ≤ L_F‖ε(u − u_h)‖ ‖ε(u − v_h)‖,
// i.e. Céa's lemma with constant L_F/m_F, and the interpolation error of u* ∈ H² is O(h).

#include <hemicontact/material/hencky.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include "support/fem_problem.hpp"
#include "support/manufactured.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace hemicontact;
using test::manufactured::eps_exact;
using test::manufactured::u_exact;

namespace {

// ε* reaches |dev ε| ~ 3, so eps_ref = 0.5 and μ_∞ = 0.3 μ_0 put most of Ω deep in the nonlinear
// range (μ varies by a factor ≈ 3 over Ω).
nlohmann::json manufactured_scene(int n) {
  nlohmann::json s = {
      {"mesh", {{"n", n}, {"diagonal", "crossed"}}},
      {"material",
       {{"model", "hencky"}, {"E", 2000}, {"nu", 0.4}, {"plane", "strain"}, {"shear_ratio", 0.3}, {"eps_ref", 0.5}}},
      {"boundary", {{"gamma1", {{{"side", "left"}}, {{"side", "right"}}, {{"side", "bottom"}}, {{"side", "top"}}}}}},
      {"solver", {{"backend", "newton"}}}};
  return validate_scene(s);
}

// f0 = −div σ(x), σ(x) = F(ε*(x)) in Voigt (σ11, σ22, σ12): (div σ)_x = ∂x σ11 + ∂y σ12,
// (div σ)_y = ∂x σ12 + ∂y σ22, by central differences with h = 1e-4: truncation h²/6·|∂³σ| ~
// 1e-9·π³·|σ| and round-off ε_mach|σ|/h ~ 1e-12·|σ|, against |f0| ~ π²|σ|: ~1e-9 relative, far
// below the discretization errors (≥ 1e-3) measured here. (The law is smooth: μ is C^∞ in s.)
test::Field2 body_force(const Material& F) {
  return [&F](double x, double y) {
    const double h = 1e-4;
    const Vec dsx = (F.stress(eps_exact(x + h, y)) - F.stress(eps_exact(x - h, y))) / (2 * h);
    const Vec dsy = (F.stress(eps_exact(x, y + h)) - F.stress(eps_exact(x, y - h))) / (2 * h);
    return Eigen::Vector2d(-(dsx[0] + dsy[2]), -(dsx[2] + dsy[1]));
  };
}

}  // namespace

// A wrong stress, tangent or load (e.g. a factor on a shear term) gives an O(1) error that does
// not decrease (order ≈ 0); a Newton solve stopped early gives an error floor. The pre-asymptotic
// terms are O(h) relative, so at h = 1/16 → 1/32 the order is within a few percent of 1: we
// require [0.9, 1.2] on the last two pairs. The energy norm is that of the small-strain tangent
// C(0) (equivalent to the nonlinear one within [m_F, L_F]).
TEST(NonlinearConvergence, ObservedOrderOneInEnergyNorm) {
  const std::vector<int> ns = {4, 8, 16, 32};
  std::vector<double> err;
  for (int n : ns) {
    const nlohmann::json scene = manufactured_scene(n);
    Model md = build_model(scene, ".");
    ASSERT_FALSE(md.material->is_linear());
    md.f = test::assemble_smooth_load(md.mesh, body_force(*md.material));
    md.fx = md.dofs.to_reduced(md.f);
    const SolveOptions opt = solve_options_from_scene(scene);
    const Solution sol = solve(md, opt);
    ASSERT_EQ(sol.formulation, "full");
    ASSERT_TRUE(sol.backend_ok) << sol.message;
    // Equilibrium r(u) = f on the free dofs, to the backend's tolerance (relative to |f|).
    const Vec res = md.dofs.to_reduced(md.internal_force(sol.u) - md.f);
    EXPECT_LE(res.cwiseAbs().maxCoeff(), 1e-8 * md.fx.cwiseAbs().maxCoeff()) << "n = " << n;
    const Mat D0 = md.material->tangent(Vec::Zero(3));
    err.push_back(test::energy_error(md.mesh, sol.u, eps_exact, D0));
  }
  for (size_t k = 0; k < ns.size(); ++k) {
    const double order = k ? std::log2(err[k - 1] / err[k]) : NAN;
    std::printf("[ orders   ] hencky n = %3d  energy error %.5e  order %5.3f\n", ns[k], err[k], order);
    if (k) {
      EXPECT_LT(err[k], err[k - 1]);
    }
    if (k + 2 >= ns.size()) {
      EXPECT_GE(order, 0.9) << "n = " << ns[k - 1] << " -> " << ns[k];
      EXPECT_LE(order, 1.2) << "n = " << ns[k - 1] << " -> " << ns[k];
    }
  }
}
