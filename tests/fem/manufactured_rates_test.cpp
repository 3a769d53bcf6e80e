// Manufactured smooth solution on the unit square, clamped on the whole boundary: the P1 errors
// must decrease at the a-priori rates, in the energy norm and in L2, on every kind of mesh.

#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/material/linear_elastic.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/generators.hpp>

#include "support/fem_problem.hpp"
#include "support/manufactured.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace hemicontact;
using hemicontact::test::Field2;

namespace {

using test::manufactured::C2;
using test::manufactured::dp;
using test::manufactured::eps_exact;
using test::manufactured::p;
using test::manufactured::PI;
using test::manufactured::u_exact;

// Body force f0 = −div σ(u) for σ = a tr(ε) I + b ε (paper §5, plane stress: a = Eκ/(1−κ²),
// b = E/(1+κ)).
//   (div σ)_i = a ∂_i(div u) + b ∂_j ε_ij,   ∂_j ε_ij = ½ (Δu_i + ∂_i div u),
//   so  f0 = −(a + b/2) ∇(div u) − (b/2) Δu.
// With s = sin π·, c = cos π·, div u = π c(x) s(y) + C2 p(x) p'(y), p'' = −2:
//   ∂x div u = −π² s(x) s(y) + C2 p'(x) p'(y),     ∂y div u = π² c(x) c(y) − 2 C2 p(x),
//   Δu1 = −2π² s(x) s(y),                          Δu2 = −2 C2 (p(x) + p(y)).
// (BodyForceIsMinusDivSigma below checks this against finite differences of σ.)
Field2 body_force(double a, double b) {
  return [a, b](double x, double y) {
    const double sx = std::sin(PI * x), sy = std::sin(PI * y), cx = std::cos(PI * x), cy = std::cos(PI * y);
    const double ddx = -PI * PI * sx * sy + C2 * dp(x) * dp(y);
    const double ddy = PI * PI * cx * cy - 2 * C2 * p(x);
    const double lap1 = -2 * PI * PI * sx * sy, lap2 = -2 * C2 * (p(x) + p(y));
    return Eigen::Vector2d(-(a + b / 2) * ddx - (b / 2) * lap1, -(a + b / 2) * ddy - (b / 2) * lap2);
  };
}

const LinearElastic& paper_linear_elastic() {
  static const LinearElastic mat(2000, 0.4, PlaneMode::STRESS);
  return mat;
}

BoundarySpec clamp_all_sides() {
  BoundarySpec spec;
  for (const char* side : {"left", "right", "bottom", "top"}) {
    BoundarySelector s;
    s.side = side;
    s.context = std::string("gamma1.") + side;
    spec.gamma1.push_back(s);
  }
  return spec;
}

}  // namespace

// The quadrature of the test support integrates x^i y^j, i + j ≤ 4, exactly on the reference
// triangle (∫ x^i y^j = i! j! / (i+j+2)!); with 20-digit constants the only error is round-off
// (a few ulps of values ≤ 0.5, hence 1e-15).
TEST(DunavantRule, ExactToDegreeFour) {
  const auto& q = test::dunavant4();
  const auto fact = [](int n) {
    double f = 1;
    for (int k = 2; k <= n; ++k) f *= k;
    return f;
  };
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; i + j <= 4; ++j) {
      double s = 0;
      for (int k = 0; k < 6; ++k) s += 0.5 * q.w[k] * std::pow(q.bary[k][1], i) * std::pow(q.bary[k][2], j);
      EXPECT_NEAR(s, fact(i) * fact(j) / fact(i + j + 2), 1e-15) << "x^" << i << " y^" << j;
    }
  // Degree 5 is not integrated exactly (so the check above could fail for a wrong rule).
  double s5 = 0;
  for (int k = 0; k < 6; ++k) s5 += 0.5 * q.w[k] * std::pow(q.bary[k][1], 5);
  EXPECT_GT(std::abs(s5 - fact(5) / fact(7)), 1e-6);
}

// The hand derivation of f0 against central differences of σ(x) = D ε(x): step h = 1e-4 gives a
// truncation error h²/6 · |∂³σ| ≈ 2e-9 · π³ · |D| ~ 1e-4 absolute against |f0| ~ 1e4, i.e. 1e-8
// relative, and round-off ε|σ|/h ≈ 2e-12 · |D| ~ 1e-8 absolute is smaller still; 1e-6 relative leaves a margin.
TEST(ManufacturedSolution, BodyForceIsMinusDivSigma) {
  const auto& mat = paper_linear_elastic();
  const Eigen::Matrix3d D = mat.D();
  const Field2 f0 = body_force(mat.a(), mat.b());
  const double h = 1e-4;
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0.3, 0.7}, {0.11, 0.42}, {0.8, 0.25}}) {
    // Voigt stress (σ11, σ22, σ12): (div σ)_x = ∂x σ11 + ∂y σ12, (div σ)_y = ∂x σ12 + ∂y σ22.
    const Eigen::Vector3d dsx = D * (eps_exact(x + h, y) - eps_exact(x - h, y)) / (2 * h);
    const Eigen::Vector3d dsy = D * (eps_exact(x, y + h) - eps_exact(x, y - h)) / (2 * h);
    const Eigen::Vector2d div(dsx[0] + dsy[2], dsx[2] + dsy[1]);
    const Eigen::Vector2d f = f0(x, y);
    EXPECT_LE((f + div).norm(), 1e-6 * f.norm()) << "at (" << x << ", " << y << ")";
  }
}

class Convergence : public ::testing::TestWithParam<Diagonal> {};

// A-priori estimates for P1 on shape-regular meshes and u ∈ H²:  ‖u − u_h‖_E = O(h) (Céa +
// interpolation) and ‖u − u_h‖_L2 = O(h²) (Aubin–Nitsche; the square is convex). Halving h must
// then divide the errors by 2 and 4, i.e. observed orders log2(e_n / e_2n) → 1 and 2. The
// pre-asymptotic terms are O(h) relative, so at the finest pairs (h = 1/16 → 1/32 → 1/64) the
// orders are within a few percent of the limit; we require ≥ 0.9 and ≥ 1.85. A wrong stiffness
// or load (e.g. a factor in a shear term) gives an O(1) error that does not decrease: order ≈ 0.
// Quadrature: degree 4 is exact for f0·φ up to O(h⁵) per cell, far below the O(h) / O(h²) errors.
TEST_P(Convergence, ObservedOrders) {
  const Diagonal diag = GetParam();
  const auto& mat = paper_linear_elastic();
  const Field2 f0 = body_force(mat.a(), mat.b());
  const std::vector<int> ns = {4, 8, 16, 32, 64};
  std::vector<double> e_energy, e_l2;
  for (int n : ns) {
    RectangleSpec spec;
    spec.nx = spec.ny = n;
    spec.diagonal = diag;
    Mesh m = make_rectangle(spec);
    assign_boundary(m, clamp_all_sides());
    const Vec u = test::solve_clamped(m, mat, test::assemble_smooth_load(m, f0));
    e_energy.push_back(test::energy_error(m, u, eps_exact, mat.D()));
    e_l2.push_back(test::l2_error(m, u, u_exact));
  }
  std::printf("[ orders   ] %-9s  n   energy error  order   L2 error      order\n", to_string(diag));
  for (size_t k = 0; k < ns.size(); ++k) {
    const double oe = k ? std::log2(e_energy[k - 1] / e_energy[k]) : NAN;
    const double ol = k ? std::log2(e_l2[k - 1] / e_l2[k]) : NAN;
    std::printf("[ orders   ] %-9s %3d  %.5e  %5.3f   %.5e  %5.3f\n", to_string(diag), ns[k], e_energy[k], oe, e_l2[k],
                ol);
    if (k) {
      EXPECT_LT(e_energy[k], e_energy[k - 1]) << "n = " << ns[k];
      EXPECT_LT(e_l2[k], e_l2[k - 1]) << "n = " << ns[k];
    }
    if (k + 2 >= ns.size()) {  // the two finest pairs
      EXPECT_GE(oe, 0.9) << "energy order, n = " << ns[k - 1] << " -> " << ns[k];
      EXPECT_GE(ol, 1.85) << "L2 order, n = " << ns[k - 1] << " -> " << ns[k];
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllDiagonals, Convergence,
                         ::testing::Values(Diagonal::RIGHT, Diagonal::LEFT, Diagonal::SYMMETRIC, Diagonal::CROSSED),
                         [](const ::testing::TestParamInfo<Diagonal>& info) {
                           return std::string(to_string(info.param));
                         });
