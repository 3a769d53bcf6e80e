#pragma once
/// @file material_factory.hpp  The elasticity law F of a scene's "material" block.

#include <hemicontact/material/material.hpp>

#include <nlohmann/json.hpp>

#include <memory>

namespace hemicontact {

/// Build the material of an effective (validated) scene's "material" block for a mesh of
/// dimension @p dim: model = linear_elastic (plane stress/strain in 2D, 3D) or hencky (plane
/// strain in 2D, 3D; hencky.hpp).
/// @throws Error naming the key: out-of-range constants, material.plane = stress with hencky,
/// hencky-only keys set for linear_elastic, hencky keys missing.
std::shared_ptr<const Material> make_material(const nlohmann::json& material, int dim);

}  // namespace hemicontact
