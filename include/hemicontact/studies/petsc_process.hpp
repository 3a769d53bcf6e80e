#pragma once
/// @file petsc_process.hpp  The petsc engine for a command that holds the whole model in this
/// process (`converge`, the adaptive loop's levels, the Python module's solve and converge):
/// hemicontact-mpi run as a process of its own, on one rank, on this process's mesh, streaming the
/// displacement back (--stream --mesh-follows); this process reads it onto its own model and judges
/// it with its own judge (check/evaluate.hpp), so that the certificate, statuses and energies are
/// those of this model, whatever ran. A process of its own because this one links Ipopt, whose
/// MUMPS defines stub MPI symbols that would take the real MPI's place (src/cli/cli.cpp).

#include <hemicontact/problem/minima_report.hpp>
#include <hemicontact/solver/adapt.hpp>
#include <hemicontact/studies/scene_solve.hpp>

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace hemicontact {

/// The petsc engine as a SceneEngine (studies/scene_solve.hpp) for the effective @p scene (relative
/// paths from @p scene_dir), whose model the caller built. Each call runs `hemicontact-mpi solve -
/// --stream --mesh-follows` once: the scene and the model's own mesh (mesh/mesh_bytes.hpp: the
/// engine solves on it, numbered as here, an adaptive level's too) on its stdin, report.json's
/// content and u on its stdout, its progress
/// and warnings passed on through this process's log (core/log.hpp: the Python module's logger
/// gets them), its error in the message of the Error thrown; no file is written. An interrupt of
/// this thread (core/interrupt.hpp) stops it within 0.1 s.
class PetscProcess {
 public:
  PetscProcess(nlohmann::json scene, const std::string& scene_dir);
  /// @brief Solve: u from the engine's file, the run's record (backend, history, verdict, skipped
  /// stages) from its report.json, and the certificate, statuses and energies by this process's
  /// judge on @p md at @p opt's tolerances. @p u_start (the whole mesh's u; null or empty: zero)
  /// goes with the mesh as ssn's start (--start-follows; the TAO backends refuse one).
  /// @throws Error with the engine's exit code and message where it did not solve (an input error,
  ///         a failure); Interrupted where this thread's interrupt check said stop; a run that did
  ///         not converge or certify is returned
  Solution operator()(const Model& md, const SolveOptions& opt, const Vec* u_start = nullptr) const;
  /// @return the engine's last report.json (its "petsc" record: ranks, Newton and Krylov counts,
  /// peak memory), or null before any call.
  const nlohmann::json& last_report() const { return *report_; }

 private:
  nlohmann::json scene_;  // the engine's: solver.engine = petsc, no files, mesh.file absolute
  std::shared_ptr<nlohmann::json> report_ = std::make_shared<nlohmann::json>();
};

/// minima's starts on the petsc engine (MinimaOptions::engine, engine_name): each a PetscProcess
/// on @p scene with its loads.scale × the load path's factor, judged here on the scaled model at
/// @p opt's tolerances. For the CLI's minima and the Python module's alike (minima_engine).
void petsc_minima_starts(const nlohmann::json& scene, const std::string& scene_dir, const SolveOptions& opt,
                         MinimaOptions& mo);

/// @return the engine `hemicontact solve` would take for the effective @p scene (choose_engine,
/// no adaptive refinement): a PetscProcess where it takes the petsc engine (logged as "@p what:
/// the petsc engine (reason)"), else the cholmod engine (solver/solve.hpp's solve).
/// @throws Error (EXIT_INPUT) where solver.engine = petsc is given and @p petsc_available is false,
///         naming why (petsc_engine_missing)
SceneEngine scene_engine(const nlohmann::json& scene, const std::string& scene_dir, bool petsc_available,
                         const std::string& what);

/// @return the adaptive loop's level engine (solver/adapt.hpp) for @p scene: a level that
/// choose_level_engine sends to the petsc engine (3D, its factorization predicted not to fit, where
/// the engine is available) is solved by a PetscProcess, its method_choice saying so
/// (PETSC_ENGINE_METHOD); any other level by the loop's own solver. Each level's choice is logged.
AdaptLevelEngine petsc_level_engine(const nlohmann::json& scene, const std::string& scene_dir);

}  // namespace hemicontact
