#pragma once
/// @file convergence.hpp  Mesh-convergence study of a scene (paper §5, Fig. 3; docs/model.md §5).
///
/// The scene is solved on uniform meshes n = L for each level L and on a reference mesh n = R,
/// every level by overriding `mesh.n` (so nx = ny [= nz for a box] = L). With u_ref the reference solution and P the
/// P1 prolongation onto the reference mesh (fem/prolongation.hpp), each level's error is
///   e_L = ‖u_ref − P u_L‖_E / ‖u_ref‖_E,   ‖v‖_E² = vᵀ K_R v = a(v, v),
/// the energy norm of the *reference* mesh's stiffness K_R. When every level divides R the
/// meshes are nested (for the right/left/crossed splits, and for symmetric ones with even n), P
/// is the exact embedding V_L ⊂ V_R and e_L is the true error of u_L measured in V_R. Between
/// consecutive levels the observed order is
///   p_i = log(e_{i−1}/e_i) / log(h_{i−1}/h_i),
/// which the paper's Theorem (optimal order, eq. (31)) predicts to be ≈ 1 for a regular solution.
///
/// Typical use (the `converge` command):
/// @code
///   const nlohmann::json scene = load_scene("problems/sofonea2017-fig2.json");
///   const ConvergenceStudy st = run_convergence(scene, "problems", {4, 8, 16, 32, 64}, 128);
///   write_convergence_csv("out/conv/convergence.csv", st);
///   std::fputs(convergence_table(st).c_str(), stdout);
/// @endcode

#include <hemicontact/core/types.hpp>

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>

#include <nlohmann/json.hpp>

#include <functional>

#include <map>
#include <string>
#include <vector>

namespace hemicontact {

/// One mesh of a convergence study (a level or the reference).
struct ConvergenceLevel {
  int n = 0;               ///< cells per side (mesh.n)
  double h = 0;            ///< the paper's h: longest side of the rectangle / n (1/n on the unit square)
  double h_max = 0;        ///< longest edge of the mesh (√2·h for the right/left splits)
  Index dofs = 0;          ///< free unknowns
  double energy_norm = 0;  ///< ‖u_L‖_E = sqrt(a(u_L, u_L)) on the level's own mesh
  double error = 0;        ///< ‖u_ref − P u_L‖_E / ‖u_ref‖_E (0 for the reference)
  double order = 0;        ///< observed order against the previous level; NaN for the first
  double seconds = 0;      ///< wall time of solve() (model assembly excluded)
  std::map<std::string, int> status_counts;  ///< Solution::status_counts()
  double certificate_residual = 0;           ///< certificate max residual
  bool converged = false;                    ///< backend and outer fixed point converged
  bool certified = false;                    ///< certificate passed
  bool ok = false;                           ///< converged && certified
  bool nested = true;                        ///< P is the exact embedding of V_L into V_ref (checked numerically)
  std::string message;                       ///< the solve's verdict
  std::string solved_by;                     ///< what produced the answer (Solution::solved_by)
};

/// The result of run_convergence().
struct ConvergenceStudy {
  ConvergenceLevel reference;            ///< the reference mesh (error 0, order NaN)
  std::vector<ConvergenceLevel> levels;  ///< the levels, coarse to fine
  /// What solved the levels and the reference: the distinct Solution::solved_by labels, joined by
  /// ", " (e.g. "exact" when the backend's stage was skipped on every level: strongly convex).
  std::string backend;
  nlohmann::json scene;                  ///< the effective scene of the reference solve

  /// @return true when the reference and every level converged and were certified.
  bool ok() const;
  /// @return the n of every mesh (reference included) that failed, e.g. {8, 128}.
  std::vector<int> failed() const;
};

/// The observed orders against a finite reference are biased upwards near the reference: for nested
/// spaces and a linear problem, Galerkin orthogonality in the energy norm gives
///   ‖u − u_L‖²_E = ‖u − u_R‖²_E + ‖u_R − u_L‖²_E,
/// so if ‖u − u_L‖_E ≈ C h_L^α then the measured e_L ≈ C sqrt(h_L^{2α} − h_R^{2α}) (relative
/// errors: C absorbs ‖u_R‖_E). fit_rate() fits C and α to that model, which removes the bias
/// and turns the errors into an estimate of the asymptotic rate (for the paper's scenes α ≈ 0.72,
/// the corner exponent where the clamped side meets the free sides; docs/convergence.md).
/// With contact the identity is approximate (the solution set is not a linear space); the
/// reported max_rel_residual says how well the model fits.
struct RateFit {
  double alpha = 0;             ///< fitted rate α
  double C = 0;                 ///< fitted constant (relative error at h = 1)
  int levels_used = 0;          ///< number of (finest) levels in the fit
  double max_rel_residual = 0;  ///< max_L |model_L / e_L − 1| over the fitted levels
  bool valid = false;           ///< false when fewer than 2 usable levels (error > 0, h > h_R)
};

/// @brief Fit e_L = C sqrt(h_L^{2α} − h_R^{2α}) (least squares in log e) to the @p max_levels
/// finest levels of @p study with error > 0 and h > h_R; α is searched in [0.05, 4].
/// @param study a finished study @param max_levels how many of the finest levels to use (≥ 2)
/// @return the fit; valid = false if fewer than 2 levels qualify
RateFit fit_rate(const ConvergenceStudy& study, int max_levels = 4);

/// Largest mesh level n (cells per side) a study accepts: 2^20, far beyond any memory (the memory
/// estimate refuses a solve long before), and small enough that n·n cannot overflow the counts.
inline constexpr int MAX_LEVEL = 1 << 20;

/// @brief Parse a list of levels: "4,8,16" or "4,8,...,128" ("..." continues the integer ratio of
/// the two preceding levels up to the level after it). The result is sorted and without repeats.
/// @param text the list @return the levels
/// @throws Error (EXIT_USAGE) naming the bad entry: not a positive integer, or a "..." without two
///         increasing levels with an integer ratio before it and one level after it
std::vector<int> parse_levels(const std::string& text);

/// @brief Solve @p scene on the reference mesh n = @p reference, then on each level n = L, and
/// measure the errors against the reference (file comment). A level equal to the reference
/// reuses the reference solution (its error is then 0 up to round-off).
///
/// Non-convergence of a solve does not throw: it is recorded in the level's flags (the errors
/// are still computed) and ConvergenceStudy::ok() is false.
/// @param scene      effective scene (load_scene()); its mesh.n / nx / ny are overridden
/// @param scene_dir  directory that relative paths of the scene are taken from
/// @param levels     mesh levels (any order; sorted ascending, repeats dropped)
/// @param reference  the reference level R
/// @return the study, levels coarse to fine
/// @throws Error (EXIT_INPUT) if there is no level, a level or R is < 1, some levels do not divide
///         R (all of them are named), or the scene's mesh is not generated (rectangle or box)
/// Called with each solved mesh while the study runs, the reference first (@p so_far has no
/// levels yet), then each level other than the reference once its error is in so_far.levels
/// (a level equal to the reference is not solved again, so not announced again): the caller keeps
/// what it wants of it as it comes (the CLI: one VTU per level and the CSV of the levels so far),
/// so that an interrupted study loses only the solve it was in, and the driver knows no files.
using LevelSolved =
    std::function<void(const ConvergenceStudy& so_far, int n, const Model& model, const Solution& solution)>;

ConvergenceStudy run_convergence(const nlohmann::json& scene, const std::string& scene_dir, std::vector<int> levels,
                                 int reference, const LevelSolved& on_level = nullptr);

}  // namespace hemicontact
