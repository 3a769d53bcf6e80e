// One free node, answers derived by hand, through the whole pipeline (validate_scene →
// assign_scene_boundary → build_model → solve() with Ipopt → certificate, statuses, energy).
//
// ---------------------------------------------------------------- the hand derivation
// Mesh: one triangle A = (0,1), B = (1,1), C = (0.5,0), stored as (A, C, B) so that it is
// positively oriented; |T| = ½·|(C−A) × (B−A)| = ½. Γ1 = AB (A and B clamped), Γ3 = AC ∪ BC.
// A and B lie on Γ1, so C is the only free node (and the only Γ3 node).
//  - Γ3 data at C: |AC| = |BC| = √5/2, so w = (|AC| + |BC|)/2 = √5/2. The outward normals of AC
//    and BC are (−2,−1)/√5 and (2,−1)/√5; their length-weighted average is (0, −2/√5), normalized
//    ν = (0, −1); τ = (−ν_y, ν_x) = (1, 0). Hence u_ν = −u_y, u_τ = u_x.
//  - Stiffness: φ_C = 1 − y, ∇φ_C = (0, −1). For u = (a, b) φ_C: ε11 = 0, ε22 = −b, 2ε12 = −a.
//    Plane stress, D = E/(1−ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]], so
//    ½ a(u,u) = |T|·½ E/(1−ν²) (b² + (1−ν)/2 a²): the reduced stiffness is diagonal,
//    k_ν = |T| E/(1−ν²) (along ν = −e_y) and k_τ = |T| E/(1−ν²)·(1−ν)/2 = |T| E/(2(1+ν)).
//  - Loads: a constant body force f0 gives each vertex |T|/3·f0, so F = f0/6 at C and
//    F_ν = F·ν = −F_y, F_τ = F_x.
//  - Energy in the local unknowns (u_ν, u_τ), λ = F_b(u_ν) = μ p(u_ν):
//      Π(u) = ½k_ν u_ν² + ½k_τ u_τ² − F_ν u_ν − F_τ u_τ + w j(u_ν) + w μ p(u_ν)|u_τ|,  u_ν ≤ g.
//    Normal and tangential parts decouple (K diagonal; λ depends on u_ν only), so:
//      normal: k_ν u + w p(u) = F_ν (+ a rigid reaction R ≥ 0 when u = g);
//      tangential: u_τ = 0 if |F_τ| ≤ w μ p(u_ν), else u_τ = (F_τ − sign(F_τ) w μ p(u_ν))/k_τ.
//    With the paper's law (32): p = 0 for r ≤ 0, c1 r on (0, r1], c1 r1 + c2 (r − r1) on (r1, r2),
//    c1 r1 + c2 (r2 − r1) + c3 (r − r2) beyond; j = ∫0^r p.
//  - Stability of the softening branch: Π_ν″ = k_ν + w c2 there. If k_ν + w c2 ≤ 0, i.e.
//    E ≤ E_crit = w|c2|(1−ν²)/|T| (≈ 209.6 for ν = 0.25), a stationary point on (r1, r2) is a
//    maximum of the 1-D energy: the branch is unstable and no solution lives on it. We take
//    E = 1000 (k_ν + w c2 ≈ 421.5 > 0); then Π_ν″ > 0 on every branch, Π is strictly convex in u_ν
//    and the hand solution is the unique minimizer.
// Every expected number below is computed from these formulas; loads are chosen from target
// displacements at ≥ 20% of a branch width from the kinks, so the statuses are unambiguous.
// Tolerance: 1e-8 relative to the displacement scale U (the certificate tolerance); the smoothing
// is exact off its windows (|u_τ| ≥ ε_τ, u_ν off the kinks) and ε_final = 1e-10·U_s, so only the
// backend tolerance (solver.tol, on the scaled problem) separates the numerical from the hand
// solution. Each case runs through three pipelines (SingleNode param, see solver_block).

#include <hemicontact/config.hpp>
#include <hemicontact/mesh/mesh.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace hemicontact {
namespace {

using json = nlohmann::json;

// ---------------------------------------------------------------- data of every case
constexpr double E = 1000, POISSON = 0.25, AREA = 0.5;
constexpr double C1 = 100, C2 = -100, C3 = 400, R1 = 0.1, R2 = 0.15, MU = 0.2;
const double W = std::sqrt(5.0) / 2;                     // (|AC| + |BC|)/2
const double K_NU = AREA * E / (1 - POISSON * POISSON);  // |T| E/(1−ν²)
const double K_TAU = AREA * E / (2 * (1 + POISSON));     // |T| E/(2(1+ν))
constexpr double TOL = 1e-8;                             // certificate tolerance

/// p_ν of (32), by hand.
double p_hand(double r) {
  if (r <= 0) return 0;
  if (r <= R1) return C1 * r;
  if (r < R2) return C1 * R1 + C2 * (r - R1);
  return C1 * R1 + C2 * (R2 - R1) + C3 * (r - R2);
}
/// j_ν = ∫0^r p_ν, by hand (areas of the pieces).
double j_hand(double r) {
  if (r <= 0) return 0;
  if (r <= R1) return 0.5 * C1 * r * r;
  const double j1 = 0.5 * C1 * R1 * R1;
  if (r < R2) return j1 + C1 * R1 * (r - R1) + 0.5 * C2 * (r - R1) * (r - R1);
  const double j2 = j1 + C1 * R1 * (R2 - R1) + 0.5 * C2 * (R2 - R1) * (R2 - R1);
  const double p2 = C1 * R1 + C2 * (R2 - R1);
  return j2 + p2 * (r - R2) + 0.5 * C3 * (r - R2) * (r - R2);
}

// ---------------------------------------------------------------- mesh and scene

Mesh one_triangle() {
  Mesh m;
  m.dim = 2;
  m.points.resize(3, 2);
  m.points << 0.0, 1.0,  // A
      1.0, 1.0,          // B
      0.5, 0.0;          // C
  m.cells.resize(1, 3);
  m.cells << 0, 2, 1;  // (A, C, B): counter-clockwise
  m.origin = "one triangle (hand-built)";
  extract_boundary_facets(m);
  const auto facet = [&](int a, int b) -> Index {
    for (Index f = 0; f < m.num_facets(); ++f)
      if ((m.facets(f, 0) == a && m.facets(f, 1) == b) || (m.facets(f, 0) == b && m.facets(f, 1) == a)) return f;
    ADD_FAILURE() << "no boundary facet (" << a << ", " << b << ")";
    return -1;
  };
  m.facet_groups["clamp"] = {facet(0, 1)};
  m.facet_groups["contact"] = {facet(0, 2), facet(1, 2)};
  return m;
}

struct NodeCase {
  double F_nu = 0, F_tau = 0;  ///< nodal load in the local frame
  json gap = "inf";
  json friction = {{"type", "coulomb_layer"}, {"mu", MU}};
  bool all_stages = false;  ///< solver.continuation.certify_below = 0: no early stop once certified
  bool continuation_only = false;  ///< solver.exact.enabled = false: the continuation's path alone
};

/// How solve() is configured: the default (formulation auto → condensed for this linear material,
/// then the exact polish), the full formulation (ElasticEnergy + LoadEnergy, no polish), and the
/// condensed formulation with the polish off — so the raw Ipopt answer is checked too.
json solver_block(const std::string& pipeline) {
  if (pipeline == "full") return {{"formulation", "full"}};
  if (pipeline == "condensed_raw") return {{"formulation", "condensed"}, {"polish", false}};
  return json::object();  // defaults
}

json make_scene(const NodeCase& c, const std::string& pipeline = "default") {
  // F = f0/6 with F_ν = −F_y, F_τ = F_x  ⇒  f0 = 6 (F_τ, −F_ν).
  const json scene = {
      {"description", "one free node (tests/solver/single_node_test.cpp)"},
      {"material", {{"model", "linear_elastic"}, {"E", E}, {"nu", POISSON}, {"plane", "stress"}}},
      {"boundary",
       {{"gamma1", json::array({{{"physical", "clamp"}}})}, {"gamma3", json::array({{{"physical", "contact"}}})}}},
      {"loads", {{"body_force", {6 * c.F_tau, -6 * c.F_nu}}}},
      {"contact",
       {{"gap", c.gap},
        {"normal_law", {{"type", "paper"}, {"c1", C1}, {"c2", C2}, {"c3", C3}, {"r1", R1}, {"r2", R2}}},
        {"friction", c.friction}}},
      {"solver", solver_block(pipeline)},
      {"output", {{"vtu", false}, {"csv", false}}}};
  json s = scene;
  // Every stage of the continuation: no early stop and no hand-over to the exact inner solver
  // (which ends the continuation once the statuses are known).
  if (c.continuation_only) s["solver"]["exact"]["enabled"] = false;
  if (c.all_stages) {
    s["solver"]["continuation"]["certify_below"] = 0;
    s["solver"]["exact"]["enabled"] = false;
  }
  return validate_scene(s);
}

struct NodeSolved {
  std::string pipeline;
  Model md;
  SolveOptions opt;
  Solution sol;
};

NodeSolved run(const NodeCase& c, const std::string& pipeline) {
  const json scene = make_scene(c, pipeline);
  Mesh mesh = one_triangle();
  assign_scene_boundary(mesh, scene);
  NodeSolved r{pipeline, build_model(scene, std::move(mesh)), solve_options_from_scene(scene), {}};
  r.sol = solve(r.md, r.opt);
  return r;
}

/// Expected answer of a case.
struct Expected {
  double u_nu, u_tau;
  std::string status;
  double lambda;                         ///< μ p(u_ν) (or the Tresca bound)
  std::optional<double> rigid_reaction;  ///< R/w = −(σ_ν + ξ) at the obstacle
};

double hand_energy(const NodeCase& c, const Expected& e) {
  return 0.5 * K_NU * e.u_nu * e.u_nu + 0.5 * K_TAU * e.u_tau * e.u_tau - c.F_nu * e.u_nu - c.F_tau * e.u_tau +
         W * j_hand(e.u_nu) + W * e.lambda * std::abs(e.u_tau);
}

/// The tangential answer for a friction bound λ: stick if |F_τ| ≤ wλ, else slip against it.
double u_tau_hand(double F_tau, double lambda) {
  if (std::abs(F_tau) <= W * lambda) return 0.0;
  return (F_tau - std::copysign(W * lambda, F_tau)) / K_TAU;
}

/// Everything every case asserts.
void check_case(const NodeCase& c, const Expected& e, const NodeSolved& r) {
  const Solution& sol = r.sol;
  ASSERT_TRUE(sol.backend_ok) << sol.message;
  ASSERT_TRUE(sol.fixed_point_converged) << sol.message;
  // solver.backend = auto: Ipopt where it is built, else the projected Newton.
  EXPECT_EQ(sol.backend, HEMICONTACT_HAS_IPOPT ? "ipopt" : "newton");
  EXPECT_EQ(sol.formulation, r.pipeline == "full" ? "full" : "condensed");
  if (r.pipeline != "default") {
    EXPECT_FALSE(sol.polish.accepted);  // the raw backend answer
  }
  EXPECT_TRUE(sol.certificate.passed) << "max residual " << sol.certificate.max_residual;
  EXPECT_LE(sol.certificate.max_residual, TOL);
  ASSERT_EQ(sol.status.size(), 1u);
  EXPECT_EQ(sol.status[0].str(), e.status);

  const double U = std::max(std::abs(e.u_nu), std::abs(e.u_tau));
  EXPECT_NEAR(sol.state.u_nu[0], e.u_nu, TOL * U);
  EXPECT_NEAR(sol.state.u_tau[0], e.u_tau, TOL * U);
  // Full displacement at C: u = u_ν ν + u_τ τ = (u_τ, −u_ν); A and B stay at 0.
  ASSERT_EQ(sol.u.size(), 6);
  EXPECT_NEAR(sol.u[4], e.u_tau, TOL * U);
  EXPECT_NEAR(sol.u[5], -e.u_nu, TOL * U);
  EXPECT_EQ(sol.u.head(4).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(sol.state.lambda[0], e.lambda, TOL * std::max(1.0, e.lambda));

  // Tractions from the equilibrium (K u − f)_C = w σ: σ_ν = (k_ν u_ν − F_ν)/w, σ_τ = (k_τ u_τ − F_τ)/w.
  const double S = std::max({std::abs(c.F_nu), std::abs(c.F_tau)}) / W;
  EXPECT_NEAR(sol.state.sigma_nu[0], (K_NU * e.u_nu - c.F_nu) / W, TOL * S);
  EXPECT_NEAR(sol.state.sigma_tau[0], (K_TAU * e.u_tau - c.F_tau) / W, TOL * S);
  // ξ = p(u_ν); the rigid foundation's share −(σ_ν + ξ) is R/w at the obstacle, 0 elsewhere.
  EXPECT_NEAR(sol.state.xi[0], p_hand(e.u_nu), TOL * S);
  const double rigid = -(sol.state.sigma_nu[0] + sol.state.xi[0]);
  EXPECT_NEAR(rigid, e.rigid_reaction.value_or(0.0), TOL * S);
  if (e.rigid_reaction) {
    EXPECT_GT(*e.rigid_reaction, 0.1 * S);  // clearly active
  }

  // Unsmoothed energy against the hand formula.
  const double E_hand = hand_energy(c, e);
  const double E_scale = 0.5 * K_NU * e.u_nu * e.u_nu + 0.5 * K_TAU * e.u_tau * e.u_tau + std::abs(c.F_nu * e.u_nu) +
                         std::abs(c.F_tau * e.u_tau) + W * std::abs(j_hand(e.u_nu)) + W * e.lambda * std::abs(e.u_tau);
  EXPECT_NEAR(sol.energy, E_hand, TOL * E_scale);
}

class SingleNode : public ::testing::TestWithParam<std::string> {};

// ---------------------------------------------------------------- the model itself

// The hand derivation's ingredients, read back from the assembled model.
TEST(SingleNodeModel, MatchesHandDerivation) {
  Mesh m = one_triangle();
  ASSERT_EQ(m.num_cells(), 1);
  EXPECT_NEAR(m.cell_measure(0), AREA, 1e-15);  // positively oriented
  ASSERT_EQ(m.num_facets(), 3);
  for (Index f = 0; f < 3; ++f) {  // outward normals: away from the opposite vertex
    const Vec n = m.facet_normal(f);
    const Vec mid = 0.5 * (m.points.row(m.facets(f, 0)) + m.points.row(m.facets(f, 1))).transpose();
    const Vec centroid = m.points.colwise().mean().transpose();
    EXPECT_GT(n.dot(mid - centroid), 0.0);
  }
  // ∇φ_C from the coordinates: φ = a + b·x solves φ(A) = φ(B) = 0, φ(C) = 1.
  Eigen::Matrix3d V;
  for (int i = 0; i < 3; ++i) V.row(i) << 1.0, m.points(i, 0), m.points(i, 1);
  const Eigen::Vector3d coef = V.fullPivLu().solve(Eigen::Vector3d(0, 0, 1));
  EXPECT_NEAR(coef[1], 0.0, 1e-15);
  EXPECT_NEAR(coef[2], -1.0, 1e-15);
  const NodeCase c{32.0, -3.0};
  const json scene = make_scene(c);
  assign_scene_boundary(m, scene);
  const Model md = build_model(scene, m);
  EXPECT_EQ(md.clamped, (std::vector<bool>{true, true, false}));
  ASSERT_EQ(md.contact.size(), 1);
  EXPECT_EQ(md.contact.node[0], 2);
  EXPECT_NEAR(md.contact.w[0], W, 1e-15);
  EXPECT_NEAR(md.contact.normal(0, 0), 0.0, 1e-15);
  EXPECT_NEAR(md.contact.normal(0, 1), -1.0, 1e-15);
  EXPECT_NEAR(md.contact.tangent(0, 0), 1.0, 1e-15);
  EXPECT_NEAR(md.contact.tangent(0, 1), 0.0, 1e-15);
  EXPECT_TRUE(std::isinf(md.contact.g[0]));
  // Reduced unknowns (x_ν, x_τ) of C; stiffness diagonal with the hand values.
  ASSERT_EQ(md.dofs.n_free(), 2);
  EXPECT_EQ(md.dofs.contact_dof(0, 0), 0);
  EXPECT_EQ(md.dofs.contact_dof(0, 1), 1);
  const Mat Kx = Mat(md.Kx.full());
  EXPECT_NEAR(Kx(0, 0), K_NU, 1e-12 * K_NU);
  EXPECT_NEAR(Kx(1, 1), K_TAU, 1e-12 * K_NU);
  EXPECT_NEAR(Kx(0, 1), 0.0, 1e-12 * K_NU);
  EXPECT_NEAR(Kx(1, 0), 0.0, 1e-12 * K_NU);
  // Nodal load F = |T|/3 f0 in the local frame.
  EXPECT_NEAR(md.fx[0], c.F_nu, 1e-12 * c.F_nu);
  EXPECT_NEAR(md.fx[1], c.F_tau, 1e-12 * c.F_nu);
  // The law and the bound are the paper's.
  ASSERT_TRUE(md.normal_law && md.friction);
  for (double r : {-0.05, 0.05, 0.125, 0.2}) {
    EXPECT_NEAR(md.normal_law->p(r), p_hand(r), 1e-12);
    EXPECT_NEAR(md.normal_law->j(r), j_hand(r), 1e-12);
    EXPECT_NEAR(md.friction->F(r), MU * p_hand(r), 1e-12);
  }
  // The softening branch is stable for this E (file comment).
  EXPECT_GT(K_NU + W * C2, 0.0);
  EXPECT_GT(E, W * std::abs(C2) * (1 - POISSON * POISSON) / AREA);
}

// ---------------------------------------------------------------- (a)–(f)

// (a) + (d): compliance branch, k_ν u + w c1 u = F_ν with 0 < u < r1, and stick |F_τ| ≤ w μ p(u).
TEST_P(SingleNode, ComplianceStick) {
  const double target = 0.5 * R1;
  NodeCase c;
  c.F_nu = (K_NU + W * C1) * target;
  c.F_tau = -0.5 * W * MU * p_hand(target);  // half the bound
  c.gap = 0.15;                              // the paper's g, not reached
  Expected e;
  e.u_nu = c.F_nu / (K_NU + W * C1);
  ASSERT_GT(e.u_nu, 0.2 * R1);
  ASSERT_LT(e.u_nu, 0.8 * R1);
  e.lambda = MU * p_hand(e.u_nu);
  ASSERT_LE(std::abs(c.F_tau), 0.9 * W * e.lambda);
  e.u_tau = u_tau_hand(c.F_tau, e.lambda);
  ASSERT_EQ(e.u_tau, 0.0);
  e.status = "compliance/stick";
  const NodeSolved r = run(c, GetParam());
  check_case(c, e, r);
  // Stick: |u_τ| ≤ 1e-8·U (the status tolerance) and |σ_τ| = |F_τ|/w < λ.
  EXPECT_LE(std::abs(r.sol.state.u_tau[0]), TOL * e.u_nu);
  EXPECT_LT(std::abs(r.sol.state.sigma_tau[0]), e.lambda);
}

// (b) + (e): softening branch, k_ν u + w (c1 r1 + c2 (u − r1)) = F_ν with r1 < u < r2, g > r2,
// and slip+ with u_τ = (F_τ − w μ p(u))/k_τ.
TEST_P(SingleNode, SofteningSlipPlus) {
  ASSERT_GT(K_NU + W * C2, 0.0) << "the softening branch would be unstable (file comment)";
  const double target = 0.5 * (R1 + R2);
  NodeCase c;
  c.F_nu = K_NU * target + W * (C1 * R1 + C2 * (target - R1));
  c.F_tau = 2.0 * W * MU * p_hand(target);  // twice the bound
  c.gap = 0.2;                              // > r2: the obstacle is not reached
  Expected e;
  // k_ν u + w c2 u = F_ν − w (c1 − c2) r1.
  e.u_nu = (c.F_nu - W * (C1 - C2) * R1) / (K_NU + W * C2);
  ASSERT_GT(e.u_nu, R1 + 0.2 * (R2 - R1));
  ASSERT_LT(e.u_nu, R2 - 0.2 * (R2 - R1));
  e.lambda = MU * p_hand(e.u_nu);
  ASSERT_GE(std::abs(c.F_tau), 1.1 * W * e.lambda);
  e.u_tau = (c.F_tau - W * e.lambda) / K_TAU;
  ASSERT_GT(e.u_tau, 0.0);
  e.status = "compliance/slip+";
  const NodeSolved r = run(c, GetParam());
  check_case(c, e, r);
  // Slip: the friction force is on the cone, opposite to the slip: σ_τ = −λ.
  EXPECT_NEAR(r.sol.state.sigma_tau[0], -e.lambda, TOL * c.F_nu / W);
}

// (c) + (e): the obstacle is reached, u = g, when F_ν − k_ν g − w p(g) > 0; that difference is the
// rigid reaction R, R/w = −(σ_ν + ξ). Slip− (friction bound μ p(g): the layer's reaction only, (34)).
TEST_P(SingleNode, ObstacleSlipMinus) {
  const double g = 0.8 * R1;  // on the compliance branch, 20% below r1
  NodeCase c;
  c.gap = g;
  c.F_nu = 1.5 * (K_NU * g + W * p_hand(g));
  c.F_tau = -2.0 * W * MU * p_hand(g);
  Expected e;
  e.u_nu = g;
  const double R = c.F_nu - K_NU * g - W * p_hand(g);
  ASSERT_GT(R, 0.0);
  e.rigid_reaction = R / W;
  e.lambda = MU * p_hand(g);
  e.u_tau = (c.F_tau + W * e.lambda) / K_TAU;
  ASSERT_LT(e.u_tau, 0.0);
  e.status = "contact/slip-";
  const NodeSolved r = run(c, GetParam());
  check_case(c, e, r);
  // σ_ν from the state: (k_ν g − F_ν)/w = −p(g) − R/w.
  EXPECT_NEAR(r.sol.state.sigma_nu[0], -p_hand(g) - R / W, TOL * c.F_nu / W);
}

// (c) + (d) at the paper's g = r2 (as the Fig. 2 contact nodes): u = g sits on a kink of p_ν, where
// p_ν is continuous (p(r2) = c1 r1 + c2 (r2 − r1)); sticking since |F_τ| ≤ w μ p(g).
TEST_P(SingleNode, ObstacleAtPaperGapStick) {
  const double g = R2;
  NodeCase c;
  c.gap = g;
  c.F_nu = 1.5 * (K_NU * g + W * p_hand(g));
  c.F_tau = 0.5 * W * MU * p_hand(g);
  Expected e;
  e.u_nu = g;
  e.rigid_reaction = (c.F_nu - K_NU * g - W * p_hand(g)) / W;
  e.lambda = MU * p_hand(g);
  e.u_tau = u_tau_hand(c.F_tau, e.lambda);
  ASSERT_EQ(e.u_tau, 0.0);
  e.status = "contact/stick";
  check_case(c, e, run(c, GetParam()));
}

// (f): F_ν < 0 lifts the node off the layer: u_ν = F_ν/k_ν < 0, p = 0, and F_b(r ≤ 0) = 0, so
// there is no friction at all: u_τ = F_τ/k_τ (free), σ_τ = 0.
TEST_P(SingleNode, SeparatedNoFriction) {
  NodeCase c;
  c.F_nu = -0.05 * K_NU;
  c.F_tau = 0.02 * K_TAU;
  c.gap = 0.15;
  Expected e;
  e.u_nu = c.F_nu / K_NU;
  ASSERT_LT(e.u_nu, 0.0);
  e.lambda = MU * p_hand(e.u_nu);
  ASSERT_EQ(e.lambda, 0.0);
  e.u_tau = c.F_tau / K_TAU;
  e.status = "separated/slip+";
  const NodeSolved r = run(c, GetParam());
  check_case(c, e, r);
  EXPECT_NEAR(r.sol.state.sigma_tau[0], 0.0, TOL * c.F_tau / W);
  EXPECT_EQ(r.sol.j_term, 0.0);
  EXPECT_EQ(r.sol.friction_term, 0.0);
}

// ---------------------------------------------------------------- (g) the outer loop

// Tresca: F_b ≡ b does not depend on u_ν, so the outer fixed point is skipped (one minimization
// per continuation stage); slip+ at u_τ = (F_τ − w b)/k_τ on the compliance branch.
TEST_P(SingleNode, TrescaSkipsFixedPoint) {
  const double b = 2.0;
  NodeCase c;
  c.friction = {{"type", "tresca"}, {"bound", b}};
  c.F_nu = (K_NU + W * C1) * 0.5 * R1;
  c.F_tau = 1.5 * W * b;
  Expected e;
  e.u_nu = c.F_nu / (K_NU + W * C1);
  e.lambda = b;
  e.u_tau = u_tau_hand(c.F_tau, b);
  ASSERT_GT(e.u_tau, 0.0);
  e.status = "compliance/slip+";
  const NodeSolved r = run(c, GetParam());
  check_case(c, e, r);
  bool skipped = false;
  for (const auto& s : r.sol.skipped) skipped |= s.rfind("fixed_point", 0) == 0;
  EXPECT_TRUE(skipped) << "Solution.skipped should mention fixed_point";
  // One minimization per continuation stage, no loop; when the exact inner solver took over (the
  // condensed pipelines: before any stage, the inner problem being strongly convex, or after one),
  // its records follow the continuation's, and it too runs λ once: one outer iteration, λ = b
  // unchanged.
  const int exact_records = r.sol.handover.used ? r.sol.handover.outer_iterations : 0;
  if (r.sol.handover.used) {
    EXPECT_EQ(exact_records, 1);
  }
  int max_stage = -1;  // no stage ran: −1
  for (const auto& h : r.sol.history) max_stage = std::max(max_stage, h.stage);
  EXPECT_EQ(static_cast<int>(r.sol.history.size()) - exact_records, max_stage + 1);  // one per stage, no loop
  for (const auto& h : r.sol.history) EXPECT_EQ(h.change_lambda, 0.0);
}

// Tresca resists slip even on a separated node (outside (15c), see TrescaBound): stick.
TEST_P(SingleNode, TrescaSeparatedStick) {
  const double b = 2.0;
  NodeCase c;
  c.friction = {{"type", "tresca"}, {"bound", b}};
  c.F_nu = -0.05 * K_NU;
  c.F_tau = 0.5 * W * b;
  Expected e;
  e.u_nu = c.F_nu / K_NU;
  e.lambda = b;
  e.u_tau = u_tau_hand(c.F_tau, b);
  ASSERT_EQ(e.u_tau, 0.0);
  e.status = "separated/stick";
  check_case(c, e, run(c, GetParam()));
}

// Coulomb on the layer: λ = μ p(u_ν) is lagged. The loop starts from λ = F_b(0) = 0 (the first
// minimization is frictionless), and since u_ν does not depend on λ here the fixed point is reached
// after one update; the final stage confirms it in a few iterations and ends at the hand value.
TEST_P(SingleNode, CoulombFixedPointConverges) {
  const double target = 0.5 * R1;
  NodeCase c;
  c.F_nu = (K_NU + W * C1) * target;
  c.F_tau = 3.0 * W * MU * p_hand(target);
  Expected e;
  e.u_nu = c.F_nu / (K_NU + W * C1);
  e.lambda = MU * p_hand(e.u_nu);
  e.u_tau = u_tau_hand(c.F_tau, e.lambda);
  ASSERT_GT(e.u_tau, 0.0);
  e.status = "compliance/slip+";
  c.all_stages = true;  // the final stage's fixed-point loop is what is tested here
  const NodeSolved r = run(c, GetParam());
  check_case(c, e, r);
  for (const auto& s : r.sol.skipped) EXPECT_NE(s.rfind("fixed_point", 0), 0u) << s;
  const auto& h = r.sol.history;
  ASSERT_GE(h.size(), 2u);
  // λ jumps from 0 to μ p(u_ν) after the first minimization: relative change 1.
  EXPECT_NEAR(h.front().change_lambda, 1.0, 1e-12);
  int final_stage = 0, in_final = 0;
  for (const auto& it : h) final_stage = std::max(final_stage, it.stage);
  for (const auto& it : h) in_final += it.stage == final_stage;
  EXPECT_GE(in_final, 2);  // the loop needs two minimizations to see no change
  EXPECT_LE(in_final, 5);  // "a few"
  EXPECT_LE(std::max(h.back().change_u, h.back().change_lambda), r.opt.tol_u);
}

// The early stop (solver.continuation.certify_below): on the same case the default run stops after
// a stage once the polished answer is certified, with fewer minimizations than running every
// stage of the continuation alone (all_stages: no early stop, no exact hand-over), and the same
// answer to round-off (both are the exact polish on the same statuses).
TEST(SingleNodeEarlyStop, CertifiedBeforeTheLastStageGivesTheSameAnswer) {
  const double target = 0.5 * R1;
  NodeCase c;
  c.F_nu = (K_NU + W * C1) * target;
  c.F_tau = 3.0 * W * MU * p_hand(target);
  c.continuation_only = true;  // the continuation's own early stop, against its own all stages
  const NodeSolved early = run(c, "default");
  c.all_stages = true;
  const NodeSolved all = run(c, "default");
  ASSERT_TRUE(early.sol.certificate.passed);
  ASSERT_TRUE(all.sol.certificate.passed);
  EXPECT_LT(early.sol.history.size(), all.sol.history.size());
  EXPECT_LT(early.sol.history.back().stage, all.sol.history.back().stage);
  bool said = false;
  for (const auto& s : early.sol.skipped) said = said || s.rfind("continuation: stages", 0) == 0;
  EXPECT_TRUE(said);
  const double U = all.sol.u.cwiseAbs().maxCoeff();
  EXPECT_LE((early.sol.u - all.sol.u).cwiseAbs().maxCoeff(), 1e-12 * U);
  EXPECT_EQ(early.sol.status[0].str(), all.sol.status[0].str());
}

INSTANTIATE_TEST_SUITE_P(Pipelines, SingleNode, ::testing::Values("default", "full", "condensed_raw"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace hemicontact
