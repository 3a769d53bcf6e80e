// The paper's scene with the nonlinear Hencky law (problems/sofonea2017-fig2-hencky.json): solved
// and certified in the full space by both backends, condensation refused, and — with a constant
// shear modulus (μ_∞ = μ_0) — the same solution as the linear plane-strain law.

#include <hemicontact/config.hpp>
#include <hemicontact/mesh/mesh.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/solve.hpp>

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

// Certificate ≤ 1e-8 (the default check.certificate_tol) with ipopt and newton; both minimize the
// same strongly convex-in-the-interior energy to the backend tolerance (1e-12, scaled) and the same
// ε-smoothing (1e-10·U_s), so they agree to ~1e-9 relative in u and energy.
TEST(HenckyScene, SolvesCertifiedWithBothBackends) {
  if (!HEMICONTACT_HAS_IPOPT) GTEST_SKIP() << "built without Ipopt (coinor-libipopt-dev): the comparison needs both backends";
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
  const Solution l =
      solve_scene({"mesh.n=16", "solver.backend=newton", "solver.formulation=full", "material.model=linear_elastic",
                   "material.shear_ratio=null", "material.eps_ref=null"});
  ASSERT_TRUE(h.ok()) << h.message;
  ASSERT_TRUE(l.ok()) << l.message;
  const double U = l.u.cwiseAbs().maxCoeff();
  const double du = (h.u - l.u).cwiseAbs().maxCoeff();
  std::printf("[ hencky   ] mu constant vs linear plane strain: max|du|/max|u| = %.3e, energies %.12g, %.12g\n", du / U,
              h.energy, l.energy);
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

namespace {

// The unit cube as n³ cubes of 6 tetrahedra around each cube's (0,0,0)–(1,1,1) diagonal (Kuhn's
// split is translation invariant, so neighbouring cubes share their face diagonals: conforming),
// with facet groups "top" (z = 1) and "bottom" (z = 0).
Mesh kuhn_cube(int n) {
  Mesh m;
  m.dim = 3;
  const int N = n + 1;
  const auto id = [N](int i, int j, int k) { return i + N * (j + N * k); };
  m.points.resize(N * N * N, 3);
  for (int k = 0; k < N; ++k)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) m.points.row(id(i, j, k)) << double(i) / n, double(j) / n, double(k) / n;
  const int perms[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  m.cells.resize(6 * n * n * n, 4);
  int c = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& p : perms) {
          const auto corner = [&](int bits) {
            return id(i + (bits & 1), j + ((bits >> 1) & 1), k + ((bits >> 2) & 1));
          };
          const int a = p[0], b = a | p[1];
          m.cells.row(c) << corner(0), corner(a), corner(b), corner(7);
          Eigen::Matrix3d J;
          for (int q = 0; q < 3; ++q)
            J.col(q) = (m.points.row(m.cells(c, q + 1)) - m.points.row(m.cells(c, 0))).transpose();
          if (J.determinant() < 0) std::swap(m.cells(c, 1), m.cells(c, 2));
          ++c;
        }
  extract_boundary_facets(m);
  for (Index f = 0; f < m.num_facets(); ++f) {
    bool top = true, bottom = true;
    for (int q = 0; q < 3; ++q) {
      top = top && m.points(m.facets(f, q), 2) == 1.0;
      bottom = bottom && m.points(m.facets(f, q), 2) == 0.0;
    }
    if (top) m.facet_groups["top"].push_back(f);
    if (bottom) m.facet_groups["bottom"].push_back(f);
  }
  m.origin = "kuhn cube " + std::to_string(n) + "^3";
  return m;
}

Solution solve_cube(const json& material) {
  json s = {{"material", material},
            {"boundary", {{"gamma1", {{{"physical", "top"}}}}, {"gamma3", {{{"physical", "bottom"}}}}}},
            {"loads", {{"body_force", {0, 0, -800}}}},
            {"contact",
             {{"gap", 0.15},
              {"normal_law", {{"type", "paper"}, {"c1", 100}, {"c2", -100}, {"c3", 400}, {"r1", 0.1}, {"r2", 0.15}}},
              {"friction", {{"type", "coulomb_layer"}, {"mu", 0.2}}}}},
            {"solver", {{"backend", "newton"}, {"formulation", "full"}}}};
  s = validate_scene(s);
  Mesh m = kuhn_cube(3);
  assign_scene_boundary(m, s);
  const Model md = build_model(s, std::move(m));
  return solve(md, solve_options_from_scene(s));
}

}  // namespace

// The 3D path end to end (NonlinearElasticEnergy on tetrahedra, 3D friction, certificate from the
// internal force): certified, and with μ_∞ = μ_0 the linear 3D solution to round-off (as in 2D).
TEST(HenckyScene, ThreeDimensionalCubeOnTheLayer) {
  const json lin = {{"model", "linear_elastic"}, {"E", 2000}, {"nu", 0.4}};
  json hen = {{"model", "hencky"}, {"E", 2000}, {"nu", 0.4}, {"shear_ratio", 1.0}, {"eps_ref", 0.1}};
  const Solution l = solve_cube(lin);
  const Solution h1 = solve_cube(hen);
  hen["shear_ratio"] = 0.5;
  const Solution h = solve_cube(hen);
  for (const Solution* s : {&l, &h1, &h}) {
    EXPECT_TRUE(s->ok()) << s->message;
    EXPECT_LE(s->certificate.max_residual, 1e-8);
  }
  const auto counts = h.status_counts();
  std::printf("[ hencky 3D] max u_nu linear %.6g, hencky %.6g; energies %.10g, %.10g; contact/compliance %d/%d\n",
              l.max_u_nu, h.max_u_nu, l.energy, h.energy, counts.at("contact"), counts.at("compliance"));
  EXPECT_GT(l.max_u_nu, 0);  // the layer is compressed: the contact terms are active
  const double U = l.u.cwiseAbs().maxCoeff();
  EXPECT_LE((h1.u - l.u).cwiseAbs().maxCoeff(), 1e-12 * U);
  EXPECT_NEAR(h1.energy, l.energy, 1e-12 * std::abs(l.energy));
  // Softer in shear: the body sags further and its energy is lower.
  EXPECT_GE(h.max_u_nu, l.max_u_nu);
  EXPECT_LT(h.energy, l.energy);
}
