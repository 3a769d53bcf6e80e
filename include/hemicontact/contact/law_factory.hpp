#pragma once
/// @file law_factory.hpp  Build the normal law (32)–(33) and the friction bound (34)/(15) from the scene JSON.
///
/// Input is the already schema-validated object with defaults injected (scene/config), so every key
/// below is present, unused ones as null. The factory still checks what the schema cannot:
/// the type-dependent keys, the table rules and (15c), with errors naming the key path.
///
/// contact.normal_law — keys type, c1, c2, c3, r1, r2, points, slope_left, slope_right:
///  - {"type":"paper","c1":100,"c2":-100,"c3":400,"r1":0.1,"r2":0.15}: eq. (32);
///  - {"type":"table","points":[[r,p],...],"slope_left":s|null,"slope_right":s|null}: a
///    PiecewiseLinearLaw; null slope_left/slope_right continue the first/last segment
///    (0 if the table has a single distinct r);
///  - {"type":"none"}: no soft layer (nullptr).
///
/// contact.friction — keys type, mu, bound, points, slope_left, slope_right:
///  - {"type":"none"}: frictionless (nullptr);
///  - {"type":"coulomb_layer","mu":0.2}: F_b = μ p_ν, eq. (34); needs a normal law;
///  - {"type":"tresca","bound":1.0}: constant slip bound (outside (15c), see TrescaBound);
///  - {"type":"table","points":[[r,F],...],"slope_left":s|null,"slope_right":s|null}: null
///    slope_left means 0 (the only value (15c) admits), null slope_right continues the last segment.
/// Keys not used by the chosen type must be null or absent.

#include <hemicontact/contact/friction_bound.hpp>
#include <hemicontact/contact/piecewise_linear_law.hpp>

#include <nlohmann/json.hpp>

#include <memory>

namespace hemicontact {

/// @brief Build the exact normal law from `contact.normal_law`.
/// @param normal_law_obj the JSON object at contact.normal_law
/// @return the law, or nullptr for type "none"
/// @throws Error (EXIT_INPUT) naming "contact.normal_law.<key>" for a missing, misplaced or invalid value
std::shared_ptr<const PiecewiseLinearLaw> make_normal_law(const nlohmann::json& normal_law_obj);

/// @brief Build the friction bound from `contact.friction`.
/// @param friction_obj the JSON object at contact.friction
/// @param normal_law   the exact normal law (may be null; required by "coulomb_layer")
/// @return the bound, or nullptr for type "none"
/// @throws Error (EXIT_INPUT) naming "contact.friction.<key>", or (15c) violations
std::shared_ptr<const FrictionBound> make_friction_bound(const nlohmann::json& friction_obj,
                                                         std::shared_ptr<const PiecewiseLinearLaw> normal_law);

}  // namespace hemicontact
