#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/generators.hpp>

#include <gtest/gtest.h>

using namespace hemicontact;

// Each kind of split must tile the rectangle exactly: the cell areas sum to its area, and every
// cell is positively oriented; the boundary has 2(nx+ny) edges of total length = perimeter.
class RectangleTiling : public ::testing::TestWithParam<std::tuple<Diagonal, int>> {};

TEST_P(RectangleTiling, AreasOrientationBoundary) {
  const auto [diag, n] = GetParam();
  RectangleSpec s;
  s.x1 = 2.0;
  s.nx = n;
  s.ny = n + 1;
  s.diagonal = diag;
  const Mesh m = make_rectangle(s);
  double area = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    EXPECT_GT(m.cell_measure(c), 0.0);
    area += m.cell_measure(c);
  }
  EXPECT_NEAR(area, 2.0, 1e-13);
  EXPECT_EQ(m.num_facets(), 2 * (s.nx + s.ny));
  double perimeter = 0;
  for (Index f = 0; f < m.num_facets(); ++f) perimeter += m.facet_measure(f);
  EXPECT_NEAR(perimeter, 6.0, 1e-13);
  // Outward normals: on the bottom side ν = (0, −1).
  for (Index f = 0; f < m.num_facets(); ++f) {
    const double ymid = 0.5 * (m.points(m.facets(f, 0), 1) + m.points(m.facets(f, 1), 1));
    if (ymid == 0.0) {
      const Vec nu = m.facet_normal(f);
      EXPECT_NEAR(nu[0], 0.0, 1e-15);
      EXPECT_NEAR(nu[1], -1.0, 1e-15);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllDiagonals, RectangleTiling,
                         ::testing::Combine(::testing::Values(Diagonal::RIGHT, Diagonal::LEFT, Diagonal::SYMMETRIC,
                                                              Diagonal::CROSSED),
                                            ::testing::Values(1, 4, 7)));
