// Newest-vertex bisection (mesh/bisection.hpp): the refined mesh is conforming (no hanging node),
// nested (the coarse P1 space embeds exactly), shape-regular (right isosceles cells stay right
// isosceles), and carries the boundary parts, tractions and groups of the coarse mesh.
#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/fem/prolongation.hpp>
#include <hemicontact/mesh/bisection.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/generators.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

using namespace hemicontact;

namespace {

Mesh square(int n, Diagonal d) {
  RectangleSpec s;
  s.nx = s.ny = n;
  s.diagonal = d;
  Mesh m = make_rectangle(s);
  BoundarySpec b;
  BoundarySelector top, left_hi, bottom;
  top.side = "top";
  left_hi.side = "left";
  left_hi.from = 0.5;
  left_hi.traction = Vec::Constant(2, 3.0);
  bottom.side = "bottom";
  b.gamma1 = {top};
  b.gamma2 = {left_hi};
  b.gamma3 = {bottom};
  assign_boundary(m, b);
  m.facet_groups["bottom"] = {};
  for (Index f = 0; f < m.num_facets(); ++f)
    if (m.facet_part[f] == Part::GAMMA3) m.facet_groups["bottom"].push_back(f);
  label_longest_edges(m);
  return m;
}

// Every edge is shared by two cells, or by one cell and then it is a boundary facet; the facets
// are exactly the one-cell edges. A hanging node would leave a long edge with one cell inside Ω.
void expect_conforming(const Mesh& m) {
  std::map<std::pair<int, int>, int> count;
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int k = 0; k < 3; ++k) {
      int a = m.cells(c, k), b = m.cells(c, (k + 1) % 3);
      count[{std::min(a, b), std::max(a, b)}]++;
    }
  std::set<std::pair<int, int>> facets;
  for (Index f = 0; f < m.num_facets(); ++f)
    facets.insert({std::min(m.facets(f, 0), m.facets(f, 1)), std::max(m.facets(f, 0), m.facets(f, 1))});
  EXPECT_EQ(facets.size(), static_cast<size_t>(m.num_facets()));
  for (const auto& [e, k] : count) {
    ASSERT_LE(k, 2);
    EXPECT_EQ(k == 1, facets.count(e) == 1) << "edge " << e.first << "-" << e.second;
  }
  // The stored facets agree with those recomputed from the cells (orientation included).
  Mesh copy = m;
  extract_boundary_facets(copy);
  std::set<std::pair<int, int>> oriented, again;
  for (Index f = 0; f < m.num_facets(); ++f) oriented.insert({m.facets(f, 0), m.facets(f, 1)});
  for (Index f = 0; f < copy.num_facets(); ++f) again.insert({copy.facets(f, 0), copy.facets(f, 1)});
  EXPECT_EQ(oriented, again);
  for (Index c = 0; c < m.num_cells(); ++c) EXPECT_GT(m.cell_measure(c), 0);
}

double min_angle_deg(const Mesh& m) {
  double lo = 180;
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVectorXd a = m.points.row(m.cells(c, (k + 1) % 3)) - m.points.row(m.cells(c, k));
      const Eigen::RowVectorXd b = m.points.row(m.cells(c, (k + 2) % 3)) - m.points.row(m.cells(c, k));
      lo = std::min(lo, std::acos(a.dot(b) / (a.norm() * b.norm())) * 180 / M_PI);
    }
  return lo;
}

}  // namespace

class BisectionRules : public ::testing::TestWithParam<std::tuple<Diagonal, BisectionRule>> {};

// Rounds of random marking (20 % of the cells; ten with one bisection, five with bisec3, which
// grows the mesh faster): conforming, areas and Γ lengths kept, marked cells split.
TEST_P(BisectionRules, RandomMarkingStaysConforming) {
  const auto [diag, rule] = GetParam();
  Mesh m = square(4, diag);
  std::mt19937 rng(7);
  const double gamma3_length = 1.0;
  const int rounds = rule == BisectionRule::BISEC3 ? 5 : 10;
  for (int round = 0; round < rounds; ++round) {
    std::vector<char> marked(static_cast<size_t>(m.num_cells()));
    for (auto& f : marked) f = std::uniform_real_distribution<double>(0, 1)(rng) < 0.2;
    const Bisection b = bisect(m, marked, rule);
    expect_conforming(b.mesh);
    double area = 0;
    for (Index c = 0; c < b.mesh.num_cells(); ++c) area += b.mesh.cell_measure(c);
    EXPECT_NEAR(area, 1.0, 1e-13);
    double g3 = 0, g3_group = 0;
    for (Index f = 0; f < b.mesh.num_facets(); ++f)
      if (b.mesh.facet_part[f] == Part::GAMMA3) g3 += b.mesh.facet_measure(f);
    for (Index f : b.mesh.facet_groups.at("bottom")) g3_group += b.mesh.facet_measure(f);
    EXPECT_NEAR(g3, gamma3_length, 1e-13);
    EXPECT_NEAR(g3_group, gamma3_length, 1e-13);
    // The total Γ2 force ∫ f2 is the same on both meshes.
    const Vec F0 = assemble_tractions(m), F1 = assemble_tractions(b.mesh);
    EXPECT_NEAR(F1.sum(), F0.sum(), 1e-12);
    EXPECT_NEAR(F0.sum(), 2 * 3.0 * 0.5, 1e-12);
    std::vector<int> children(static_cast<size_t>(m.num_cells()), 0);
    for (int p : b.cell_parent) children[static_cast<size_t>(p)]++;
    for (size_t c = 0; c < marked.size(); ++c)
      if (marked[c]) {
        EXPECT_GE(children[c], rule == BisectionRule::BISEC3 ? 4 : 2);
      }
    m = b.mesh;
  }
  EXPECT_GT(m.num_cells(), 4 * 4 * 2 * 2);
}

INSTANTIATE_TEST_SUITE_P(Meshes, BisectionRules,
                         ::testing::Combine(::testing::Values(Diagonal::RIGHT, Diagonal::SYMMETRIC, Diagonal::CROSSED),
                                            ::testing::Values(BisectionRule::NEWEST_VERTEX, BisectionRule::BISEC3)));

// Nested spaces: carrying a P1 field by midpoint averaging equals evaluating it by point location,
// and an affine field is reproduced exactly.
TEST(Bisection, ProlongationIsTheExactEmbedding) {
  Mesh m = square(3, Diagonal::RIGHT);
  std::mt19937 rng(3);
  Vec u(2 * m.num_nodes());
  for (Index i = 0; i < u.size(); ++i) u[i] = std::normal_distribution<double>(0, 1)(rng);
  for (int round = 0; round < 4; ++round) {
    std::vector<char> marked(static_cast<size_t>(m.num_cells()), 0);
    marked[0] = marked[static_cast<size_t>(m.num_cells() / 2)] = 1;
    const Bisection b = bisect(m, marked, BisectionRule::NEWEST_VERTEX);
    const Vec by_parents = prolongate_bisection(b, u, 2);
    const Vec by_location = prolongate(m, u, b.mesh);
    EXPECT_LT((by_parents - by_location).cwiseAbs().maxCoeff(), 1e-12);
    m = b.mesh;
    u = by_parents;
  }
  Vec affine(2 * m.num_nodes());
  for (Index v = 0; v < m.num_nodes(); ++v) {
    affine[2 * v] = 1 + 2 * m.points(v, 0) - m.points(v, 1);
    affine[2 * v + 1] = 3 * m.points(v, 1);
  }
  const Bisection b = bisect(m, std::vector<char>(static_cast<size_t>(m.num_cells()), 1));
  const Vec fine = prolongate_bisection(b, affine, 2);
  for (Index v = 0; v < b.mesh.num_nodes(); ++v) {
    EXPECT_NEAR(fine[2 * v], 1 + 2 * b.mesh.points(v, 0) - b.mesh.points(v, 1), 1e-13);
    EXPECT_NEAR(fine[2 * v + 1], 3 * b.mesh.points(v, 1), 1e-13);
  }
}

// Refining 12 times towards a corner: newest-vertex bisection of right isosceles triangles labelled
// at the hypotenuse produces only right isosceles triangles (min angle exactly 45°), and the
// closure stays local (far from the corner the mesh is unchanged).
TEST(Bisection, CornerRefinementKeepsTheAngles) {
  Mesh m = square(4, Diagonal::SYMMETRIC);
  for (int round = 0; round < 12; ++round) {
    std::vector<char> marked(static_cast<size_t>(m.num_cells()), 0);
    for (Index c = 0; c < m.num_cells(); ++c)
      for (int k = 0; k < 3; ++k)
        if (m.points(m.cells(c, k), 0) == 0 && m.points(m.cells(c, k), 1) == 1) marked[static_cast<size_t>(c)] = 1;
    m = bisect(m, marked, BisectionRule::NEWEST_VERTEX).mesh;
  }
  expect_conforming(m);
  EXPECT_NEAR(min_angle_deg(m), 45.0, 1e-9);
  EXPECT_LT(m.min_edge_length(), 1.0 / 4 / 32);
  EXPECT_LT(m.num_cells(), 400);  // 32 initial cells; graded, not uniform, refinement
}

// Above max_nodes a refinement is counted, not built: the count is the node count of the mesh the
// same marks make without a limit, at the limit the mesh is built as without one.
TEST(Bisection, AboveMaxNodesTheRefinementIsCountedNotBuilt) {
  const Mesh m = square(4, Diagonal::SYMMETRIC);
  std::vector<char> marked(static_cast<size_t>(m.num_cells()), 0);
  marked[3] = marked[10] = 1;
  for (const BisectionRule rule : {BisectionRule::NEWEST_VERTEX, BisectionRule::BISEC3}) {
    const Bisection full = bisect(m, marked, rule);
    ASSERT_TRUE(full.built);
    EXPECT_EQ(full.nodes, full.mesh.num_nodes());
    EXPECT_GT(full.nodes, m.num_nodes());
    const Bisection counted = bisect(m, marked, rule, full.nodes - 1);
    EXPECT_FALSE(counted.built);
    EXPECT_EQ(counted.nodes, full.nodes);
    EXPECT_EQ(counted.mesh.num_nodes(), 0);
    const Bisection at_limit = bisect(m, marked, rule, full.nodes);
    ASSERT_TRUE(at_limit.built);
    EXPECT_EQ(at_limit.mesh.cells, full.mesh.cells);
  }
}

TEST(Bisection, RejectsBadInput) {
  EXPECT_THROW(parse_bisection_rule("red"), Error);
  BoxSpec s;
  s.nx = s.ny = s.nz = 1;
  Mesh box = make_box(s);
  EXPECT_THROW(bisect(box, std::vector<char>(static_cast<size_t>(box.num_cells()), 1)), Error);
}

TEST(GradedRectangle, GradesTowardsTheChosenEnds) {
  RectangleSpec s;
  s.nx = s.ny = 8;
  s.grade_x = GradeTowards::BOTH;
  s.grade_y = GradeTowards::HIGH;
  s.grading_power = 2;
  const Mesh m = make_rectangle(s);
  // Grid line 1 of x sits at ½(2/8)² = 1/32; the last y line below the top at 1 − (1/8)².
  EXPECT_NEAR(m.points(1, 0), 1.0 / 32, 1e-15);
  EXPECT_NEAR(m.points(7 * 9, 1), 1 - 1.0 / 64, 1e-15);
  EXPECT_NEAR(m.points(4, 0), 0.5, 1e-15);
  double area = 0;
  for (Index c = 0; c < m.num_cells(); ++c) area += m.cell_measure(c);
  EXPECT_NEAR(area, 1.0, 1e-14);
  EXPECT_EQ(grade_map(0.3, GradeTowards::NONE, 3), 0.3);
  EXPECT_THROW(parse_grade_towards("middle", "mesh.grading.x"), Error);
  s.perturb = 0.1;
  EXPECT_THROW(make_rectangle(s), Error);
}
