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
///   certify:    the judge of check/judge.hpp node by node on each piece's owned nodes, its maxima
///               and sums reduced over the ranks
///
/// The mesh is always distributed (docs/petsc-engine.md, "Distributed mesh"; solve_slabs): a
/// generated box or rectangle is made per rank in slabs of cell layers (make_slab), a box on more
/// ranks than layers in blocks of cell columns (make_block), any other mesh (a Gmsh file, a
/// perturbed or crossed one) is made on rank 0 and distributed by DMPlex (make_plex_piece); each
/// rank builds only its piece's model, PETSc's rows are its owned nodes', the ghosts' rows come
/// from their owners, the certificate and the energies are reductions over the owned nodes, and no
/// rank holds the whole mesh or solution. (The replicated layout, every rank building the whole
/// model, was retired: these layouts solve every scene it solved, in less memory per rank.)

#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>
#include <hemicontact/scene/slab_mesh.hpp>

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

/// A rank's piece of the distributed mesh (solver.petsc.mesh, docs/petsc-engine.md "Distributed
/// mesh"): the local mesh holds every cell that touches an owned
/// node, so that each owned node's row is complete locally; the other local nodes are ghosts, each
/// owned by one other rank, and the engine gets their PETSc rows from their owners by the whole
/// mesh's node number (Engine::exchange_ghosts). Three producers: make_slab (a generated box or
/// rectangle in slabs of cell layers), make_block (a box in blocks of cell columns) and
/// make_plex_piece (a Gmsh file, or another mesh rank 0 makes, distributed by DMPlex).
/// Local node and cell indices are those of the rank's own mesh.
struct Piece {
  std::vector<char> owned_node;  ///< per local node: owned by this rank
  std::vector<char> owned_cell;  ///< per local cell: this rank's (each cell is one rank's; VTU pieces)
  std::vector<long> global_node;  ///< per local node: its number in the whole mesh (the report's "node")
  std::vector<int> owner;         ///< per local node: the rank that owns it
  /// Per local node: every cell of the whole mesh that touches it is local (its boundary facets,
  /// and so its clamping, Γ3 frame and unknowns, are those of the whole mesh). Empty: every node
  /// (the slabs, whose cuts are planes of grid nodes). A node without it is an outer ghost, in no
  /// cell that touches an owned node: its rows enter no owned row, and a difference between its
  /// unknowns and its owner's is not an error (it gets no PETSc row).
  std::vector<char> complete;
  long global_nodes = 0, global_cells = 0;  ///< the whole mesh's counts (sums over the ranks)
  std::string layout = "slabs";              ///< "slabs", "blocks", "dmplex" or "given" (--mesh-follows)
  std::string partitioner;                   ///< dmplex: PETSc's partitioner type (e.g. ptscotch)
  // The slabs only: the rank owns the node layers [c0, c1) along the cut (the last rank also layer
  // c1 = layers) and holds the cell layers [max(c0 − 1, 0), c1).
  int axis = 0, layers = 0;  ///< the cut (SlabCut)
  int c0 = 0, c1 = 0;        ///< owned cell layers [c0, c1)
  // The blocks only: the ranks form a grid_x × grid_y grid over the box's cell columns; this rank
  // owns the node columns of block [i0, i1) × [j0, j1) (the last block in x also node column nx,
  // in y ny) and holds the cell columns [max(i0 − 1, 0), i1) × [max(j0 − 1, 0), j1), every z layer.
  int grid_x = 0, grid_y = 0;
  BlockRange block;
  /// @return report.json's petsc.mesh: "distributed (per-rank slabs)", "distributed (per-rank blocks,
  /// px x py)", "distributed (DMPlex, <partitioner>)" or, for a mesh given on stdin, "the caller's
  /// mesh, whole, on one rank (--mesh-follows)".
  std::string describe() const {
    if (layout == "slabs") return "distributed (per-rank slabs)";
    if (layout == "blocks")
      return "distributed (per-rank blocks, " + std::to_string(grid_x) + " x " + std::to_string(grid_y) + ")";
    if (layout == "given") return "the caller's mesh, whole, on one rank (--mesh-follows)";
    return "distributed (DMPlex, " + partitioner + ")";
  }
};

/// @brief This rank's slab of the scene's generated mesh (collective): the cell layers split evenly
/// over the ranks, the mesh of its layers with the boundary parts of the whole mesh. Refuses a
/// selector that selects nothing on every rank, and more ranks than cell layers (EXIT_INPUT).
Piece make_slab(const nlohmann::json& scene, MPI_Comm comm, Mesh& mesh);

/// A generated piece's selectors: each must select a facet on some rank (what assign_boundary
/// checks on a whole mesh), @p counts this rank's (build_slab_mesh's order). Collective.
/// @throws Error EXIT_INPUT naming the selector that selects nothing anywhere.
void check_selectors_somewhere(const nlohmann::json& scene, const std::vector<long>& counts, MPI_Comm comm);

/// The whole mesh's node and cell counts of @p s (global_nodes, global_cells): the sums of the
/// ranks' owned ones. Collective.
void count_whole_mesh(Piece& s, MPI_Comm comm);

/// The ranks' grid over a box's cell columns (x by y): px·py = ranks, px <= nx, py <= ny.
struct BlockGrid {
  int px = 0, py = 0;  ///< 0, 0: no such grid
};

/// @return among the grids of @p ranks blocks over nx × ny cell columns, the one with the least cut
/// area (blocks closest to square); {0, 0} when none fits (a prime count of ranks above nx and ny).
BlockGrid block_grid(int nx, int ny, int ranks);

/// @brief This rank's block of the scene's generated box (collective): the ranks in a block_grid
/// over the cell columns, every z layer in each block (so that Γ3 on the bottom reaches each), the
/// mesh of its columns and one column of cells below in x and in y, with the boundary parts of the
/// whole box. For more ranks than a slab cut has layers. Refuses what make_slab refuses, a scene that
/// is not a box, and a count of ranks that makes no grid (EXIT_INPUT).
Piece make_block(const nlohmann::json& scene, MPI_Comm comm, Mesh& mesh);

/// @brief This rank's piece of the scene's mesh (collective): rank 0 makes the whole mesh as
/// build_mesh does (a Gmsh file read by read_gmsh with its checks, or a generated mesh; the
/// boundary parts assigned on the whole mesh), builds a DMPlex of it and distributes it with
/// PETSc's partitioner and an overlap; each rank's @p mesh is then its cells (rank 0 frees the
/// whole mesh). The scene's input
/// errors (a missing file, a selector that selects nothing) are thrown on every rank alike.
Piece make_plex_piece(const nlohmann::json& scene, const std::string& scene_dir, MPI_Comm comm, Mesh& mesh);

/// @brief Each ghost node's boundary data from its owner (collective), for build_model of this
/// rank's piece (@p mesh, @p pc): its Γ3 weight and normal sum, its clamping and rollers. A piece
/// holds only some of a ghost's facets, or none where Γ3 or Γ1 ends on its ghost layer, and its own
/// data would give the ghost another frame, membership or clamping, and so other unknowns, than its
/// owner does.
GivenBoundary ghost_boundary_from_owners(const Mesh& mesh, const Piece& pc, MPI_Comm comm);

/// What the distributed path leaves for the writers: this rank's piece (the local nodes' u, the
/// local Γ3 nodes' state and statuses, read with the global scales), and the report's reductions.
struct SlabResult {
  Solution piece;                                            ///< u, state and status of the local model
  nlohmann::json status_counts = nlohmann::json::object();   ///< over all ranks
  long gamma3_nodes = 0;                                     ///< over all ranks
  long local_nodes_max = 0;                                  ///< the most nodes a rank holds (ghosts included)
  long ghosts = 0;                                           ///< ghost nodes given rows by their owners (all ranks)
};

/// @brief Solve on the pieces (collective; ssn, or TAO then the polish). @p md is this rank's piece
/// (make_slab, make_block or make_plex_piece, ghost_boundary_from_owners, build_model(scene, mesh,
/// false, ..., &given)); the model is not changed and nothing global is gathered. The judge's
/// residual K x − f is PETSc's product.
/// @param x0 ssn's start in the piece's reduced unknowns (null: zero; --start-follows); refused by TAO
/// @return the scalars of the answer (energies, certificate, verdict; its vectors empty); @p out the piece.
/// @throws Error EXIT_INPUT for what the engine cannot do (a nonlinear material, a piece without a
///         free node, a non-TAO backend), EXIT_NOT_CONVERGED when a Krylov solve outside TAO fails
///         (the message names PETSc's reason, e.g. KSP_DIVERGED_ITS). Collective: every rank throws
///         the same error.
Solution solve_slabs(const Model& md, const Piece& slab, const SolveOptions& opt, MPI_Comm comm, EngineReport& report,
                     SlabResult& out, const Vec* x0 = nullptr);

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
