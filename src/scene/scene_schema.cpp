// The scene schema: the one place where a scene key, its type, its range and its documentation
// are written (polyfem json-specs); the solver's and the adaptive loop's defaults are read from
// their options structs (build_scene_schema). validate_scene() and schema_markdown() in config.cpp only
// interpret this table, and docs/scene-format.md is generated from it.
//
// Rows appear in documentation order. A parent row must come before its children; config.cpp
// checks that, and that every default satisfies its own row, when it first indexes the table.

#include <hemicontact/check/adapt_options.hpp>
#include <hemicontact/problem/solve_options.hpp>
#include <hemicontact/scene/config.hpp>

#include <string>
#include <utility>
#include <vector>

namespace hemicontact {
namespace {

using nlohmann::json;

/// An optional key.
SchemaEntry key(std::string pointer, std::string type, json default_value, std::string doc,
                std::vector<std::string> options = {}) {
  SchemaEntry e;
  e.pointer = std::move(pointer);
  e.type = std::move(type);
  e.default_value = std::move(default_value);
  e.doc = std::move(doc);
  e.options = std::move(options);
  return e;
}

/// A key that must be present whenever its parent is (no default).
SchemaEntry required(std::string pointer, std::string type, std::string doc, std::vector<std::string> options = {}) {
  SchemaEntry e = key(std::move(pointer), std::move(type), json(), std::move(doc), std::move(options));
  e.required = true;
  return e;
}

/// A closed object whose keys are the rows below it; absent → {} plus the children's defaults.
SchemaEntry section(std::string pointer, std::string doc) {
  return key(std::move(pointer), "object", json::object(), std::move(doc));
}

SchemaEntry above(SchemaEntry e, double lo) {
  e.min = lo;
  e.min_exclusive = true;
  return e;
}
SchemaEntry at_least(SchemaEntry e, double lo) {
  e.min = lo;
  e.min_exclusive = false;
  return e;
}
SchemaEntry below(SchemaEntry e, double hi) {
  e.max = hi;
  e.max_exclusive = true;
  return e;
}
SchemaEntry at_most(SchemaEntry e, double hi) {
  e.max = hi;
  e.max_exclusive = false;
  return e;
}
SchemaEntry at_most_items(SchemaEntry e, std::size_t n) {
  e.max_items = n;
  return e;
}

// The three boundary parts share one selector shape; generating their rows keeps the three
// copies identical instead of writing (and later editing) them three times.
void add_selector(std::vector<SchemaEntry>& t, const std::string& gamma, const std::string& doc, bool with_traction) {
  const std::string p = "/boundary/" + gamma;
  // Without a clamped part the elastic problem is not coercive, so Γ1 has no default.
  t.push_back(gamma == "gamma1" ? required(p, "array", doc) : key(p, "array", json::array(), doc));
  t.push_back(key(p + "/*", "object", json::object(),
                  "A selector: the facets it matches belong to this boundary part. Set exactly "
                  "one of `side` and `physical`; `from`/`to` restrict a side only (refused on a "
                  "physical group). A selector that selects no facet is an error."));
  t.push_back(key(p + "/*/side", "string|null", nullptr,
                  "Side of the mesh's bounding box: left/right = x min/max; bottom/top = y min/max "
                  "in 2D, z min/max in 3D; front/back = y min/max (3D only).",
                  {"left", "right", "bottom", "top", "front", "back"}));
  t.push_back(key(p + "/*/physical", "string|null", nullptr, "Gmsh physical group name (mesh.type = gmsh)."));
  t.push_back(key(p + "/*/from", "number|null", nullptr,
                  "The facet midpoint's coordinate along the side must lie in [from, to); null = "
                  "−∞. The coordinate is, in 2D, y on left/right and x on bottom/top; in 3D, the "
                  "vertical z on left/right/front/back and x on bottom/top. Half-open, so [0.5,1) "
                  "and [0,0.5) split a side without overlap."));
  t.push_back(key(p + "/*/to", "number|null", nullptr, "Upper end of [from, to), excluded; null = +∞."));
  if (with_traction)
    t.push_back(key(p + "/*/traction", "number[]", json{0, 0},
                    "Traction f2 on these facets, d components (the default is 2D: give it on a 3D mesh)."));
}

std::vector<SchemaEntry> build_scene_schema() {
  std::vector<SchemaEntry> t;
  // The solver's, the check's and the adaptive loop's defaults have one home, the member
  // initialisers of SolveOptions (and its BackendOptions) and of AdaptOptions: the rows below inject
  // those values, so a scene and a default-constructed options struct (tests, benches) cannot disagree.
  // This table is the one home of each key's type, range and documentation, and of the defaults
  // that no options struct holds (mesh, material, loads, output).
  const SolveOptions D;

  t.push_back(key("/description", "string", "", "Free text; echoed in the report."));

  // ------------------------------------------------------------------ mesh
  t.push_back(section("/mesh", "The triangulation of Ω."));
  t.push_back(key("/mesh/type", "string", "rectangle",
                  "rectangle: structured triangulation of x × y; box: structured tetrahedral mesh of "
                  "x × y × z (3D); gmsh: read `file`.",
                  {"rectangle", "box", "gmsh"}));
  t.push_back(key("/mesh/x", "number[]", json{0, 1}, "Interval [x0, x1] of the rectangle or box."));
  t.push_back(key("/mesh/y", "number[]", json{0, 1}, "Interval [y0, y1] of the rectangle or box."));
  t.push_back(key("/mesh/z", "number[]", json{0, 1}, "Interval [z0, z1] of the box (3D)."));
  t.push_back(at_least(key("/mesh/n", "integer|null", nullptr,
                           "If set, nx = ny = nz = n: validation copies it into nx, ny and nz "
                           "(overriding them), so `--set mesh.n=64` refines a scene in every "
                           "direction. Refused with mesh.type = gmsh (a Gmsh mesh is used as read)."),
                       1));
  t.push_back(at_least(key("/mesh/nx", "integer", 8, "Cells along x (rectangle, box)."), 1));
  t.push_back(at_least(key("/mesh/ny", "integer", 8, "Cells along y (rectangle, box)."), 1));
  t.push_back(at_least(key("/mesh/nz", "integer", 8, "Cells along z (box)."), 1));
  t.push_back(key("/mesh/diagonal", "string", "right",
                  "right: each cell split by the diagonal from (x_i,y_j) to (x_{i+1},y_{j+1}); "
                  "left: the other one; symmetric: right on the left half, mirrored on the right "
                  "half; crossed: four triangles around the cell centre.",
                  {"right", "left", "symmetric", "crossed"}));
  t.push_back(key("/mesh/pattern", "string", "kuhn",
                  "Box (3D): each hexahedral cell is split into 6 tetrahedra. kuhn: all cells along "
                  "the main diagonal (x_i,y_j,z_k)–(x_{i+1},y_{j+1},z_{k+1}) (conforming; the xz "
                  "faces carry the 2D `right` diagonal); symmetric: kuhn mirrored in the upper x "
                  "and y halves, so the mesh is mirror-symmetric about x = mid and y = mid (needs "
                  "even nx, ny).",
                  {"kuhn", "symmetric"}));
  t.push_back(key("/mesh/file", "string|null", nullptr,
                  "Gmsh mesh file (mesh.type = gmsh; MSH version 2.x or 4.x, ASCII or binary), relative to "
                  "the scene file's directory. It must start with `$MeshFormat`: Gmsh reads anything else as "
                  "a script (see allow_scripts). Refused with another mesh.type (it would be ignored)."));
  t.push_back(key("/mesh/allow_scripts", "boolean", false,
                  "true: mesh.file may be any file Gmsh reads, .geo scripts included. A Gmsh script RUNS CODE "
                  "with your rights (SystemCall runs shell commands, Printf writes files): set it only for "
                  "scripts you trust. false: only MSH files."));
  // Below 0.5 h two neighbouring nodes cannot meet or swap places. The right triangles of the
  // right/left/symmetric meshes keep a positive area for perturb ≤ 0.35 (worst case over all moves
  // of the three vertices within their discs, by numerical minimization: 15 % of the area is left
  // at 0.3, 1 % at 0.35); beyond, or on crossed meshes earlier, a cell can invert and check_cells
  // reports it.
  t.push_back(below(at_least(key("/mesh/perturb", "number", 0,
                                 "Interior nodes are moved randomly by up to this fraction of h "
                                 "(Euclidean distance, uniform in the disc or ball; robustness "
                                 "tests on irregular meshes). Right/left/symmetric rectangles "
                                 "cannot invert a cell up to 0.35; beyond (or on crossed meshes "
                                 "and boxes earlier) a cell can invert, which is an input error "
                                 "naming it (lower perturb or change `seed`). Refused above 0 with "
                                 "mesh.type = gmsh."),
                             0),
                    0.5));
  t.push_back(at_least(key("/mesh/seed", "integer", 1, "Seed of the random perturbation (same seed, same mesh)."), 0));
  t.push_back(section("/mesh/grading",
                      "Graded rectangle (a priori refinement towards chosen sides and the corners where "
                      "they meet): grid line i of a graded axis sits at φ(i/n) with φ(t) = t^power "
                      "(low), 1 − (1 − t)^power (high) or both mirrored halves (both); docs/adaptivity.md. "
                      "Rectangles only: x or y other than none is refused with another mesh.type."));
  t.push_back(key("/mesh/grading/x", "string", "none", "Which end(s) of x get the small cells.",
                  {"none", "low", "high", "both"}));
  t.push_back(key("/mesh/grading/y", "string", "none", "Which end(s) of y get the small cells.",
                  {"none", "low", "high", "both"}));
  // β ≤ 10 covers corner exponents α ≥ 0.1; beyond, the smallest cell (1/n)^β is below round-off
  // at any useful n (the generator also refuses a degenerate smallest cell, naming this key).
  t.push_back(at_most(at_least(key("/mesh/grading/power", "number", 1,
                                   "Grading exponent β ≥ 1 (1: uniform). A corner singularity r^α needs β ≥ 1/α "
                                   "for the optimal rate (α = 0.72 at the paper's clamped corners: β ≈ 1.4)."),
                               1),
                      10));

  // ------------------------------------------------------------------ material
  t.push_back(section("/material", "Constitutive law F (paper eq. (12); docs/model.md §1)."));
  t.push_back(key("/material/model", "string", "linear_elastic",
                  "linear_elastic: linear isotropic elasticity. hencky: nonlinear Hencky-type law "
                  "W = (K/2)(tr ε)² + Φ(|dev ε|²) whose shear modulus μ(s) = μ_∞ + (μ_0 − μ_∞)/√(1 + s/eps_ref²) "
                  "falls (or rises) from μ_0 to μ_∞ = shear_ratio·μ_0 (plane strain and 3D only; "
                  "include/hemicontact/material/hencky.hpp).",
                  {"linear_elastic", "hencky"}));
  t.push_back(above(required("/material/E", "number",
                             "Young's modulus E (hencky: of the small-strain limit; bulk modulus "
                             "E/(3(1 − 2 nu)), μ_0 = E/(2(1 + nu)))."),
                    0));
  // (−1, 1) keeps both E/(1+κ) and the plane-stress factor 1/(1−κ²) finite and positive; the
  // materials refuse κ ≥ 0.5 in every plane (linear_elastic.cpp, hencky.cpp), with their own
  // message, and the text says so (it said plane strain only).
  t.push_back(below(above(required("/material/nu", "number",
                                   "Poisson's ratio κ. The material needs κ < 0.5 in plane stress, plane "
                                   "strain and 3D alike (0.5 is incompressible; checked by the material), "
                                   "so the range in effect is (−1, 0.5)."),
                          -1),
                    1));
  t.push_back(key("/material/plane", "string", "stress",
                  "2-D reduction: plane stress (the paper's example) or plane strain (the only one for "
                  "hencky). A 3D mesh uses 3D elasticity and ignores the default; `strain` on a 3D "
                  "mesh is an error.",
                  {"stress", "strain"}));
  t.push_back(above(key("/material/shear_ratio", "number|null", nullptr,
                        "hencky only (required there): μ_∞/μ_0, the large-strain over the small-strain "
                        "shear modulus (< 1 softens, > 1 stiffens, 1 is linear)."),
                    0));
  t.push_back(above(key("/material/eps_ref", "number|null", nullptr,
                        "hencky only (required there): reference deviatoric strain ε_ref: at |dev ε| = ε_ref, "
                        "μ − μ_∞ = (μ_0 − μ_∞)/√2."),
                    0));

  // ------------------------------------------------------------------ boundary
  t.push_back(section("/boundary", "The split of ∂Ω into Γ1, Γ2, Γ3 (docs/model.md §1), as lists of facet selectors."));
  add_selector(t, "gamma1", "Γ1, clamped (u = 0): list of selectors.", false);
  add_selector(t, "gamma2", "Γ2, traction f2: list of selectors, each with its traction.", true);
  add_selector(t, "gamma3", "Γ3, contact with the foundation: list of selectors.", false);
  add_selector(t, "rollers",
               "Roller (symmetry-plane) conditions: on the selected facets' nodes the listed "
               "displacement components are zero, the others free (e.g. a plane-strain slab: "
               "`{\"side\": \"front\", \"components\": [\"y\"]}`). A roller on a Γ3 node must be "
               "tangent to Γ3. Γ1 is still required (coercivity).",
               false);
  t.push_back(required("/boundary/rollers/*/components", "array", "The components held at zero, e.g. [\"y\"]."));
  t.push_back(required("/boundary/rollers/*/components/*", "string", "A component name.", {"x", "y", "z"}));

  // ------------------------------------------------------------------ loads
  t.push_back(section("/loads", "Volume and surface loads."));
  t.push_back(key("/loads/body_force", "number[]", json{0, 0}, "Body force f0."));
  t.push_back(key("/loads/scale", "number", 1, "Multiplies f0 and every f2 (load-scaled scenes)."));

  // ------------------------------------------------------------------ contact
  t.push_back(section("/contact", "Contact on Γ3: soft layer of thickness g on a rigid foundation."));
  // The object form's keys are ordinary rows below: they are checked whenever gap is an object.
  t.push_back(key("/contact/gap", "number|string|object|null", nullptr,
                  "Thickness g ≥ 0 of the soft layer (eq. (5)): a number (constant); null or "
                  "\"inf\" (no rigid obstacle); or {\"along\": \"x\", \"points\": [[x, g], ...]}, "
                  "piecewise linear in one coordinate."));
  t.push_back(required("/contact/gap/along", "string", "Object form of gap: the coordinate g is a function of.",
                       {"x", "y", "z"}));
  t.push_back(at_most_items(required("/contact/gap/points", "number[][]",
                                     "Object form of gap: [[coordinate, g], ...], coordinates strictly "
                                     "increasing, g ≥ 0."),
                            MAX_TABLE_POINTS));

  t.push_back(section("/contact/normal_law", "Normal compliance of the soft layer, p_ν = j_ν′."));
  t.push_back(key("/contact/normal_law/type", "string", "none",
                  "none: no soft layer; paper: piecewise linear (32) with c1, c2, c3, r1, r2; "
                  "table: piecewise linear through `points`.",
                  {"none", "paper", "table"}));
  t.push_back(key("/contact/normal_law/c1", "number|null", nullptr, "Slope of p_ν on (0, r1] (32)."));
  t.push_back(key("/contact/normal_law/c2", "number|null", nullptr, "Slope on (r1, r2) (32); negative = softening."));
  t.push_back(key("/contact/normal_law/c3", "number|null", nullptr, "Slope for r ≥ r2 (32)."));
  t.push_back(key("/contact/normal_law/r1", "number|null", nullptr, "First kink of p_ν (32)."));
  t.push_back(key("/contact/normal_law/r2", "number|null", nullptr, "Second kink of p_ν (32)."));
  t.push_back(at_most_items(key("/contact/normal_law/points", "number[][]|null", nullptr,
                                "type table: [[r, p_ν(r)], ...], r non-decreasing; a repeated r is a jump of p_ν at r "
                                "(∂j_ν is then the interval between the one-sided limits). Null slopes continue the "
                                "first/last segment."),
                            MAX_TABLE_POINTS));
  t.push_back(key("/contact/normal_law/slope_left", "number|null", nullptr,
                  "type table: slope of p_ν before the first point."));
  t.push_back(
      key("/contact/normal_law/slope_right", "number|null", nullptr, "type table: slope of p_ν after the last point."));

  t.push_back(section("/contact/friction", "Friction bound F_b (eqs. (6), (34))."));
  t.push_back(key("/contact/friction/type", "string", "none",
                  "none: frictionless; coulomb_layer: F_b = μ p_ν(u_ν) (34); tresca: F_b = "
                  "bound; table: piecewise linear F_b(u_ν) through `points`.",
                  {"none", "coulomb_layer", "tresca", "table"}));
  t.push_back(
      at_least(key("/contact/friction/mu", "number|null", nullptr, "Friction coefficient μ in F_b = μ p_ν (34)."), 0));
  t.push_back(at_least(key("/contact/friction/bound", "number|null", nullptr, "type tresca: the constant F_b."), 0));
  t.push_back(at_most_items(key("/contact/friction/points", "number[][]|null", nullptr,
                                "type table: [[u_ν, F_b(u_ν)], ...], u_ν non-decreasing (a repeated u_ν is a jump). "
                                "Null slope_left means 0, as (15c) requires."),
                            MAX_TABLE_POINTS));
  t.push_back(
      key("/contact/friction/slope_left", "number|null", nullptr, "type table: slope of F_b before the first point."));
  t.push_back(
      key("/contact/friction/slope_right", "number|null", nullptr, "type table: slope of F_b after the last point."));

  // ------------------------------------------------------------------ solver
  // ε's and tolerances are relative to the displacement scale U so that one scene works at any
  // load level.
  t.push_back(section("/solver", "NLP backend, smoothing and the outer loops (docs/model.md §2)."));
  t.push_back(key("/solver/backend", "string", D.backend,
                  "NLP backend by name (hemicontact backends lists them): \"ipopt\", \"newton\", "
                  "\"nlopt:mma\", ... A named backend runs at least the first ε-stage, then the exact "
                  "solver takes over. auto = the engine's own (ipopt here; ssn in the petsc engine), "
                  "whose stage is skipped where the inner problem is strongly convex (unique "
                  "minimizer); the report says which ran."));
  t.push_back(key("/solver/engine", "string", D.engine,
                  "cholmod: one process, sparse Cholesky (CHOLMOD) and static condensation. petsc: the "
                  "distributed engine (hemicontact-mpi, run as mpirun -np P hemicontact solve ...): "
                  "unknowns and the assembly of K spread over the MPI ranks, semismooth Newton on the "
                  "unsmoothed statuses (backend ssn, what auto means there) or TAO bounded "
                  "Newton with the continuation, fixed point and exact polish (tao:bnls, tao:bntr, "
                  "tao:bntl), CG with algebraic multigrid, the same certificate. Only `solve`; "
                  "needs a build with PETSc (libpetsc-real-dev). auto: `solve` runs the petsc engine in "
                  "one process where solver.method_choice.petsc_above says so (a large 3D mesh), the "
                  "cholmod engine otherwise and in every other command; report.json engine_choice says "
                  "which and why.",
                  {"auto", "cholmod", "petsc"}));
  t.push_back(section("/solver/petsc", "Settings of the petsc engine (solver.engine = petsc)."));
  t.push_back(below(above(key("/solver/petsc/ksp_rtol", "number", D.petsc.ksp_rtol,
                              "Relative residual reduction of each CG solve (ssn: the floor of its "
                              "steps' rtol; tao:*: elastic solve, TAO's Newton steps, polish steps)."),
                          0),
                    1));
  t.push_back(at_least(key("/solver/petsc/ksp_max_it", "integer", D.petsc.ksp_max_it,
                           "CG iterations per solve; a solve stopped by it fails with PETSc's reason "
                           "(exit code 3)."),
                       1));
  t.push_back(key("/solver/petsc/pc", "string", D.petsc.pc,
                  "Preconditioner of the full-size solves (ssn's steps; tao:*: elastic solve, "
                  "polish): gamg (smoothed aggregation; near-null space: near_null_space) or hypre (BoomerAMG).",
                  {"gamg", "hypre"}));
  t.push_back(key("/solver/petsc/near_null_space", "string", D.petsc.near_null_space,
                  "GAMG's near-null space: translations (d modes: half the AMG memory, about twice the "
                  "CG iterations in 3D) or rigid (translations and rotations; for slender bodies).",
                  {"translations", "rigid"}));
  t.push_back(key("/solver/petsc/mesh", "string", D.petsc.mesh,
                  "Where the mesh lives: auto (a generated box or rectangle, not perturbed, is made per rank in "
                  "slabs of cell layers; a box with more ranks than layers in blocks of cell columns, per rank "
                  "too; any other mesh, a Gmsh file included, is made by rank 0 and distributed by DMPlex; no "
                  "rank holds the whole mesh; report.json from reductions, its per-node list gathered from the "
                  "ranks' owned Γ3 nodes; petsc.mesh says which ran) or blocks (a box in blocks at any rank "
                  "count that makes a grid). The replicated layout (every rank building the whole mesh) was "
                  "retired: these solve every scene it solved, in less memory per rank.",
                  {"auto", "blocks"}));
  t.push_back(key("/solver/petsc/newton_pc", "string", D.petsc.newton_pc,
                  "Preconditioner of TAO's Newton steps (the Hessian on the inactive set): hypre "
                  "(BoomerAMG) or gamg.",
                  {"hypre", "gamg"}));
  t.push_back(above(key("/solver/petsc/acceptable_tol", "number", D.petsc.acceptable_tol,
                        "TAO stopped short of solver.tol but the first-order residual (scaled) is at most "
                        "this: the minimization is acceptable (the polish and the certificate decide)."),
                    0));
  t.push_back(at_least(key("/solver/petsc/polish_max_iters", "integer", D.petsc.polish_max_iters,
                           "Newton iterations of the exact polish on the identified statuses."),
                       1));
  t.push_back(at_least(key("/solver/petsc/pc_rebuild", "number", D.petsc.pc_rebuild,
                           "Backend ssn: reuse the AMG hierarchy until a step takes more than this times "
                           "the CG iterations per decade of its reference (the larger of the step that "
                           "built it and the first step that reused it)."),
                       1));
  t.push_back(key("/solver/petsc/options", "string", D.petsc.options,
                  "Extra PETSc options (e.g. \"-ssn_ksp_monitor -pc_gamg_threshold 0.02\"), checked against a "
                  "whitelist: solver settings (ksp_type, ksp_rtol, ksp_max_it, pc_type, pc_gamg_*, "
                  "pc_hypre_boomeramg_*, mg_levels_*, tao_max_it, tao_gatol, ...) without or with the "
                  "engine's prefixes elastic_, polish_, ssn_, tao_; values of the right kind and in range; "
                  "monitors and views (ksp_monitor, ksp_view, tao_monitor, ...) without a value, printing to "
                  "stdout. No option that names a file or a viewer (src/scene/petsc_options.cpp); "
                  "-log_view only through PETSC_OPTIONS (PETSc starts its log before the scene is read)."));
  // ------------------------------------------------------------------ solver.ssn
  t.push_back(section("/solver/ssn",
                      "Backend ssn: semismooth Newton on the unsmoothed statuses, the full space's exact "
                      "solver of both engines (what solver.backend = auto runs in the petsc engine and "
                      "where the method choice takes the full formulation)."));
  t.push_back(at_least(key("/solver/ssn/max_iters", "integer", D.ssn.max_iters,
                           "Step cap, both engines; statuses are read again at every step, and reaching "
                           "the cap is exit code 3."),
                       1));
  t.push_back(below(above(key("/solver/ssn/step_rtol", "number", D.ssn.step_rtol,
                              "Petsc engine: CG rtol of a step while statuses still change (a step with no "
                              "change uses solver.petsc.ksp_rtol; the cholmod engine factorizes such steps "
                              "and solves the others by CG on the last factor to solver.petsc.ksp_rtol)."),
                          0),
                    1));
  t.push_back(below(above(key("/solver/ssn/tol", "number", D.ssn.tol,
                              "Petsc engine: converged when the statuses held and the residual (max norm "
                              "over max|f|) is at most this (the cholmod engine's ssn steps on to "
                              "round-off: its steps then cost one CG iteration)."),
                          0),
                    1e-6));
  t.push_back(key("/solver/formulation", "string", D.formulation,
                  "Unknowns the NLP sees: full = all free dofs; condensed = interior dofs "
                  "eliminated onto Γ3 by static condensation (one sparse factorization, a dense "
                  "problem on the Γ3 unknowns; exact for linear materials); auto = chosen from the "
                  "scene's numbers before any numeric work (solver.method_choice): condensed for a "
                  "linear material whose factorization and dense Γ3 work cost at most the full "
                  "formulation's factorizations and fit in memory, full otherwise (then solver.backend = auto "
                  "means ssn, the full space's exact solver). report.json method_choice says what was chosen and why.",
                  {"auto", "full", "condensed"}));
  const MethodChoiceOptions MC;  // the defaults' one home
  t.push_back(section("/solver/method_choice",
                      "The cost model of solver.formulation = auto (solver/method_choice.hpp), in flops "
                      "of CHOLMOD's symbolic analysis of the condensation."));
  t.push_back(above(key("/solver/method_choice/dense_work", "number", MC.dense_work,
                        "The condensed path's dense Γ3 work in units of m³ flops (m Γ3 unknowns): the "
                        "Schur complement, the exact solver's dense factorizations, the polish."),
                    0));
  t.push_back(at_least(key("/solver/method_choice/full_factorizations", "number", MC.full_factorizations,
                           "The full formulation's numeric factorizations per solve (newton steps); "
                           "condensed where one factorization with the dense Γ3 block plus dense_work·m³ "
                           "is at most this × one factorization without it."),
                       1));
  t.push_back(at_least(key("/solver/method_choice/condensed_below", "number", MC.condensed_below,
                           "Condensed whatever the full formulation costs where the condensed path's whole "
                           "work (factorization + dense Γ3 work) is at most this many flops: its exact "
                           "solver answers to round-off at no real cost (unless full_cheaper_by says otherwise)."),
                       0));
  t.push_back(at_least(key("/solver/method_choice/full_cheaper_by", "number", MC.full_cheaper_by,
                           "Below condensed_below, full all the same where the full formulation's work is "
                           "at least this many times less than the condensed path's (a long strip: the "
                           "dense Γ3 work is then the whole cost)."),
                       1));
  t.push_back(at_least(key("/solver/method_choice/small_fraction", "number", MC.small_fraction,
                           "Condensed at once where the dense Γ3 work is at most this fraction of the "
                           "condensation's factorization; above, the full formulation's factorization is "
                           "analysed too and the two works compared."),
                       0));
  t.push_back(at_least(key("/solver/method_choice/petsc_above", "number", MC.petsc_above,
                           "solver.engine = auto (`hemicontact solve` only): the petsc engine in one process "
                           "for a 3D mesh of at least this many unknowns (3 per node: a generated box, or a "
                           "Gmsh file whose header gives its node count), a linear material and no adaptive "
                           "refinement; the cholmod engine below it and elsewhere."),
                       0));
  t.push_back(at_least(key("/solver/method_choice/petsc_restarts_above", "number", MC.petsc_restarts_above,
                           "solver.engine = auto for `hemicontact minima`: its starts go to the petsc engine "
                           "(a process each, judged here) for a 3D mesh of at least this many unknowns; below, "
                           "the cholmod engine in this process, whose one factorization serves every start."),
                       0));
  t.push_back(at_most(above(key("/solver/method_choice/memory_fraction", "number", MC.memory_fraction,
                                "The condensed path's dense Γ3 matrices (7 of m × m doubles) may use at "
                                "most this fraction of the memory available; above, full."),
                            0),
                      1));
  t.push_back(key("/solver/ordering", "string", D.ordering,
                  "Fill-reducing ordering of every sparse factorization: amd (cheapest to compute), "
                  "metis or nesdis (nested dissection: less fill, costlier ordering). auto = for the "
                  "condensation (on the node graph) amd for 2D meshes up to 200 000 nodes, metis for "
                  "larger 2D meshes, nesdis for 3D; for a whole-mesh factorization (the full formulation's, "
                  "ssn's Newton matrices, a linear solve) amd up to 20 000 unknowns, nesdis above.",
                  {"auto", "amd", "metis", "nesdis"}));
  t.push_back(key("/solver/polish", "boolean", D.polish,
                  "After the smoothed solve, solve the unsmoothed conditions of (22) exactly on the "
                  "identified statuses (condensed formulation, 2D); kept only if the statuses stay "
                  "and the certificate improves."));
  t.push_back(above(key("/solver/tol", "number", D.backend_options.tol,
                        "Backend first-order tolerance, on the nondimensionalized problem "
                        "(unknowns / U_s, energy / (‖f‖∞ U_s))."),
                    0));
  t.push_back(
      at_least(key("/solver/max_iter", "integer", D.backend_options.max_iter, "Backend iterations per solve."), 1));
  t.push_back(at_least(
      key("/solver/print_level", "integer", D.backend_options.print_level, "Backend verbosity (0 = silent)."), 0));
  t.push_back(key("/solver/options", "object*", json::object(),
                  "Passed verbatim to the backend (e.g. Ipopt's mu_strategy); not checked here."));
  t.push_back(above(key("/solver/eps_tau", "number", D.eps_tau,
                        "Final friction smoothing width ε_τ, relative to the displacement scale U."),
                    0));
  t.push_back(
      above(key("/solver/eps_nu", "number", D.eps_nu, "Final width ε_ν of the mollified p_ν, relative to U."), 0));
  t.push_back(section("/solver/continuation", "Continuation in ε_τ, ε_ν with warm starts."));
  t.push_back(above(key("/solver/continuation/eps_start", "number", D.eps_start, "First ε, relative to U."), 0));
  t.push_back(below(above(key("/solver/continuation/factor", "number", D.eps_factor,
                              "ε is multiplied by it each step until eps_tau / eps_nu."),
                          0),
                    1));
  t.push_back(at_most(at_least(key("/solver/continuation/certify_below", "number", D.certify_below,
                                   "After a stage that moved the Γ3 unknowns and λ by at most this "
                                   "(relative), polish and certify; if the certificate passes, the "
                                   "remaining stages are skipped. 0: run every stage."),
                               0),
                      1));
  t.push_back(section("/solver/fixed_point", "Outer loop λ_i = F_b(u_ν,i) (docs/model.md §2)."));
  t.push_back(at_most(above(key("/solver/fixed_point/tol_u", "number", D.tol_u,
                                "Converged when the relative change of u on Γ3 and of λ is ≤ tol_u."),
                            0),
                      1e-2));
  t.push_back(at_least(key("/solver/fixed_point/max_iters", "integer", D.max_outer, "Outer iteration limit."), 1));
  t.push_back(at_most(
      above(key("/solver/fixed_point/relaxation", "number", D.relaxation,
                "θ in λ ← (1−θ)λ + θ F_b(u_ν): the continuation's update, and the mixing of the "
                "exact solver's Anderson step (its extrapolated λ plus θ times the extrapolated update)."),
            0),
      1));
  t.push_back(key("/solver/fixed_point/allow_not_converged", "boolean", D.allow_not_converged,
                  "true: reaching max_iters is a warning instead of an error."));
  t.push_back(below(above(key("/solver/fixed_point/contraction_floor", "number", D.contraction_floor,
                              "Updates ‖Δλ‖∞ at or below this × ‖λ‖∞ are the inner solves' round-off, "
                              "not the map's contraction: they enter no contraction factor ρ_k."),
                          0),
                    1));
  t.push_back(below(above(key("/solver/fixed_point/stall_ratio", "number", D.stall_ratio,
                              "Non-contraction test: the update has not shrunk below this × the previous "
                              "one for stall_iters outer iterations in a row → stop and say so."),
                          0),
                    1));
  t.push_back(at_least(key("/solver/fixed_point/stall_iters", "integer", D.stall_iters, "See stall_ratio."), 1));
  t.push_back(at_most(at_least(key("/solver/fixed_point/anderson_memory", "integer", D.anderson_memory,
                                   "Anderson acceleration of λ = F_b(u_ν) in the exact solver: the "
                                   "number of past updates combined (0: the plain iteration)."),
                               0),
                      50));
  t.push_back(section("/solver/exact",
                      "The exact inner solver (no smoothing) and the hand-over to it (condensed "
                      "formulation): it takes over once the statuses stop changing between stages, or the "
                      "backend stalls or fails."));
  t.push_back(key("/solver/exact/enabled", "boolean", D.exact,
                  "Default true: the exact solver replaces the costly late ε-stages. false: the ε-continuation and "
                  "the polish alone (the design's path)."));
  // The floor: the coupled residual's round-off (a relative residual of a double at unit scale, times
  // the conditioning of the condensed problem) — fig2 reaches 1e-14 up to n = 512 but not 1e-15 at
  // n = 128, where a smaller tolerance could only end in exit 3 on a certified answer.
  t.push_back(at_most(at_least(key("/solver/exact/tol", "number", D.exact_inner.tol,
                                   "Stationarity residual (certificate units) at which the exact solver stops; "
                                   "at least 1e-14, the round-off of the residual itself."),
                               1e-14),
                      1e-3));
  t.push_back(at_least(key("/solver/exact/polish_above", "number", D.exact_inner.polish_above,
                           "The polish after the exact solver runs only when the exact solver's coupled "
                           "residual (certificate units) is above this; below it the answer is at round-off."),
                       0));
  t.push_back(at_least(key("/solver/exact/max_rounds", "integer", D.exact_inner.max_rounds,
                           "Coordinate sweep + Newton rounds per inner solve."),
                       1));
  t.push_back(at_most(at_least(key("/solver/exact/max_halvings", "integer", D.exact_inner.max_halvings,
                                   "Backtracking halvings of a Newton step on the exact energy."),
                               1),
                      60));
  t.push_back(at_least(key("/solver/exact/after_stage", "integer", D.exact_after_stage,
                           "Hand over after this continuation stage at the latest (earlier when the "
                           "statuses stop changing or the backend stalls)."),
                       0));
  t.push_back(key("/solver/exact/start", "string", D.exact_start,
                  "Start the exact solver before any continuation stage: auto = when the inner "
                  "problem is strongly convex (unique minimizer, reached from any start) and "
                  "solver.backend is auto (a named backend runs its first stage); convex = when "
                  "strongly convex, whatever the backend; always; never = after the backend's stage 0 "
                  "at the earliest. Not certified from there: see fallback.",
                  {"auto", "convex", "always", "never"}));
  t.push_back(key("/solver/exact/fallback", "boolean", D.exact_start_fallback,
                  "When the exact solver's answer from the start is not certified, run the continuation "
                  "from the same start (true) or stop with that answer and its reason (false)."));
  t.push_back(at_least(key("/solver/exact/stage_max_iter", "integer", D.exact_stage_max_iter,
                           "Backend iterations per minimization while the exact solver can take over; "
                           "more is a stall and hands over (0: solver.max_iter alone)."),
                       0));
  t.push_back(at_most(at_least(key("/solver/exact/stage_tol", "number", D.exact_stage_tol,
                                   "First-order tolerance of the backend's stage while the exact solver can "
                                   "take over (the larger of this and solver.tol): the stage only finds the "
                                   "statuses' neighbourhood. 0: solver.tol alone."),
                               0.0),
                      1e-2));
  t.push_back(at_least(key("/solver/exact/convexity_max_unknowns", "integer",
                           D.convexity_max_unknowns,
                           "Check the strong convexity of the inner problem (a dense Cholesky) up to this "
                           "many condensed unknowns."),
                       0));

  // ------------------------------------------------------------------ check
  t.push_back(section("/check", "Acceptance of the computed solution (docs/model.md §3, §4)."));
  // Upper bounds: a tolerance of 1e300 would accept any answer as certified and exit 0 "ok". A
  // certificate looser than 1e-3 accepts answers wrong in the third digit.
  t.push_back(at_most(
      above(key("/check/certificate_tol", "number", D.certificate_tol,
                "Largest normalized certificate residual accepted."),
            0),
      1e-3));
  t.push_back(at_most(
      above(key("/check/status_tol", "number", D.status_tol, "Relative to U: decides stick / contact / separated."),
            0),
      1e-3));
  t.push_back(key("/check/smallness", "boolean", D.smallness,
                  "Evaluate the smallness condition (21) (uniqueness guaranteed: yes/no)."));
  t.push_back(key("/check/smallness_method", "string", D.smallness_method,
                  "auto: decide (21) by bracketing its eigenvalues with those of the solver's "
                  "condensed stiffness (no factorization), and compute them exactly only when the "
                  "bracket cannot decide; exact: always compute them (one extra sparse "
                  "factorization of the ε:ε Gram matrix). report.json smallness.method says which.",
                  {"auto", "exact"}));
  t.push_back(at_least(key("/check/dense_max_unknowns", "integer", D.dense_max_unknowns,
                           "Above this many Γ3 unknowns the checks form no dense Γ3 matrix: (21) and the "
                           "inner-convexity test take their eigenvalues from Lanczos on the solve's own "
                           "factor (no extra factorization), and (21) is decided by its bracket alone "
                           "(undecided: reported as not computed, with the reason)."),
                       0));
  t.push_back(at_most(above(key("/check/lanczos_tol", "number", D.lanczos_tol,
                                "Relative Ritz residual at which Lanczos stops (check.dense_max_unknowns); "
                                "the eigenvalues are known to this relative accuracy and the bracket of "
                                "(21) is widened by it."),
                            0),
                      1e-2));
  t.push_back(at_most(above(key("/check/lanczos_decide_tol", "number", D.lanczos_decide_tol,
                                "Relative Ritz residual at which Lanczos may stop early where its bracket "
                                "already decides (21) and the inner-convexity test (check.lanczos_tol "
                                "otherwise)."),
                            0),
                      1e-2));
  t.push_back(at_least(key("/check/lanczos_max_iter", "integer", D.lanczos_max_iter,
                           "Lanczos steps at most (memory: Γ3 unknowns × this doubles)."),
                       1));

  // ------------------------------------------------------------------ adapt
  const AdaptOptions A;  // the defaults' one home
  t.push_back(section("/adapt",
                      "Adaptive refinement (2D and 3D): solve, estimate, Dörfler-mark, bisect, until the "
                      "estimated relative energy-norm error is below target_error (docs/adaptivity.md)."));
  // The estimate is relative to ‖u_h‖_E; below 1e-6 the estimator itself is round-off dominated.
  t.push_back(below(above(key("/adapt/target_error", "number|null", nullptr,
                              "Target of the estimated relative error η/‖u_h‖_E; null: no adaptation "
                              "(the scene's mesh is solved as it is)."),
                          1e-6),
                    1));
  t.push_back(key("/adapt/reference_energy", "number|null", nullptr,
                  "The energy Π(u) of the exact solution when it is known (extrapolated from uniform "
                  "meshes, docs/adaptivity.md §6); each level then also reports the reference-measured "
                  "error sqrt(2 (Π(u_h) − Π(u))) / ‖u_h‖_E. null: none."));
  t.push_back(at_least(key("/adapt/max_dofs", "integer", A.max_dofs,
                           "No mesh with more free unknowns (d per node) is solved: the loop stops "
                           "before it."),
                       1));
  t.push_back(at_least(key("/adapt/max_levels", "integer", A.max_levels, "At most this many meshes, the first included."), 1));
  // Below 0.1 a level refines a handful of cells: θ = 1e-9 took thousands of levels to a target.
  t.push_back(at_most(at_least(key("/adapt/theta", "number", A.theta,
                                   "Dörfler bulk parameter θ: the fewest cells whose η_T² sum to θ·η² are "
                                   "refined (θ = 1: all; at least 0.1, or the loop needs hundreds of levels)."),
                               0.1),
                      1));
  t.push_back(at_least(key("/adapt/landing", "number", A.landing,
                           "The last step: when the Dörfler step would overshoot landing × N* nodes, "
                           "N* = N (η/target)^d the need predicted by the optimal rate η ∝ N^(-1/d), "
                           "only the largest indicators are marked, about as many as reach it; 0: off, "
                           "else >= 1 (the margin, against a step that falls short of the target)."),
                       0));
  t.push_back(at_most(at_least(key("/adapt/lookahead", "integer", A.lookahead,
                                   "At most this many refinement steps between two solves: the steps after the "
                                   "first mark indicators predicted from the last solve, while the mesh is "
                                   "predicted to miss the target (1: a solve after every step; only with "
                                   "landing on)."),
                               1),
                      8));
  // OpenBLAS's thread table is fixed when it is built (Debian: 64): 64 and more hung the loop.
  t.push_back(at_most(at_least(key("/adapt/blas_threads", "integer", A.blas_threads,
                                   "OpenBLAS threads during the adaptive loop, restored after it (0: leave the "
                                   "BLAS as configured; OPENBLAS_NUM_THREADS in the environment wins). The 2D "
                                   "levels' small supernodes gain nothing from BLAS threads (docs/adaptivity.md)."),
                               0),
                      32));
  t.push_back(key("/adapt/estimator", "string", to_string(A.estimator),
                  "zz: Zienkiewicz–Zhu recovery of the strain; zz_contact: zz plus the Γ3 contact-traction "
                  "mismatch on the Γ3 cells (refines along Γ3: docs/adaptivity.md); residual: element "
                  "residuals, traction jumps, Γ2 traction and the same Γ3 contact-traction mismatch.",
                  {"zz", "zz_contact", "residual"}));
  t.push_back(key("/adapt/bisection", "string", to_string(A.bisection),
                  "bisec3: every edge of a marked cell is bisected (2D: 4 children, 3D: 8); newest_vertex: only "
                  "its refinement edge (2 children). Both with the conforming closure.",
                  {"bisec3", "newest_vertex"}));

  // ------------------------------------------------------------------ output
  t.push_back(section("/output", "Files written next to report.json."));
  t.push_back(key("/output/vtu", "boolean", true, "VTK file: u, status, σ_ν, σ_τ, λ."));
  t.push_back(key("/output/vtu_format", "string", "binary",
                  "solution.vtu storage: binary (appended, zlib-compressed when built with zlib; ~5x "
                  "smaller and faster) or ascii (every number in full, for diffs).",
                  {"binary", "ascii"}));
  t.push_back(key("/output/csv", "boolean", true, "One CSV row per Γ3 node."));
  t.push_back(key("/output/plot", "boolean", false, "Pictures (needs python3-matplotlib)."));

  return t;
}

}  // namespace

const std::vector<SchemaEntry>& scene_schema() {
  static const std::vector<SchemaEntry> table = build_scene_schema();
  return table;
}

}  // namespace hemicontact
