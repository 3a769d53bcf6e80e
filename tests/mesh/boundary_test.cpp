// Boundary parts: side selectors with half-open intervals, the errors of bad selectors, clamped
// nodes, and the Γ3 contact nodes built from the tags.

#include <hemicontact/mesh/boundary.hpp>

#include <hemicontact/contact/contact_nodes.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/fem/assembly.hpp>
#include <hemicontact/mesh/generators.hpp>

#include "support/selectors.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace hemicontact;
using hemicontact::test::side;

namespace {

BoundarySelector load(BoundarySelector s, double fx, double fy) {
  s.traction = (Vec(2) << fx, fy).finished();
  return s;
}

Mesh square(int nx, int ny, Diagonal diag = Diagonal::RIGHT, double x1 = 1.0) {
  RectangleSpec s;
  s.x1 = x1;
  s.nx = nx;
  s.ny = ny;
  s.diagonal = diag;
  return make_rectangle(s);
}

// The message of the Error assign_boundary throws ("(no error)" if none).
std::string error_of(Mesh m, const BoundarySpec& spec) {
  try {
    assign_boundary(m, spec);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT);
    return e.what();
  }
  return "(no error)";
}

int count(const Mesh& m, Part p) {
  int n = 0;
  for (Part q : m.facet_part) n += (q == p);
  return n;
}

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

}  // namespace

// Paper's example: the traction acts on {0}×[0.5, 1), not on {0}×[0, 0.5). The two half-open
// intervals tile the side: every left facet is selected exactly once (an overlap would throw).
TEST(AssignBoundary, HalfOpenIntervalsSplitASide) {
  Mesh m = square(4, 8);
  BoundarySpec spec;
  spec.gamma1 = {side("top", "gamma1[0]")};
  spec.gamma2 = {load(side("left", "gamma2[0]", 0.5), 8e-3, 0), load(side("left", "gamma2[1]", -INF, 0.5), 0, 0)};
  assign_boundary(m, spec);
  EXPECT_EQ(count(m, Part::GAMMA1), 4);
  EXPECT_EQ(count(m, Part::GAMMA2), 8);
  EXPECT_EQ(count(m, Part::GAMMA3), 0);
  ASSERT_EQ(m.tractions.size(), 2u);
  for (Index f = 0; f < m.num_facets(); ++f) {
    if (m.facet_part[f] != Part::GAMMA2) continue;
    const double ymid = 0.5 * (m.points(m.facets(f, 0), 1) + m.points(m.facets(f, 1), 1));
    EXPECT_EQ(m.facet_load[f], ymid >= 0.5 ? 0 : 1) << "facet at y = " << ymid;
  }
  // Total traction force: 8e-3 × length 0.5 in x (summation of 5 nodal shares: round-off only).
  const Vec f = assemble_tractions(m);
  double fx = 0;
  for (Index a = 0; a < m.num_nodes(); ++a) fx += f[2 * a];
  EXPECT_NEAR(fx, 4e-3, 1e-16);
}

// The interval is [from, to) on the facet midpoint: with ny = 2 the left midpoints are 0.25 and
// 0.75 (exact binary fractions), so [0.25, 0.75) takes exactly the lower one and [0.75, …) the
// upper one, and [0, 0.25) takes none.
TEST(AssignBoundary, IntervalIsClosedBelowOpenAbove) {
  Mesh m = square(2, 2);
  BoundarySpec spec;
  spec.gamma1 = {side("top", "gamma1[0]")};
  spec.gamma3 = {side("left", "gamma3[0]", 0.25, 0.75), side("left", "gamma3[1]", 0.75, 1.25)};
  assign_boundary(m, spec);
  EXPECT_EQ(count(m, Part::GAMMA3), 2);
  spec.gamma3 = {side("left", "gamma3[0]", 0.0, 0.25)};
  EXPECT_TRUE(contains(error_of(m, spec), "gamma3[0] selects no boundary facet"));
}

TEST(AssignBoundary, BadSelectorsThrowNamingTheSelector) {
  const Mesh m = square(4, 4);
  const auto top = side("top", "boundary.gamma1[0]");
  BoundarySpec spec;

  spec.gamma1 = {top};
  spec.gamma2 = {load(side("left", "boundary.gamma2[0]", 2.0, 3.0), 1, 0)};
  std::string e = error_of(m, spec);
  EXPECT_TRUE(contains(e, "boundary.gamma2[0]") && contains(e, "selects no boundary facet")) << e;

  spec.gamma2 = {load(side("diagonal", "boundary.gamma2[0]"), 1, 0)};
  e = error_of(m, spec);
  EXPECT_TRUE(contains(e, "boundary.gamma2[0].side") && contains(e, "'diagonal'")) << e;

  spec.gamma2 = {};
  spec.gamma3 = {side("top", "boundary.gamma3[0]", 0.25, 0.75)};
  e = error_of(m, spec);
  EXPECT_TRUE(contains(e, "boundary.gamma3[0]") && contains(e, "boundary.gamma1[0]") && contains(e, "both select"))
      << e;

  spec.gamma3 = {};
  BoundarySelector group;
  group.physical = "contact";
  group.context = "boundary.gamma3[0]";
  spec.gamma3 = {group};
  e = error_of(m, spec);
  EXPECT_TRUE(contains(e, "boundary.gamma3[0].physical") && contains(e, "'contact'")) << e;

  BoundarySelector neither;
  neither.context = "boundary.gamma3[0]";
  spec.gamma3 = {neither};
  e = error_of(m, spec);
  EXPECT_TRUE(contains(e, "boundary.gamma3[0]") && contains(e, "exactly one of")) << e;

  spec.gamma3 = {};
  spec.gamma1 = {};
  spec.gamma2 = {load(side("left", "boundary.gamma2[0]"), 1, 0)};
  e = error_of(m, spec);
  EXPECT_TRUE(contains(e, "Γ1")) << e;

  // And the same spec with a Γ1 is fine (the errors above come from the bad selectors).
  spec.gamma1 = {top};
  EXPECT_EQ(error_of(m, spec), "(no error)");
}

// Γ1 = top clamps exactly the nx + 1 nodes at y = 1 (the crossed centre nodes are interior).
TEST(ClampedNodes, TopSide) {
  Mesh m = square(4, 3, Diagonal::CROSSED);
  BoundarySpec spec;
  spec.gamma1 = {side("top", "gamma1[0]")};
  assign_boundary(m, spec);
  const std::vector<bool> clamped = clamped_nodes(m);
  ASSERT_EQ(clamped.size(), static_cast<size_t>(m.num_nodes()));
  int n = 0;
  for (Index a = 0; a < m.num_nodes(); ++a) {
    n += clamped[a];
    EXPECT_EQ(clamped[a], m.points(a, 1) == 1.0) << "node " << a;
  }
  EXPECT_EQ(n, 5);
}

// Γ3 = bottom of [0, 2]×[0, 1] with 8 cells (h = 0.25): 9 nodes left to right, nodal-quadrature
// weights h (h/2 at the two ends, Σ w = 2 = |Γ3|), ν = (0, −1), τ = (1, 0). All values are exact
// binary fractions, so they are compared exactly up to one ulp of summation.
TEST(ContactNodes, BottomSide) {
  Mesh m = square(8, 3, Diagonal::SYMMETRIC, 2.0);
  BoundarySpec spec;
  spec.gamma1 = {side("top", "gamma1[0]")};
  spec.gamma3 = {side("bottom", "gamma3[0]")};
  assign_boundary(m, spec);
  Gap gap;
  gap.constant = 0.15;
  const ContactNodes c = make_contact_nodes(m, clamped_nodes(m), gap);
  ASSERT_EQ(c.size(), 9);
  const double h = 0.25;
  for (Index i = 0; i < c.size(); ++i) {
    SCOPED_TRACE("contact node " + std::to_string(i));
    EXPECT_EQ(m.points(c.node[i], 1), 0.0);
    EXPECT_DOUBLE_EQ(m.points(c.node[i], 0), i * h);  // sorted left to right
    EXPECT_DOUBLE_EQ(c.w[i], (i == 0 || i == 8) ? h / 2 : h);
    EXPECT_DOUBLE_EQ(c.normal(i, 0), 0.0);
    EXPECT_DOUBLE_EQ(c.normal(i, 1), -1.0);
    EXPECT_DOUBLE_EQ(c.tangent(i, 0), 1.0);
    EXPECT_DOUBLE_EQ(c.tangent(i, 1), 0.0);
    EXPECT_EQ(c.g[i], 0.15);
  }
  EXPECT_DOUBLE_EQ(c.w.sum(), 2.0);

  // A node on Γ1 ∩ Γ3 is clamped, not a contact node: clamp the left side instead.
  spec.gamma1 = {side("left", "gamma1[0]")};
  assign_boundary(m, spec);
  const ContactNodes c2 = make_contact_nodes(m, clamped_nodes(m), gap);
  ASSERT_EQ(c2.size(), 8);
  EXPECT_DOUBLE_EQ(m.points(c2.node[0], 0), h);
  EXPECT_DOUBLE_EQ(c2.w[0], h);
}

TEST(ContactNodes, NegativeGapThrows) {
  Mesh m = square(4, 2);
  BoundarySpec spec;
  spec.gamma1 = {side("top", "gamma1[0]")};
  spec.gamma3 = {side("bottom", "gamma3[0]")};
  assign_boundary(m, spec);
  const auto clamped = clamped_nodes(m);
  Gap negative;
  negative.constant = -0.1;
  EXPECT_THROW(make_contact_nodes(m, clamped, negative), Error);
  // Piecewise linear g from 0.1 at x = 0 to −0.1 at x = 1: negative at x ≥ 0.75 only.
  Gap ramp;
  ramp.points = {{0.0, 0.1}, {1.0, -0.1}};
  try {
    make_contact_nodes(m, clamped, ramp);
    ADD_FAILURE() << "no error for a negative thickness";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "contact.gap")) << e.what();
  }
  // g = 0 is allowed (no soft layer: the rigid foundation is touched at once).
  Gap zero;
  zero.constant = 0.0;
  EXPECT_NO_THROW(make_contact_nodes(m, clamped, zero));
}
