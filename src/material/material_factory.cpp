#include <hemicontact/material/material_factory.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/material/hencky.hpp>
#include <hemicontact/material/linear_elastic.hpp>

namespace hemicontact {

std::shared_ptr<const Material> make_material(const nlohmann::json& mat, int dim) {
  const std::string model = mat.at("model").get<std::string>();
  const double E = mat.at("E").get<double>(), nu = mat.at("nu").get<double>();
  const bool strain = mat.at("plane") == "strain";
  // A 3D body is full 3D elasticity: `plane` is a 2D reduction. Its default ("stress") is ignored
  // for a 3D mesh; an explicit "strain" on a 3D mesh is a contradiction and rejected.
  if (dim == 3 && strain)
    input_error(
        "material.plane: 'strain' is a 2D reduction, but the mesh is 3D (3D elasticity is used): "
        "remove material.plane");
  if (model == "linear_elastic") {
    // The nonlinear law's constants are null by default; set for a linear law they would be ignored.
    for (const char* k : {"shear_ratio", "eps_ref"})
      if (mat.contains(k) && !mat.at(k).is_null())
        input_error(std::string("material.") + k + ": only used by material.model = hencky (model is linear_elastic)");
    const PlaneMode mode = dim == 3 ? PlaneMode::NONE_3D : (strain ? PlaneMode::STRAIN : PlaneMode::STRESS);
    return std::make_shared<LinearElastic>(E, nu, mode);
  }
  if (model == "hencky") {
    // Plane stress for a nonlinear law needs σ33(ε) = 0 solved for ε33 at every evaluation.
    if (dim == 2 && !strain)
      input_error(
          "material.plane = stress: the hencky law is implemented for plane strain and 3D only "
          "(plane stress would need a local solve for eps_33); set material.plane = \"strain\"");
    for (const char* k : {"shear_ratio", "eps_ref"})
      if (!mat.contains(k) || mat.at(k).is_null())
        input_error(std::string("material.") + k + ": required for material.model = hencky");
    return std::make_shared<Hencky>(
        Hencky::from_young(E, nu, mat.at("shear_ratio").get<double>(), mat.at("eps_ref").get<double>(), dim));
  }
  input_error("material.model: unknown model '" + model + "' (linear_elastic, hencky)");
}

}  // namespace hemicontact
