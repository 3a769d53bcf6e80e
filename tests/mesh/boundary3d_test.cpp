// 3D side selectors (left/right = x, front/back = y, bottom/top = z; `from`/`to` along z on the
// lateral sides and along x on bottom/top), the 2D names unchanged, and the Γ3 nodal weights of a
// 3D contact face (a third of the touching triangle areas: Σ w = area of Γ3).

#include <hemicontact/mesh/boundary.hpp>

#include <hemicontact/contact/contact_nodes.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/mesh/generators.hpp>

#include "../support/expect_error.hpp"

#include "support/selectors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace hemicontact;
using hemicontact::test::expect_input_error;
using hemicontact::test::side;

namespace {

Mesh box(int nx, int ny, int nz) {
  BoxSpec s;
  s.x1 = 2.0;  // distinct extents, so a wrong axis would select a wrong area
  s.y1 = 3.0;
  s.nx = nx;
  s.ny = ny;
  s.nz = nz;
  s.pattern = BoxPattern::SYMMETRIC;
  return make_box(s);
}

// Area and outward normal check of the facets tagged @p p.
double area_of(const Mesh& m, Part p, const Vec& normal) {
  double a = 0;
  for (Index f = 0; f < m.num_facets(); ++f)
    if (m.facet_part[f] == p) {
      a += m.facet_measure(f);
      EXPECT_NEAR((m.facet_normal(f) - normal).norm(), 0.0, 1e-14);
    }
  return a;
}

Vec e(double x, double y, double z) { return (Vec(3) << x, y, z).finished(); }

}  // namespace

// Each of the six sides, alone as Γ3 with the opposite side (or another) clamped, has the area and
// outward normal of its face of [0,2]×[0,3]×[0,1].
TEST(Boundary3D, SixSidesSelectTheirFaces) {
  struct Case {
    const char* side;
    const char* clamp;
    double area;
    Vec normal;
  };
  const Case cases[] = {{"left", "right", 3.0, e(-1, 0, 0)}, {"right", "left", 3.0, e(1, 0, 0)},
                        {"front", "back", 2.0, e(0, -1, 0)}, {"back", "front", 2.0, e(0, 1, 0)},
                        {"bottom", "top", 6.0, e(0, 0, -1)}, {"top", "bottom", 6.0, e(0, 0, 1)}};
  for (const auto& c : cases) {
    Mesh m = box(4, 2, 3);
    BoundarySpec spec;
    spec.gamma1 = {side(c.clamp, "gamma1[0]")};
    spec.gamma3 = {side(c.side, "gamma3[0]")};
    assign_boundary(m, spec);
    EXPECT_NEAR(area_of(m, Part::GAMMA3, c.normal), c.area, 1e-12) << c.side;
  }
}

// from/to: along z on lateral sides ([0.5, 1) = the upper half), along x on bottom/top; half-open
// intervals tile a side without overlap.
TEST(Boundary3D, IntervalsAlongZOnLateralSidesAndXOnBottom) {
  Mesh m = box(4, 2, 4);
  BoundarySpec spec;
  spec.gamma1 = {side("top", "gamma1[0]")};
  spec.gamma2 = {side("left", "gamma2[0]", 0.5), side("left", "gamma2[1]", -INF, 0.5)};
  for (auto& s : spec.gamma2) s.traction = e(1, 0, 0);
  spec.gamma3 = {side("bottom", "gamma3[0]", 0.0, 1.0)};  // x ∈ [0, 1): half of the 2×3 bottom
  assign_boundary(m, spec);
  double upper = 0, lower = 0;
  for (Index f = 0; f < m.num_facets(); ++f) {
    if (m.facet_part[f] != Part::GAMMA2) continue;
    double zmid = 0;
    for (int a = 0; a < 3; ++a) zmid += m.points(m.facets(f, a), 2) / 3;
    (m.facet_load[f] == 0 ? upper : lower) += m.facet_measure(f);
    EXPECT_EQ(m.facet_load[f] == 0, zmid >= 0.5);
  }
  EXPECT_NEAR(upper, 1.5, 1e-12);
  EXPECT_NEAR(lower, 1.5, 1e-12);
  EXPECT_NEAR(area_of(m, Part::GAMMA3, e(0, 0, -1)), 3.0, 1e-12);
}

// Σ_i w_i = area of Γ3 (each triangle gives a third of its area to each of its nodes), the
// normals of a flat bottom are (0,0,−1), and the frame (ν, τ1, ν×τ1) is orthonormal. Nodes on the
// clamped Γ1 (the left side here) are not contact nodes, so the sum over the free ones is smaller
// by exactly the weights of the clamped edge.
TEST(Boundary3D, ContactWeightsAreAThirdOfTheTouchingAreas) {
  Mesh m = box(4, 2, 3);
  BoundarySpec spec;
  spec.gamma1 = {side("top", "gamma1[0]")};
  spec.gamma3 = {side("bottom", "gamma3[0]")};
  assign_boundary(m, spec);
  const ContactNodes c = make_contact_nodes(m, clamped_nodes(m), Gap{});
  EXPECT_EQ(c.size(), 5 * 3);
  EXPECT_NEAR(c.w.sum(), 6.0, 1e-12);
  for (Index k = 0; k < c.size(); ++k) {
    EXPECT_NEAR((c.normal.row(k) - e(0, 0, -1).transpose()).norm(), 0.0, 1e-15);
    EXPECT_NEAR(c.tangent.row(k).norm(), 1.0, 1e-15);
    EXPECT_NEAR(c.tangent.row(k).dot(c.normal.row(k)), 0.0, 1e-15);
  }
  // The weight of one node by hand: an interior bottom node of the symmetric pattern touches
  // triangles of area hx·hy/2 each; their count times a third must be its weight.
  int touching_area_checked = 0;
  for (Index k = 0; k < c.size(); ++k) {
    double w = 0;
    for (Index f = 0; f < m.num_facets(); ++f)
      if (m.facet_part[f] == Part::GAMMA3)
        for (int a = 0; a < 3; ++a)
          if (m.facets(f, a) == c.node[k]) w += m.facet_measure(f) / 3;
    EXPECT_NEAR(c.w[k], w, 1e-15);
    ++touching_area_checked;
  }
  EXPECT_EQ(touching_area_checked, 15);

  Mesh m2 = box(4, 2, 3);
  spec.gamma1 = {side("left", "gamma1[0]")};
  assign_boundary(m2, spec);
  const ContactNodes c2 = make_contact_nodes(m2, clamped_nodes(m2), Gap{});
  EXPECT_EQ(c2.size(), 4 * 3);
  EXPECT_LT(c2.w.sum(), 6.0 - 1e-3);
}

TEST(Boundary3D, ErrorsNameTheSelector) {
  Mesh m = box(2, 2, 2);
  BoundarySpec spec;
  spec.gamma1 = {side("top", "boundary.gamma1[0]")};
  spec.gamma3 = {side("north", "boundary.gamma3[0]")};
  expect_input_error([&] { assign_boundary(m, spec); }, {"boundary.gamma3[0].side", "'north'", "front, back"});
  // front/back are 3D names.
  RectangleSpec r;
  Mesh sq = make_rectangle(r);
  BoundarySpec s2;
  s2.gamma1 = {side("front", "boundary.gamma1[0]")};
  expect_input_error([&] { assign_boundary(sq, s2); }, {"boundary.gamma1[0].side", "'front'", "3D meshes only"});
  // Interval with no facet.
  Mesh m3 = box(2, 2, 2);
  BoundarySpec s3;
  s3.gamma1 = {side("left", "boundary.gamma1[0]", 1.5, 2.0)};
  expect_input_error([&] { assign_boundary(m3, s3); }, {"boundary.gamma1[0] selects no boundary facet"});
}
