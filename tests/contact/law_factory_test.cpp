// Tests of law_factory: JSON (schema-validated, defaults injected as null) → normal law (32) and
// friction bound (34)/(15); round trips and errors that name the key path.

#include <hemicontact/contact/law_factory.hpp>
#include <hemicontact/core/error.hpp>

#include "support/expect_error.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

using json = nlohmann::json;

using hemicontact::test::expect_input_error;

/// contact.normal_law as scene/config delivers it: every key present, unused ones null.
json normal_law_obj(const json& set) {
  json obj = {{"type", nullptr}, {"c1", nullptr},     {"c2", nullptr},         {"c3", nullptr},         {"r1", nullptr},
              {"r2", nullptr},   {"points", nullptr}, {"slope_left", nullptr}, {"slope_right", nullptr}};
  if (set.is_object()) obj.update(set);
  return obj;
}

/// contact.friction as scene/config delivers it.
json friction_obj(const json& set) {
  json obj = {{"type", nullptr},   {"mu", nullptr},         {"bound", nullptr},
              {"points", nullptr}, {"slope_left", nullptr}, {"slope_right", nullptr}};
  if (set.is_object()) obj.update(set);
  return obj;
}

json paper_json() {
  return normal_law_obj({{"type", "paper"}, {"c1", 100}, {"c2", -100}, {"c3", 400}, {"r1", 0.1}, {"r2", 0.15}});
}

TEST(LawFactory, PaperAndEquivalentTableAgree) {
  const auto paper = make_normal_law(paper_json());
  ASSERT_TRUE(paper);
  // The same law written as a table, twice: explicit end slopes, and null slope_left with an
  // extra point on the flat part so that "continue the first segment" gives slope 0.
  const auto table = make_normal_law(normal_law_obj(
      {{"type", "table"}, {"points", {{0, 0}, {0.1, 10}, {0.15, 5}}}, {"slope_left", 0}, {"slope_right", 400}}));
  const auto table_nulls = make_normal_law(
      normal_law_obj({{"type", "table"}, {"points", {{-1, 0}, {0, 0}, {0.1, 10}, {0.15, 5}, {0.2, 25}}}}));
  ASSERT_TRUE(table && table_nulls);
  for (int i = 0; i <= 1000; ++i) {
    const double r = -0.5 + 1.0 * i / 1000.0;
    SCOPED_TRACE("r = " + std::to_string(r));
    // Same breakpoints up to the extra (inactive) ones; sums differ only by rounding (~1e-13).
    EXPECT_NEAR(paper->p(r), table->p(r), 1e-12);
    EXPECT_NEAR(paper->p(r), table_nulls->p(r), 1e-12);
    EXPECT_NEAR(paper->j(r), table->j(r), 1e-12);
    EXPECT_NEAR(paper->j(r), table_nulls->j(r), 1e-12);
    EXPECT_NEAR(paper->dp(r), table->dp(r), 1e-9);  // table slopes = differences/0.05: ~1 ulp off
  }
  EXPECT_EQ(paper->one_sided_lipschitz(), 100.0);
  EXPECT_NEAR(table->one_sided_lipschitz(), 100.0, 1e-9);
}

TEST(LawFactory, NullSlopesAndNone) {
  const auto law = make_normal_law(normal_law_obj({{"type", "table"}, {"points", {{0, 0}, {0.1, 1}, {0.2, 3}}}}));
  EXPECT_NEAR(law->slope_left(), 10.0, 1e-12);
  EXPECT_NEAR(law->slope_right(), 20.0, 1e-12);
  EXPECT_EQ(make_normal_law(normal_law_obj({{"type", "none"}})), nullptr);
  EXPECT_EQ(make_normal_law(json{{"type", "none"}}), nullptr);  // absent keys = null
}

struct BadJson {
  std::string name;
  json obj;
  std::vector<std::string> message_parts;
};

class LawFactoryErrors : public ::testing::TestWithParam<BadJson> {};

TEST_P(LawFactoryErrors, NamesTheKey) {
  SCOPED_TRACE(GetParam().name);
  expect_input_error([&] { make_normal_law(GetParam().obj); }, GetParam().message_parts);
}

INSTANTIATE_TEST_SUITE_P(
    LawFactoryCases, LawFactoryErrors,
    ::testing::Values(
        BadJson{"unknown_type", normal_law_obj({{"type", "cubic"}}), {"contact.normal_law.type", "cubic"}},
        BadJson{"missing_type", normal_law_obj({}), {"contact.normal_law.type"}},
        BadJson{"missing_c1",
                normal_law_obj({{"type", "paper"}, {"c2", -100}, {"c3", 400}, {"r1", 0.1}, {"r2", 0.15}}),
                {"contact.normal_law.c1", "required"}},
        BadJson{
            "c1_string",
            normal_law_obj({{"type", "paper"}, {"c1", "100"}, {"c2", -100}, {"c3", 400}, {"r1", 0.1}, {"r2", 0.15}}),
            {"contact.normal_law.c1", "number"}},
        BadJson{"bad_kinks",
                normal_law_obj({{"type", "paper"}, {"c1", 100}, {"c2", -100}, {"c3", 400}, {"r1", 0.2}, {"r2", 0.15}}),
                {"contact.normal_law.r2"}},
        BadJson{"points_with_paper",
                [] {
                  json o = paper_json();
                  o["points"] = {{0, 0}};
                  return o;
                }(),
                {"contact.normal_law.points", "not used by type 'paper'"}},
        BadJson{"c1_with_table",
                normal_law_obj({{"type", "table"}, {"points", {{0, 0}}}, {"c1", 3}}),
                {"contact.normal_law.c1", "not used by type 'table'"}},
        BadJson{"slope_with_none",
                normal_law_obj({{"type", "none"}, {"slope_right", 1}}),
                {"contact.normal_law.slope_right", "not used by type 'none'"}},
        BadJson{"missing_points", normal_law_obj({{"type", "table"}}), {"contact.normal_law.points", "required"}},
        BadJson{"point_not_pair",
                normal_law_obj({{"type", "table"}, {"points", {{0, 0}, {0.1, 1, 2}}}}),
                {"contact.normal_law.points[1]", "[r, value]"}},
        BadJson{"decreasing_r",
                normal_law_obj({{"type", "table"}, {"points", {{0, 0}, {0.2, 1}, {0.1, 2}}}}),
                {"contact.normal_law.points[2]: r decreases (0.1 after 0.2)"}},
        BadJson{"unknown_key",
                [] {
                  json o = paper_json();
                  o["c4"] = 1;
                  return o;
                }(),
                {"contact.normal_law.c4", "unknown key"}},
        BadJson{"not_object", json::array({1, 2}), {"contact.normal_law", "object"}}),
    [](const ::testing::TestParamInfo<BadJson>& info) { return info.param.name; });

TEST(FrictionFactory, BuildsEachType) {
  const auto law = make_normal_law(paper_json());
  EXPECT_EQ(make_friction_bound(friction_obj({{"type", "none"}}), law), nullptr);

  const auto coulomb = make_friction_bound(friction_obj({{"type", "coulomb_layer"}, {"mu", 0.2}}), law);
  ASSERT_TRUE(coulomb);
  for (double r : {-0.1, 0.05, 0.12, 0.2}) EXPECT_NEAR(coulomb->F(r), 0.2 * law->p(r), 1e-14);
  EXPECT_TRUE(coulomb->depends_on_u_nu());

  const auto tresca = make_friction_bound(friction_obj({{"type", "tresca"}, {"bound", 1.0}}), nullptr);
  ASSERT_TRUE(tresca);
  EXPECT_EQ(tresca->F(-1.0), 1.0);
  EXPECT_FALSE(tresca->depends_on_u_nu());

  // null slope_left → 0 for friction tables ((15c)), null slope_right → last segment.
  const auto table =
      make_friction_bound(friction_obj({{"type", "table"}, {"points", {{0, 0}, {0.1, 1}, {0.2, 1.5}}}}), nullptr);
  ASSERT_TRUE(table);
  EXPECT_EQ(table->F(-1.0), 0.0);
  EXPECT_NEAR(table->F(0.3), 2.0, 1e-13);
  EXPECT_NEAR(table->lipschitz(), 10.0, 1e-12);
}

class FrictionFactoryErrors : public ::testing::TestWithParam<BadJson> {};

TEST_P(FrictionFactoryErrors, NamesTheKey) {
  SCOPED_TRACE(GetParam().name);
  const bool with_law = GetParam().name.rfind("nolaw", 0) != 0;
  const auto law = with_law ? make_normal_law(paper_json()) : nullptr;
  expect_input_error([&] { make_friction_bound(GetParam().obj, law); }, GetParam().message_parts);
}

INSTANTIATE_TEST_SUITE_P(
    FrictionFactoryCases, FrictionFactoryErrors,
    ::testing::Values(
        BadJson{"nolaw_coulomb",
                friction_obj({{"type", "coulomb_layer"}, {"mu", 0.2}}),
                {"contact.friction.type", "needs a normal law"}},
        BadJson{"unknown_type", friction_obj({{"type", "coulomb"}}), {"contact.friction.type", "coulomb"}},
        BadJson{"missing_mu", friction_obj({{"type", "coulomb_layer"}}), {"contact.friction.mu", "required"}},
        BadJson{"negative_mu", friction_obj({{"type", "coulomb_layer"}, {"mu", -0.2}}), {"contact.friction.mu"}},
        BadJson{"mu_with_tresca",
                friction_obj({{"type", "tresca"}, {"bound", 1}, {"mu", 0.2}}),
                {"contact.friction.mu", "not used by type 'tresca'"}},
        BadJson{"missing_bound", friction_obj({{"type", "tresca"}}), {"contact.friction.bound", "required"}},
        BadJson{"negative_bound", friction_obj({{"type", "tresca"}, {"bound", -1}}), {"contact.friction.bound"}},
        BadJson{"points_with_none",
                friction_obj({{"type", "none"}, {"points", {{0, 0}}}}),
                {"contact.friction.points", "not used by type 'none'"}},
        BadJson{"table_15c",
                friction_obj({{"type", "table"}, {"points", {{-0.1, 0.3}, {0, 0}, {0.1, 1}}}}),
                {"contact.friction: F_b(-0.1) = 0.3 but (15c) requires F_b(r) = 0 for r <= 0"}},
        BadJson{"table_bad_point",
                friction_obj({{"type", "table"}, {"points", {{0, 0}, {"a", 1}}}}),
                {"contact.friction.points[1]"}},
        BadJson{"table_decreasing",
                friction_obj({{"type", "table"}, {"points", {{0, 0}, {0.2, 1}, {0.1, 2}}}}),
                {"contact.friction.points[2]", "r decreases"}}),
    [](const ::testing::TestParamInfo<BadJson>& info) { return info.param.name; });

}  // namespace
}  // namespace hemicontact
