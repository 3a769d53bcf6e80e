#pragma once
/// @file engine_choice.hpp  solver.engine = auto, read from the scene alone (no mesh, no model):
/// the cholmod engine's programs and the petsc engine's (hemicontact-mpi) both decide with it, and
/// it reads the scene and, for a Gmsh mesh, its file's header (mesh/msh_peek.hpp).

#include <nlohmann/json.hpp>

#include <string>

namespace hemicontact {

/// solver.engine = auto: which engine `hemicontact solve` runs (and `converge` and the Python
/// module's solve and converge, level by level: the petsc engine is a program of its own, which the
/// CLI execs and they stream from, studies/petsc_process.hpp). The petsc engine in one process (ssn
/// with CG + AMG: no factorization, no dense Γ3 work) for a 3D mesh of at least
/// solver.method_choice.petsc_above unknowns (a generated box, or a Gmsh file whose header gives its
/// size: mesh/msh_peek.hpp) and a linear material, where this build has it; the cholmod engine
/// otherwise (minima, path, 2D, or where petsc_engine_missing). Decided from the scene alone,
/// before any mesh is made. With adaptive refinement the loop runs in the cholmod engine's process
/// and each level chooses again (choose_level_engine).
struct EngineChoice {
  std::string engine;      ///< "cholmod" or "petsc"
  bool automatic = false;  ///< solver.engine was auto
  std::string reason;
};
/// @return which engine, "(auto)" where solver.engine = auto chose it, and why (the log's line,
/// `solve`'s "engine" summary row).
std::string describe(const EngineChoice& c);
/// @return the path of the petsc engine's program, hemicontact-mpi: $HEMICONTACT_MPI where set;
/// else the first that exists of: beside this process's executable (the CLI's build or install
/// folder), the build tree's that this library was built with, the installed one; the last of
/// those where none exists.
std::string petsc_engine_program();
/// @return why the petsc engine cannot run from this program ("" where it can): this build has
/// none, or its program is not where petsc_engine_program looks (a library used without it).
std::string petsc_engine_missing();
/// @return petsc_engine_missing() is empty: what the callers of choose_engine pass as petsc_built.
inline bool petsc_engine_available() { return petsc_engine_missing().empty(); }

/// @param scene a validated scene @param scene_dir where a relative mesh.file is found
/// @param petsc_built the petsc engine can run (petsc_engine_available; the engine's own program: true)
/// @param adaptive the scene asks for adaptive refinement (adapt_requested)
EngineChoice choose_engine(const nlohmann::json& scene, const std::string& scene_dir, bool petsc_built,
                           bool adaptive);
/// An adaptive level's method_choice.chosen (and report's "method") where the petsc engine solved it.
inline constexpr const char* PETSC_ENGINE_METHOD = "petsc engine";

/// What the engine of an adaptive level is decided on (choose_level_engine).
struct LevelNumbers {
  int dim = 0;
  double unknowns = 0;           ///< this level's, dim × nodes
  double previous_unknowns = 0;  ///< the previous level's (0: this is the first level)
  double previous_factor_nnz = 0;  ///< its factorization's entries in this process (0: none made)
  bool previous_petsc = false;     ///< the previous level went to the petsc engine
  double memory_bytes = 0;         ///< what this process may still use (available_memory_bytes)
};
/// The engine of one level of the adaptive loop (a mesh the loop made). Adaptive meshes are graded
/// towards Γ3's edges and their Γ3 stays small, where this process's factorization beats the
/// petsc engine's CG + AMG (the 3D scene to 7 %: 59k unknowns 1.0 against 2.1 s, 355k 12.7
/// against 18.9 s; docs/adaptivity.md), so size alone does not send a level there: a 3D level goes
/// to the petsc engine where its factorization would not fit, predicted from the previous level's
/// (nnz · (N/N_prev)^(4/3), nested dissection's growth in 3D, 8 bytes each) against
/// solver.method_choice.memory_fraction of @p n.memory_bytes, and stays there once it went. The
/// first level (the scene's own, uniform mesh) is decided as choose_engine decides it. A given
/// solver.engine stays given; what only the cholmod engine has keeps it (choose_engine's rules).
EngineChoice choose_level_engine(const nlohmann::json& scene, const LevelNumbers& n, bool petsc_built);
/// The engine of a command that restarts one solver from many points in this process (path, the
/// Python module's path; minima where it stays in this process, minima_engine): the cholmod engine,
/// whose method choice (condensed or full) it uses. (converge and the module's solve take choose_engine's, the petsc engine streamed back:
/// studies/petsc_process.hpp.) Where `hemicontact solve` would
/// have taken the petsc engine automatically, the reason says so, with choose_engine's numbers,
/// so that a slow in-process 3D run says where the fast one is.
/// @param command the command's name, for the reason ("minima", "path", "the Python module's minima", ...)
EngineChoice in_process_engine(const nlohmann::json& scene, const std::string& scene_dir, bool petsc_built,
                               const std::string& command);
/// minima's engine: choose_engine's rule with solver.method_choice.petsc_restarts_above for its
/// threshold (a search restarts one solver many times: the in-process factorization, made once,
/// serves every start), or solver.engine = petsc given. On the petsc engine every start is a
/// process of its own (studies/petsc_process.hpp), judged and second-order checked here
/// (MinimaOptions::engine). The cholmod engine in this process where --backends names backends
/// or --barriers asks for the barriers, which both need the in-process solver, the reason saying
/// so; a given petsc with either is refused (EXIT_INPUT), naming why.
EngineChoice minima_engine(const nlohmann::json& scene, const std::string& scene_dir, bool petsc_built,
                           bool backends_named, bool barriers);
/// The log's "engine ... (auto): reason" line, when the choice was automatic.
void log_engine_choice(const EngineChoice& c);
/// report.json's engine_choice.
nlohmann::json engine_choice_json(const EngineChoice& c);

}  // namespace hemicontact
