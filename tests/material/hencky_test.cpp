// The Hencky-type law (hencky.hpp): W → σ → C by finite differences, the constants m_F and L_F of
// (12) against sampled pairs of strains and against the tangent's spectrum, and the small-strain
// limit against LinearElastic.

#include <hemicontact/material/hencky.hpp>
#include <hemicontact/material/linear_elastic.hpp>
#include <hemicontact/material/material_factory.hpp>

#include "support/expect_error.hpp"
#include "support/fd_check.hpp"

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include <random>

using namespace hemicontact;

namespace {

// E = 2000, ν = 0.4 (the paper's constants): κ = E/(3(1−2ν)) = 3333.3, μ_0 = E/(2(1+ν)) = 714.3.
constexpr double E = 2000, NU = 0.4;

// Strain (Voigt, engineering shears) → Frobenius coordinates: shears carry the factor 1/√2 there
// (|ε|² = Σ ε_ii² + 2 Σ ε_ij² = Σ v_i² + ½ Σ γ_ij²); stresses σ_ij carry √2. Then ⟨σ, ε⟩ = σ_voigt·ε_voigt.
double strain_norm(const Vec& v, int d) {
  return std::sqrt(v.head(d).squaredNorm() + 0.5 * v.tail(v.size() - d).squaredNorm());
}
double stress_norm(const Vec& s, int d) {
  return std::sqrt(s.head(d).squaredNorm() + 2 * s.tail(s.size() - d).squaredNorm());
}

// The tangent as an operator on symmetric tensors with the Frobenius inner product: Ĉ = S C S,
// S = diag(1, .., √2, ..) (stress coordinates × √2 on shears, strain coordinates ÷ √2).
Mat frobenius_tangent(const Mat& C, int d) {
  Vec S = Vec::Ones(C.rows());
  S.tail(C.rows() - d).setConstant(std::sqrt(2.0));
  return S.asDiagonal() * C * S.asDiagonal();
}

// A random strain whose size is `scale` (in each Voigt component, uniform in [−scale, scale]).
Vec random_strain(std::mt19937& rng, int d, double scale) {
  std::uniform_real_distribution<double> u(-1, 1);
  Vec v(voigt_size(d));
  for (Index i = 0; i < v.size(); ++i) v[i] = scale * u(rng);
  return v;
}

struct Case {
  const char* name;
  int dim;
  double shear_ratio, eps_ref;
};

const Case kCases[] = {
    {"Soft2D", 2, 0.3, 0.01}, {"Stiff2D", 2, 2.5, 0.05}, {"Soft3D", 3, 0.3, 0.01}, {"Stiff3D", 3, 2.5, 0.05}};

class HenckyLaw : public ::testing::TestWithParam<Case> {};

}  // namespace

// Central differences, step 1e-6 on strains of size ~ε_ref ∈ [0.01, 0.05] (and up to 30 ε_ref):
// truncation h²/6·|W'''| ~ 1e-12·μ_0/ε_ref ≲ 1e-7 absolute against |σ| ~ 10..1e3, round-off
// ε_mach|W|/h ~ 1e-10·|W|; 1e-6 relative (1e-5 for the tangent, one more difference) leaves margin.
TEST_P(HenckyLaw, FiniteDifferences) {
  const Case c = GetParam();
  const Hencky law = Hencky::from_young(E, NU, c.shear_ratio, c.eps_ref, c.dim);
  std::mt19937 rng(7);
  for (double scale : {0.1, 1.0, 5.0, 30.0}) {
    for (int k = 0; k < 5; ++k) {
      const Vec e = random_strain(rng, c.dim, scale * c.eps_ref);
      const Vec fd_s = test::fd_gradient([&](const Vec& v) { return law.energy_density(v); }, e);
      EXPECT_TRUE(test::near_rel(law.stress(e), fd_s, 1e-6, 0)) << "stress, scale " << scale;
      const Mat fd_C = test::fd_jacobian([&](const Vec& v) { return law.stress(v); }, e);
      const Mat C = law.tangent(e);
      EXPECT_TRUE(test::near_rel(C, fd_C, 1e-5, 0)) << "tangent, scale " << scale;
      EXPECT_LE((C - C.transpose()).cwiseAbs().maxCoeff(), 1e-13 * C.cwiseAbs().maxCoeff());
    }
  }
}

// (12)(a), (12)(b) on random pairs, with the Frobenius norms (not the Voigt 2-norm: a missing √2
// on shears would show up as a ratio outside [m_F, L_F]). Pairs far apart (secant) and close
// (the tangent). Then the spectrum of the Frobenius tangent lies in [m_F, L_F] for all strains,
// and the bounds are sharp: they are reached at the strains the derivation names (hencky.hpp).
TEST_P(HenckyLaw, MonotoneAndLipschitzConstants) {
  const Case c = GetParam();
  const int d = c.dim;
  const Hencky law = Hencky::from_young(E, NU, c.shear_ratio, c.eps_ref, d);
  const double mF = law.m_F(), LF = law.L_F();
  ASSERT_GT(mF, 0);
  std::mt19937 rng(11);
  double lo = INF, hi = 0;
  for (double scale : {0.1, 1.0, 10.0, 100.0}) {
    for (int k = 0; k < 200; ++k) {
      const Vec a = random_strain(rng, d, scale * c.eps_ref);
      const Vec b =
          (k % 2) ? random_strain(rng, d, scale * c.eps_ref) : Vec(a + random_strain(rng, d, 1e-3 * scale * c.eps_ref));
      const Vec ds = law.stress(a) - law.stress(b), de = a - b;
      const double n2 = std::pow(strain_norm(de, d), 2);
      const double mono = ds.dot(de) / n2, lip = stress_norm(ds, d) / strain_norm(de, d);
      EXPECT_GE(mono, mF * (1 - 1e-12)) << "scale " << scale;
      EXPECT_LE(lip, LF * (1 + 1e-12)) << "scale " << scale;
      lo = std::min(lo, mono);
      hi = std::max(hi, lip);
      Eigen::SelfAdjointEigenSolver<Mat> es(frobenius_tangent(law.tangent(a), d));
      EXPECT_GE(es.eigenvalues().minCoeff(), mF * (1 - 1e-12));
      EXPECT_LE(es.eigenvalues().maxCoeff(), LF * (1 + 1e-12));
    }
  }
  std::printf("[ constants] %s: m_F = %.6g (sampled min %.6g), L_F = %.6g (sampled max %.6g)\n", c.name, mF, lo, LF,
              hi);
  // Sharpness: pure shear γ12 at s = 0 and s ≫ s_0 (μ → μ_0 and μ → μ_∞); the spectrum's extremes
  // there are the bounds (to O(√(s_0/s)) at the far end).
  double eig_lo = INF, eig_hi = 0;
  for (double gamma : {0.0, 1e4 * c.eps_ref}) {
    Vec e = Vec::Zero(voigt_size(d));
    e[voigt_size(d) - 1] = gamma;
    Eigen::SelfAdjointEigenSolver<Mat> es(frobenius_tangent(law.tangent(e), d));
    eig_lo = std::min(eig_lo, es.eigenvalues().minCoeff());
    eig_hi = std::max(eig_hi, es.eigenvalues().maxCoeff());
  }
  EXPECT_NEAR(eig_lo, mF, 1e-3 * mF);
  EXPECT_NEAR(eig_hi, LF, 1e-3 * LF);
}

// The small-strain limit is LinearElastic(E, ν) (plane strain / 3D): tangent at 0 equal to D, and
// with μ_∞ = μ_0 the law is linear at every strain, with LinearElastic's m_F and L_F.
TEST_P(HenckyLaw, SmallStrainLimitIsLinearElastic) {
  const Case c = GetParam();
  const LinearElastic lin(E, NU, c.dim == 2 ? PlaneMode::STRAIN : PlaneMode::NONE_3D);
  const Hencky law = Hencky::from_young(E, NU, c.shear_ratio, c.eps_ref, c.dim);
  const Vec zero = Vec::Zero(voigt_size(c.dim));
  EXPECT_TRUE(test::near_rel(law.tangent(zero), lin.D(), 1e-14, 0));
  EXPECT_TRUE(law.stress(zero).isZero(0));  // (12)(d): F(0) = 0
  const Hencky flat = Hencky::from_young(E, NU, 1.0, c.eps_ref, c.dim);
  std::mt19937 rng(3);
  for (int k = 0; k < 10; ++k) {
    const Vec e = random_strain(rng, c.dim, 10 * c.eps_ref);
    EXPECT_TRUE(test::near_rel(flat.stress(e), lin.stress(e), 1e-13, 0));
    EXPECT_NEAR(flat.energy_density(e), lin.energy_density(e), 1e-13 * lin.energy_density(e));
    EXPECT_TRUE(test::near_rel(flat.tangent(e), lin.D(), 1e-13, 0));
  }
  EXPECT_NEAR(flat.m_F(), lin.m_F(), 1e-12 * lin.m_F());
  EXPECT_NEAR(flat.L_F(), lin.L_F(), 1e-12 * lin.L_F());
  // The nonlinear law's constants bracket the linear one's from the μ range.
  EXPECT_FALSE(law.is_linear());
  EXPECT_NE(law.describe().find("hencky"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Cases, HenckyLaw, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

// The closed forms for the paper's E, ν with μ_∞ = μ_0/2 (the hencky scene): κ = 10000/3,
// μ_0 = 5000/7; 2D: m_F = min(2μ_∞, 2κ + 2μ_∞/3) = 2μ_∞ = 5000/7, L_F = max(2μ_0, 2κ + 2μ_0/3)
// = 20000/3 + 10000/21 = 150000/21; 3D: m_F = 2μ_∞, L_F = 3κ = 10000.
TEST(Hencky, ClosedFormConstants) {
  const Hencky h2 = Hencky::from_young(E, NU, 0.5, 0.02, 2), h3 = Hencky::from_young(E, NU, 0.5, 0.02, 3);
  EXPECT_NEAR(h2.kappa(), 10000.0 / 3, 1e-10);
  EXPECT_NEAR(h2.mu0(), 5000.0 / 7, 1e-10);
  EXPECT_NEAR(h2.m_F(), 5000.0 / 7, 1e-10);
  EXPECT_NEAR(h2.L_F(), 150000.0 / 21, 1e-9);
  EXPECT_NEAR(h3.m_F(), 5000.0 / 7, 1e-10);
  EXPECT_NEAR(h3.L_F(), 10000.0, 1e-9);
  // μ(s) and Φ(s): μ(0) = μ_0, μ(s_0) − μ_∞ = (μ_0 − μ_∞)/√2, Φ' = μ by differences.
  const double s0 = 0.02 * 0.02;
  EXPECT_DOUBLE_EQ(h2.mu(0), h2.mu0());
  EXPECT_NEAR(h2.mu(s0) - h2.mu_inf(), (h2.mu0() - h2.mu_inf()) / std::sqrt(2.0), 1e-10);
  // Step 1e-4 (s + s_0): truncation ~1e-8 relative (μ varies on the scale s + s_0), round-off
  // ε_mach μ/h ≲ 1e-5 absolute against |μ'| ≥ 1e2.
  for (double s : {1e-8, s0, 100 * s0}) {
    const double hs = 1e-4 * (s + s0);
    EXPECT_NEAR((h2.Phi(s + hs) - h2.Phi(s - hs)) / (2 * hs), h2.mu(s), 1e-6 * h2.mu(s));
    EXPECT_NEAR((h2.mu(s + hs) - h2.mu(s - hs)) / (2 * hs), h2.dmu(s), 1e-6 * std::abs(h2.dmu(s)));
  }
}

TEST(Hencky, FactoryErrorsNameTheKey) {
  nlohmann::json m = {{"model", "hencky"},  {"E", E},         {"nu", NU}, {"plane", "stress"},
                      {"shear_ratio", 0.5}, {"eps_ref", 0.02}};
  test::expect_input_error([&] { make_material(m, 2); }, {"material.plane", "plane strain"});
  EXPECT_EQ(make_material(m, 3)->dim(), 3);  // plane is irrelevant in 3D
  m["plane"] = "strain";
  EXPECT_FALSE(make_material(m, 2)->is_linear());
  m["eps_ref"] = nullptr;
  test::expect_input_error([&] { make_material(m, 2); }, {"material.eps_ref", "required"});
  m["eps_ref"] = 0.02;
  m["nu"] = 0.5;
  test::expect_input_error([&] { make_material(m, 2); }, {"material.nu"});
  nlohmann::json lin = {{"model", "linear_elastic"}, {"E", E}, {"nu", NU}, {"plane", "strain"}, {"shear_ratio", 0.5}};
  test::expect_input_error([&] { make_material(lin, 2); }, {"material.shear_ratio", "hencky"});
  lin.erase("shear_ratio");
  EXPECT_TRUE(make_material(lin, 2)->is_linear());
}
