// The paper's example (docs/model.md §5) against an independent exact solution
// (tests/data/paper-reference-small.json; its "about" field says how it was computed):
// n = 4, 8, 'right' mesh, loads as printed (s = 1) and × 1e6 (s = 1e6). Every case with both
// exact backends (ipopt, newton) and both paths: the default (the exact inner solver takes over
// from the continuation) and the continuation alone (solver.exact.enabled = false):
// the default certifies what the continuation certified, with the same answer; and the full-space
// exact solver (backend ssn, solver/ssn.hpp), whose flag `exact` changes nothing.
#include <hemicontact/config.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <tuple>

using namespace hemicontact;
using json = nlohmann::json;

namespace {

json reference() {
  std::ifstream in(HEMICONTACT_SOURCE_DIR "/tests/data/paper-reference-small.json");
  return json::parse(in);
}

json paper_scene(int n, double s, const std::string& backend, bool exact) {
  json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-printed.json");
  scene["mesh"]["n"] = n;
  scene["mesh"]["diagonal"] = "right";
  scene["loads"]["scale"] = s;
  scene["solver"]["backend"] = backend;
  if (!exact) scene["solver"]["exact"]["enabled"] = false;  // otherwise the default (on)
  return validate_scene(scene);
}

// (case index, backend, exact inner solver on = the default)
using Param = std::tuple<int, std::string, bool>;

}  // namespace

class PaperReference : public ::testing::TestWithParam<Param> {};

TEST_P(PaperReference, MatchesIndependentExactSolution) {
  const auto& [index, backend, exact] = GetParam();
  if (std::string(backend) == "ipopt" && !HEMICONTACT_HAS_IPOPT)
    GTEST_SKIP() << "built without Ipopt (coinor-libipopt-dev): the newton cases cover the reference";
  const json c = reference()["cases"][index];
  const int n = c["n"];
  const double s = c["s"];
  SCOPED_TRACE("n = " + std::to_string(n) + ", s = " + std::to_string(s) + ", " + backend +
               (exact ? ", default (exact inner solver)" : ", continuation alone"));
  const json scene = paper_scene(n, s, backend, exact);
  const Model md = build_model(scene, ".");
  const SolveOptions opt = solve_options_from_scene(scene);
  ASSERT_EQ(opt.exact, exact);
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
  // error the ε-smoothing (O(ε_τ) = 1e-10 U) or a wrong status would leave. The energy and the
  // energy norm are stationary or quadratic in u (error O(δu²) + summation round-off); the two
  // contact terms are first-order in u, and their tolerance follows from TOL_U below.
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
  // The contact terms J = Σ w j_ν(u_ν) and FR = Σ w F_b(u_ν)|u_τ| move to first order with u: an
  // error |δu| ≤ δ = TOL_U·U (the bound asserted above) moves them by at most
  //   |δJ| ≤ δ Σ w |p_ν(u_ν)|,   |δFR| ≤ δ Σ w (F_b(u_ν) + L_Fb |u_τ|)   (j_ν' = p_ν, (15a)),
  // which, relative to J and FR, exceeds TOL_U wherever |u_τ| or u_ν is small against U (slipping
  // nodes with |u_τ| ≈ U/5 here). These bounds, from the reference's own u, are the tolerances;
  // never below TOL_E (the summation's round-off).
  double dJ = 0, dFR = 0;
  for (Index k = 0; k < md.contact.size(); ++k) {
    const double un = -uy[k], ut = ux[k], w = md.contact.w[k];  // ν = (0, −1), τ = (1, 0)
    if (md.normal_law) dJ += w * std::abs(md.normal_law->p(un));
    if (md.friction) dFR += w * (md.friction->F(un) + md.friction->lipschitz() * std::abs(ut));
  }
  const double TOL_J = std::max(TOL_E, TOL_U * U * dJ / std::max(std::abs(J), 1e-300));
  const double TOL_FR = std::max(TOL_E, TOL_U * U * dFR / std::max(std::abs(FR), 1e-300));
  EXPECT_LE(rel(sol.energy, E), TOL_E);
  EXPECT_LE(rel(sol.energy_norm, EN), TOL_E);
  EXPECT_LE(rel(sol.j_term, J), TOL_J);
  EXPECT_LE(rel(sol.friction_term, FR), TOL_FR);
  std::printf(
      "[ reference] n=%d s=%g %s%s: max |du|/U %.1e, max |dsigma|/S %.1e, energy %.1e, energy_norm %.1e, "
      "j %.1e (tol %.1e), friction %.1e (tol %.1e) (relative)\n",
      n, s, backend.c_str(), exact ? " (default)" : " (continuation alone)", err_u, err_s, rel(sol.energy, E),
      rel(sol.energy_norm, EN), rel(sol.j_term, J), TOL_J, rel(sol.friction_term, FR), TOL_FR);
  // What each path did: the default hands over to the exact solver or certifies on the way
  // (never a later ε-stage after a certified answer); the continuation alone never hands over.
  if (!exact) {
    EXPECT_FALSE(sol.handover.used);
  }
  const auto counts = sol.status_counts();
  for (const auto& [key, val] : c["counts"].items()) EXPECT_EQ(counts.at(key), val.get<int>()) << key;
}

INSTANTIATE_TEST_SUITE_P(AllCases, PaperReference,
                         ::testing::Combine(::testing::Range(0, 4), ::testing::Values("ipopt", "newton", "ssn"),
                                            ::testing::Bool()),
                         [](const ::testing::TestParamInfo<Param>& info) {
                           return "case" + std::to_string(std::get<0>(info.param)) + "_" + std::get<1>(info.param) +
                                  (std::get<2>(info.param) ? "_default" : "_continuation");
                         });
