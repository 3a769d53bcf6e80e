// Stiffness and load assembly: patch test, rigid motions, symmetry and definiteness of K,
// and the totals of the body-force and traction vectors.

#include <hemicontact/fem/assembly.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/dof_map.hpp>
#include <hemicontact/fem/sparse_cholesky.hpp>
#include <hemicontact/material/linear_elastic.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/generators.hpp>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>

using namespace hemicontact;

namespace {

// A perturbed, off-origin, non-square rectangle so that nothing is accidentally symmetric.
Mesh perturbed_mesh(Diagonal diag, int nx = 6, int ny = 5) {
  RectangleSpec s;
  s.x0 = -0.5;
  s.x1 = 1.5;
  s.y0 = 0.25;
  s.y1 = 1.25;
  s.nx = nx;
  s.ny = ny;
  s.diagonal = diag;
  s.perturb = 0.25;
  s.seed = 7;
  return make_rectangle(s);
}

const LinearElastic& paper_material() {
  static const LinearElastic mat(2000, 0.4, PlaneMode::STRESS);
  return mat;
}

// Nodal values of the field u(x) = A x + b.
Vec nodal_field(const Mesh& m, const Eigen::Matrix2d& A, const Eigen::Vector2d& b) {
  Vec u(2 * m.num_nodes());
  for (Index a = 0; a < m.num_nodes(); ++a) u.segment<2>(2 * a) = A * m.points.row(a).transpose() + b;
  return u;
}

// ‖K‖_∞ (largest absolute row sum): |(K u)_i| ≤ ‖K‖_∞ ‖u‖_∞ is the scale of every entry of K u.
double inf_norm(const SpMat& K) {
  Vec rows = Vec::Zero(K.rows());
  for (int k = 0; k < K.outerSize(); ++k)
    for (SpMat::InnerIterator it(K, k); it; ++it) rows[it.row()] += std::abs(it.value());
  return rows.maxCoeff();
}

double total_area(const Mesh& m) {
  double s = 0;
  for (Index c = 0; c < m.num_cells(); ++c) s += m.cell_measure(c);
  return s;
}

}  // namespace

// Tolerance of the identities on K u below. Each entry (K u)_i is a sum of at most ~20 products
// (a node has ≤ 9 neighbours × 2 components), and each K_ij a sum of ≤ 8 element contributions
// computed with relative error O(ε); floating-point summation bounds the error by
// c·ε·Σ_j |K_ij||u_j| ≤ c·ε·‖K‖_∞‖u‖_∞ with c ≲ 30, i.e. ≲ 1e-14 relative. We allow 1e-12, which
// is still ten orders below the O(1) relative defect of an inconsistent element.
constexpr double KU_TOL = 1e-12;

class PatchTest : public ::testing::TestWithParam<Diagonal> {};

// For u linear, ε(u) is constant, so σ = D ε is constant and div σ = 0: the discrete equations
// (K u)_a = ∫Ω σ : ε(φ_a) = ∫∂Ω σn φ_a hold exactly for P1 (φ_a is linear on each facet). Hence
// (K u)_a = 0 at interior nodes and Σ_{F ∋ a} |F|/2 σ n_F at boundary nodes, and
// ½ uᵀ K u = ½ |Ω| ε : D ε.
TEST_P(PatchTest, LinearFieldGivesConsistentBoundaryForces) {
  const Mesh m = perturbed_mesh(GetParam());
  const auto& mat = paper_material();
  const SpMat K = assemble_stiffness(m, mat);
  Eigen::Matrix2d A;
  A << 0.3, -0.7, 0.45, 0.2;
  const Eigen::Vector2d b(0.1, -0.2);
  const Vec u = nodal_field(m, A, b);
  const Eigen::Vector3d eps(A(0, 0), A(1, 1), A(0, 1) + A(1, 0));  // Voigt, engineering shear
  const Eigen::Vector3d sv = mat.D() * eps;
  Eigen::Matrix2d sigma;
  sigma << sv[0], sv[2], sv[2], sv[1];

  Vec expected = Vec::Zero(u.size());
  std::vector<bool> on_boundary(m.num_nodes(), false);
  for (Index f = 0; f < m.num_facets(); ++f) {
    const Eigen::Vector2d tn = sigma * m.facet_normal(f);
    for (int k = 0; k < 2; ++k) {
      expected.segment<2>(2 * m.facets(f, k)) += 0.5 * m.facet_measure(f) * tn;
      on_boundary[m.facets(f, k)] = true;
    }
  }
  const Vec Ku = K * u;
  const double scale = inf_norm(K) * u.lpNorm<Eigen::Infinity>();
  int interior = 0;
  for (Index a = 0; a < m.num_nodes(); ++a) {
    if (!on_boundary[a]) ++interior;
    for (int i = 0; i < 2; ++i)
      EXPECT_NEAR(Ku[2 * a + i], expected[2 * a + i], KU_TOL * scale)
          << (on_boundary[a] ? "boundary" : "interior") << " node " << a << " component " << i;
  }
  EXPECT_GT(interior, 0);  // the test does check interior nodes
  // The boundary forces are not trivially zero (so the comparison above has content).
  EXPECT_GT(expected.lpNorm<Eigen::Infinity>(), 1e-3 * scale);

  // Energy: |Ω| = 2 exactly (the boundary nodes are not perturbed).
  const double energy = 0.5 * u.dot(Ku);
  EXPECT_NEAR(energy, 0.5 * 2.0 * eps.dot(sv), 1e-12 * std::abs(eps.dot(sv)));
  EXPECT_NEAR(total_area(m), 2.0, 1e-14);
}

// Rigid motions have ε = 0: translations (1,0), (0,1) and the infinitesimal rotation (−y, x) are
// in the kernel of K. Same round-off bound as above.
TEST_P(PatchTest, RigidMotionsAreInTheKernel) {
  const Mesh m = perturbed_mesh(GetParam());
  const SpMat K = assemble_stiffness(m, paper_material());
  Eigen::Matrix2d rot;
  rot << 0, -1, 1, 0;
  const std::vector<std::pair<Eigen::Matrix2d, Eigen::Vector2d>> motions = {
      {Eigen::Matrix2d::Zero(), Eigen::Vector2d(1, 0)},
      {Eigen::Matrix2d::Zero(), Eigen::Vector2d(0, 1)},
      {rot, Eigen::Vector2d::Zero()}};
  for (size_t k = 0; k < motions.size(); ++k) {
    const Vec r = nodal_field(m, motions[k].first, motions[k].second);
    EXPECT_LE((K * r).lpNorm<Eigen::Infinity>(), KU_TOL * inf_norm(K) * r.lpNorm<Eigen::Infinity>())
        << "rigid motion " << k;
  }
  // Control: a stretch (ε ≠ 0) is not in the kernel.
  const Vec s = nodal_field(m, Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero());
  EXPECT_GT((K * s).lpNorm<Eigen::Infinity>(), 1e-3 * inf_norm(K) * s.lpNorm<Eigen::Infinity>());
}

// K is symmetric up to the round-off of Bᵀ(D B) (entries (i,j) and (j,i) are summed in different
// orders: a few ulps of max|K|). The full K has exactly the 3 rigid motions as kernel
// (eigenvalues at the round-off level n·ε·λ_max ≈ 1e-14 λ_max, below 1e-10 λ_max, while the
// smallest elastic mode of this coarse mesh is ~1e-2 λ_max); clamping the top removes them, so
// the reduced K_x is positive definite and CHOLMOD factorizes it.
// (Measured on these 4×3 meshes: asymmetry ~1e-16, rigid eigenvalues ~1e-16 λ_max.)
TEST_P(PatchTest, SymmetricAndDefiniteAfterClamping) {
  Mesh m = perturbed_mesh(GetParam(), 4, 3);
  const SpMat K = assemble_stiffness(m, paper_material());
  const SpMat Kt = K.transpose();
  const double kmax = Mat(K).cwiseAbs().maxCoeff();
  EXPECT_LE(Mat(K - Kt).cwiseAbs().maxCoeff(), 1e-14 * kmax);

  const Eigen::SelfAdjointEigenSolver<Mat> eig{Mat(K)};
  const Vec& lam = eig.eigenvalues();  // increasing
  const double lmax = lam[lam.size() - 1];
  for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(lam[k]), 1e-10 * lmax) << "rigid eigenvalue " << k;
  EXPECT_GT(lam[3], 1e-4 * lmax);  // measured ≈ 1e-2

  BoundarySpec spec;
  BoundarySelector top;
  top.side = "top";
  top.context = "gamma1[0]";
  spec.gamma1.push_back(top);
  assign_boundary(m, spec);
  const DofMap dofs(m, clamped_nodes(m), ContactNodes{});
  const SpMat Kx = dofs.reduce(K);
  EXPECT_EQ(Kx.rows(), K.rows() - 2 * (4 + 1));  // the 5 top nodes are eliminated
  const Eigen::SelfAdjointEigenSolver<Mat> eig_x{Mat(Kx)};
  EXPECT_GT(eig_x.eigenvalues()[0], 1e-4 * lmax);  // measured ≈ 5e-3
  SparseCholesky chol;
  EXPECT_NO_THROW(chol.compute(Kx));
  // ...and it solves: backward stability gives ‖K_x x − b‖ ≲ c·ε·‖K_x‖‖x‖ ≤ c·ε·κ(K_x)‖b‖, with
  // κ(K_x) ≈ 2e2 here (measured), i.e. ~1e-13 relative; 1e-11 leaves a margin.
  const Vec rhs = Vec::LinSpaced(Kx.rows(), -1.0, 2.0);
  const Vec x = chol.solve(rhs);
  EXPECT_LE((Kx * x - rhs).norm(), 1e-11 * rhs.norm());
}

INSTANTIATE_TEST_SUITE_P(AllDiagonals, PatchTest,
                         ::testing::Values(Diagonal::RIGHT, Diagonal::LEFT, Diagonal::SYMMETRIC, Diagonal::CROSSED),
                         [](const ::testing::TestParamInfo<Diagonal>& info) {
                           return std::string(to_string(info.param));
                         });

// Σ_a φ_a = 1 and Σ_a x_a φ_a = x for P1, so the assembled body force has total f0 |Ω| and first
// moment f0 ∫Ω x, exactly up to summation round-off (1e-13 relative for a few hundred terms).
TEST(LoadAssembly, BodyForceTotals) {
  const Mesh m = perturbed_mesh(Diagonal::CROSSED);
  const Vec f0 = (Vec(2) << 0.7, -1.3).finished();
  const Vec f = assemble_body_force(m, f0);
  double area = 0, moment_x = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    const double A = m.cell_measure(c);
    area += A;
    moment_x += A * (m.points(m.cells(c, 0), 0) + m.points(m.cells(c, 1), 0) + m.points(m.cells(c, 2), 0)) / 3;
  }
  for (int i = 0; i < 2; ++i) {
    double total = 0, first = 0;
    for (Index a = 0; a < m.num_nodes(); ++a) {
      total += f[2 * a + i];
      first += m.points(a, 0) * f[2 * a + i];
    }
    EXPECT_NEAR(total, f0[i] * area, 1e-13 * std::abs(f0[i] * area)) << "component " << i;
    EXPECT_NEAR(first, f0[i] * moment_x, 1e-13 * std::abs(f0[i]) * area) << "component " << i;
  }
}

// The traction vector carries Σ_{Γ2 facets} |F| f2 in total, per selector, and nothing at nodes
// off Γ2.
TEST(LoadAssembly, TractionTotals) {
  Mesh m = perturbed_mesh(Diagonal::RIGHT);
  BoundarySpec spec;
  BoundarySelector top, left, right, bottom;
  top.side = "top";
  top.context = "gamma1[0]";
  left.side = "left";
  left.from = 0.7;  // facet midpoints at y = 0.75, 0.95, 1.15 (ny = 5 on [0.25, 1.25]): length 0.6
  left.traction = (Vec(2) << 3.0, -1.0).finished();
  left.context = "gamma2[0]";
  right.side = "right";
  right.traction = (Vec(2) << -2.0, 0.5).finished();
  right.context = "gamma2[1]";
  bottom.side = "bottom";
  bottom.traction = (Vec(2) << 0.0, 4.0).finished();
  bottom.context = "gamma2[2]";
  spec.gamma1 = {top};
  spec.gamma2 = {left, right, bottom};
  assign_boundary(m, spec);
  const Vec f = assemble_tractions(m);
  // Lengths: upper 3 facets of the left side 0.6, right side 1, bottom 2.
  const Eigen::Vector2d want = 0.6 * left.traction + 1.0 * right.traction + 2.0 * bottom.traction;
  double fx = 0, fy = 0;
  std::vector<bool> on_gamma2(m.num_nodes(), false);
  for (Index k = 0; k < m.num_facets(); ++k)
    if (m.facet_part[k] == Part::GAMMA2)
      for (int a = 0; a < 2; ++a) on_gamma2[m.facets(k, a)] = true;
  for (Index a = 0; a < m.num_nodes(); ++a) {
    fx += f[2 * a];
    fy += f[2 * a + 1];
    if (!on_gamma2[a]) {
      EXPECT_EQ(f.segment<2>(2 * a).norm(), 0.0) << "node " << a;
    }
  }
  EXPECT_NEAR(fx, want[0], 1e-13);
  EXPECT_NEAR(fy, want[1], 1e-13);
}
