// The paper's scenes (problems/sofonea2017-*.json) solved through the whole pipeline:
// the Fig. 2 status pattern, the printed scene's all-compliance answer, the certificate, mirror
// symmetry, skipping of the outer loop without friction, and the certificate catching violations.
#include <hemicontact/check/certificate.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <map>

using namespace hemicontact;
using json = nlohmann::json;

namespace {

struct Solved {
  Model md;
  SolveOptions opt;
  Solution sol;
};

Solved solve_scene(const std::string& name, const std::vector<std::string>& overrides) {
  const json scene = load_scene(HEMICONTACT_SOURCE_DIR "/problems/" + name + ".json", overrides);
  Solved s{build_model(scene, HEMICONTACT_SOURCE_DIR "/problems"), solve_options_from_scene(scene), {}};
  s.sol = solve(s.md, s.opt);
  return s;
}

// Mirror node of each node about x = 1/2 (by coordinates; exact on symmetric meshes).
std::vector<Index> mirror_nodes(const Mesh& m) {
  std::map<std::pair<long long, long long>, Index> at;
  const auto key = [](double x, double y) { return std::make_pair(std::llround(x * 1e9), std::llround(y * 1e9)); };
  for (Index v = 0; v < m.num_nodes(); ++v) at[key(m.points(v, 0), m.points(v, 1))] = v;
  std::vector<Index> mir(m.num_nodes(), -1);
  for (Index v = 0; v < m.num_nodes(); ++v) {
    auto it = at.find(key(1.0 - m.points(v, 0), m.points(v, 1)));
    if (it != at.end()) mir[v] = it->second;
  }
  return mir;
}

}  // namespace

class Fig2Pattern : public ::testing::TestWithParam<int> {};

// docs/model.md §5 / paper Fig. 2: a few nodes at each end in normal compliance slipping outward
// (slip− on the left, slip+ on the right), all others at u_ν = g slipping, the centre node sticking.
TEST_P(Fig2Pattern, StatusesCertificateSymmetry) {
  const int n = GetParam();
  SCOPED_TRACE("n = " + std::to_string(n));
  const Solved s = solve_scene("sofonea2017-fig2", {"mesh.n=" + std::to_string(n)});
  const Solution& sol = s.sol;
  ASSERT_TRUE(sol.backend_ok && sol.fixed_point_converged) << sol.message;
  EXPECT_TRUE(sol.certificate.passed);
  EXPECT_LE(sol.certificate.max_residual, 1e-8);
  const Index N = s.md.contact.size();
  ASSERT_EQ(N, n + 1);
  const Index centre = n / 2;
  int compliance_left = 0, compliance_right = 0;
  for (Index k = 0; k < N; ++k) {
    SCOPED_TRACE("node " + std::to_string(k) + ": " + sol.status[k].str());
    const NodeStatus st = sol.status[k];
    if (k == centre) {
      EXPECT_EQ(st.str(), "contact/stick");
      continue;
    }
    EXPECT_EQ(st.tangential, k < centre ? TangentialStatus::SLIP_MINUS : TangentialStatus::SLIP_PLUS);
    if (st.normal == NormalStatus::COMPLIANCE)
      (k < centre ? compliance_left : compliance_right)++;
    else
      EXPECT_EQ(st.normal, NormalStatus::CONTACT);
  }
  // "A few" end nodes: at least the end node, and compliance only at the ends (contiguous runs).
  EXPECT_GE(compliance_left, 1);
  EXPECT_EQ(compliance_left, compliance_right);
  for (Index k = 0; k < compliance_left; ++k) EXPECT_EQ(sol.status[k].normal, NormalStatus::COMPLIANCE);
  EXPECT_LT(compliance_left, N / 4);

  // Mirror symmetry of the symmetric mesh's solution: u_x(1−x,y) = −u_x(x,y), u_y equal. The
  // solution is determined to the solver tolerance (certificate 1e-8 relative), so compare at 1e-7·U.
  const auto mir = mirror_nodes(s.md.mesh);
  const double U = sol.u.cwiseAbs().maxCoeff();
  double asym = 0;
  for (Index v = 0; v < s.md.mesh.num_nodes(); ++v) {
    ASSERT_GE(mir[v], 0);
    asym = std::max(asym, std::abs(sol.u[2 * v] + sol.u[2 * mir[v]]));
    asym = std::max(asym, std::abs(sol.u[2 * v + 1] - sol.u[2 * mir[v] + 1]));
  }
  EXPECT_LE(asym, 1e-7 * U);
}

INSTANTIATE_TEST_SUITE_P(Refinements, Fig2Pattern, ::testing::Values(16, 32, 64));

// As printed, the loads are ~1e-6 of Fig. 2's: u ~ 1e-7 ≪ r1, so every node is in compliance.
TEST(PrintedScene, AllNodesInCompliance) {
  const Solved s = solve_scene("sofonea2017-printed", {});
  ASSERT_TRUE(s.sol.backend_ok && s.sol.fixed_point_converged) << s.sol.message;
  EXPECT_LE(s.sol.certificate.max_residual, 1e-8);
  for (const auto& st : s.sol.status) EXPECT_EQ(st.normal, NormalStatus::COMPLIANCE);
  EXPECT_LT(s.sol.max_u_nu, 1e-5);
  EXPECT_GT(s.sol.max_u_nu, 0.0);
}

// Without friction there is nothing to lag: one minimization per continuation stage, no loop.
TEST(FrictionlessScene, SkipsOuterLoop) {
  const Solved s = solve_scene("sofonea2017-frictionless", {"mesh.n=16"});
  ASSERT_TRUE(s.sol.backend_ok) << s.sol.message;
  EXPECT_TRUE(s.sol.certificate.passed);
  bool skipped = false;
  for (const auto& m : s.sol.skipped) skipped |= m.rfind("fixed_point", 0) == 0;
  EXPECT_TRUE(skipped);
  int max_stage = 0;
  for (const auto& h : s.sol.history) max_stage = std::max(max_stage, h.stage);
  EXPECT_EQ(static_cast<int>(s.sol.history.size()), max_stage + 1);  // exactly one per stage
  for (Index k = 0; k < s.md.contact.size(); ++k) EXPECT_EQ(s.sol.state.lambda[k], 0.0);
}

// The certificate is computed from u alone, so corrupting u must show up in the right residual.
TEST(Certificate, FlagsInjectedViolations) {
  const Solved s = solve_scene("sofonea2017-fig2", {"mesh.n=16"});
  ASSERT_TRUE(s.sol.certificate.passed);
  const Model& md = s.md;
  const auto residual = [&](const Vec& u, const std::string& name) {
    const auto c = certify(md, u, contact_state(md, u), s.opt.certificate_tol, s.opt.status_tol);
    for (const auto& r : c.residuals)
      if (r.name == name) return r.value;
    return -1.0;
  };
  const Index k = 4;  // a contact node (u_ν = g) on the left half
  ASSERT_EQ(s.sol.status[k].normal, NormalStatus::CONTACT);
  const int v = md.contact.node[k];
  // Penetration by 1e-3·g: ν = (0,−1), so u_ν = −u_y.
  Vec u = s.sol.u;
  u[2 * v + 1] -= 1e-3 * md.contact.g[k];
  EXPECT_GT(residual(u, "feasibility"), 1e-4);
  // Slip in the wrong direction at a slipping node: |σ_τ + λ u_τ/|u_τ|| ≈ 2λ.
  u = s.sol.u;
  u[2 * v] = -u[2 * v];
  EXPECT_GT(residual(u, "slip_direction"), 1e-5);
  // An interior node moved: equilibrium breaks there.
  u = s.sol.u;
  const Index interior = md.mesh.num_nodes() / 2;
  u[2 * interior] += 1e-6 * u.cwiseAbs().maxCoeff();
  EXPECT_GT(residual(u, "equilibrium"), 1e-8);
  // Lifting a contact node off the obstacle while keeping the rigid reaction: complementarity.
  u = s.sol.u;
  u[2 * v + 1] += 1e-3 * md.contact.g[k];
  EXPECT_GT(residual(u, "complementarity"), 1e-5);
  EXPECT_FALSE(certify(md, u, contact_state(md, u), s.opt.certificate_tol, s.opt.status_tol).passed);
}
