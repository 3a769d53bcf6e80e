#pragma once
/// @file build_model.hpp  From an effective scene (scene/config.hpp: loaded, validated, defaults
/// injected) to the Model every stage reads, and to the options of its solve.

#include <hemicontact/mesh/mesh.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <nlohmann/json.hpp>

#include <string>

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
/// into PETSc and sets Model::Kx_apply; issue 16).
Model build_model(const nlohmann::json& scene, Mesh mesh, bool stiffness = true);

/// @brief Estimated peak memory (bytes) of a default solve on a mesh of @p nodes nodes in
/// dimension @p dim (fitted to measured runs: see build_model.cpp).
double estimate_solve_memory(double nodes, int dim);

/// @brief Refuse (Error, EXIT_INPUT) a mesh whose solve would need more memory than the machine
/// has available (MemAvailable), naming the estimate, what is available and @p size_keys, the
/// keys that set the size ("mesh.n = 1000000"). Called before a generated mesh is allocated.
/// @param petsc the estimate of the petsc engine (no factorization) instead of the cholmod engine's.
void check_memory(double nodes, int dim, const std::string& size_keys, bool petsc = false);

/// @brief Estimated peak memory (bytes, all ranks) of the petsc engine on @p nodes nodes.
double estimate_petsc_memory(double nodes, int dim);

/// Build the whole model from an effective (validated) scene.
/// @throws Error naming the key for every semantic input problem (no Γ1, negative g, ν ≥ 0.5, ...).
Model build_model(const nlohmann::json& scene, const std::string& scene_dir, bool stiffness = true);

/// @return the options of an effective scene.
SolveOptions solve_options_from_scene(const nlohmann::json& scene);

}  // namespace hemicontact
