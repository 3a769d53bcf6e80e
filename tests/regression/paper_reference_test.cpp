// The paper's example (MODEL.md §5) against an independent exact solution
// (tests/data/paper-reference-small.json, a copy of shared/data/paper-reference-small.json):
// n = 4, 8, 'right' mesh, loads as printed (s = 1) and × 1e6 (s = 1e6).
#include <hemicontact/driver/solve.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

using namespace hemicontact;
using json = nlohmann::json;

namespace {

json reference() {
  std::ifstream in(HEMICONTACT_SOURCE_DIR "/tests/data/paper-reference-small.json");
  return json::parse(in);
}

json paper_scene(int n, double s) {
  json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-printed.json");
  scene["mesh"]["n"] = n;
  scene["mesh"]["diagonal"] = "right";
  scene["loads"]["scale"] = s;
  return validate_scene(scene);
}

}  // namespace

class PaperReference : public ::testing::TestWithParam<int> {};

TEST_P(PaperReference, MatchesIndependentExactSolution) {
  const json c = reference()["cases"][GetParam()];
  const int n = c["n"];
  const double s = c["s"];
  SCOPED_TRACE("n = " + std::to_string(n) + ", s = " + std::to_string(s));
  const json scene = paper_scene(n, s);
  const Model md = build_model(scene, ".");
  const SolveOptions opt = solve_options_from_scene(scene);
  const Solution sol = solve(md, opt);
  ASSERT_TRUE(sol.backend_ok) << sol.message;
  ASSERT_TRUE(sol.fixed_point_converged) << sol.message;
  EXPECT_TRUE(sol.certificate.passed) << "max residual " << sol.certificate.max_residual;
  EXPECT_EQ(md.dofs.n_free(), c["dofs"].get<Index>());

  // The reference solves the same discrete problem exactly (residual < 1e-12), and so does the
  // polished answer (the polish solves the unsmoothed system on the statuses: certificate ~1e-14),
  // so the two differ by the round-off of two direct solves, κ(K)·ε_mach ≈ 1e3·2e-16 at n = 8
  // (measured: u ≤ 2.1e-14 U, tractions ≤ 1.6e-13 S, energy terms ≤ 6.3e-14 relative). The
  // tolerances below leave a factor 16..50 for other CPUs and BLAS kernels, and are far below any
  // error the ε-smoothing (O(ε_τ) = 1e-10 U) or a wrong status would leave.
  constexpr double TOL_U = 1e-12, TOL_S = 1e-11, TOL_E = 1e-12;
  const double U = c["max_u_nu"].get<double>();
  const auto ux = c["bottom_ux"].get<std::vector<double>>(), uy = c["bottom_uy"].get<std::vector<double>>();
  const auto sn = c["bottom_sigma_nu"].get<std::vector<double>>(),
             st = c["bottom_sigma_tau"].get<std::vector<double>>();
  const auto statuses = c["statuses"].get<std::vector<std::string>>();
  ASSERT_EQ(md.contact.size(), static_cast<Index>(ux.size()));
  const double S = std::max(std::abs(*std::min_element(sn.begin(), sn.end())), 1e-300);
  double err_u = 0, err_s = 0;
  for (Index k = 0; k < md.contact.size(); ++k) {
    SCOPED_TRACE("node " + std::to_string(k));
    const int v = md.contact.node[k];
    EXPECT_NEAR(sol.u[2 * v], ux[k], TOL_U * U);
    EXPECT_NEAR(sol.u[2 * v + 1], uy[k], TOL_U * U);
    EXPECT_NEAR(sol.state.sigma_nu[k], sn[k], TOL_S * S);
    EXPECT_NEAR(sol.state.sigma_tau[k], st[k], TOL_S * S);
    EXPECT_EQ(sol.status[k].str(), statuses[k]);
    err_u = std::max({err_u, std::abs(sol.u[2 * v] - ux[k]) / U, std::abs(sol.u[2 * v + 1] - uy[k]) / U});
    err_s =
        std::max({err_s, std::abs(sol.state.sigma_nu[k] - sn[k]) / S, std::abs(sol.state.sigma_tau[k] - st[k]) / S});
  }
  const auto rel = [](double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); };
  const double E = c["energy"].get<double>(), EN = c["energy_norm"].get<double>();
  const double J = c["j_term"].get<double>(), FR = c["friction_term"].get<double>();
  EXPECT_LE(rel(sol.energy, E), TOL_E);
  EXPECT_LE(rel(sol.energy_norm, EN), TOL_E);
  EXPECT_LE(rel(sol.j_term, J), TOL_E);
  EXPECT_LE(rel(sol.friction_term, FR), TOL_E);
  std::printf(
      "[ reference] n=%d s=%g: max |du|/U %.1e, max |dsigma|/S %.1e, energy %.1e, energy_norm %.1e, "
      "j %.1e, friction %.1e (relative)\n",
      n, s, err_u, err_s, rel(sol.energy, E), rel(sol.energy_norm, EN), rel(sol.j_term, J), rel(sol.friction_term, FR));
  const auto counts = sol.status_counts();
  for (const auto& [key, val] : c["counts"].items()) EXPECT_EQ(counts.at(key), val.get<int>()) << key;
}

INSTANTIATE_TEST_SUITE_P(AllCases, PaperReference, ::testing::Range(0, 4));
