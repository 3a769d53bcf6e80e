#include <hemicontact/fem/prolongation.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/material/linear_elastic.hpp>
#include <hemicontact/mesh/generators.hpp>

#include <gtest/gtest.h>

#include <random>
#include <tuple>

using namespace hemicontact;

namespace {

Mesh rectangle(int n, Diagonal diag, double perturb = 0, double x1 = 1.0) {
  RectangleSpec s;
  s.x1 = x1;
  s.y0 = -0.5;
  s.y1 = 1.5;  // a 1 × 2 rectangle off the origin: nothing relies on a unit square
  s.nx = n;
  s.ny = 2 * n;
  s.diagonal = diag;
  s.perturb = perturb;
  s.seed = 7;
  return make_rectangle(s);
}

// u(x) = A x + b, node-major: an affine field is in every P1 space, so any correct point location
// and barycentric interpolation reproduces it up to round-off.
Vec affine_field(const Mesh& m) {
  Mat A(m.dim, m.dim);
  Vec b(m.dim);
  if (m.dim == 2) {
    A << 0.3, -1.7, 2.1, 0.4;
    b << 0.25, -3.0;
  } else {
    A << 0.3, -1.7, 2.1, 0.4, 1.1, -0.2, -0.9, 0.6, 1.3;
    b << 0.25, -3.0, 1.5;
  }
  Vec u(m.num_nodes() * m.dim);
  for (Index a = 0; a < m.num_nodes(); ++a) u.segment(m.dim * a, m.dim) = A * m.points.row(a).transpose() + b;
  return u;
}

Vec random_field(Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Vec v(n);
  for (Index i = 0; i < n; ++i) v[i] = U(rng);
  return v;
}

const Diagonal ALL_DIAGONALS[] = {Diagonal::RIGHT, Diagonal::LEFT, Diagonal::SYMMETRIC, Diagonal::CROSSED};

class ProlongationByDiagonal : public ::testing::TestWithParam<Diagonal> {};

}  // namespace

// Nested (n → 2n), non-nested (n → 2n+1) and a perturbed fine mesh: the affine field must come out
// exact to round-off (values are O(5), so 1e-13 absolute is a few ulps).
TEST_P(ProlongationByDiagonal, ReproducesAffineFieldsExactly) {
  const Mesh coarse = rectangle(4, GetParam());
  const Vec u = affine_field(coarse);
  for (const auto& [n, perturb] : {std::pair{8, 0.0}, std::pair{9, 0.0}, std::pair{8, 0.3}}) {
    for (const Diagonal fd : ALL_DIAGONALS) {
      SCOPED_TRACE(std::string("fine n = ") + std::to_string(n) + ", perturb " + std::to_string(perturb) + ", " +
                   to_string(fd));
      const Mesh fine = rectangle(n, fd, perturb);
      const Vec Pu = prolongate(coarse, u, fine);
      ASSERT_EQ(Pu.size(), fine.num_nodes() * 2);
      EXPECT_LE((Pu - affine_field(fine)).cwiseAbs().maxCoeff(), 1e-13);
    }
  }
}

// Restriction by sampling at the coarse nodes is prolongate(fine → coarse) itself (the coarse
// nodes are fine nodes); after P it must give back the coarse vector: R P = I.
TEST_P(ProlongationByDiagonal, RestrictionAfterProlongationIsIdentity) {
  const Mesh coarse = rectangle(5, GetParam());
  const Mesh fine = rectangle(10, GetParam());
  const Vec u = random_field(coarse.num_nodes() * 2, 11);
  const Vec back = prolongate(fine, prolongate(coarse, u, fine), coarse);
  EXPECT_LE((back - u).cwiseAbs().maxCoeff(), 1e-13);
}

// On nested meshes P is the embedding V_h ⊂ V_h/2, so the energy is preserved:
// (P u)ᵀ K_fine (P u) = uᵀ K_coarse u (the same function, the same integral a(u, u)).
TEST_P(ProlongationByDiagonal, NestedEmbeddingPreservesTheEnergy) {
  const LinearElastic mat(2000, 0.4, PlaneMode::STRESS);
  const Mesh coarse = rectangle(4, GetParam());
  const Mesh fine = rectangle(8, GetParam());
  const SpMat Kc = assemble_stiffness(coarse, mat), Kf = assemble_stiffness(fine, mat);
  const Vec u = random_field(coarse.num_nodes() * 2, 5);
  const Vec Pu = prolongate(coarse, u, fine);
  const double ec = u.dot(Kc * u), ef = Pu.dot(Kf * Pu);
  EXPECT_NEAR(ef, ec, 1e-12 * ec);
  EXPECT_NEAR(energy_norm_difference(Kf, Pu, Vec::Zero(Pu.size())), std::sqrt(ec), 1e-12 * std::sqrt(ec));
}

INSTANTIATE_TEST_SUITE_P(AllDiagonals, ProlongationByDiagonal, ::testing::ValuesIn(ALL_DIAGONALS),
                         [](const auto& info) { return std::string(to_string(info.param)); });

// 3-D: the unit cube split into the 6 Kuhn tetrahedra around the diagonal (0,0,0)–(1,1,1); the
// "fine mesh" is a cloud of points (prolongate reads only the fine points), including the corners.
TEST(Prolongation, ReproducesAffineFieldsIn3D) {
  Mesh cube;
  cube.dim = 3;
  cube.points.resize(8, 3);
  for (int v = 0; v < 8; ++v) cube.points.row(v) << (v & 1), (v >> 1) & 1, (v >> 2) & 1;
  cube.cells.resize(6, 4);
  cube.cells << 0, 1, 3, 7, 0, 1, 5, 7, 0, 2, 3, 7, 0, 2, 6, 7, 0, 4, 5, 7, 0, 4, 6, 7;
  Mesh cloud;
  cloud.dim = 3;
  const RowMat r = (RowMat::Random(200, 3).array() + 1.0) / 2.0;  // in [0, 1]^3
  cloud.points.resize(208, 3);
  cloud.points << r, cube.points;
  const Vec Pu = prolongate(cube, affine_field(cube), cloud);
  EXPECT_LE((Pu - affine_field(cloud)).cwiseAbs().maxCoeff(), 1e-13);
}

// A fine node outside the coarse domain is an error that names the node.
TEST(Prolongation, NodeOutsideTheCoarseDomainThrows) {
  const Mesh coarse = rectangle(4, Diagonal::RIGHT);
  const Mesh wider = rectangle(8, Diagonal::RIGHT, 0.0, 1.1);
  const Vec u = affine_field(coarse);
  try {
    prolongate(coarse, u, wider);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fine node"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("lies in no cell"), std::string::npos) << e.what();
  }
  // Wrong field size and mismatched dimensions are errors too.
  EXPECT_THROW(prolongate(coarse, Vec::Zero(3), coarse), Error);
  EXPECT_THROW(energy_norm_difference(SpMat(4, 4), Vec::Zero(4), Vec::Zero(5)), Error);
}

// energy_norm_difference is sqrt((a − b)ᵀ K (a − b)) on a hand-checkable K.
TEST(Prolongation, EnergyNormDifferenceIsTheKNorm) {
  SpMat K(2, 2);
  K.insert(0, 0) = 2.0;
  K.insert(0, 1) = 1.0;
  K.insert(1, 0) = 1.0;
  K.insert(1, 1) = 3.0;
  Vec a(2), b(2);
  a << 1.0, 2.0;
  b << 0.0, 1.0;  // e = (1, 1): eᵀKe = 2 + 1 + 1 + 3 = 7
  EXPECT_NEAR(energy_norm_difference(K, a, b), std::sqrt(7.0), 1e-15);
  EXPECT_EQ(energy_norm_difference(K, a, a), 0.0);
}
