// The certificate on its own (docs/model.md §4, check/certificate.hpp): each residual is the formula of
// the header, evaluated on a Γ3 state whose entries are set by hand, so every expected value below
// is exact (a few multiplications by powers of two of the scales, exact in binary): feasibility,
// normal, complementarity, friction cone, slip direction and equilibrium, their worst node, the
// scales U, F, S, the verdict against the tolerance, NaN as a failure, and the dofs the
// equilibrium residual must not read (Γ3 and clamped nodes).
#include <hemicontact/check/certificate.hpp>
#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

namespace hemicontact {
namespace {

// The paper's Fig. 2 scene at n = 8 (symmetric mesh): statuses of every kind (compliance, contact;
// stick, slip±), solved and certified once for the whole file.
struct Fig2 {
  Model md;
  SolveOptions opt;
  Solution sol;
  Fig2() {
    const nlohmann::json s = load_scene(HEMICONTACT_SOURCE_DIR "/problems/sofonea2017-fig2.json", {"mesh.n=8"});
    md = build_model(s, ".");
    opt = solve_options_from_scene(s);
    sol = solve(md, opt);
  }
};
const Fig2& fig2() {
  static const Fig2 f;
  return f;
}

const CertificateResidual& residual(const CertificateReport& r, const std::string& name) {
  for (const auto& c : r.residuals)
    if (c.name == name) return c;
  throw std::runtime_error("no residual " + name);
}

/// The first Γ3 node whose status string satisfies @p pred.
Index node_where(const Solution& sol, const std::function<bool(const NodeStatus&)>& pred) {
  for (size_t k = 0; k < sol.status.size(); ++k)
    if (pred(sol.status[k])) return static_cast<Index>(k);
  throw std::runtime_error("no such node");
}

CertificateReport certify_state(const ContactState& s, double tol = 1e-8) {
  const Fig2& f = fig2();
  return certify(f.md, f.sol.u, s, tol, f.opt.status_tol);
}

TEST(Certificate, SolvedSceneHasEveryResidualAtRoundoff) {
  const Fig2& f = fig2();
  ASSERT_TRUE(f.sol.ok()) << f.sol.message;
  const CertificateReport r = certify_state(f.sol.state);
  ASSERT_EQ(r.residuals.size(), 6u);
  const char* names[] = {"feasibility", "normal", "complementarity", "friction_cone", "slip_direction", "equilibrium"};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(r.residuals[i].name, names[i]);
    EXPECT_LE(r.residuals[i].value, 1e-12) << names[i];
  }
  EXPECT_TRUE(r.passed);
  // The scales of the header: U = max nodal |u|, F = max |f|, S = max(F/w̄, max λ, max |ξ|).
  EXPECT_EQ(r.length_scale, f.sol.u.cwiseAbs().maxCoeff());
  EXPECT_EQ(r.force_scale, f.md.f.cwiseAbs().maxCoeff());
  const double S = std::max(
      {r.force_scale / f.md.contact.w.mean(), f.sol.state.lambda.maxCoeff(), f.sol.state.xi.cwiseAbs().maxCoeff()});
  EXPECT_EQ(r.traction_scale, S);
}

// Where u = 0 (the start of a solve, a scene whose loads vanish) the length scale U is the mesh's
// longest edge, a length either way; the judge reads the edges only then.
TEST(Certificate, ZeroDisplacementTakesTheLongestEdgeAsItsLength) {
  const Fig2& f = fig2();
  ContactState s = f.sol.state;
  s.u_nu.setZero();
  s.u_tau.setZero();
  s.u_tau_vec.setZero();
  const CertificateReport r = certify(f.md, Vec::Zero(f.sol.u.size()), s, 1e-8, f.opt.status_tol);
  EXPECT_EQ(r.length_scale, f.md.mesh.max_edge_length());
  EXPECT_GT(r.length_scale, 0.0);
}

// Each residual in turn: one node's entries moved by a chosen multiple of the scale; the residual
// is that multiple, at that node, and it decides max_residual and the verdict.
TEST(Certificate, EachResidualIsItsFormula) {
  const Fig2& f = fig2();
  const CertificateReport r0 = certify_state(f.sol.state);
  const double U = r0.length_scale, S = r0.traction_scale, F = r0.force_scale;
  const Index contact = node_where(f.sol, [](const NodeStatus& s) { return s.normal == NormalStatus::CONTACT; });
  const Index compliance = node_where(f.sol, [](const NodeStatus& s) { return s.normal == NormalStatus::COMPLIANCE; });
  const Index slipping =
      node_where(f.sol, [](const NodeStatus& s) { return s.tangential == TangentialStatus::SLIP_PLUS; });

  {  // u_ν = g + U/4: feasibility (u_ν − g)/U
    ContactState s = f.sol.state;
    s.u_nu[contact] = f.md.contact.g[contact] + 0.25 * U;
    const CertificateReport r = certify_state(s);
    EXPECT_DOUBLE_EQ(residual(r, "feasibility").value, 0.25);
    EXPECT_EQ(residual(r, "feasibility").worst, contact);
    EXPECT_FALSE(r.passed);
  }
  {  // σ_ν + ξ = S/8 > 0 at a compliance node: normal (σ_ν + ξ)/S, and complementarity
     // |min((g − u_ν)/U, −(σ_ν + ξ)/S)| = 1/8 once the node is U/2 away from g.
    ContactState s = f.sol.state;
    s.sigma_nu[compliance] = -s.xi[compliance] + 0.125 * S;
    s.u_nu[compliance] = f.md.contact.g[compliance] - 0.5 * U;
    const CertificateReport r = certify_state(s);
    EXPECT_DOUBLE_EQ(residual(r, "normal").value, 0.125);
    EXPECT_EQ(residual(r, "normal").worst, compliance);
    EXPECT_DOUBLE_EQ(residual(r, "complementarity").value, 0.125);  // |min(1/2, −1/8)|
  }
  {  // complementarity alone: u_ν = g − U/2, σ_ν + ξ = −S/4 (a pulling gap): |min(1/2, 1/4)| = 1/4
    ContactState s = f.sol.state;
    s.sigma_nu[compliance] = -s.xi[compliance] - 0.25 * S;
    s.u_nu[compliance] = f.md.contact.g[compliance] - 0.5 * U;
    const CertificateReport r = certify_state(s);
    EXPECT_DOUBLE_EQ(residual(r, "complementarity").value, 0.25);
    EXPECT_EQ(residual(r, "complementarity").worst, compliance);
    EXPECT_LE(residual(r, "normal").value, 1e-12);
  }
  {  // |σ_τ| = λ + S/16: friction cone (|σ_τ| − λ)/S
    ContactState s = f.sol.state;
    s.sigma_tau[slipping] = -(s.lambda[slipping] + 0.0625 * S);
    const CertificateReport r = certify_state(s);
    EXPECT_DOUBLE_EQ(residual(r, "friction_cone").value, 0.0625);
    EXPECT_EQ(residual(r, "friction_cone").worst, slipping);
  }
  {  // −σ_τ = λ u_τ/|u_τ| off by S/32 along τ on a slipping node: slip direction |σ_τ + λ t|/S
    ContactState s = f.sol.state;
    const Eigen::RowVectorXd t = s.u_tau_vec.row(slipping) / s.u_tau_vec.row(slipping).norm();
    s.sigma_tau_vec.row(slipping) = -s.lambda[slipping] * t + 0.03125 * S * t;
    const CertificateReport r = certify_state(s);
    EXPECT_NEAR(residual(r, "slip_direction").value, 0.03125, 1e-15);
    EXPECT_EQ(residual(r, "slip_direction").worst, slipping);
  }
  {  // an interior nodal force of 3F/8: equilibrium |(K u − f)_j|/F at dof j
    ContactState s = f.sol.state;
    Index j = -1;
    for (Index v = 0; v < f.md.mesh.num_nodes() && j < 0; ++v)
      if (!f.md.clamped[v] &&
          std::find(f.md.contact.node.begin(), f.md.contact.node.end(), v) == f.md.contact.node.end())
        j = 2 * v + 1;
    ASSERT_GE(j, 0);
    s.residual[j] = 0.375 * F;
    const CertificateReport r = certify_state(s);
    EXPECT_DOUBLE_EQ(residual(r, "equilibrium").value, 0.375);
    EXPECT_EQ(residual(r, "equilibrium").worst, j);
    EXPECT_DOUBLE_EQ(r.max_residual, 0.375);
    EXPECT_FALSE(certify_state(s, 0.37).passed);
    EXPECT_TRUE(certify_state(s, 0.38).passed);
  }
}

// The equilibrium residual reads free dofs away from Γ3 only: the reaction of a clamped node and
// the nodal force of a Γ3 node (that is the contact traction) are not residuals.
TEST(Certificate, EquilibriumSkipsClampedAndGamma3Dofs) {
  const Fig2& f = fig2();
  ContactState s = f.sol.state;
  const int v3 = f.md.contact.node[0];
  Index clamped = -1;
  for (Index v = 0; v < f.md.mesh.num_nodes(); ++v)
    if (f.md.clamped[v]) clamped = v;
  ASSERT_GE(clamped, 0);
  s.residual[2 * v3] = 1e6 * f.md.f.cwiseAbs().maxCoeff();
  s.residual[2 * clamped + 1] = 1e6 * f.md.f.cwiseAbs().maxCoeff();
  EXPECT_LE(residual(certify_state(s), "equilibrium").value, 1e-12);
}

// A NaN anywhere fails the certificate: it is read as an infinite residual, never as a pass
// (std::max(0, NaN) is 0: the residuals must not go through it).
TEST(Certificate, NanIsAFailure) {
  const Fig2& f = fig2();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::string field : {"sigma_nu", "u_nu", "sigma_tau", "lambda", "residual"}) {
    SCOPED_TRACE(field);
    ContactState s = f.sol.state;
    if (field == "sigma_nu") s.sigma_nu[0] = nan;
    if (field == "u_nu") s.u_nu[0] = nan;
    if (field == "sigma_tau") s.sigma_tau[0] = nan;
    if (field == "lambda") s.lambda[0] = nan;
    if (field == "residual") s.residual.setConstant(nan);
    const CertificateReport r = certify_state(s);
    EXPECT_EQ(r.max_residual, INF);
    EXPECT_FALSE(r.passed);
  }
}

}  // namespace
}  // namespace hemicontact
