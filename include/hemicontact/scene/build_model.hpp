#pragma once
/// @file build_model.hpp  From an effective scene (scene/config.hpp: loaded, validated, defaults
/// injected) to the Model every stage reads, and to the options of its solve.

#include <hemicontact/mesh/mesh.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <utility>

namespace hemicontact {

/// Build the mesh of a scene (generator or Gmsh file) and tag its boundary parts.
/// @param scene effective scene; @param scene_dir directory that relative paths are taken from.
Mesh build_mesh(const nlohmann::json& scene, const std::string& scene_dir);

/// Check the cells and tag the boundary parts of @p mesh from the scene's "boundary" selectors
/// (and scale the tractions by loads.scale).
void assign_scene_boundary(Mesh& mesh, const nlohmann::json& scene);

/// Build the model from an effective scene and a mesh whose boundary parts are already assigned
/// (assign_scene_boundary); the scene's "mesh" block is then not read. Used by tests and studies.
/// @param stiffness false: K_x is not assembled (the petsc engine assembles each rank's own rows
/// into PETSc, whose product gives the judge its residual K x − f).
/// @param piece true: @p mesh is one rank's piece of a distributed mesh (the petsc engine's), which
/// may hold no Γ3 node although the whole mesh has some: the check that a contact law has Γ3 nodes
/// is then the caller's, over the ranks.
/// @param given a piece's ghost nodes' boundary data from their owners (Γ3 sums, clamping,
/// rollers), or null.
Model build_model(const nlohmann::json& scene, Mesh mesh, bool stiffness = true, bool piece = false,
                  const GivenBoundary* given = nullptr);

/// @brief Estimated peak memory (bytes) of a default solve on a mesh of @p nodes nodes in
/// dimension @p dim with @p gamma3_nodes Γ3 nodes: estimate_sparse_memory + dense_gamma3_memory.
double estimate_solve_memory(double nodes, int dim, double gamma3_nodes = 0);

/// @brief The sparse part of estimate_solve_memory (fitted to measured runs: see build_model.cpp).
double estimate_sparse_memory(double nodes, int dim);

/// @brief The dense part of estimate_solve_memory: the condensed Γ3 matrices, O((d·Γ3 nodes)²).
double dense_gamma3_memory(double gamma3_nodes, int dim);

/// Bytes this process may still allocate (-1: nothing known) and the limit that sets it, in words.
struct MemoryBudget {
  double bytes = -1;
  std::string limit;
};

/// @brief The smallest of: the machine's MemAvailable; RLIMIT_AS (ulimit -v) less the address
/// space already mapped; RLIMIT_DATA (ulimit -d) less the data in use; the cgroup's limit
/// (v2 memory.max, v1 memory.limit_in_bytes, of the process's group and the groups above it) less
/// its usage (without the inactive page cache, which the kernel reclaims first).
MemoryBudget memory_budget();

/// @brief The cgroup part of memory_budget(), read below @p root ("" = the real /proc and /sys;
/// tests pass a folder laid out like them).
MemoryBudget cgroup_memory_budget(const std::string& root);

/// @brief Refuse (Error, EXIT_INPUT) a solve that would need more memory than this process may
/// use (memory_budget(): MemAvailable, ulimit -v, the cgroup limit), naming the estimate, what is
/// available and what limits it, and @p size_keys, the keys that set the size ("mesh.n = 1000000").
/// Called before a generated mesh is allocated, and again once Γ3 is known.
/// @param petsc the estimate of the petsc engine (no factorization) instead of the cholmod engine's.
/// @param gamma3_nodes Γ3 nodes (the cholmod engine's dense condensed matrices); 0 before the mesh exists.
void check_memory(double nodes, int dim, const std::string& size_keys, bool petsc = false, double gamma3_nodes = 0);

/// @return @p need and @p have bytes as GB texts with as many significant digits (2 to 6) as it
/// takes for them to differ, for a memory refusal ("needs about 1.14 GB ... 1.12 GB are available").
std::pair<std::string, std::string> distinct_gigabytes(double need, double have);

/// @brief Estimated peak memory (bytes, all ranks) of the petsc engine on @p nodes nodes.
double estimate_petsc_memory(double nodes, int dim);

/// Build the whole model from an effective (validated) scene.
/// @throws Error naming the key for every semantic input problem (no Γ1, negative g, ν ≥ 0.5, ...).
Model build_model(const nlohmann::json& scene, const std::string& scene_dir, bool stiffness = true);

/// @return the options of an effective scene.
SolveOptions solve_options_from_scene(const nlohmann::json& scene);

}  // namespace hemicontact
