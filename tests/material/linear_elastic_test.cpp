// LinearElastic: the paper's plane-stress law, plane-strain Lamé values, 3D, the constants
// m_F / L_F of (12), and the input checks.

#include <hemicontact/material/linear_elastic.hpp>

#include <hemicontact/core/error.hpp>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdlib>
#include <string>

using namespace hemicontact;

namespace {

// Symmetric d×d tensor → Voigt strain (engineering shears) and Voigt stress → tensor.
Vec to_voigt_strain(const Mat& t) {
  const int d = static_cast<int>(t.rows());
  Vec v(voigt_size(d));
  for (int i = 0; i < d; ++i) v[i] = t(i, i);
  if (d == 2) {
    v[2] = 2 * t(0, 1);
  } else {
    v[3] = 2 * t(1, 2);
    v[4] = 2 * t(0, 2);
    v[5] = 2 * t(0, 1);
  }
  return v;
}

Mat from_voigt_stress(const Vec& s, int d) {
  Mat t(d, d);
  if (d == 2) {
    t << s[0], s[2], s[2], s[1];
  } else {
    t << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  }
  return t;
}

// Frobenius-orthonormal basis of the symmetric d×d tensors: e_i⊗e_i, (e_i⊗e_j + e_j⊗e_i)/√2.
std::vector<Mat> symmetric_basis(int d) {
  std::vector<Mat> basis;
  for (int i = 0; i < d; ++i) {
    Mat E = Mat::Zero(d, d);
    E(i, i) = 1;
    basis.push_back(E);
  }
  for (int i = 0; i < d; ++i)
    for (int j = i + 1; j < d; ++j) {
      Mat E = Mat::Zero(d, d);
      E(i, j) = E(j, i) = 1 / std::sqrt(2.0);
      basis.push_back(E);
    }
  return basis;
}

// Matrix of F on the symmetric tensors in the orthonormal basis: M_ij = E_i : F(E_j).
Mat operator_matrix(const Material& mat) {
  const int d = mat.dim();
  const auto basis = symmetric_basis(d);
  const int n = static_cast<int>(basis.size());
  Mat M(n, n);
  for (int j = 0; j < n; ++j) {
    const Mat sigma = from_voigt_stress(mat.stress(to_voigt_strain(basis[j])), d);
    for (int i = 0; i < n; ++i) M(i, j) = (basis[i].array() * sigma.array()).sum();
  }
  return M;
}

Mat random_symmetric(int d, unsigned seed) {
  std::srand(seed);
  Mat t = Mat::Random(d, d);
  return 0.5 * (t + t.transpose());
}

// All comparisons below are of closed-form quantities O(E) computed in a handful of flops:
// 1e-12 relative is ~1e4 ulps.
constexpr double REL = 1e-12;

}  // namespace

// Paper §5: (Fτ)_ab = Eκ/(1−κ²)(τ11+τ22)δ_ab + E/(1+κ) τ_ab, with E = 2000, κ = 0.4.
TEST(LinearElastic, PlaneStressIsThePapersFormula) {
  const double E = 2000, k = 0.4;
  const LinearElastic mat(E, k, PlaneMode::STRESS);
  EXPECT_EQ(mat.dim(), 2);
  EXPECT_TRUE(mat.is_linear());
  EXPECT_NEAR(mat.a(), 800.0 / 0.84, REL * E);  // 952.38…
  EXPECT_NEAR(mat.b(), 2000.0 / 1.4, REL * E);  // 1428.57…
  for (unsigned seed : {1u, 2u, 3u}) {
    const Mat eps = random_symmetric(2, seed);
    const Mat want = E * k / (1 - k * k) * eps.trace() * Mat::Identity(2, 2) + E / (1 + k) * eps;
    const Mat got = from_voigt_stress(mat.stress(to_voigt_strain(eps)), 2);
    EXPECT_LE((got - want).norm(), REL * E * eps.norm()) << "seed " << seed;
    // W = ½ ε : F ε, and the tangent is the constant D.
    EXPECT_NEAR(mat.energy_density(to_voigt_strain(eps)), 0.5 * (eps.array() * want.array()).sum(), REL * E);
  }
  // The textbook plane-stress matrix E/(1−ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]].
  Mat D(3, 3);
  D << 1, k, 0, k, 1, 0, 0, 0, (1 - k) / 2;
  D *= E / (1 - k * k);
  EXPECT_LE((mat.D() - D).norm(), REL * E);
  EXPECT_LE((mat.tangent(Vec::Random(3)) - D).norm(), REL * E);
}

// Plane strain: λ = Eν/((1+ν)(1−2ν)), μ = E/(2(1+ν)); for E = 2000, ν = 0.4: λ = 2857.142…,
// μ = 714.285…, σ = λ tr ε I + 2μ ε. 3D: the same Lamé values with a 6×6 D.
TEST(LinearElastic, PlaneStrainAnd3DLameValues) {
  const LinearElastic ps(2000, 0.4, PlaneMode::STRAIN);
  EXPECT_NEAR(ps.a(), 2000.0 / 0.7, REL * 2000);
  EXPECT_NEAR(ps.b(), 2 * 2000.0 / 2.8, REL * 2000);
  const LinearElastic solid(2000, 0.4, PlaneMode::NONE_3D);
  EXPECT_EQ(solid.dim(), 3);
  EXPECT_EQ(solid.D().rows(), 6);
  const double lambda = 2000.0 / 0.7, mu = 2000.0 / 2.8;
  for (const LinearElastic* m : {&ps, &solid}) {
    const int d = m->dim();
    const Mat eps = random_symmetric(d, 5);
    const Mat want = lambda * eps.trace() * Mat::Identity(d, d) + 2 * mu * eps;
    const Mat got = from_voigt_stress(m->stress(to_voigt_strain(eps)), d);
    EXPECT_LE((got - want).norm(), REL * 2000 * eps.norm()) << m->describe();
  }
}

// m_F and L_F of (12) are the extreme eigenvalues of F as a symmetric operator on the symmetric
// tensors (Frobenius inner product). The dense eigen-solver is accurate to ~ε·‖M‖, hence REL.
// ν < 0 makes the spherical eigenvalue b + d·a the smaller one, ν > 0 the larger one.
TEST(LinearElastic, MonotonicityAndLipschitzConstantsAreExtremeEigenvalues) {
  for (const PlaneMode mode : {PlaneMode::STRESS, PlaneMode::STRAIN, PlaneMode::NONE_3D})
    for (const double nu : {-0.3, 0.0, 0.25, 0.4, 0.49}) {
      const LinearElastic mat(2000, nu, mode);
      const Mat M = operator_matrix(mat);
      EXPECT_LE((M - M.transpose()).norm(), REL * M.norm());
      const Eigen::SelfAdjointEigenSolver<Mat> eig(M);
      const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
      SCOPED_TRACE(mat.describe());
      EXPECT_NEAR(mat.m_F(), lo, REL * hi);
      EXPECT_NEAR(mat.L_F(), hi, REL * hi);
      EXPECT_GT(mat.m_F(), 0.0);
    }
}

// Out-of-range parameters: the message names the offending key, as the config would.
TEST(LinearElastic, RejectsBadParameters) {
  const auto message = [](double E, double nu, PlaneMode mode) -> std::string {
    try {
      (void)LinearElastic(E, nu, mode);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), EXIT_INPUT);
      return e.what();
    }
    return "(no error)";
  };
  for (const PlaneMode mode : {PlaneMode::STRESS, PlaneMode::STRAIN, PlaneMode::NONE_3D}) {
    for (const double nu : {0.5, 0.7, -1.0, -1.5, std::nan("")})
      EXPECT_NE(message(2000, nu, mode).find("material.nu"), std::string::npos) << "nu = " << nu;
    for (const double E : {0.0, -1.0, INF, std::nan("")})
      EXPECT_NE(message(E, 0.3, mode).find("material.E"), std::string::npos) << "E = " << E;
  }
  EXPECT_NO_THROW(LinearElastic(2000, 0.4999, PlaneMode::STRAIN));
}
