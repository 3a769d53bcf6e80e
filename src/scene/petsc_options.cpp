// solver.petsc.options: the PETSc options a scene may pass to the petsc engine, and those it may not.
//
// PETSc options reach far beyond the solvers: viewers write any file (-ksp_view ascii:PATH,
// -ksp_view_mat binary:PATH, -log_view :PATH), -options_file reads one (and printed the first line
// of /etc/passwd in its error), -start_in_debugger runs a program, and a preconditioner that needs
// set-up the engine does not do (-pc_type mg without its levels' operators) crashed PETSc. A
// blacklist would trail every PETSc release; so this is a whitelist: each option is a known stem
// under one of the engine's prefixes, with a value of a known kind in a bounded range. Monitors and
// views without a value (they print to stdout) stay allowed; with a value (a viewer: a file, a
// socket, a format) they are refused.
#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/config.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace hemicontact {
namespace {

enum class Kind { FLAG, BOOL, INT, REAL, CHOICE };

struct Rule {
  Rule(const char* s, Kind k, double l = 0, double h = 0, std::vector<const char*> c = {})
      : stem(s), kind(k), lo(l), hi(h), choices(std::move(c)) {}
  const char* stem;                  // the option's name after its prefix, lower case
  Kind kind;
  double lo, hi;                     // INT, REAL: the closed range [lo, hi]
  std::vector<const char*> choices;  // CHOICE
};

// The options prefixes of the engine's solvers (src/petsc/petsc_solvers.cpp: create_cg's "elastic_",
// "polish_", "ssn_"; TAO's own options and its KSP's, "tao_" and "tao_bnk_"); "" for options
// that apply to every solver.
const std::vector<std::string>& prefixes() {
  static const std::vector<std::string> p = {"", "elastic_", "polish_", "ssn_", "tao_bnk_", "tao_"};
  return p;
}

// Krylov methods and preconditioners that need nothing the engine does not set up (mg needs
// levels' operators, fieldsplit the fields, shell a callback; lu/cholesky in parallel a package).
const std::vector<const char*> KSP_TYPES = {"cg", "pipecg", "cr", "gmres", "fgmres", "minres",
                                            "bcgs", "richardson", "chebyshev", "preonly"};
const std::vector<const char*> PC_TYPES = {"gamg", "hypre", "jacobi", "pbjacobi", "bjacobi",
                                           "sor", "ilu", "icc", "asm", "none"};

const std::vector<Rule>& rules() {
  constexpr double BIG = 1e300;
  static const std::vector<Rule> r = {
      // Krylov solves
      {"ksp_type", Kind::CHOICE, 0, 0, KSP_TYPES},
      {"ksp_rtol", Kind::REAL, 1e-300, 0.999999},
      {"ksp_atol", Kind::REAL, 0, BIG},
      {"ksp_divtol", Kind::REAL, 1, BIG},
      {"ksp_max_it", Kind::INT, 1, 1e6},
      {"ksp_norm_type", Kind::CHOICE, 0, 0, {"preconditioned", "unpreconditioned", "natural", "none"}},
      {"ksp_gmres_restart", Kind::INT, 1, 1000},
      {"ksp_initial_guess_nonzero", Kind::BOOL},
      // monitors and views: to stdout only (no value)
      {"ksp_monitor", Kind::FLAG},
      {"ksp_monitor_short", Kind::FLAG},
      {"ksp_monitor_true_residual", Kind::FLAG},
      {"ksp_converged_reason", Kind::FLAG},
      {"ksp_view", Kind::FLAG},
      {"pc_view", Kind::FLAG},
      // Not log_view: PETSc starts its event log in PetscInitialize, before the scene's options
      // are read, and -log_view then failed in PetscFinalize (PETSC_OPTIONS=-log_view works).
      {"info", Kind::FLAG},
      {"options_left", Kind::FLAG},
      // preconditioners
      {"pc_type", Kind::CHOICE, 0, 0, PC_TYPES},
      {"pc_sor_omega", Kind::REAL, 1e-3, 1.999},
      {"pc_sor_its", Kind::INT, 1, 100},
      {"pc_factor_levels", Kind::INT, 0, 10},
      {"pc_asm_overlap", Kind::INT, 0, 10},
      {"sub_pc_type", Kind::CHOICE, 0, 0, {"ilu", "icc", "jacobi", "sor", "none"}},
      {"sub_ksp_type", Kind::CHOICE, 0, 0, {"preonly", "richardson"}},
      // GAMG (and the levels of its multigrid: pc_mg_levels caps their number)
      {"pc_gamg_type", Kind::CHOICE, 0, 0, {"agg", "classical"}},
      {"pc_gamg_threshold", Kind::REAL, -1, 1},
      {"pc_gamg_threshold_scale", Kind::REAL, 0, 1},
      {"pc_gamg_agg_nsmooths", Kind::INT, 0, 10},
      {"pc_gamg_square_graph", Kind::INT, 0, 10},
      {"pc_gamg_sym_graph", Kind::BOOL},
      {"pc_gamg_coarse_eq_limit", Kind::INT, 1, 1e7},
      {"pc_gamg_process_eq_limit", Kind::INT, 1, 1e7},
      {"pc_gamg_repartition", Kind::BOOL},
      {"pc_gamg_reuse_interpolation", Kind::BOOL},
      {"pc_gamg_use_sa_esteig", Kind::BOOL},
      {"pc_gamg_esteig_ksp_max_it", Kind::INT, 1, 100},
      {"pc_gamg_esteig_ksp_type", Kind::CHOICE, 0, 0, {"cg", "gmres"}},
      {"pc_mg_levels", Kind::INT, 1, 30},
      {"pc_mg_cycle_type", Kind::CHOICE, 0, 0, {"v", "w"}},
      {"mg_levels_ksp_type", Kind::CHOICE, 0, 0, {"chebyshev", "richardson", "cg", "gmres"}},
      {"mg_levels_pc_type", Kind::CHOICE, 0, 0, {"jacobi", "pbjacobi", "sor", "bjacobi", "none"}},
      {"mg_levels_ksp_max_it", Kind::INT, 1, 100},
      {"mg_coarse_pc_type", Kind::CHOICE, 0, 0, {"bjacobi", "jacobi", "redundant", "svd", "none"}},
      {"mg_coarse_ksp_type", Kind::CHOICE, 0, 0, {"preonly", "cg", "gmres"}},
      // GAMG's Galerkin products (the engine defaults to hypre's on several ranks: docs/petsc-engine.md)
      {"matptap_via", Kind::CHOICE, 0, 0, {"scalable", "nonscalable", "allatonce", "allatonce_merged", "hypre"}},
      // BoomerAMG
      {"pc_hypre_type", Kind::CHOICE, 0, 0, {"boomeramg"}},
      {"pc_hypre_boomeramg_strong_threshold", Kind::REAL, 0, 1},
      {"pc_hypre_boomeramg_max_levels", Kind::INT, 2, 30},
      {"pc_hypre_boomeramg_max_iter", Kind::INT, 1, 100},
      {"pc_hypre_boomeramg_agg_nl", Kind::INT, 0, 10},
      {"pc_hypre_boomeramg_agg_num_paths", Kind::INT, 1, 10},
      {"pc_hypre_boomeramg_p_max", Kind::INT, 0, 100},
      {"pc_hypre_boomeramg_truncfactor", Kind::REAL, 0, 1},
      {"pc_hypre_boomeramg_nodal_coarsen", Kind::INT, 0, 6},
      {"pc_hypre_boomeramg_vec_interp_variant", Kind::INT, 0, 3},
      {"pc_hypre_boomeramg_coarsen_type",
       Kind::CHOICE,
       0,
       0,
       {"cljp", "ruge-stueben", "modifiedruge-stueben", "falgout", "pmis", "hmis"}},
      {"pc_hypre_boomeramg_interp_type",
       Kind::CHOICE,
       0,
       0,
       {"classical", "direct", "multipass", "multipass-wts", "ext+i", "ext+i-cc", "standard", "standard-wts",
        "block", "block-wtd", "ff", "ff1", "ext", "ad-wts", "ext-mm", "ext+i-mm", "ext+e-mm"}},
      {"pc_hypre_boomeramg_relax_type_all",
       Kind::CHOICE,
       0,
       0,
       {"jacobi", "sequential-gauss-seidel", "seqboundary-gauss-seidel", "sor/jacobi", "backward-sor/jacobi",
        "symmetric-sor/jacobi", "l1scaled-sor/jacobi", "l1-gauss-seidel", "backward-l1-gauss-seidel", "cg",
        "chebyshev", "l1scaled-jacobi"}},
      // TAO
      {"tao_max_it", Kind::INT, 1, 1e6},
      {"tao_max_funcs", Kind::INT, 1, 1e8},
      {"tao_gatol", Kind::REAL, 0, BIG},
      {"tao_grtol", Kind::REAL, 0, 1},
      {"tao_gttol", Kind::REAL, 0, 1},
      {"tao_monitor", Kind::FLAG},
      {"tao_ls_monitor", Kind::FLAG},
      {"tao_converged_reason", Kind::FLAG},
      {"tao_view", Kind::FLAG},
      {"tao_ls_type", Kind::CHOICE, 0, 0, {"more-thuente", "armijo", "unit"}},
      {"tao_bnk_max_cg_its", Kind::INT, 0, 1e6},
  };
  return r;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A token that starts an option: '-' then a letter (a value may be a negative number, "-1e-3").
bool is_option(const std::string& t) { return t.size() >= 2 && t[0] == '-' && std::isalpha(static_cast<unsigned char>(t[1])); }

const Rule* find_rule(const std::string& name) {
  for (const std::string& p : prefixes()) {
    if (name.compare(0, p.size(), p) != 0) continue;
    const std::string stem = name.substr(p.size());
    for (const Rule& r : rules())
      if (stem == r.stem) return &r;
  }
  return nullptr;
}

std::string range(const Rule& r) {
  std::ostringstream os;
  os << r.lo << ".." << r.hi;
  return os.str();
}

}  // namespace

void check_petsc_options(const std::string& options, const std::string& key) {
  const auto fail = [&](const std::string& why) {
    input_error("scene key '" + key + "': " + why +
                "; PETSc options from a scene may set the solvers (KSP, PC, GAMG, BoomerAMG, TAO tolerances) "
                "and print monitors and views to stdout, never name a file (docs/scene-format.md)");
  };
  // PETSc's own tokenizer also honours quotes; no allowed value needs them.
  if (options.find_first_of("\"'`") != std::string::npos) fail("quotes are not accepted in '" + options + "'");
  std::istringstream in(options);
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  for (size_t i = 0; i < tokens.size(); ++i) {
    const std::string& t = tokens[i];
    if (!is_option(t)) fail("'" + t + "' is not an option (options start with '-')");
    // PETSc matches option names without regard to case (-KSP_VIEW is -ksp_view).
    const std::string name = lower(t.substr(1));
    const bool has_value = i + 1 < tokens.size() && !is_option(tokens[i + 1]);
    const std::string value = has_value ? tokens[i + 1] : "";
    if (has_value) ++i;
    const Rule* r = find_rule(name);
    if (r == nullptr) fail("option '" + t + "' is not accepted (not a solver setting the petsc engine allows)");
    const std::string shown = "option '" + t + "'";
    switch (r->kind) {
      case Kind::FLAG:
        if (has_value)
          fail(shown + " takes no value here: '" + value +
               "' would send its output to a file or another viewer (without a value it prints to stdout)");
        break;
      case Kind::BOOL:
        if (has_value && lower(value) != "true" && lower(value) != "false" && value != "1" && value != "0" &&
            lower(value) != "yes" && lower(value) != "no")
          fail(shown + " expects true or false, got '" + value + "'");
        break;
      case Kind::INT: {
        errno = 0;
        char* end = nullptr;
        const long v = has_value ? std::strtol(value.c_str(), &end, 10) : 0;
        if (!has_value || errno != 0 || *end != '\0' || v < r->lo || v > r->hi)
          fail(shown + " expects an integer in " + range(*r) + ", got '" + value + "'");
        break;
      }
      case Kind::REAL: {
        errno = 0;
        char* end = nullptr;
        const double v = has_value ? std::strtod(value.c_str(), &end) : 0;
        if (!has_value || errno != 0 || *end != '\0' || !std::isfinite(v) || v < r->lo || v > r->hi)
          fail(shown + " expects a number in " + range(*r) + ", got '" + value + "'");
        break;
      }
      case Kind::CHOICE: {
        const bool ok = has_value && std::any_of(r->choices.begin(), r->choices.end(),
                                                 [&](const char* c) { return lower(value) == c; });
        if (!ok) {
          std::string list;
          for (const char* c : r->choices) list += (list.empty() ? "" : ", ") + std::string(c);
          fail(shown + " expects one of " + list + ", got '" + value + "'");
        }
        break;
      }
    }
  }
}

}  // namespace hemicontact
