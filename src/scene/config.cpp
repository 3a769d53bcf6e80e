#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/text.hpp>
#include <hemicontact/scene/config.hpp>
#include <set>
#include <sstream>
#include <unordered_map>

namespace hemicontact {
namespace {

using nlohmann::json;

// ============================================================== names and paths
// Schema rows are addressed by JSON pointers (with "*" for array elements); users see dotted
// paths with [i] for array elements, the form that error messages print and --set accepts.

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? sep : "") + parts[i];
  return out;
}

// RFC 6901 escaping, so that a user key such as "continuation/eps_start" cannot address a row.
std::string escape_segment(const std::string& key) {
  std::string out;
  for (char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return out;
}

std::string parent_pointer(const std::string& pointer) { return pointer.substr(0, pointer.rfind('/')); }
std::string last_segment(const std::string& pointer) { return pointer.substr(pointer.rfind('/') + 1); }

std::string child_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string element_path(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

/// "/boundary/gamma2/*/traction" → "boundary.gamma2[*].traction".
std::string dotted_from_pointer(const std::string& pointer) {
  std::string path;
  for (const std::string& seg : split(pointer.substr(1), '/')) path = seg == "*" ? path + "[*]" : child_path(path, seg);
  return path;
}

/// "boundary.gamma2[0].traction" or "boundary.gamma2.0.traction" → {boundary, gamma2, 0, traction};
/// empty when a segment is empty (malformed).
std::vector<std::string> split_dotted(const std::string& dotted) {
  std::string flat;
  bool in_index = false;  // between [ and ]: digits only ("a[1=2", "a]", "a[x]" are malformed)
  bool closed = false;    // just after ]: only ., [ or the end may follow ("a[1]b" is malformed)
  for (char c : dotted) {
    if (closed && c != '.' && c != '[') return {};
    closed = false;
    if (c == '[') {
      if (in_index) return {};
      in_index = true;
      flat += '.';
    } else if (c == ']') {
      if (!in_index || flat.empty() || flat.back() == '.') return {};
      in_index = false;
      closed = true;
    } else {
      if (in_index && !std::isdigit(static_cast<unsigned char>(c))) return {};
      flat += c;
    }
  }
  if (in_index) return {};
  std::vector<std::string> segs = split(flat, '.');
  for (const std::string& s : segs)
    if (s.empty()) return {};
  return segs;
}

bool is_index(const std::string& s) {
  return !s.empty() && s.size() < 10 &&
         std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// Optimal-string-alignment distance: Levenshtein plus adjacent transpositions ("alnog" →
/// "along" is 1), the commonest typo in a key.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// ============================================================== values and messages

std::string kind(const json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "boolean";
  if (v.is_number_integer()) return "integer";
  if (v.is_number()) return "number";
  if (v.is_string()) return "string";
  if (v.is_array()) return "array";
  return "object";
}

/// "string \"abc\"", "number 2.5", "null": the kind and a bounded excerpt of the value.
std::string show(const json& v) {
  if (v.is_null()) return "null";
  std::string text = v.dump();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return kind(v) + " " + text;
}

std::string format_number(double x) {
  std::ostringstream os;
  os.precision(15);
  os << x;
  return os.str();
}

[[noreturn]] void key_error(const std::string& path, const std::string& message) {
  input_error(path.empty() ? "scene: " + message : "scene key '" + printable(path) + "': " + message);
}

/// "> 0", ">= 1", "> 0 and <= 1"; empty without bounds. Shared by messages and the docs.
std::string range_text(const SchemaEntry& e) {
  std::vector<std::string> parts;
  if (e.min) parts.push_back((e.min_exclusive ? "> " : ">= ") + format_number(*e.min));
  if (e.max) parts.push_back((e.max_exclusive ? "< " : "<= ") + format_number(*e.max));
  return join(parts, " and ");
}

// ============================================================== types

const std::set<std::string>& type_tokens() {
  static const std::set<std::string> tokens = {"number", "integer", "string", "boolean",  "null",
                                               "object", "object*", "array",  "number[]", "number[][]"};
  return tokens;
}

bool is_number_array(const json& v) {
  return v.is_array() && std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); });
}

// 32-bit because the consumers store counts and seeds in int; an integral float (8.0) counts.
bool is_int32(const json& v) {
  if (v.is_number_unsigned()) return v.get<std::uint64_t>() <= static_cast<std::uint64_t>(INT_MAX);
  if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    return i >= INT_MIN && i <= INT_MAX;
  }
  if (!v.is_number_float()) return false;
  const double x = v.get<double>();
  return std::isfinite(x) && x == std::floor(x) && x >= INT_MIN && x <= INT_MAX;
}

bool matches(const json& v, const std::string& token) {
  if (token == "number") return v.is_number();
  if (token == "integer") return is_int32(v);
  if (token == "string") return v.is_string();
  if (token == "boolean") return v.is_boolean();
  if (token == "null") return v.is_null();
  if (token == "object" || token == "object*") return v.is_object();
  if (token == "array") return v.is_array();
  if (token == "number[]") return is_number_array(v);
  if (token == "number[][]")
    return v.is_array() && std::all_of(v.begin(), v.end(), [](const json& r) { return is_number_array(r); });
  return false;
}

// ============================================================== the indexed table

struct SchemaIndex {
  std::unordered_map<std::string, const SchemaEntry*> by_pointer;
  /// Named children of each object row ("" = the top level), in table order.
  std::unordered_map<std::string, std::vector<const SchemaEntry*>> children;
};

const SchemaIndex& schema_index();

void validate_object(json& obj, const std::string& pointer, const std::string& path, const SchemaIndex& idx);

/// Why the petsc engine's replicated layout (every rank building the whole model) was retired, for
/// both settings that only it read: a scene written for it is told where to go instead.
const char* const REPLICATED_RETIRED =
    "the replicated layout of the petsc engine was retired: the distributed layouts (slabs, blocks, "
    "DMPlex) solve every scene, in less memory per rank (docs/petsc-engine.md)";

/// String values that were retired: the message that replaces "is not one of".
const std::map<std::pair<std::string, std::string>, std::string>& retired_values() {
  static const std::map<std::pair<std::string, std::string>, std::string> retired = {
      {{"/solver/petsc/mesh", "replicated"},
       std::string(REPLICATED_RETIRED) + "; use \"auto\" (the default) or \"blocks\""},
  };
  return retired;
}

/// Check @p v against row @p e; with @p recurse, also its keys / elements (injecting defaults).
void check_value(json& v, const SchemaEntry& e, const std::string& path, const SchemaIndex& idx, bool recurse) {
  const std::vector<std::string> alternatives = split(e.type, '|');
  const auto hit =
      std::find_if(alternatives.begin(), alternatives.end(), [&](const std::string& t) { return matches(v, t); });
  if (hit == alternatives.end()) {
    std::vector<std::string> shown;
    for (const std::string& t : alternatives) shown.push_back(t == "object*" ? "object" : t);
    key_error(path, "expected " + join(shown, " or ") + ", got " + show(v));
  }
  // Store 8.0 as 8 so that readers and the echoed report see an integer.
  if (*hit == "integer" && v.is_number_float()) v = static_cast<std::int64_t>(v.get<double>());

  if (v.is_number()) {
    const double x = v.get<double>();
    const bool low = e.min && (e.min_exclusive ? !(x > *e.min) : !(x >= *e.min));
    const bool high = e.max && (e.max_exclusive ? !(x < *e.max) : !(x <= *e.max));
    if (low || high) input_error("scene key '" + path + "' must be " + range_text(e) + ", got " + v.dump());
  }
  if (v.is_array() && e.max_items && v.size() > *e.max_items)
    input_error("scene key '" + path + "' has " + std::to_string(v.size()) + " elements; at most " +
                std::to_string(*e.max_items) + " are allowed");
  if (v.is_string() && !e.options.empty() &&
      std::find(e.options.begin(), e.options.end(), v.get<std::string>()) == e.options.end()) {
    const auto retired = retired_values().find({e.pointer, v.get<std::string>()});
    if (retired != retired_values().end()) key_error(path, v.dump() + ": " + retired->second);
    key_error(path, v.dump() + " is not one of: " + join(e.options, ", "));
  }

  if (!recurse) return;
  if (*hit == "object") {
    validate_object(v, e.pointer, path, idx);
  } else if (v.is_array()) {
    const auto element = idx.by_pointer.find(e.pointer + "/*");
    if (element != idx.by_pointer.end())
      for (std::size_t i = 0; i < v.size(); ++i) check_value(v[i], *element->second, element_path(path, i), idx, true);
  }
}

/// Keys that moved: their new home, so that a scene written for an older version is told where
/// its setting went instead of which keys exist (ssn's settings serve both engines since they left
/// solver.petsc).
const std::map<std::string, std::string>& moved_keys() {
  static const std::map<std::string, std::string> moved = {
      {"/solver/petsc/ssn_max_iters", "solver.ssn.max_iters"},
      {"/solver/petsc/ssn_rtol", "solver.ssn.step_rtol"},
      {"/solver/petsc/ssn_tol", "solver.ssn.tol"},
  };
  return moved;
}

/// Keys that were retired with what they set: why, instead of a near sibling's name.
const std::map<std::string, std::string>& retired_keys() {
  static const std::map<std::string, std::string> retired = {
      // The graph partition of the whole model's nodes: the slabs and blocks are their own
      // partition, and DMPlex partitions with PT-Scotch.
      {"/solver/petsc/partition", REPLICATED_RETIRED},
  };
  return retired;
}

/// " (did you mean 'mesh.n'?)": a moved key's new home, a near sibling, else the same name
/// elsewhere in the table (e.g. "solver.mu" → "contact.friction.mu"), else the allowed keys.
std::string unknown_key_hint(const std::string& key, const std::string& pointer, const std::string& path,
                             const SchemaIndex& idx) {
  const auto moved = moved_keys().find(pointer + "/" + escape_segment(key));
  if (moved != moved_keys().end()) return " (moved to '" + moved->second + "')";
  const auto retired = retired_keys().find(pointer + "/" + escape_segment(key));
  if (retired != retired_keys().end()) return " (" + retired->second + ")";
  const auto it = idx.children.find(pointer);
  const std::vector<const SchemaEntry*> none;
  const auto& siblings = it == idx.children.end() ? none : it->second;
  const std::size_t threshold = std::max<std::size_t>(1, key.size() / 3);
  std::string best;
  std::size_t best_distance = threshold + 1;
  for (const SchemaEntry* s : siblings) {
    const std::string name = last_segment(s->pointer);
    const std::size_t d = edit_distance(lower(key), lower(name));
    if (d < best_distance) best = name, best_distance = d;
  }
  if (!best.empty()) return " (did you mean '" + child_path(path, best) + "'?)";
  for (const SchemaEntry& e : scene_schema())
    if (lower(last_segment(e.pointer)) == lower(key))
      return " (did you mean '" + dotted_from_pointer(e.pointer) + "'?)";
  std::vector<std::string> names;
  for (const SchemaEntry* s : siblings) names.push_back(last_segment(s->pointer));
  return " (allowed here: " + join(names, ", ") + ")";
}

void validate_object(json& obj, const std::string& pointer, const std::string& path, const SchemaIndex& idx) {
  for (auto& item : obj.items()) {
    const std::string& k = item.key();
    const auto row = k == "*" ? idx.by_pointer.end() : idx.by_pointer.find(pointer + "/" + escape_segment(k));
    if (row == idx.by_pointer.end())
      input_error("scene: unknown key '" + printable(child_path(path, k)) + "'" +
                  printable(unknown_key_hint(k, pointer, path, idx)));
    check_value(item.value(), *row->second, child_path(path, k), idx, true);
  }
  const auto it = idx.children.find(pointer);
  if (it == idx.children.end()) return;
  for (const SchemaEntry* c : it->second) {
    const std::string name = last_segment(c->pointer);
    if (obj.contains(name)) continue;
    if (c->required) input_error("scene: missing required key '" + child_path(path, name) + "' (" + c->doc + ")");
    obj[name] = c->default_value;
    check_value(obj[name], *c, child_path(path, name), idx, true);  // a section's own defaults
  }
}

// A malformed table is a bug: report it as internal on first use, and in every test run.
SchemaIndex build_index(const std::vector<SchemaEntry>& table) {
  SchemaIndex idx;
  const auto bug = [](const SchemaEntry& e, const std::string& what) {
    throw Error("scene schema row '" + e.pointer + "': " + what, EXIT_INTERNAL);
  };
  for (const SchemaEntry& e : table) {
    if (e.pointer.size() < 2 || e.pointer[0] != '/') bug(e, "not a JSON pointer");
    if (!idx.by_pointer.emplace(e.pointer, &e).second) bug(e, "duplicate row");
    for (const std::string& t : split(e.type, '|'))
      if (!type_tokens().count(t)) bug(e, "unknown type '" + t + "'");
    const std::string parent = parent_pointer(e.pointer);
    const std::string name = last_segment(e.pointer);
    if (!parent.empty()) {
      const auto p = idx.by_pointer.find(parent);
      if (p == idx.by_pointer.end()) bug(e, "parent row missing or listed after it");
      const auto ptypes = split(p->second->type, '|');
      const char* needed = name == "*" ? "array" : "object";
      if (std::find(ptypes.begin(), ptypes.end(), needed) == ptypes.end())
        bug(e, std::string("parent is not an ") + needed);
    }
    if (name != "*") idx.children[parent].push_back(&e);
    if (e.required && !e.default_value.is_null()) bug(e, "a required row has a default");
    if (!e.required) {
      json d = e.default_value;
      try {
        check_value(d, e, dotted_from_pointer(e.pointer), idx, false);
      } catch (const Error& err) {
        bug(e, std::string("default does not satisfy the row: ") + err.what());
      }
    }
  }
  return idx;
}

const SchemaIndex& schema_index() {
  static const SchemaIndex idx = build_index(scene_schema());
  return idx;
}

// ============================================================== checks beyond single rows

// JSON text cannot hold NaN or inf, but a scene assembled in code can, and nlohmann would
// silently dump it as null in the report.
void check_finite(const json& v, const std::string& path) {
  if (v.is_number_float() && !std::isfinite(v.get<double>()))
    key_error(path, std::string("number is not finite (") + (std::isnan(v.get<double>()) ? "nan" : "inf") + ")");
  if (v.is_object())
    for (const auto& item : v.items()) check_finite(item.value(), child_path(path, item.key()));
  if (v.is_array())
    for (std::size_t i = 0; i < v.size(); ++i) check_finite(v[i], element_path(path, i));
}

// Every result file is JSON, which is UTF-8: a key or string that is not would make the report
// unwritable after the whole computation, so it is refused here, naming it. Iterative, as depth_of:
// no recursion over a structure that came from outside.
void check_text(const json& scene) {
  const std::string advice =
      "; scene text must be UTF-8, as the JSON results are (re-encode it, e.g. iconv -f latin1 -t utf-8)";
  std::vector<std::pair<const json*, std::string>> todo{{&scene, ""}};
  while (!todo.empty()) {
    const auto [v, path] = todo.back();
    todo.pop_back();
    if (v->is_string() && invalid_utf8_at(v->get_ref<const std::string&>()) != std::string::npos)
      key_error(path, "the text is not valid UTF-8 (" + describe_invalid_utf8(v->get_ref<const std::string&>()) + ")" +
                          advice);
    if (v->is_object())
      for (const auto& item : v->items()) {
        if (invalid_utf8_at(item.key()) != std::string::npos)
          key_error(child_path(path, item.key()), "the key is not valid UTF-8 (" + describe_invalid_utf8(item.key()) +
                                                      ")" + advice);
        todo.emplace_back(&item.value(), child_path(path, item.key()));
      }
    if (v->is_array())
      for (std::size_t i = 0; i < v->size(); ++i) todo.emplace_back(&(*v)[i], element_path(path, i));
  }
}

// A file name is handed to the C library, which ends it at a NUL byte: "m.msh\u0000.txt" would
// read m.msh, and the messages printed the name cut short.
void check_file_name(const json& name, const std::string& path) {
  if (!name.is_string()) return;
  const std::string& text = name.get_ref<const std::string&>();
  const size_t nul = text.find('\0');
  if (nul != std::string::npos)
    key_error(path, "the file name holds a NUL byte (\\u0000) at character " + std::to_string(nul + 1) + " ('" +
                        printable(text) + "'); a file name cannot contain one");
  if (text.empty()) key_error(path, "empty file name");
}

// Keys of one mesh type set on a scene of another changed nothing, silently (an audit of the schema):
// refused where the key's default tells a set value apart (null, 0, "none"). mesh.nx/ny/nz,
// x/y/z, diagonal and pattern have non-null defaults and cannot be told apart here.
void check_mesh_keys(const json& mesh) {
  const std::string type = mesh.at("type").get<std::string>();
  // A Gmsh scene without its file: build_mesh's "mesh.file: required" is the first thing to fix.
  if (type == "gmsh" && mesh.at("file").is_null()) return;
  const std::string is = " (mesh.type is '" + type + "')";
  if (type != "gmsh" && !mesh.at("file").is_null())
    key_error("mesh.file", "is read for mesh.type = \"gmsh\" only" + is + ": remove it, or set mesh.type");
  if (type == "gmsh") {
    if (!mesh.at("n").is_null())
      key_error("mesh.n", "refines a generated mesh (rectangle, box); a Gmsh mesh is used as read" + is);
    if (mesh.at("perturb").get<double>() > 0)
      key_error("mesh.perturb", "moves the nodes of a generated mesh (rectangle, box), not of a Gmsh mesh" + is);
  }
  const json& g = mesh.at("grading");
  if (type != "rectangle" && (g.at("x") != "none" || g.at("y") != "none"))
    key_error("mesh.grading", "grades a rectangle's grid lines only" + is);
  // Keys with a default of their own: refused where set to another value and not read. (nx, ny,
  // nz only on a Gmsh mesh: elsewhere mesh.n copies itself into all three whatever the type.)
  const auto unread = [&](const char* key, bool read) {
    const std::string dotted = std::string("mesh.") + key;
    if (!read && mesh.at(key) != schema_default(dotted))
      key_error(dotted, "is not read for this mesh" + is + " and would be ignored: remove it, or set mesh.type");
  };
  unread("diagonal", type == "rectangle");
  unread("pattern", type == "box");
  unread("z", type == "box");
  unread("x", type != "gmsh");
  unread("y", type != "gmsh");
  // A Gmsh scene refuses mesh.n (above), so a grid size there was set by hand, and dropped.
  for (const char* k : {"nx", "ny", "nz"}) unread(k, type != "gmsh");
}

void check_selectors(const json& boundary) {
  for (const char* gamma : {"gamma1", "gamma2", "gamma3", "rollers"}) {
    const json& list = boundary.at(gamma);
    for (std::size_t i = 0; i < list.size(); ++i) {
      const json& s = list[i];
      const std::string path = element_path(std::string("boundary.") + gamma, i);
      const bool side = !s.at("side").is_null(), physical = !s.at("physical").is_null();
      if (side && physical) key_error(path, "set exactly one of 'side' and 'physical', not both");
      if (!side && !physical)
        key_error(path, "set exactly one of 'side' (a side of the bounding box) and 'physical' (a Gmsh group)");
      const json &from = s.at("from"), &to = s.at("to");
      // [from, to) is measured along a side of the bounding box; a physical group has no such axis,
      // and an interval on it was silently ignored (the whole group selected).
      if (physical && !(from.is_null() && to.is_null()))
        key_error(path + (from.is_null() ? ".to" : ".from"),
                  "an interval [from, to) restricts a 'side' selector only (it is measured along the side); "
                  "a 'physical' group is taken whole: remove from/to, or make the group smaller in the mesh");
      if (from.is_number() && to.is_number() && !(from.get<double>() < to.get<double>()))
        key_error(path, "empty range [from, to) = [" + from.dump() + ", " + to.dump() + ")");
    }
  }
}

/// A piecewise-linear table [[x, y], ...]: pairs, x increasing, optionally y ≥ 0. With
/// @p allow_jumps (the p_ν and F_b tables) an x may repeat once: a jump of the law at x
/// (the law's own validation then checks the rest, e.g. no x three times).
void check_points(const json& points, const std::string& path, bool nonnegative, const std::string& y_name,
                  bool allow_jumps = false) {
  if (points.is_null()) return;
  if (points.empty()) key_error(path, "needs at least one point [x, " + y_name + "]");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const json& p = points[i];
    if (p.size() != 2) key_error(element_path(path, i), "expected a pair [x, " + y_name + "], got " + p.dump());
    if (nonnegative && p[1].get<double>() < 0)
      key_error(element_path(path, i), "negative thickness " + y_name + " = " + p[1].dump());
    if (i == 0) continue;
    const double x = p[0].get<double>(), x_prev = points[i - 1][0].get<double>();
    if (allow_jumps ? x < x_prev : !(x > x_prev))
      key_error(element_path(path, i), std::string("x must be ") +
                                           (allow_jumps ? "non-decreasing" : "strictly increasing") + ", got " +
                                           p[0].dump() + " after " + points[i - 1][0].dump());
  }
}

// mesh.x, mesh.y: [a, b] with a < b (the generator would only say "empty rectangle").
void check_interval(const json& v, const std::string& path) {
  if (v.size() != 2 || !(v[0].get<double>() < v[1].get<double>()))
    key_error(path, "expected an interval [a, b] with a < b, got " + v.dump());
  // Lengths, areas and volumes are products of widths: a width near the double range would make
  // them inf or 0 ("measure -nan" deep in the mesh code). 1e-100..1e100 leaves room for cubes.
  const double a = v[0].get<double>(), b = v[1].get<double>(), w = b - a;
  if (!(w <= 1e100) || !(w >= 1e-100) || std::max(std::abs(a), std::abs(b)) > 1e100)
    key_error(path, "the interval " + v.dump() +
                        " is out of range: coordinates and the width b - a must lie within 1e-100..1e100 "
                        "(choose other length units)");
}

void check_gap(const json& gap) {
  if (gap.is_number() && gap.get<double>() < 0) input_error("contact.gap: negative thickness g = " + gap.dump());
  if (gap.is_string() && gap.get<std::string>() != "inf")
    input_error("contact.gap: the only string allowed is \"inf\" (no rigid obstacle), got " + gap.dump());
  if (gap.is_object()) check_points(gap.at("points"), "contact.gap.points", true, "g");
}

// solver.options is passed to the backend verbatim, but a scene may not make the tool write or
// read files of its choosing (output_file could truncate any writable file): Ipopt's
// file options are refused here, before anything runs.
void check_solver_options(const json& solver) {
  for (const char* file_option : {"output_file", "option_file_name", "print_options_documentation"})
    if (solver.at("options").contains(file_option))
      key_error(std::string("solver.options.") + file_option,
                "Ipopt options that name or write files are not accepted from a scene (it writes only into "
                "its --out folder); Ipopt's log goes to stderr with solver.print_level");
}

// The continuation runs from eps_start down to eps_tau/eps_nu by `factor` per stage: a factor near
// 1 means millions of stages (an effective hang), so the number of stages it implies is bounded.
void check_continuation(const json& solver) {
  const double start = solver.at("continuation").at("eps_start").get<double>();
  const double factor = solver.at("continuation").at("factor").get<double>();
  const double final_eps = std::min(solver.at("eps_tau").get<double>(), solver.at("eps_nu").get<double>());
  if (start <= final_eps) return;
  const double stages = std::ceil(std::log(final_eps / start) / std::log(factor));
  if (!(stages <= MAX_CONTINUATION_STAGES))
    key_error("solver.continuation.factor",
              format_number(factor) + " takes " + format_number(stages) + " stages from eps_start = " +
                  format_number(start) + " down to " + format_number(final_eps) + "; at most " +
                  std::to_string(MAX_CONTINUATION_STAGES) + " are allowed (a factor <= " +
                  format_number(std::pow(final_eps / start, 1.0 / MAX_CONTINUATION_STAGES)) + ")");
}

// ============================================================== reading files

/// "parse error at line L, column C: <nlohmann's description>". nlohmann's byte is the
/// 1-based position of the last character read; nlohmann's own line count is off by one after
/// a newline, hence computed here.
std::string describe_parse_error(const std::string& text, const json::parse_error& e) {
  const std::size_t offset = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + offset, '\n'));
  const std::size_t line_start = offset == 0 ? 0 : text.rfind('\n', offset - 1);
  const std::size_t column = line_start == std::string::npos || offset == 0 ? offset + 1 : offset - line_start;
  std::string what = e.what();
  const std::size_t colon = what.find(": ", what.find("parse error"));
  if (colon != std::string::npos) what = what.substr(colon + 2);
  return "parse error at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + what;
}

/// The message for nesting beyond MAX_SCENE_DEPTH.
std::string too_deep() {
  return "nesting deeper than " + std::to_string(MAX_SCENE_DEPTH) +
         " levels of objects and arrays (a scene needs at most 5; the limit keeps every walk of the scene bounded)";
}

/// Parse JSON text with nesting limited to MAX_SCENE_DEPTH: nlohmann's parser itself is iterative,
/// but the structure it builds is walked recursively afterwards (validation, dump), so a deeply
/// nested text must be refused while parsing, before the structure exists.
json parse_bounded(const std::string& text, const std::string& what) {
  return json::parse(text, [&](int depth, json::parse_event_t, json&) {
    if (static_cast<std::size_t>(depth) > MAX_SCENE_DEPTH) input_error(what + ": " + too_deep());
    return true;
  });
}

/// The nesting depth of @p v, without recursion (a scene assembled in code is not parsed).
std::size_t depth_of(const json& v) {
  std::size_t deepest = 0;
  std::vector<std::pair<const json*, std::size_t>> todo{{&v, 0}};
  while (!todo.empty()) {
    const auto [node, d] = todo.back();
    todo.pop_back();
    if (!node->is_structured()) continue;
    deepest = std::max(deepest, d + 1);
    if (d + 1 > MAX_SCENE_DEPTH) return d + 1;  // deep enough to refuse: no need to go on
    for (const auto& child : *node) todo.emplace_back(&child, d + 1);
  }
  return deepest;
}

/// nlohmann keeps the last of duplicate keys silently; in a scene that hides an edit.
json parse_rejecting_duplicates(const std::string& text, const std::string& file) {
  struct Frame {
    bool is_array;
    std::size_t index;
    std::string key;
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  const auto callback = [&](int depth, json::parse_event_t event, json& parsed) {
    using E = json::parse_event_t;
    if (static_cast<std::size_t>(depth) > MAX_SCENE_DEPTH) input_error("scene file '" + file + "': " + too_deep());
    const bool element = event == E::object_start || event == E::array_start || event == E::value;
    if (element && !stack.empty() && stack.back().is_array) ++stack.back().index;
    if (event == E::object_start || event == E::array_start) stack.push_back({event == E::array_start, 0, {}, {}});
    if (event == E::object_end || event == E::array_end) stack.pop_back();
    if (event == E::key) {
      const std::string k = parsed.get<std::string>();
      if (!stack.back().keys.insert(k).second) {
        std::string path;
        for (std::size_t i = 0; i + 1 < stack.size(); ++i)
          path = stack[i].is_array ? element_path(path, stack[i].index - 1) : child_path(path, stack[i].key);
        input_error("scene file '" + file + "': duplicate key '" + printable(child_path(path, k)) + "'");
      }
      stack.back().key = k;
    }
    return true;
  };
  return json::parse(text, callback);
}

/// Where a number that overflows a double (1e999: JSON has no inf, nlohmann refuses it) sits:
/// its key, line and column. nlohmann names only the token, so the token is replaced by a marker
/// string and the text parsed again to find the marker's path.
std::string describe_overflow(const std::string& text, const json::exception& e) {
  const std::string what = e.what();
  const std::size_t q1 = what.find("parsing '"), q2 = what.rfind('\'');
  if (q1 == std::string::npos || q2 == std::string::npos || q2 <= q1 + 9) return what;
  const std::string token = what.substr(q1 + 9, q2 - q1 - 9);
  const std::size_t at = text.find(token);
  if (at == std::string::npos) return what;
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + at, '\n'));
  const std::size_t nl = text.rfind('\n', at);
  const std::size_t column = nl == std::string::npos ? at + 1 : at - nl;
  std::string where = "line " + std::to_string(line) + ", column " + std::to_string(column);
  const std::string marker = "\"hemicontact:overflow\"";
  std::string key;
  try {
    const json marked = parse_bounded(std::string(text).replace(at, token.size(), marker), "scene");
    const std::function<bool(const json&, const std::string&)> find = [&](const json& v, const std::string& p) {
      if (v.is_string() && v.get<std::string>() == "hemicontact:overflow") return key = p, true;
      if (v.is_object())
        for (const auto& item : v.items())
          if (find(item.value(), child_path(p, item.key()))) return true;
      if (v.is_array())
        for (std::size_t i = 0; i < v.size(); ++i)
          if (find(v[i], element_path(p, i))) return true;
      return false;
    };
    find(marked, "");
  } catch (const json::exception&) {
    // a second overflowing number: line and column of the first are still right
  }
  return (key.empty() ? "" : "key '" + key + "': ") + "number " + token + " overflows a double (" + where +
         "); scene numbers must be finite";
}

json value_from_text(const std::string& text, const std::string& assignment) {
  try {
    return parse_bounded(text, "--set '" + assignment.substr(0, 80) + (assignment.size() > 80 ? "...'" : "'"));
  } catch (const json::parse_error&) {
    return text;  // not JSON: a plain string such as gmsh or monotone
  } catch (const json::exception& e) {
    input_error("--set '" + assignment + "': " + e.what() +
                " (the value is not a finite double; scene numbers must be finite)");  // 1e999
  }
}

}  // namespace

// ============================================================== public API

const json& schema_default(const std::string& dotted) {
  for (const SchemaEntry& e : scene_schema())
    if (dotted_from_pointer(e.pointer) == dotted) return e.default_value;
  input_error("schema_default: no scene key '" + dotted + "'");
}

json validate_scene(json scene) {
  const SchemaIndex& idx = schema_index();
  if (!scene.is_object()) key_error("", "the top level must be a JSON object, got " + show(scene));
  if (depth_of(scene) > MAX_SCENE_DEPTH) input_error("scene: " + too_deep());
  check_text(scene);
  check_finite(scene, "");
  validate_object(scene, "", "", idx);
  check_selectors(scene["boundary"]);
  check_file_name(scene["mesh"]["file"], "mesh.file");
  check_mesh_keys(scene["mesh"]);
  check_gap(scene["contact"]["gap"]);
  check_interval(scene["mesh"]["x"], "mesh.x");
  check_interval(scene["mesh"]["y"], "mesh.y");
  check_interval(scene["mesh"]["z"], "mesh.z");
  check_solver_options(scene["solver"]);
  check_petsc_options(scene["solver"]["petsc"]["options"].get<std::string>(), "solver.petsc.options");
  check_continuation(scene["solver"]);
  check_points(scene["contact"]["normal_law"]["points"], "contact.normal_law.points", false, "p", true);
  check_points(scene["contact"]["friction"]["points"], "contact.friction.points", false, "F_b", true);
  json& mesh = scene["mesh"];
  if (!mesh["n"].is_null()) mesh["nx"] = mesh["ny"] = mesh["nz"] = mesh["n"];
  return scene;
}

void check_key_range(const std::string& dotted, double value, const std::string& what, ExitCode code) {
  std::string pointer = "/" + dotted;
  std::replace(pointer.begin(), pointer.end(), '.', '/');
  const auto row = schema_index().by_pointer.find(pointer);
  if (row == schema_index().by_pointer.end()) throw Error("check_key_range: no scene key '" + dotted + "'", EXIT_INTERNAL);
  const SchemaEntry& e = *row->second;
  const bool low = e.min && (e.min_exclusive ? !(value > *e.min) : !(value >= *e.min));
  const bool high = e.max && (e.max_exclusive ? !(value < *e.max) : !(value <= *e.max));
  if (low || high || !std::isfinite(value))
    throw Error(what + ": must be " + (e.min || e.max ? range_text(e) : std::string("finite")) +
                    " (the range of scene key '" + dotted + "'), got " + format_number(value),
                code);
}

void apply_override(json& scene, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos) input_error("--set '" + assignment + "': expected path=value, e.g. mesh.n=64");
  const std::string shown = assignment.size() > 80 ? assignment.substr(0, 80) + "..." : assignment;
  const std::vector<std::string> segs = split_dotted(assignment.substr(0, eq));
  if (segs.empty()) input_error("--set '" + shown + "': malformed path (an empty key, or a [ without its ])");
  if (segs.size() > MAX_SCENE_DEPTH)
    input_error("--set '" + shown + "': a path of " + std::to_string(segs.size()) + " keys; " + too_deep());
  json value = value_from_text(assignment.substr(eq + 1), assignment);

  json* cur = &scene;
  std::string path;
  for (const std::string& seg : segs) {
    if (cur->is_null() && seg == "0") *cur = json::array();  // "gamma3.0.side=bottom" starts a list
    if (cur->is_array()) {
      if (!is_index(seg))
        input_error("--set '" + assignment + "': '" + path + "' is an array; '" + seg + "' is not an index");
      const std::size_t i = std::stoul(seg);
      if (i > cur->size())
        input_error("--set '" + assignment + "': index " + seg + " out of range ('" + path + "' has " +
                    std::to_string(cur->size()) + " elements)");
      if (i == cur->size()) cur->push_back(nullptr);  // appending one element is allowed
      cur = &(*cur)[i];
      path = element_path(path, i);
    } else if (cur->is_object() || cur->is_null()) {
      cur = &(*cur)[seg];  // creates the intermediate object
      path = child_path(path, seg);
    } else {
      input_error("--set '" + assignment + "': cannot set a key inside '" + path + "', which is " + show(*cur));
    }
  }
  *cur = std::move(value);
}

json load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) input_error("scene file '" + path + "' not found");
  if (fs::is_directory(path, ec)) input_error("scene file '" + path + "' is a directory");
  // Checked before opening: a FIFO would block in open(), /dev/zero and /dev/urandom never end.
  if (!fs::is_regular_file(path, ec))
    input_error("scene file '" + path + "' is not a regular file (a device, FIFO or socket); give a .json file");
  std::ifstream in(path, std::ios::binary);
  if (!in) input_error("scene file '" + path + "' cannot be read");
  // Bounded read (the file may grow, or be swapped, after the check): one byte more than allowed
  // tells "too long".
  std::string text;
  char chunk[1 << 16];
  while (text.size() <= MAX_SCENE_BYTES && in.read(chunk, sizeof chunk).gcount() > 0)
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) input_error("scene file '" + path + "' cannot be read");
  if (text.size() > MAX_SCENE_BYTES)
    input_error("scene file '" + path + "' is longer than " + std::to_string(MAX_SCENE_BYTES >> 20) +
                " MB (MAX_SCENE_BYTES); a scene is a few KB, its tables at most " + std::to_string(MAX_TABLE_POINTS) +
                " points each");
  return load_scene_text(text, path, overrides);
}

json load_scene_text(const std::string& text, const std::string& path, const std::vector<std::string>& overrides) {
  json scene;
  try {
    scene = parse_rejecting_duplicates(text, path);
  } catch (const json::parse_error& e) {
    input_error("scene file '" + path + "': " + printable(describe_parse_error(text, e)));
  } catch (const json::exception& e) {
    input_error("scene file '" + path + "': " + describe_overflow(text, e));  // number overflow (1e999)
  }
  for (const std::string& o : overrides) apply_override(scene, o);
  return validate_scene(std::move(scene));
}

std::string scene_directory(const std::string& scene_path) {
  const std::string dir = std::filesystem::path(scene_path).parent_path().string();
  return dir.empty() ? "." : dir;
}

std::string scene_path_of(const std::string& written, const std::string& scene_dir) {
  const std::filesystem::path p = written;
  return p.is_relative() ? (std::filesystem::path(scene_dir) / p).string() : p.string();
}

const json& scene_at(const json& scene, const std::string& dotted) {
  const json* cur = &scene;
  for (const std::string& seg : split_dotted(dotted)) {
    if (cur->is_array() && is_index(seg) && std::stoul(seg) < cur->size()) {
      cur = &(*cur)[std::stoul(seg)];
    } else if (cur->is_object() && cur->contains(seg)) {
      cur = &(*cur)[seg];
    } else {
      throw Error("config: key '" + dotted +
                      "' is not in the effective scene (not in the schema, or "
                      "the scene was not validated)",
                  EXIT_INTERNAL);
    }
  }
  return *cur;
}

namespace {
template <class T>
T get_as(const json& scene, const std::string& dotted, bool ok(const json&), const char* what) {
  const json& v = scene_at(scene, dotted);
  if (!ok(v)) throw Error("config: key '" + dotted + "' is " + show(v) + ", not " + what, EXIT_INTERNAL);
  return v.get<T>();
}
}  // namespace

double get_number(const json& s, const std::string& dotted) {
  return get_as<double>(
      s, dotted, [](const json& v) { return v.is_number(); }, "a number");
}
int get_int(const json& s, const std::string& dotted) {
  return get_as<int>(
      s, dotted, [](const json& v) { return v.is_number_integer() && is_int32(v); }, "an integer");
}
std::string get_string(const json& s, const std::string& dotted) {
  return get_as<std::string>(
      s, dotted, [](const json& v) { return v.is_string(); }, "a string");
}
bool get_bool(const json& s, const std::string& dotted) {
  return get_as<bool>(
      s, dotted, [](const json& v) { return v.is_boolean(); }, "a boolean");
}

// ============================================================== documentation

namespace {

std::string cell(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? "\\|" : c == '\n' ? " " : std::string(1, c);
  return out;
}

std::string code(const std::string& s) { return "`" + s + "`"; }

std::string table(const std::vector<const SchemaEntry*>& rows) {
  std::string t = "| key | type | default | allowed | description |\n|---|---|---|---|---|\n";
  for (const SchemaEntry* e : rows) {
    const std::string def = e->required                       ? "**required**"
                            : last_segment(e->pointer) == "*" ? "—"
                                                              : code(e->default_value.dump());
    std::vector<std::string> allowed;
    for (const std::string& o : e->options) allowed.push_back(code(o));
    if (e->min || e->max) allowed.push_back(code(range_text(*e)));
    if (e->max_items) allowed.push_back("at most " + std::to_string(*e->max_items) + " elements");
    t += "| " + cell(code(dotted_from_pointer(e->pointer))) + " | " + cell(code(e->type)) + " | " + cell(def) + " | " +
         cell(join(allowed, ", ")) + " | " + cell(e->doc) + " |\n";
  }
  return t;
}

const char* const MARKDOWN_HEADER = R"(# Scene file format

<!-- Generated from src/scene/scene_schema.cpp by hemicontact::schema_markdown(); do not edit by hand.
     Regenerate: HEMICONTACT_REGENERATE_DOCS=1 build-config/tests/hemicontact_tests --gtest_filter=SceneSchema.MarkdownMatchesDoc -->

A scene is one JSON object. `hemicontact solve scene.json` reads it, applies the `--set`
overrides, checks it against the tables below and fills in every default. The report echoes this
*effective* scene, so a run can be repeated from its report alone.

## Rules

- **Keys** are written as dotted paths; `[*]` means every element of an array
  (`boundary.gamma2[*].traction` is the traction of each Γ2 selector). A key that is not in the
  tables is an error, with a suggestion for the closest known key. Open objects (`object*`) are
  passed through unchecked.
- **Types.** `number` accepts integers; `integer` must be integral and fit in 32 bits (`8.0` is
  read as `8`); `a|b` allows either; `number[]` is an array of numbers and `number[][]` an array
  of such arrays. Numbers must be finite. Strings with listed values must be one of them,
  numbers must lie in the listed range, and arrays have at most the listed number of elements.
- **The file** is a regular file (not a device or a pipe) of at most 16 MB (`MAX_SCENE_BYTES`).
- **Defaults.** An absent key gets its default, inside every element of an array of objects too.
  Keys marked **required** have none. Checks that involve several keys (κ < 0.5 in plane strain,
  the parameters a `normal_law.type` needs, ...) are made by the component that uses them.
- **Selectors.** `boundary.gamma1`, `gamma2` and `gamma3` are lists of selectors. Each sets
  exactly one of `side` (a side of the mesh's bounding box) and `physical` (a Gmsh physical
  group) and may keep only the facets whose midpoint coordinate along the side lies in the
  half-open interval [from, to), with from < to.
- **Gap.** `contact.gap` is a number ≥ 0 (constant thickness), `null` or `"inf"` (no rigid
  obstacle), or `{"along": "x", "points": [[x, g], ...]}`: piecewise linear in one coordinate,
  coordinates strictly increasing, g ≥ 0. The `points` of the tabulated laws are pairs with
  non-decreasing first entries: a repeated r is a jump of p_ν (or F_b) at r.
- **`mesh.n`**, if set, overrides `mesh.nx`, `mesh.ny` and `mesh.nz`: the effective scene has nx = ny = nz = n.
- **Paths** such as `mesh.file` are relative to the directory of the scene file.
- **Text.** Keys and strings (`--set` values too) must be UTF-8, as the JSON results are: other
  bytes are refused at the start, naming the key.
- **Overrides.** `--set path=value` is applied before validation, so a misspelt key is reported
  as unknown. The path is dotted (`mesh.n=64`, `solver.options.mu_strategy=monotone`); an array
  element is a number segment or brackets (`boundary.gamma2.0.traction=[1,0]` or
  `boundary.gamma2[0].traction=[1,0]`; the index equal to the length appends). The value is
  JSON when it parses (numbers, `true`, `null`, arrays, objects, `"quoted"` strings) and a plain
  string otherwise. Missing intermediate objects are created (a missing list by index `0`).
)";

}  // namespace

std::string schema_markdown() {
  const auto& rows = scene_schema();
  std::vector<const SchemaEntry*> top;
  for (const SchemaEntry& e : rows)
    if (parent_pointer(e.pointer).empty()) top.push_back(&e);

  std::string md = MARKDOWN_HEADER;
  md += "\n## Top level\n\n" + table(top);
  for (const SchemaEntry* section : top) {
    if (section->type != "object") continue;
    std::vector<const SchemaEntry*> below;
    for (const SchemaEntry& e : rows)
      if (e.pointer.rfind(section->pointer + "/", 0) == 0) below.push_back(&e);
    md += "\n## " + code(last_segment(section->pointer)) + "\n\n" + section->doc + "\n\n" + table(below);
  }
  return md;
}

}  // namespace hemicontact
