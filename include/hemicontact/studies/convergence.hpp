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
///
/// The study's result (ConvergenceStudy, its levels and the rate fit) is a plain record in
/// problem/convergence_study.hpp, which the writers (output/study_writers.hpp) read.

#include <hemicontact/problem/convergence_study.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/solver/engine_choice.hpp>

#include <nlohmann/json.hpp>

#include <functional>

#include <map>
#include <string>
#include <vector>

namespace hemicontact {

/// Largest mesh level n (cells per side) a study accepts: 2^20, far beyond any memory (the memory
/// estimate refuses a solve long before), and small enough that n·n cannot overflow the counts.
inline constexpr int MAX_LEVEL = 1 << 20;

/// @brief Parse a list of levels: "4,8,16" or "4,8,...,128" ("..." continues the integer ratio of
/// the two preceding levels up to the level after it). The result is sorted and without repeats.
/// @param text the list @return the levels
/// @throws Error (EXIT_USAGE) naming the bad entry: not a positive integer, or a "..." without two
///         increasing levels with an integer ratio before it and one level after it
std::vector<int> parse_levels(const std::string& text);
/// @return the engine the reference mesh n = @p reference is solved by: the one `hemicontact solve`
/// would take for it (solver/engine_choice.hpp's choose_engine; a generated mesh; any other is
/// judged as given, and refused by the study). Each level is chosen for alike (run_convergence).
EngineChoice convergence_engine(const nlohmann::json& scene, const std::string& scene_dir, int reference,
                                bool petsc_built);

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

/// @param petsc_built  a level whose `hemicontact solve` would take the petsc engine (choose_engine:
///                     a large 3D box, or solver.engine = petsc) runs it, as a process of its own
///                     (studies/petsc_process.hpp); false: every level on the cholmod engine
ConvergenceStudy run_convergence(const nlohmann::json& scene, const std::string& scene_dir, std::vector<int> levels,
                                 int reference, const LevelSolved& on_level = nullptr, bool petsc_built = false);

}  // namespace hemicontact
