#pragma once
/// @file petsc_engine.hpp  The distributed engine (solver.engine = "petsc"): the same problem,
/// algorithm and certificate as ContactSolver (driver/solve.hpp), with the unknowns spread over the
/// MPI ranks and every linear solve by CG with algebraic multigrid instead of CHOLMOD.
///
///   unknowns:   the reduced x of DofMap (Γ3 nodes in their local (ν, τ) frames, so u_ν ≤ g is the
///               bound x_ν ≤ g), split into contiguous row blocks of size d (one node per block);
///               each rank owns its rows of K and of every vector, and the Γ3 nodes whose rows it owns
///   scales:     the elastic solve K z = f (CG + GAMG with the rigid-body modes): U_s = ‖z‖∞, F_s = ‖f‖∞
///   minimize:   Π_λ,ε(x) = ½xᵀKx − fᵀx + Σ w j_ε(x_ν) + Σ w λ f0(|x_τ|, ε)  (docs/model.md §2),
///               nondimensionalized as the cholmod engine does, by TAO's bounded Newton (tao:bnls,
///               tao:bntr, tao:bntl); its Newton steps are CG + BoomerAMG on the Hessian restricted to
///               the inactive set
///   continuation and outer fixed point λ = F_b(u_ν): the schedule and stopping rules of driver/solve.cpp
///   polish:     Newton on the unsmoothed conditions of (22) with the statuses fixed (full space:
///               contact x_ν = g, stick x_τ = 0, compliance w p(x_ν) on its branch, slip w λ t), CG + GAMG
///   certify:    the certificate of check/certificate.hpp on the gathered u (every rank holds the model)
///
/// The model (mesh, K, f) is built on every rank by the same code as the cholmod engine, and each
/// rank copies its own rows of K into PETSc (per-rank mesh generation and assembly are not done yet:
/// the model is replicated, see docs/petsc-engine.md): the certificate, the report and the writers then read
/// the same Model, and the answers are comparable to round-off.

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <mpi.h>
#include <nlohmann/json.hpp>

#include <string>

namespace hemicontact::petsc_engine {

/// The engine's own record for report.json ("petsc"): ranks, the distribution, the Newton and
/// Krylov counts of every stage, and each rank's peak memory.
struct EngineReport {
  nlohmann::json json = nlohmann::json::object();
};

/// Solve @p md on the ranks of @p comm (collective; every rank passes the same model and options).
/// Each rank copies its rows of md.Kx into PETSc; the model itself is not changed (its K_x, the
/// only stiffness it keeps, is what the certificate reads).
/// @return the same Solution on every rank (x and u gathered).
/// @throws Error EXIT_INPUT for what the engine cannot do (a nonlinear material, more ranks than
///         cells or than node blocks, a non-TAO backend), EXIT_NOT_CONVERGED when a Krylov solve
///         outside TAO fails (the message names PETSc's reason, e.g. KSP_DIVERGED_ITS). Collective:
///         every rank throws the same error.
Solution solve(Model& md, const SolveOptions& opt, MPI_Comm comm, EngineReport& report);

/// Replace PETSc's error handler (traceback on every rank) by one that keeps the failure's first
/// message for the engine's Error, which then names @p user_options (solver.petsc.options) when
/// set, with exit code 2 (an input error, not a crash). Call once after PetscInitialize.
void install_error_handler(const std::string& user_options);

/// @return this process's resident memory now (kB), from /proc/self/statm (0 if unreadable).
long current_rss_kb();

/// @return the TAO type of a backend name ("tao:bnls" → "bnls"); "ipopt", the scene default, means
/// tao:bnls here. @throws Error EXIT_INPUT naming solver.backend for any other backend.
std::string tao_type(const std::string& backend);

}  // namespace hemicontact::petsc_engine
