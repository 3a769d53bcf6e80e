#pragma once
/// @file petsc_engine.hpp  The distributed engine (solver.engine = "petsc"): the same problem,
/// algorithm and certificate as ContactSolver (solver/solve.hpp), with the unknowns spread over the
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
///   continuation and outer fixed point λ = F_b(u_ν): the schedule and stopping rules of solver/solve.cpp
///   polish:     Newton on the unsmoothed conditions of (22) with the statuses fixed (full space:
///               contact x_ν = g, stick x_τ = 0, compliance w p(x_ν) on its branch, slip w λ t), CG + GAMG
///   certify:    the certificate of check/certificate.hpp on the gathered u (replicated model), or its
///               formulas node by node on each slab's owned nodes with the maxima reduced (slabs)
///
/// Two layouts (docs/petsc-engine.md, "Distributed mesh"). A generated box or rectangle solved by
/// ssn is made per rank in slabs of cell layers (make_slab, solve_slabs): each rank builds only its
/// slab's model, PETSc's rows are its owned nodes', the certificate and the energies are reductions
/// over the owned nodes, and no rank holds the whole mesh or solution. Anything else (Gmsh files,
/// perturbed meshes, TAO) builds the whole model on every rank (solve): each rank copies its own
/// rows of K into PETSc, and the certificate, the report and the writers read the gathered answer.

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <mpi.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

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

/// A rank's slab of a generated mesh (the distributed path: solver.petsc.mesh, docs/petsc-engine.md
/// "Distributed mesh"): the rank owns the node layers [c0, c1) along the cut (the last rank also
/// layer c1 = layers) and holds the cell layers [max(c0 − 1, 0), c1), every cell that touches an
/// owned node; the nodes of layer c0 − 1 and of layer c1 are ghosts, owned by the ranks below and
/// above. Local node and cell indices are those of the rank's own mesh (build_slab_mesh).
struct Slab {
  int axis = 0, layers = 0;  ///< the cut (SlabCut)
  int c0 = 0, c1 = 0;        ///< owned cell layers [c0, c1)
  std::vector<char> owned_node;  ///< per local node: owned by this rank
  std::vector<char> owned_cell;  ///< per local cell: in layers [c0, c1) (the ghost layer is not)
  /// Ghost nodes of layer c0 − 1 (owned by rank − 1) and of layer c1 (rank + 1), and the owned nodes
  /// that are ghosts there (layers c0 and c1 − 1), each in local index order: the same order on
  /// both sides (the generators number a layer's nodes in the same relative order on every rank).
  std::vector<Index> recv_below, recv_above, send_below, send_above;
  long global_nodes = 0, global_cells = 0;  ///< the whole mesh's counts (sums over the ranks)
};

/// @brief This rank's slab of the scene's generated mesh (collective): the cell layers split evenly
/// over the ranks, the mesh of its layers with the boundary parts of the whole mesh. Refuses a
/// selector that selects nothing on every rank, and more ranks than cell layers (EXIT_INPUT).
Slab make_slab(const nlohmann::json& scene, MPI_Comm comm, Mesh& mesh);

/// What the distributed path leaves for the writers: this rank's piece (the local nodes' u, the
/// local Γ3 nodes' state and statuses, read with the global scales), and the report's reductions.
struct SlabResult {
  Solution piece;                                            ///< u, state and status of the local model
  nlohmann::json status_counts = nlohmann::json::object();   ///< over all ranks
  long gamma3_nodes = 0;                                     ///< over all ranks
  long local_nodes_max = 0;                                  ///< the most nodes a rank holds (ghosts included)
};

/// @brief Solve on the slabs (collective; ssn, or TAO without the polish): as solve(), but @p md is this rank's
/// slab (make_slab, build_model(scene, mesh, false)) and nothing global is gathered. @return the
/// scalars of the answer (energies, certificate, verdict; its vectors empty); @p out the piece.
Solution solve_slabs(Model& md, const Slab& slab, const SolveOptions& opt, MPI_Comm comm, EngineReport& report,
                     SlabResult& out);

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
