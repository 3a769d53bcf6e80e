#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/fem/dof_map.hpp>
#include <hemicontact/material/linear_elastic.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/generators.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace hemicontact;

namespace {
// A rotated, perturbed rectangle: Γ3 frames are then genuine rotations, not signed permutations.
struct DofSetup {
  Mesh mesh;
  std::vector<bool> clamped;
  ContactNodes contact;
  DofMap dofs;
  SpMat K;
};

DofSetup make_setup(Diagonal diag) {
  DofSetup s;
  RectangleSpec r;
  r.nx = 7;
  r.ny = 5;
  r.diagonal = diag;
  r.perturb = 0.2;
  s.mesh = make_rectangle(r);
  BoundarySpec b;
  b.gamma1 = {BoundarySelector{"top", "", -INF, INF, Vec(), "gamma1", {}}};
  b.gamma3 = {BoundarySelector{"bottom", "", -INF, INF, Vec(), "gamma3", {}}};
  assign_boundary(s.mesh, b);
  const double a = 0.5;  // rotate the body by ~29° after tagging
  for (Index v = 0; v < s.mesh.num_nodes(); ++v) {
    const double x = s.mesh.points(v, 0), y = s.mesh.points(v, 1);
    s.mesh.points(v, 0) = std::cos(a) * x - std::sin(a) * y;
    s.mesh.points(v, 1) = std::sin(a) * x + std::cos(a) * y;
  }
  s.clamped = clamped_nodes(s.mesh);
  Gap g;
  g.constant = 0.1;
  s.contact = make_contact_nodes(s.mesh, s.clamped, g);
  s.dofs = DofMap(s.mesh, s.clamped, s.contact);
  s.K = assemble_stiffness(s.mesh, LinearElastic(1.0, 0.3, PlaneMode::STRESS));
  return s;
}
}  // namespace

class DofMapByDiagonal : public ::testing::TestWithParam<Diagonal> {};

// The fast Tᵀ K T (rotate node blocks, select, renumber) equals the sparse-product definition.
TEST_P(DofMapByDiagonal, FastReduceEqualsProducts) {
  const DofSetup s = make_setup(GetParam());
  ASSERT_GT(s.contact.size(), 0);
  const SpMat fast = s.dofs.reduce(s.K), ref = s.dofs.reduce_by_products(s.K);
  const double scale = Mat(ref).cwiseAbs().maxCoeff();
  EXPECT_LE(Mat(fast - ref).cwiseAbs().maxCoeff(), 1e-14 * scale);
  EXPECT_TRUE(fast.isCompressed());
  for (Index j = 0; j < fast.cols(); ++j)  // sorted inner indices (CHOLMOD and Ipopt rely on it)
    for (int p = fast.outerIndexPtr()[j] + 1; p < fast.outerIndexPtr()[j + 1]; ++p)
      ASSERT_LT(fast.innerIndexPtr()[p - 1], fast.innerIndexPtr()[p]);
}

// Round trips: T has orthonormal columns, so Tᵀ T = I and x = Tᵀ(T x); Γ3 dofs are last and hold
// (u·ν, u·τ) of their node.
TEST_P(DofMapByDiagonal, RoundTripAndLocalFrames) {
  const DofSetup s = make_setup(GetParam());
  const Vec x = Vec::LinSpaced(s.dofs.n_free(), -1.0, 2.0);
  const Vec u = s.dofs.to_full(x);
  EXPECT_LE((s.dofs.to_reduced(u) - x).cwiseAbs().maxCoeff(), 1e-15 * 4);
  for (Index k = 0; k < s.contact.size(); ++k) {
    const int v = s.contact.node[k];
    const Vec uv = u.segment(2 * v, 2);
    EXPECT_NEAR(uv.dot(s.contact.normal.row(k).transpose()), x[s.dofs.contact_dof(k, 0)], 1e-14);
    EXPECT_NEAR(uv.dot(s.contact.tangent.row(k).transpose()), x[s.dofs.contact_dof(k, 1)], 1e-14);
  }
  for (Index v = 0; v < s.mesh.num_nodes(); ++v)
    if (s.clamped[v]) {
      EXPECT_EQ(u.segment(2 * v, 2).norm(), 0.0);
    }
}

INSTANTIATE_TEST_SUITE_P(AllDiagonals, DofMapByDiagonal,
                         ::testing::Values(Diagonal::RIGHT, Diagonal::LEFT, Diagonal::SYMMETRIC, Diagonal::CROSSED));

// The reduced stiffness is the largest array of a run and must move, not be copied, from
// reduce into the model and with the DofMap (Eigen 3.4's SparseMatrix has no move constructor;
// MovableSpMat adds one). A copy would allocate new storage: the value array's address tells.
TEST(MovableSpMat, ReducedStiffnessMovesWithoutACopy) {
  const DofSetup s = make_setup(Diagonal::RIGHT);
  MovableSpMat a = s.dofs.reduce(s.K);
  const double* values = a.valuePtr();
  const SpMat ref = a;  // a copy, to compare the values after the moves
  MovableSpMat b = std::move(a);
  EXPECT_EQ(b.valuePtr(), values);
  MovableSpMat c;
  c = std::move(b);
  EXPECT_EQ(c.valuePtr(), values);
  EXPECT_EQ(Mat(c - ref).cwiseAbs().maxCoeff(), 0.0);
  const SpMat& as_spmat = c;  // still a SpMat for every reader
  EXPECT_EQ(as_spmat.nonZeros(), ref.nonZeros());
  DofMap d1 = s.dofs;
  const double* t_values = d1.T().valuePtr();
  const DofMap d2 = std::move(d1);
  EXPECT_EQ(d2.T().valuePtr(), t_values);
}
