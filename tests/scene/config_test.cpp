// Tests of the scene schema: defaults, round trip, every error class with its message, --set
// overrides, file loading, and the generated docs/scene-format.md.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include "../support/expect_error.hpp"
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace hemicontact {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

/// The message of the Error thrown by @p f (and that it is an input error); "" if none.
std::string config_input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), EXIT_INPUT) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected an input error";
  return "";
}

/// The smallest valid scene: the required keys only.
json minimal_scene() {
  return json::parse(R"({
    "material": {"E": 2000, "nu": 0.4},
    "boundary": {"gamma1": [{"side": "top"}]}
  })");
}

/// The paper's example (docs/model.md §5), exercising most sections.
json paper_scene() {
  return json::parse(R"({
    "description": "paper example",
    "mesh": {"n": 16, "diagonal": "symmetric"},
    "material": {"E": 2000, "nu": 0.4, "plane": "stress"},
    "boundary": {
      "gamma1": [{"side": "top"}],
      "gamma2": [{"side": "left", "from": 0.5, "traction": [8e-3, 0]},
                 {"side": "right", "from": 0.5, "traction": [-8e-3, 0]},
                 {"side": "left", "to": 0.5}, {"side": "right", "to": 0.5}],
      "gamma3": [{"side": "bottom"}]
    },
    "loads": {"body_force": [0, -0.5e-3]},
    "contact": {
      "gap": {"along": "x", "points": [[0, 0.15], [1.0, 0.2]]},
      "normal_law": {"type": "paper", "c1": 100, "c2": -100, "c3": 400, "r1": 0.1, "r2": 0.15},
      "friction": {"type": "coulomb_layer", "mu": 0.2}
    },
    "solver": {"options": {"mu_strategy": "adaptive"}, "fixed_point": {"max_iters": 20.0}}
  })");
}

TEST(SceneSchema, DefaultsInjectedEverywhere) {
  json s = minimal_scene();
  s["boundary"]["gamma2"] = json::array({json{{"side", "left"}, {"from", 0.5}}});
  const json e = validate_scene(s);
  EXPECT_EQ(e["description"], "");
  EXPECT_EQ(e["mesh"]["type"], "rectangle");
  EXPECT_EQ(e["mesh"]["x"], json({0, 1}));
  EXPECT_EQ(e["mesh"]["nx"], 8);
  EXPECT_TRUE(e["mesh"]["n"].is_null());
  EXPECT_EQ(e["material"]["plane"], "stress");
  EXPECT_EQ(e["solver"]["continuation"]["factor"], 1e-2);
  EXPECT_EQ(e["solver"]["fixed_point"]["relaxation"], 1);
  EXPECT_EQ(e["solver"]["options"], json::object());
  EXPECT_EQ(e["contact"]["normal_law"]["type"], "none");
  EXPECT_TRUE(e["contact"]["gap"].is_null());
  EXPECT_EQ(e["boundary"]["gamma3"], json::array());
  // Inside array elements: each selector gets from/to (and traction on Γ2) ...
  EXPECT_TRUE(e["boundary"]["gamma1"][0]["from"].is_null());
  EXPECT_TRUE(e["boundary"]["gamma1"][0]["physical"].is_null());
  EXPECT_FALSE(e["boundary"]["gamma1"][0].contains("traction"));
  EXPECT_EQ(e["boundary"]["gamma2"][0]["traction"], json({0, 0}));
  EXPECT_TRUE(e["boundary"]["gamma2"][0]["to"].is_null());
  // ... while given values are kept.
  EXPECT_EQ(e["boundary"]["gamma2"][0]["from"], 0.5);
  EXPECT_EQ(e["material"]["E"], 2000);
}

TEST(SceneSchema, EveryOptionalRowIsPresentAfterValidation) {
  const json e = validate_scene(minimal_scene());
  for (const SchemaEntry& row : scene_schema()) {
    // Rows under array elements or inside the object form of gap exist only with their parent.
    if (row.pointer.find('*') != std::string::npos || row.pointer.rfind("/contact/gap/", 0) == 0) continue;
    SCOPED_TRACE(row.pointer);
    ASSERT_TRUE(e.contains(json::json_pointer(row.pointer)));
    if (!row.required) {
      EXPECT_EQ(e[json::json_pointer(row.pointer)].is_object(), row.type == "object" || row.type == "object*");
    }
  }
}

TEST(SceneSchema, SchemaTableIsWellFormed) {
  std::set<std::string> seen;
  for (const SchemaEntry& row : scene_schema()) {
    SCOPED_TRACE(row.pointer);
    EXPECT_TRUE(seen.insert(row.pointer).second) << "duplicate row";
    EXPECT_FALSE(row.doc.empty());
    if (row.required) {
      EXPECT_TRUE(row.default_value.is_null());
    }
    if (!row.options.empty() && row.default_value.is_string()) {
      EXPECT_NE(std::find(row.options.begin(), row.options.end(), row.default_value.get<std::string>()),
                row.options.end());
    }
  }
  // The contract's spot checks: a default written in two places would show up here first.
  const auto row = [](const std::string& p) {
    for (const SchemaEntry& r : scene_schema())
      if (r.pointer == p) return r;
    ADD_FAILURE() << "no row " << p;
    return SchemaEntry{};
  };
  EXPECT_EQ(row("/solver/tol").default_value, 1e-12);
  EXPECT_EQ(row("/solver/max_iter").default_value, 3000);
  EXPECT_EQ(row("/solver/fixed_point/tol_u").default_value, 1e-12);
  EXPECT_EQ(row("/boundary/gamma2/*/traction").default_value, json({0, 0}));
  EXPECT_TRUE(row("/material/E").required);
  EXPECT_TRUE(row("/boundary/gamma1").required);
  EXPECT_EQ(row("/solver/options").type, "object*");
}

TEST(SceneSchema, EffectiveSceneRoundTrips) {
  for (const json& s : {minimal_scene(), paper_scene()}) {
    const json once = validate_scene(s);
    EXPECT_EQ(validate_scene(once), once);
    EXPECT_EQ(validate_scene(json::parse(once.dump())), once);  // through text, as in report.json
  }
}

TEST(SceneSchema, MeshNSetsNxAndNy) {
  json s = minimal_scene();
  s["mesh"] = {{"n", 32}, {"nx", 4}};
  const json e = validate_scene(s);
  EXPECT_EQ(e["mesh"]["nx"], 32);
  EXPECT_EQ(e["mesh"]["ny"], 32);
}

TEST(SceneSchema, IntegralFloatIsStoredAsInteger) {
  const json e = validate_scene(paper_scene());
  EXPECT_TRUE(e["solver"]["fixed_point"]["max_iters"].is_number_integer());
  EXPECT_EQ(get_int(e, "solver.fixed_point.max_iters"), 20);
}

TEST(SceneSchema, OpenObjectsAcceptAnything) {
  json s = minimal_scene();
  const json anything = json::parse(R"({"a": [1, {"b": null}], "nx": "not checked", "E": -1})");
  s["solver"]["options"] = anything;
  const json e = validate_scene(s);
  EXPECT_EQ(e["solver"]["options"], anything);
}

// ---------------------------------------------------------------- errors

TEST(SceneSchemaErrors, UnknownKeyNamesDottedPathWithHint) {
  json s = minimal_scene();
  s["mesh"]["nn"] = 4;
  const std::string msg = config_input_error_of([&] { validate_scene(s); });
  EXPECT_CONTAINS(msg, "scene: unknown key 'mesh.nn' (did you mean 'mesh.n'?)");
}

// ssn's settings left solver.petsc for solver.ssn (both engines read them): an older scene is told
// where each went, and the value lands there once moved.
TEST(SceneSchemaErrors, AMovedKeyNamesItsNewHome) {
  const std::pair<const char*, const char*> moved[] = {{"ssn_max_iters", "solver.ssn.max_iters"},
                                                       {"ssn_rtol", "solver.ssn.step_rtol"},
                                                       {"ssn_tol", "solver.ssn.tol"}};
  for (const auto& [old_key, new_key] : moved) {
    json s = minimal_scene();
    s["solver"]["petsc"][old_key] = 7;
    EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                    std::string("unknown key 'solver.petsc.") + old_key + "' (moved to '" + new_key + "')");
  }
  json s = minimal_scene();
  s["solver"]["ssn"]["max_iters"] = 7;
  const SolveOptions o = solve_options_from_scene(validate_scene(s));
  EXPECT_EQ(o.ssn.max_iters, 7);
  EXPECT_EQ(o.ssn.tol, SsnOptions{}.tol);
}

// The petsc engine's replicated layout was retired: a scene that asks for it, or sets the graph
// partition that only it read, is told why and where to go instead of which values or keys exist.
TEST(SceneSchemaErrors, TheRetiredReplicatedLayoutSaysWhereToGo) {
  json s = minimal_scene();
  s["solver"]["petsc"]["mesh"] = "replicated";
  const std::string msg = config_input_error_of([&] { validate_scene(s); });
  EXPECT_CONTAINS(msg, "scene key 'solver.petsc.mesh': \"replicated\": the replicated layout of the petsc engine was "
                       "retired: the distributed layouts (slabs, blocks, DMPlex) solve every scene");
  EXPECT_CONTAINS(msg, "use \"auto\" (the default) or \"blocks\"");
  EXPECT_EQ(msg.find("is not one of"), std::string::npos) << msg;
  json p = minimal_scene();
  p["solver"]["petsc"]["partition"] = "natural";
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(p); }),
                  "unknown key 'solver.petsc.partition' (the replicated layout of the petsc engine was retired");
  // The layouts that remain are accepted as they were.
  for (const char* layout : {"auto", "blocks"}) {
    json ok = minimal_scene();
    ok["solver"]["petsc"]["mesh"] = layout;
    EXPECT_EQ(solve_options_from_scene(validate_scene(ok)).petsc.mesh, layout);
  }
}

TEST(SceneSchemaErrors, UnknownKeyInsideArrayElement) {
  json s = minimal_scene();
  s["boundary"]["gamma1"][0]["traction"] = {1, 0};  // only Γ2 selectors carry a traction
  const std::string msg = config_input_error_of([&] { validate_scene(s); });
  EXPECT_CONTAINS(msg, "unknown key 'boundary.gamma1[0].traction'");
  EXPECT_CONTAINS(msg, "boundary.gamma2[*].traction");
}

TEST(SceneSchemaErrors, UnknownKeyHintFromElsewhereOrList) {
  json s = minimal_scene();
  s["solver"]["mu"] = 0.2;
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "did you mean 'contact.friction.mu'?");
  s = minimal_scene();
  s["output"]["zzzzzz"] = true;
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "(allowed here: vtu, vtu_format, csv, plot)");
  s = minimal_scene();
  s["solver"]["continuation/eps_start"] = 1e-3;  // a '/' in a key must not address a row
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "unknown key 'solver.continuation/eps_start'");
}

TEST(SceneSchemaErrors, WrongType) {
  json s = minimal_scene();
  s["mesh"]["nx"] = "abc";
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "scene key 'mesh.nx': expected integer, got string \"abc\"");
  s["mesh"]["nx"] = 2.5;
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'mesh.nx': expected integer, got number 2.5");
  s["mesh"]["nx"] = 1e10;  // integral but beyond int
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "expected integer");
  s = minimal_scene();
  s["mesh"]["n"] = true;
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "scene key 'mesh.n': expected integer or null, got boolean true");
  s = minimal_scene();
  s["boundary"]["gamma2"] = {{{"side", "left"}, {"traction", {1, "x"}}}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "scene key 'boundary.gamma2[0].traction': expected number[]");
  s = minimal_scene();
  s["boundary"]["gamma1"] = {{"side", "top"}};  // an object, not a list of selectors
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'boundary.gamma1': expected array");
  EXPECT_CONTAINS(config_input_error_of([] { validate_scene(json::array()); }), "top level must be a JSON object");
}

TEST(SceneSchemaErrors, EnumListsOptions) {
  json s = minimal_scene();
  s["mesh"]["diagonal"] = "diag";
  const std::string msg = config_input_error_of([&] { validate_scene(s); });
  EXPECT_CONTAINS(msg, "scene key 'mesh.diagonal': \"diag\" is not one of: right, left, symmetric, crossed");
  s = minimal_scene();
  s["boundary"]["gamma1"][0]["side"] = "up";
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "'boundary.gamma1[0].side': \"up\" is not one of: left, right, bottom, top");
}

TEST(SceneSchemaErrors, RequiredMissing) {
  json s = minimal_scene();
  s["material"].erase("E");
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene: missing required key 'material.E'");
  s = minimal_scene();
  s.erase("boundary");
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "missing required key 'boundary.gamma1'");
  s = paper_scene();
  s["contact"]["gap"].erase("points");
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "missing required key 'contact.gap.points'");
}

TEST(SceneSchemaErrors, Ranges) {
  const auto with = [](const std::string& pointer, const json& v) {
    json s = minimal_scene();
    s[json::json_pointer(pointer)] = v;
    return config_input_error_of([&] { validate_scene(s); });
  };
  EXPECT_CONTAINS(with("/material/E", -1), "scene key 'material.E' must be > 0, got -1");
  EXPECT_CONTAINS(with("/material/E", 0), "must be > 0, got 0");
  EXPECT_CONTAINS(with("/mesh/nx", 0), "scene key 'mesh.nx' must be >= 1, got 0");
  EXPECT_CONTAINS(with("/mesh/n", 0), "scene key 'mesh.n' must be >= 1");
  EXPECT_CONTAINS(with("/solver/continuation/factor", 1), "must be > 0 and < 1, got 1");
  EXPECT_CONTAINS(with("/solver/fixed_point/relaxation", 0), "must be > 0 and <= 1, got 0");
  EXPECT_CONTAINS(with("/solver/fixed_point/relaxation", 1.5), "must be > 0 and <= 1, got 1.5");
  EXPECT_CONTAINS(with("/solver/eps_tau", 0.0), "'solver.eps_tau' must be > 0");
  EXPECT_CONTAINS(with("/solver/max_iter", 0), "'solver.max_iter' must be >= 1");
  EXPECT_CONTAINS(with("/check/certificate_tol", -1e-3), "'check.certificate_tol' must be > 0");
  // The bounds themselves, where allowed, pass.
  json s = minimal_scene();
  s["solver"]["fixed_point"]["relaxation"] = 1;
  s["mesh"]["nx"] = 1;
  EXPECT_NO_THROW(validate_scene(s));
}

TEST(SceneSchemaErrors, NonFiniteNumbers) {
  json s = minimal_scene();
  s["material"]["E"] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'material.E': number is not finite (nan)");
  s = minimal_scene();
  s["solver"]["options"]["x"] = {1.0, std::numeric_limits<double>::infinity()};  // even in open objects
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "'solver.options.x[1]': number is not finite (inf)");
}

TEST(SceneSchemaErrors, SelectorNeedsExactlyOneOfSideAndPhysical) {
  json s = paper_scene();
  s["boundary"]["gamma2"][1]["physical"] = "right_wall";
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "scene key 'boundary.gamma2[1]': set exactly one of 'side' and 'physical', not both");
  s = paper_scene();
  s["boundary"]["gamma3"][0].erase("side");
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'boundary.gamma3[0]': set exactly one of");
  s = paper_scene();
  s["boundary"]["gamma2"][0]["to"] = 0.5;  // from = 0.5
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "'boundary.gamma2[0]': empty range [from, to) = [0.5, 0.5)");
}

// An interval on a physical group was ignored: {"physical": "contact", "from": 100, "to": 200}
// selected the whole group and certified. It is refused, naming the key, on every
// boundary part and on the rollers.
TEST(SceneSchemaErrors, IntervalOnAPhysicalSelectorIsRefused) {
  for (const char* part : {"gamma1", "gamma3", "rollers"}) {
    SCOPED_TRACE(part);
    json s = paper_scene();
    json sel = {{"physical", "contact"}, {"from", 100}, {"to", 200}};
    if (std::string(part) == "rollers") sel["components"] = {"x"};
    s["boundary"][part] = json::array({sel});
    EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                    std::string("scene key 'boundary.") + part + "[0].from': an interval [from, to) restricts a 'side'");
    s["boundary"][part][0].erase("from");
    EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                    std::string("scene key 'boundary.") + part + "[0].to'");
  }
  // The rollers are checked as the three parts are (they were not before).
  json s = paper_scene();
  s["boundary"]["rollers"] = json::array({{{"side", "left"}, {"physical", "x"}, {"components", {"x"}}}});
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "'boundary.rollers[0]': set exactly one of 'side' and 'physical', not both");
}

// A key of one mesh type on a scene of another changed nothing: refused, naming it.
TEST(SceneSchemaErrors, MeshKeysOfAnotherMeshTypeAreRefused) {
  json s = paper_scene();
  s["mesh"]["file"] = "m.msh";  // a rectangle
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "scene key 'mesh.file': is read for mesh.type = \"gmsh\" only (mesh.type is 'rectangle')");
  s = paper_scene();
  s["mesh"] = {{"type", "gmsh"}, {"file", "m.msh"}, {"n", 8}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'mesh.n': refines a generated mesh");
  s["mesh"] = {{"type", "gmsh"}, {"file", "m.msh"}, {"perturb", 0.1}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'mesh.perturb'");
  s["mesh"] = {{"type", "box"}, {"grading", {{"x", "low"}}}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "scene key 'mesh.grading': grades a rectangle's grid lines only (mesh.type is 'box')");
  s["mesh"] = {{"type", "box"}, {"diagonal", "crossed"}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "scene key 'mesh.diagonal': is not read for this mesh (mesh.type is 'box')");
  s["mesh"] = {{"type", "rectangle"}, {"pattern", "symmetric"}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'mesh.pattern'");
  s["mesh"] = {{"type", "rectangle"}, {"z", {0, 2}}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'mesh.z'");
  s["mesh"] = {{"type", "gmsh"}, {"file", "m.msh"}, {"x", {0, 4}}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "scene key 'mesh.x'");
  for (const char* k : {"nx", "ny", "nz"}) {  // a grid size on a mesh read as it is
    s["mesh"] = {{"type", "gmsh"}, {"file", "m.msh"}, {k, 5}};
    EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                    std::string("scene key 'mesh.") + k + "': is not read for this mesh (mesh.type is 'gmsh')");
  }
  s["mesh"] = {{"type", "gmsh"}, {"file", "m.msh"}};
  EXPECT_NO_THROW(validate_scene(s));
  // An effective scene (every default filled in) validates again: the defaults are not "set".
  for (const char* type : {"rectangle", "box"}) {
    json e = paper_scene();
    e["mesh"] = {{"type", type}, {"n", 4}};
    EXPECT_NO_THROW(validate_scene(validate_scene(e))) << type;
  }
}

// A NUL byte in mesh.file ended the name early in every system call (and cut the messages short).
TEST(SceneSchemaErrors, NulByteInMeshFileIsRefused) {
  json s = paper_scene();
  s["mesh"] = {{"type", "gmsh"}, {"file", std::string("m.msh\0.txt", 11)}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "scene key 'mesh.file': the file name holds a NUL byte (\\u0000) at character 6");
}

TEST(SceneSchemaErrors, Gap) {
  json s = minimal_scene();
  for (const json& ok : {json(0.15), json(0), json("inf"), json(nullptr)}) {
    s["contact"]["gap"] = ok;
    EXPECT_NO_THROW(validate_scene(s)) << ok;
  }
  s["contact"]["gap"] = -0.1;
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "contact.gap: negative thickness g = -0.1");
  s["contact"]["gap"] = "infinite";
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "contact.gap: the only string allowed is \"inf\"");
  s["contact"]["gap"] = json::array({0.1});
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }),
                  "'contact.gap': expected number or string or object or null");

  json t = paper_scene();
  t["contact"]["gap"]["along"] = "r";
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(t); }), "'contact.gap.along': \"r\" is not one of: x, y, z");
  t = paper_scene();
  t["contact"]["gap"]["alnog"] = "x";
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(t); }),
                  "unknown key 'contact.gap.alnog' (did you mean 'contact.gap.along'?)");
  t = paper_scene();
  t["contact"]["gap"]["points"] = {{0, 0.1}, {1, -0.1}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(t); }), "'contact.gap.points[1]': negative thickness g = -0.1");
  t["contact"]["gap"]["points"] = {{0.5, 0.1}, {0.5, 0.1}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(t); }), "'contact.gap.points[1]': x must be strictly increasing");
  t["contact"]["gap"]["points"] = {{0.5, 0.1, 3}};
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(t); }), "'contact.gap.points[0]': expected a pair");
  t = paper_scene();
  t["contact"]["friction"]["points"] = {{1, 0}, {0, 1}};  // the law tables share the shape check
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(t); }), "'contact.friction.points[1]': x must be non-decreasing");
  // ...but a repeated r is allowed there: it is a jump of the law.
  t = paper_scene();
  t["contact"]["normal_law"] = {{"type", "table"}, {"points", {{0, 0}, {0.1, 10}, {0.1, 2}}}};
  EXPECT_NO_THROW(validate_scene(t));
}

// ---------------------------------------------------------------- overrides

TEST(SceneOverrides, NestedArrayAndOpenPaths) {
  json s = paper_scene();
  apply_override(s, "mesh.n=128");
  apply_override(s, "boundary.gamma2.0.traction=[1,0]");
  apply_override(s, "boundary.gamma2[1].from=0.25");
  apply_override(s, "solver.options.mu_strategy=monotone");
  apply_override(s, "solver.options.linear_solver=\"ma27\"");
  apply_override(s, "solver.options.note=a=b");  // split at the first '='
  apply_override(s, "output.vtu=false");
  apply_override(s, "contact.gap=inf");
  apply_override(s, "solver.options.deep.new.key=null");                   // intermediate objects are created
  apply_override(s, "boundary.gamma3.1={\"side\":\"top\",\"from\":0.9}");  // index == size appends
  const json e = validate_scene(s);
  EXPECT_EQ(e["mesh"]["n"], 128);
  EXPECT_EQ(e["mesh"]["nx"], 128);
  EXPECT_EQ(e["boundary"]["gamma2"][0]["traction"], json({1, 0}));
  EXPECT_EQ(e["boundary"]["gamma2"][0]["from"], 0.5);  // siblings untouched
  EXPECT_EQ(e["boundary"]["gamma2"][1]["from"], 0.25);
  EXPECT_EQ(e["solver"]["options"]["mu_strategy"], "monotone");
  EXPECT_EQ(e["solver"]["options"]["linear_solver"], "ma27");
  EXPECT_EQ(e["solver"]["options"]["note"], "a=b");
  EXPECT_EQ(e["output"]["vtu"], false);
  EXPECT_EQ(e["contact"]["gap"], "inf");
  EXPECT_TRUE(e["solver"]["options"]["deep"]["new"]["key"].is_null());
  EXPECT_EQ(e["boundary"]["gamma3"][1]["to"], nullptr);
  EXPECT_EQ(e["boundary"]["gamma3"][1]["from"], 0.9);
}

TEST(SceneOverrides, LaterOverrideWinsAndCreatesFromNothing) {
  json s;
  apply_override(s, "material.E=1");
  apply_override(s, "material.E=3");
  apply_override(s, "boundary.gamma1.0.side=top");  // index 0 of an absent key starts a list
  EXPECT_EQ(s, json::parse(R"({"material": {"E": 3}, "boundary": {"gamma1": [{"side": "top"}]}})"));
}

TEST(SceneOverrides, MalformedAssignments) {
  json s = paper_scene();
  EXPECT_CONTAINS(config_input_error_of([&] { apply_override(s, "mesh.n"); }), "--set 'mesh.n': expected path=value");
  EXPECT_CONTAINS(config_input_error_of([&] { apply_override(s, "mesh..n=3"); }), "--set 'mesh..n=3': malformed path");
  EXPECT_CONTAINS(config_input_error_of([&] { apply_override(s, "=3"); }), "malformed path");
  EXPECT_CONTAINS(config_input_error_of([&] { apply_override(s, "boundary.gamma2.7.from=0"); }),
                  "index 7 out of range ('boundary.gamma2' has 4 elements)");
  EXPECT_CONTAINS(config_input_error_of([&] { apply_override(s, "boundary.gamma2.first.from=0"); }),
                  "'boundary.gamma2' is an array; 'first' is not an index");
  EXPECT_CONTAINS(config_input_error_of([&] { apply_override(s, "material.E.value=3"); }),
                  "cannot set a key inside 'material.E', which is integer 2000");
  EXPECT_CONTAINS(config_input_error_of([&] { apply_override(s, "material.E=1e999"); }), "--set 'material.E=1e999'");
}

TEST(SceneOverrides, OverrideToUnknownKeyIsReportedAsUnknown) {
  json s = paper_scene();
  apply_override(s, "mesh.nn=128");
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "unknown key 'mesh.nn' (did you mean 'mesh.n'?)");
  s = paper_scene();
  apply_override(s, "mesh.n=abc");  // not JSON → a string → a type error, not silently 0
  EXPECT_CONTAINS(config_input_error_of([&] { validate_scene(s); }), "'mesh.n': expected integer or null, got string \"abc\"");
}

// ---------------------------------------------------------------- files

class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device rd;
    m_dir = fs::temp_directory_path() / ("hemicontact_config_test_" + std::to_string(rd()));
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = m_dir / name;
    std::ofstream(p) << text;
    return p.string();
  }
  fs::path m_dir;
};

TEST_F(SceneFiles, LoadAppliesOverridesThenValidates) {
  const std::string path = write("ok.json", paper_scene().dump(2));
  const json e = load_scene(path, {"mesh.n=4", "solver.backend=newton"});
  EXPECT_EQ(e["mesh"]["nx"], 4);
  EXPECT_EQ(get_string(e, "solver.backend"), "newton");
  EXPECT_EQ(e, validate_scene(e));
  EXPECT_CONTAINS(config_input_error_of([&] { load_scene(path, {"mesh.nn=4"}); }), "unknown key 'mesh.nn'");
}

TEST_F(SceneFiles, MissingFile) {
  EXPECT_CONTAINS(config_input_error_of([&] { load_scene((m_dir / "x.json").string(), {}); }), "x.json' not found");
  EXPECT_CONTAINS(config_input_error_of([&] { load_scene(m_dir.string(), {}); }), "is a directory");
}

TEST_F(SceneFiles, MalformedJsonGivesLineAndColumn) {
  //                                       line 3: `  "mesh": {"n": 4,},` → column 19 is the '}'
  const std::string path = write("bad.json", "{\n  \"description\": \"x\",\n  \"mesh\": {\"n\": 4,},\n}\n");
  const std::string msg = config_input_error_of([&] { load_scene(path, {}); });
  EXPECT_CONTAINS(msg, "scene file '" + path + "': parse error at line 3, column 19: ");
  EXPECT_CONTAINS(msg, "syntax error");
  // An error at the end of a line is placed on that line, not on the next one.
  const std::string path2 = write("bad2.json", "{\n  \"a\": tru\n}");
  EXPECT_CONTAINS(config_input_error_of([&] { load_scene(path2, {}); }), "parse error at line 2, column 11");
}

TEST_F(SceneFiles, DuplicateKeyIsAnError) {
  const std::string path =
      write("dup.json", R"({"boundary": {"gamma2": [{"side": "left"}, {"side": "left", "from": 0, "from": 1}]}})");
  EXPECT_CONTAINS(config_input_error_of([&] { load_scene(path, {}); }), "duplicate key 'boundary.gamma2[1].from'");
  const std::string path2 = write("dup2.json", R"({"mesh": {"n": 2}, "mesh": {"n": 3}})");
  EXPECT_CONTAINS(config_input_error_of([&] { load_scene(path2, {}); }), "duplicate key 'mesh'");
}

TEST(SceneDirectory, ParentOrDot) {
  EXPECT_EQ(scene_directory("problems/paper.json"), "problems");
  EXPECT_EQ(scene_directory("/a/b/c.json"), "/a/b");
  EXPECT_EQ(scene_directory("c.json"), ".");
}

TEST(SceneAccessors, TypedReadsAndInternalErrors) {
  const json e = validate_scene(paper_scene());
  EXPECT_EQ(get_number(e, "material.E"), 2000.0);
  EXPECT_EQ(get_int(e, "mesh.ny"), 16);
  EXPECT_EQ(get_string(e, "boundary.gamma2[1].side"), "right");
  EXPECT_EQ(get_number(e, "boundary.gamma2.1.traction.0"), -8e-3);
  EXPECT_TRUE(get_bool(e, "output.csv"));
  EXPECT_EQ(scene_at(e, "contact.gap.along"), "x");
  for (const auto& read : std::vector<std::function<void()>>{[&] { get_number(e, "material.EE"); },
                                                             [&] { get_number(e, "contact.friction.bound"); },
                                                             [&] { get_int(e, "material.nu"); }}) {
    try {
      read();
      ADD_FAILURE() << "expected an internal error";
    } catch (const Error& err) {
      EXPECT_EQ(err.code(), EXIT_INTERNAL) << err.what();
    }
  }
}

// ---------------------------------------------------------------- generated documentation

TEST(SceneSchema, MarkdownMatchesDoc) {
  const fs::path doc = fs::path(HEMICONTACT_SOURCE_DIR) / "docs" / "scene-format.md";
  const std::string generated = schema_markdown();
  if (const char* regen = std::getenv("HEMICONTACT_REGENERATE_DOCS"); regen && std::string(regen) == "1") {
    std::ofstream(doc, std::ios::binary) << generated;
    GTEST_SKIP() << "rewrote " << doc;
  }
  std::ifstream in(doc, std::ios::binary);
  std::ostringstream committed;
  committed << in.rdbuf();
  EXPECT_TRUE(committed.str() == generated)
      << doc << " differs from schema_markdown() (src/scene/scene_schema.cpp). Regenerate it with\n"
      << "  HEMICONTACT_REGENERATE_DOCS=1 build-config/tests/hemicontact_tests "
         "--gtest_filter=SceneSchema.MarkdownMatchesDoc\nand commit the result.";
}

TEST(SceneSchema, MarkdownListsEveryRow) {
  const std::string md = schema_markdown();
  EXPECT_CONTAINS(md, "| `boundary.gamma2[*].traction` | `number[]` | `[0,0]` |");
  EXPECT_CONTAINS(md, "| `mesh.n` | `integer\\|null` | `null` | `>= 1` |");
  EXPECT_CONTAINS(md, "| `material.E` | `number` | **required** | `> 0` |");
  for (const SchemaEntry& row : scene_schema()) {
    std::string dotted = row.pointer.substr(1);
    for (std::size_t p; (p = dotted.find("/*")) != std::string::npos;) dotted.replace(p, 2, "[*]");
    for (char& c : dotted) c = c == '/' ? '.' : c;
    EXPECT_CONTAINS(md, "| `" + dotted + "` |");
  }
}

}  // namespace
}  // namespace hemicontact
