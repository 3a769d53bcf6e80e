#include <hemicontact/contact/law_factory.hpp>

#include <hemicontact/core/error.hpp>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

namespace hemicontact {

namespace {

using json = nlohmann::json;

// Defaults are injected as null (scene/config), so "absent" and "null" mean the same: not set.
bool is_set(const json& obj, const std::string& key) {
  const auto it = obj.find(key);
  return it != obj.end() && !it->is_null();
}

// The schema should have rejected unknown keys already; checking again costs nothing and
// keeps the factory safe when called from tests or other drivers with hand-made JSON.
void check_object(const json& obj, const std::string& ctx, const std::vector<std::string>& known) {
  if (!obj.is_object()) input_error(ctx + ": expected an object (got " + obj.dump() + ")");
  for (const auto& item : obj.items())
    if (std::find(known.begin(), known.end(), item.key()) == known.end())
      input_error(ctx + "." + item.key() + ": unknown key");
}

std::string read_type(const json& obj, const std::string& ctx, const std::vector<std::string>& allowed) {
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  if (!is_set(obj, "type") || !obj.at("type").is_string()) input_error(ctx + ".type: required string, one of " + list);
  const std::string type = obj.at("type").get<std::string>();
  if (std::find(allowed.begin(), allowed.end(), type) == allowed.end())
    input_error(ctx + ".type: unknown type '" + type + "' (expected one of " + list + ")");
  return type;
}

void check_unused(const json& obj, const std::string& ctx, const std::string& type,
                  const std::vector<std::string>& unused) {
  for (const auto& key : unused)
    if (is_set(obj, key))
      input_error(ctx + "." + key + ": not used by type '" + type + "'; it must be null or absent (got " +
                  obj.at(key).dump() + ")");
}

double required_number(const json& obj, const std::string& ctx, const std::string& key, const std::string& type) {
  if (!is_set(obj, key)) input_error(ctx + "." + key + ": required by type '" + type + "'");
  const json& v = obj.at(key);
  if (!v.is_number()) input_error(ctx + "." + key + ": expected a number (got " + v.dump() + ")");
  return v.get<double>();
}

std::optional<double> optional_number(const json& obj, const std::string& ctx, const std::string& key) {
  if (!is_set(obj, key)) return std::nullopt;
  const json& v = obj.at(key);
  if (!v.is_number()) input_error(ctx + "." + key + ": expected a number or null (got " + v.dump() + ")");
  return v.get<double>();
}

std::vector<PiecewiseLinearLaw::Point> read_points(const json& obj, const std::string& ctx, const std::string& type) {
  const std::string key = ctx + ".points";
  if (!is_set(obj, "points")) input_error(key + ": required by type '" + type + "'");
  const json& pts = obj.at("points");
  if (!pts.is_array()) input_error(key + ": expected an array of [r, value] pairs");
  std::vector<PiecewiseLinearLaw::Point> out;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const json& pt = pts[i];
    if (!pt.is_array() || pt.size() != 2 || !pt[0].is_number() || !pt[1].is_number())
      input_error(key + "[" + std::to_string(i) + "]: expected [r, value], two numbers (got " + pt.dump() + ")");
    out.push_back({pt[0].get<double>(), pt[1].get<double>()});
  }
  return out;
}

}  // namespace

std::shared_ptr<const PiecewiseLinearLaw> make_normal_law(const json& obj) {
  const std::string ctx = "contact.normal_law";
  check_object(obj, ctx, {"type", "c1", "c2", "c3", "r1", "r2", "points", "slope_left", "slope_right"});
  const std::string type = read_type(obj, ctx, {"paper", "table", "none"});
  if (type == "none") {
    check_unused(obj, ctx, type, {"c1", "c2", "c3", "r1", "r2", "points", "slope_left", "slope_right"});
    return nullptr;
  }
  if (type == "paper") {
    check_unused(obj, ctx, type, {"points", "slope_left", "slope_right"});
    return std::make_shared<const PiecewiseLinearLaw>(
        PiecewiseLinearLaw::paper(required_number(obj, ctx, "c1", type), required_number(obj, ctx, "c2", type),
                                  required_number(obj, ctx, "c3", type), required_number(obj, ctx, "r1", type),
                                  required_number(obj, ctx, "r2", type), ctx));
  }
  check_unused(obj, ctx, type, {"c1", "c2", "c3", "r1", "r2"});
  return std::make_shared<const PiecewiseLinearLaw>(read_points(obj, ctx, type),
                                                    optional_number(obj, ctx, "slope_left"),
                                                    optional_number(obj, ctx, "slope_right"), ctx);
}

std::shared_ptr<const FrictionBound> make_friction_bound(const json& obj,
                                                         std::shared_ptr<const PiecewiseLinearLaw> normal_law) {
  const std::string ctx = "contact.friction";
  check_object(obj, ctx, {"type", "mu", "bound", "points", "slope_left", "slope_right"});
  const std::string type = read_type(obj, ctx, {"none", "coulomb_layer", "tresca", "table"});
  if (type == "none") {
    check_unused(obj, ctx, type, {"mu", "bound", "points", "slope_left", "slope_right"});
    return nullptr;
  }
  if (type == "coulomb_layer") {
    check_unused(obj, ctx, type, {"bound", "points", "slope_left", "slope_right"});
    const double mu = required_number(obj, ctx, "mu", type);
    if (!normal_law)
      input_error(ctx +
                  ".type: 'coulomb_layer' (F_b = mu p_nu, eq. (34)) needs a normal law, "
                  "but contact.normal_law.type is 'none'");
    return std::make_shared<const CoulombLayerBound>(mu, std::move(normal_law), ctx);
  }
  if (type == "tresca") {
    check_unused(obj, ctx, type, {"mu", "points", "slope_left", "slope_right"});
    return std::make_shared<const TrescaBound>(required_number(obj, ctx, "bound", type), ctx);
  }
  check_unused(obj, ctx, type, {"mu", "bound"});
  // null slope_left → 0, not "continue the first segment" as for the normal law: (15c) forces
  // F_b = 0 for r ≤ 0, so 0 is the only admissible value and the natural default.
  const std::optional<double> slope_left = optional_number(obj, ctx, "slope_left");
  return std::make_shared<const TableBound>(PiecewiseLinearLaw(read_points(obj, ctx, type), slope_left.value_or(0.0),
                                                               optional_number(obj, ctx, "slope_right"), ctx),
                                            ctx);
}

}  // namespace hemicontact
