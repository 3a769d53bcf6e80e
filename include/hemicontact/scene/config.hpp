#pragma once
/// @file config.hpp  Scene files: the schema table, validation with default injection, `--set`
/// overrides, loading, and the generated reference docs/scene-format.md.
///
/// The design follows polyfem's json-specs: *one* table of {pointer, type, default, doc} is the
/// single place where a key, its type and its default are written. validate_scene() checks a
/// scene against it and injects every default, so no later code guesses a default or reads a
/// key that might be absent; schema_markdown() renders the same table as the user
/// documentation, so the documentation cannot drift from the code.
///
/// Typical use (the CLI):
/// @code
///   const nlohmann::json scene = load_scene(path, set_args);   // throws Error (EXIT_INPUT)
///   const int nx = get_int(scene, "mesh.nx");                  // always present after loading
/// @endcode

#include <hemicontact/core/error.hpp>

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace hemicontact {

/// One row of the scene schema (polyfem json-specs style).
///
/// A row describes the value at @ref pointer. Rows whose pointer is a direct child of an
/// `object` row list that object's allowed keys; any other key is an error. A `*` segment stands
/// for every element of an array, so `/boundary/gamma2/*/traction` is the `traction` key of each
/// Γ2 selector.
struct SchemaEntry {
  /// JSON pointer with `*` for "every array element", e.g. "/boundary/gamma2/*/traction".
  std::string pointer;
  /// Allowed type(s): "number", "integer", "string", "boolean", "null", "object", "object*",
  /// "array", "number[]", "number[][]", or a union joined by "|" such as "number|null".
  /// "object" has its keys checked against the child rows; "object*" is an open object whose
  /// content is passed through unchecked (backend options, regression expectations).
  std::string type;
  /// Injected when the key is absent (ignored when @ref required). Objects default to {} and
  /// then receive their children's defaults.
  nlohmann::json default_value;
  /// One-line description; it becomes the "description" column of docs/scene-format.md.
  std::string doc;
  /// Allowed values when the value is a string (an enum); empty = any string.
  std::vector<std::string> options;
  /// The key must be present whenever its parent object is.
  bool required = false;
  /// Lower bound on a numeric value (not checked for null or non-numeric alternatives).
  std::optional<double> min;
  /// true: value > @ref min; false: value ≥ @ref min.
  bool min_exclusive = false;
  /// Upper bound on a numeric value (not checked for null or non-numeric alternatives).
  std::optional<double> max;
  /// true: value < @ref max; false: value ≤ @ref max.
  bool max_exclusive = false;
  /// Most elements an array value may have (tables: their length is the work of every evaluation).
  std::optional<std::size_t> max_items;
};

/// @brief The scene schema: every key a scene may contain, in documentation order.
/// @return the table, built once (defined in src/scene/scene_schema.cpp).
const std::vector<SchemaEntry>& scene_schema();
/// @return the schema's default of the key at dotted path @p dotted (e.g. "solver.backend"), for
/// texts that state it (the CLI's help): written once, in the table. @throws Error for an unknown key.
const nlohmann::json& schema_default(const std::string& dotted);

/// Deepest nesting of objects and arrays a scene may have (the deepest valid scene needs 5, e.g.
/// boundary.gamma2[0].traction[1]). Checked while parsing a file or a --set value, on --set
/// paths and on a scene built in code, so that no walk of the scene recurses deeper: a text
/// nested 40 000 levels deep would otherwise overflow the stack.
inline constexpr std::size_t MAX_SCENE_DEPTH = 32;

/// Longest scene file read (bytes): a scene is a few KB and its longest tables (MAX_TABLE_POINTS
/// points each) take well under 1 MB; a path such as /dev/zero or a huge file must not be read
/// for minutes. Non-regular files (devices, FIFOs) are refused before they are opened.
inline constexpr std::size_t MAX_SCENE_BYTES = 16u << 20;

/// Most points of a piecewise-linear table (contact.gap.points, contact.normal_law.points,
/// contact.friction.points): measured laws have tens to hundreds. The solve's cost grows faster
/// than the table (fig2 at n = 16 with a p_ν table: 0.14 s at 10³ points, 13 s at 10⁴, 9 minutes
/// at 10⁵, without a progress line), so 10³ keeps any scene's table cheap.
inline constexpr std::size_t MAX_TABLE_POINTS = 1000;

/// Most continuation stages a scene may ask for (solver.continuation: eps_start → eps_tau, eps_nu
/// by factor per stage): the default takes 5; a factor of 0.9999999 would take 2·10⁸.
inline constexpr int MAX_CONTINUATION_STAGES = 200;

/// @brief Validate a scene against scene_schema() and inject defaults.
///
/// Checks, in order: nesting at most MAX_SCENE_DEPTH; no non-finite numbers anywhere; every key is known (an unknown key is an
/// error with a closest-match hint); every value has an allowed type ("integer" must be integral
/// and fit in 32 bits; an integral float such as 8.0 is stored as 8); enum options; numeric
/// ranges; required keys. Absent keys receive their defaults, also inside every element of an
/// array of objects. Then a few checks that concern one value each but do not fit the table:
/// each boundary selector sets exactly one of `side`/`physical` and has `from < to`;
/// `contact.gap` is ≥ 0, "inf", null, or a well-formed piecewise-linear object. Finally
/// `mesh.n`, when set, is copied into `mesh.nx` and `mesh.ny` so that later code reads only those.
///
/// The result is a fixed point: validate_scene(validate_scene(s)) == validate_scene(s).
/// @param scene the parsed scene (after overrides)
/// @return the effective scene, with every default present
/// @throws Error (EXIT_INPUT) naming the dotted key, e.g. "scene key 'mesh.n': expected
///         integer, got string \"abc\""
nlohmann::json validate_scene(nlohmann::json scene);

/// @brief Check solver.petsc.options (the PETSc options passed to the petsc engine) against a
/// whitelist (src/scene/petsc_options.cpp): each option a known solver setting under one of the
/// engine's prefixes (elastic_, polish_, ssn_, tao_, tao_bnk_), its value of the right kind and in
/// range; monitors and views only without a value (stdout), so that no option names a file.
/// @param key the scene key named in messages
/// @throws Error (EXIT_INPUT) naming the key and the option
void check_petsc_options(const std::string& options, const std::string& key);

/// @brief Check a number given for scene key @p dotted some other way (a command-line option such as
/// converge's --graded-power, which sets mesh.grading.power) against that key's row: finite and in
/// its range, so that both ways share one bound.
/// @param what the option as the user wrote it, named in the message
/// @throws Error (@p code) "WHAT: must be >= 1 and <= 10 (the range of scene key 'mesh.grading.power'), got inf"
void check_key_range(const std::string& dotted, double value, const std::string& what, ExitCode code);

/// @brief Apply one `--set path=value` assignment to a (not yet validated) scene.
///
/// The path is dotted (`mesh.n`, `solver.options.mu_strategy`); array elements are selected by a
/// number segment (`boundary.gamma2.0.traction`) or by brackets as printed in error messages
/// (`boundary.gamma2[0].traction`); an index equal to the array size appends. Missing
/// intermediate objects are created, and a missing array when the segment is `0`. The value is
/// parsed as JSON when it parses (numbers, true/false, null, arrays, objects, quoted strings)
/// and is otherwise taken as a plain string, so `--set mesh.type=gmsh` needs no shell quoting.
/// Overrides are applied before validation, so a misspelt key is reported as unknown by
/// validate_scene().
/// @param scene      the scene to modify
/// @param assignment "path=value" (split at the first '=')
/// @throws Error (EXIT_INPUT) for a missing '=', an empty path segment, an array index out of
///         range, or a path that runs through a non-container value
void apply_override(nlohmann::json& scene, const std::string& assignment);

/// @brief Read a scene file, apply overrides in order, and validate.
/// @param path      the scene file (JSON)
/// @param overrides `--set` assignments, applied left to right (a later one wins)
/// @return the effective scene (see validate_scene())
/// @throws Error (EXIT_INPUT): "scene file 'x.json' not found", "scene file 'x.json': parse
///         error at line L, column C: ...", a duplicate key, or any validation error
nlohmann::json load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// @brief load_scene() on the text of a scene file (the fuzz target's entry, and load_scene's
/// own second half). @param text the file's text @param name the file name used in messages
/// @param overrides `--set` assignments @return the effective scene @throws as load_scene()
nlohmann::json load_scene_text(const std::string& text, const std::string& name,
                               const std::vector<std::string>& overrides = {});

/// @brief Directory that relative paths inside a scene (e.g. `mesh.file`) are resolved against.
/// @param scene_path the path the scene was loaded from
/// @return its parent directory, or "." for a bare file name
std::string scene_directory(const std::string& scene_path);

/// @brief A path written in a scene (e.g. `mesh.file`) as the program opens it: relative ones
/// against @p scene_dir (scene_directory), absolute ones as given.
std::string scene_path_of(const std::string& written, const std::string& scene_dir);

/// @brief The user reference for the scene format, generated from scene_schema().
///
/// docs/scene-format.md is exactly this text; a unit test (SceneSchema.MarkdownMatchesDoc)
/// fails when they differ and says how to regenerate the file.
/// @return Markdown: rules of the format, then one table per top-level section
std::string schema_markdown();

/// @brief The value at a dotted key of a validated scene.
/// @param scene  the effective scene returned by validate_scene() or load_scene()
/// @param dotted e.g. "solver.fixed_point.tol_u" or "boundary.gamma2[0].traction"
/// @return a reference into @p scene
/// @throws Error (EXIT_INTERNAL) when the key is absent: after validation that is a bug
///         (a key read that is not in the schema), not an input error
const nlohmann::json& scene_at(const nlohmann::json& scene, const std::string& dotted);

/// @brief A number at a dotted key. @param scene effective scene @param dotted key
/// @return the value @throws Error (EXIT_INTERNAL) if absent or not a number (e.g. null)
double get_number(const nlohmann::json& scene, const std::string& dotted);

/// @brief An integer at a dotted key. @param scene effective scene @param dotted key
/// @return the value (validation guarantees it fits in int) @throws Error (EXIT_INTERNAL)
int get_int(const nlohmann::json& scene, const std::string& dotted);

/// @brief A string at a dotted key. @param scene effective scene @param dotted key
/// @return the value @throws Error (EXIT_INTERNAL) if absent or not a string
std::string get_string(const nlohmann::json& scene, const std::string& dotted);

/// @brief A boolean at a dotted key. @param scene effective scene @param dotted key
/// @return the value @throws Error (EXIT_INTERNAL) if absent or not a boolean
bool get_bool(const nlohmann::json& scene, const std::string& dotted);

}  // namespace hemicontact
