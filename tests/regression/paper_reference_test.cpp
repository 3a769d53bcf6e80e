// The paper's example (MODEL.md §5) against an independent exact solution
// (tests/data/paper-reference-small.json, a copy of shared/data/paper-reference-small.json):
// n = 4, 8, 'right' mesh, loads as printed (s = 1) and × 1e6 (s = 1e6).
#include <hemicontact/driver/model.hpp>
#include <hemicontact/driver/solve.hpp>
#include <hemicontact/io/config.hpp>

#include <gtest/gtest.h>

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

  // The reference solves the same discrete problem exactly (residual < 1e-12); our answer carries
  // the certificate tolerance 1e-8 (relative) plus the ε-smoothing error O(ε_τ) = 1e-10·U, so
  // displacements and energies must agree to ~1e-7 relative.
  const double U = c["max_u_nu"].get<double>();
  const auto ux = c["bottom_ux"].get<std::vector<double>>(), uy = c["bottom_uy"].get<std::vector<double>>();
  const auto sn = c["bottom_sigma_nu"].get<std::vector<double>>(), st = c["bottom_sigma_tau"].get<std::vector<double>>();
  const auto statuses = c["statuses"].get<std::vector<std::string>>();
  ASSERT_EQ(md.contact.size(), static_cast<Index>(ux.size()));
  const double S = std::max(std::abs(*std::min_element(sn.begin(), sn.end())), 1e-300);
  for (Index k = 0; k < md.contact.size(); ++k) {
    SCOPED_TRACE("node " + std::to_string(k));
    const int v = md.contact.node[k];
    EXPECT_NEAR(sol.u[2 * v], ux[k], 1e-7 * U);
    EXPECT_NEAR(sol.u[2 * v + 1], uy[k], 1e-7 * U);
    EXPECT_NEAR(sol.state.sigma_nu[k], sn[k], 1e-6 * S);
    EXPECT_NEAR(sol.state.sigma_tau[k], st[k], 1e-6 * S);
    EXPECT_EQ(sol.status[k].str(), statuses[k]);
  }
  const double E = std::abs(c["energy"].get<double>());
  EXPECT_NEAR(sol.energy, c["energy"].get<double>(), 1e-7 * E);
  EXPECT_NEAR(sol.energy_norm, c["energy_norm"].get<double>(), 1e-7 * c["energy_norm"].get<double>());
  EXPECT_NEAR(sol.j_term, c["j_term"].get<double>(), 1e-6 * std::abs(c["j_term"].get<double>()));
  EXPECT_NEAR(sol.friction_term, c["friction_term"].get<double>(), 1e-6 * std::abs(c["friction_term"].get<double>()));
  const auto counts = sol.status_counts();
  for (const auto& [key, val] : c["counts"].items()) EXPECT_EQ(counts.at(key), val.get<int>()) << key;
}

INSTANTIATE_TEST_SUITE_P(AllCases, PaperReference, ::testing::Range(0, 4));
