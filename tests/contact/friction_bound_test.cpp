// Tests of the friction bounds F_b (paper (6), (15), (34)): values, L_Fb, depends_on_u_nu, and
// the (15c) validation with messages that name the key.

#include <hemicontact/contact/friction_bound.hpp>
#include <hemicontact/contact/piecewise_linear_law.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/types.hpp>

#include "support/expect_error.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

using hemicontact::test::expect_input_error;

std::shared_ptr<const PiecewiseLinearLaw> paper_ptr() {
  return std::make_shared<const PiecewiseLinearLaw>(PiecewiseLinearLaw::paper(100, -100, 400, 0.1, 0.15));
}

TEST(FrictionCoulomb, PaperBoundIsMuTimesP) {
  const CoulombLayerBound fb(0.2, paper_ptr());
  // (34) with the paper's μ = 0.2: F_b = 0.2·p_ν; values of p_ν from (32) by hand.
  EXPECT_EQ(fb.F(-1.0), 0.0);
  EXPECT_NEAR(fb.F(0.05), 1.0, 1e-13);
  EXPECT_NEAR(fb.F(0.12), 1.6, 1e-13);
  EXPECT_NEAR(fb.F(0.2), 5.0, 1e-13);
  // L_Fb = μ · max|slope| = 0.2 · 400.
  EXPECT_NEAR(fb.lipschitz(), 80.0, 1e-13);
  EXPECT_TRUE(fb.depends_on_u_nu());
  EXPECT_NE(fb.describe().find("(34)"), std::string::npos);
  // μ = 0: F_b ≡ 0, no outer loop needed, and no 0·INF.
  const CoulombLayerBound frictionless(0.0, paper_ptr());
  EXPECT_FALSE(frictionless.depends_on_u_nu());
  EXPECT_EQ(frictionless.lipschitz(), 0.0);
  EXPECT_EQ(frictionless.F(0.2), 0.0);
}

TEST(FrictionCoulomb, JumpingLawIsNotLipschitz) {
  const auto law = std::make_shared<const PiecewiseLinearLaw>(
      PiecewiseLinearLaw({{-0.05, 0.0}, {0.0, 0.0}, {0.1, 10.0}, {0.1, 4.0}, {0.2, 6.0}}, 0.0, 50.0));
  const CoulombLayerBound fb(0.5, law);
  EXPECT_EQ(fb.lipschitz(), INF);
  EXPECT_NEAR(fb.F(0.1), 2.0, 1e-13);  // right limit: 0.5 · 4
}

TEST(FrictionCoulomb, RejectsBadMuAndNullLaw) {
  expect_input_error([] { CoulombLayerBound(-0.1, paper_ptr()); }, {"contact.friction.mu"});
  expect_input_error([] { CoulombLayerBound(NAN, paper_ptr()); }, {"contact.friction.mu"});
  expect_input_error([] { CoulombLayerBound(0.2, nullptr); }, {"contact.friction.type", "normal law"});
}

TEST(FrictionCoulomb, RejectsNormalLawViolating15c) {
  // p_ν < 0 for r < 0 (an adhesive layer): μ p_ν breaks (15c); the message says where to look.
  const auto law =
      std::make_shared<const PiecewiseLinearLaw>(PiecewiseLinearLaw({{-0.1, -1.0}, {0.0, 0.0}, {0.1, 10.0}}, 0.0, 0.0));
  expect_input_error(
      [&] { CoulombLayerBound(0.2, law); },
      {"contact.friction: F_b(-0.1) = -0.2 but (15c) requires F_b(r) = 0 for r <= 0", "(34)", "contact.normal_law"});
  // ... but μ = 0 makes F_b ≡ 0, which satisfies (15c).
  EXPECT_NO_THROW(CoulombLayerBound(0.0, law));
}

TEST(FrictionTresca, ConstantBound) {
  const TrescaBound fb(1.5);
  EXPECT_EQ(fb.F(-3.0), 1.5);  // deliberately nonzero for r <= 0 (outside (15c))
  EXPECT_EQ(fb.F(0.3), 1.5);
  EXPECT_EQ(fb.lipschitz(), 0.0);
  EXPECT_FALSE(fb.depends_on_u_nu());
  expect_input_error([] { TrescaBound{-1.0}; }, {"contact.friction.bound", ">= 0"});
  expect_input_error([] { TrescaBound{INF}; }, {"contact.friction.bound"});
}

TEST(FrictionTable, ValuesLipschitzAndDependence) {
  const TableBound fb(PiecewiseLinearLaw({{0.0, 0.0}, {0.1, 1.0}, {0.3, 2.0}}, 0.0, 0.0));
  EXPECT_EQ(fb.F(-0.2), 0.0);
  EXPECT_NEAR(fb.F(0.05), 0.5, 1e-14);
  EXPECT_NEAR(fb.F(0.2), 1.5, 1e-14);
  EXPECT_NEAR(fb.F(1.0), 2.0, 1e-14);
  EXPECT_NEAR(fb.lipschitz(), 10.0, 1e-12);
  EXPECT_TRUE(fb.depends_on_u_nu());
  const TableBound zero(PiecewiseLinearLaw({{0.0, 0.0}, {1.0, 0.0}}, 0.0, 0.0));
  EXPECT_FALSE(zero.depends_on_u_nu());
  const TableBound step(PiecewiseLinearLaw({{0.0, 0.0}, {0.1, 0.0}, {0.1, 1.0}}, 0.0, 0.0));
  EXPECT_EQ(step.lipschitz(), INF);  // (15a) fails; accepted, reported as INF
}

struct Bad15c {
  std::string name;
  std::vector<PiecewiseLinearLaw::Point> points;
  double slope_left, slope_right;
  std::vector<std::string> message_parts;
};

class FrictionTableValidation : public ::testing::TestWithParam<Bad15c> {};

TEST_P(FrictionTableValidation, Rejects15cViolations) {
  const Bad15c& bad = GetParam();
  SCOPED_TRACE(bad.name);
  expect_input_error(
      [&] {
        TableBound(PiecewiseLinearLaw(bad.points, bad.slope_left, bad.slope_right, "contact.friction"),
                   "contact.friction");
      },
      bad.message_parts);
}

const std::string ZERO_RULE = "but (15c) requires F_b(r) = 0 for r <= 0";
const std::string SIGN_RULE = "but (15c) requires F_b(r) >= 0 for r >= 0";

INSTANTIATE_TEST_SUITE_P(
    FrictionTables, FrictionTableValidation,
    ::testing::Values(
        Bad15c{"value_at_negative_r",
               {{-0.1, 0.3}, {0.0, 0.0}, {0.1, 1.0}},
               0.0,
               0.0,
               {"contact.friction: F_b(-0.1) = 0.3 " + ZERO_RULE}},
        Bad15c{"slope_left", {{0.0, 0.0}, {0.1, 1.0}}, 2.0, 0.0, {"contact.friction", "slope_left", ZERO_RULE}},
        Bad15c{"value_at_zero", {{0.0, 0.5}, {0.1, 1.0}}, 0.0, 0.0, {"contact.friction: F_b(0) = 0.5 " + ZERO_RULE}},
        Bad15c{"jump_at_zero",
               {{0.0, 0.0}, {0.0, 1.0}, {0.1, 1.0}},
               0.0,
               0.0,
               {"contact.friction: F_b(0) = 1 " + ZERO_RULE}},
        Bad15c{"zero_inside_segment",
               {{-0.1, 0.0}, {0.1, 1.0}},
               0.0,
               0.0,
               {"contact.friction: F_b(0) = 0.5 " + ZERO_RULE}},
        Bad15c{"all_negative_rising",
               {{-0.2, 0.0}, {-0.1, 0.0}},
               0.0,
               1.0,
               {"contact.friction: F_b(0) = 0.1 " + ZERO_RULE}},
        Bad15c{"first_point_positive",
               {{0.1, 0.2}, {0.2, 1.0}},
               0.0,
               0.0,
               {"contact.friction: F_b(0) = 0.2 " + ZERO_RULE}},
        Bad15c{"negative_value",
               {{0.0, 0.0}, {0.1, -1.0}, {0.2, 1.0}},
               0.0,
               0.0,
               {"contact.friction: F_b(0.1) = -1 " + SIGN_RULE}},
        Bad15c{"negative_after_drop",
               {{0.0, 0.0}, {0.1, 1.0}, {0.1, -0.5}, {0.2, 1.0}},
               0.0,
               0.0,
               {"contact.friction: F_b(0.1) = -0.5 " + SIGN_RULE}},
        Bad15c{"slope_right", {{0.0, 0.0}, {0.1, 1.0}}, 0.0, -20.0, {"contact.friction", "slope_right", SIGN_RULE}}),
    [](const ::testing::TestParamInfo<Bad15c>& info) { return info.param.name; });

TEST(FrictionTable, AcceptsBoundaryCases) {
  // Zero up to 0.05 then rising; zero at a negative breakpoint; a jump up at r > 0.
  EXPECT_NO_THROW(TableBound(PiecewiseLinearLaw({{-1.0, 0.0}, {0.05, 0.0}, {0.2, 1.0}}, 0.0, 0.0)));
  EXPECT_NO_THROW(TableBound(PiecewiseLinearLaw({{0.0, 0.0}, {0.1, 0.0}, {0.1, 2.0}}, 0.0, 3.0)));
}

}  // namespace
}  // namespace hemicontact
