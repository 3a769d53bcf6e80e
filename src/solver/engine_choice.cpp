#include <hemicontact/solver/engine_choice.hpp>

#include <hemicontact/core/format.hpp>

namespace hemicontact {

EngineChoice choose_engine(const nlohmann::json& scene, bool petsc_built, bool adaptive) {
  const std::string asked = scene.at("solver").at("engine").get<std::string>();
  if (asked != "auto") return {asked, false, "solver.engine = " + asked + " (given)"};
  const auto cholmod = [](const std::string& why) { return EngineChoice{"cholmod", true, why}; };
  if (!petsc_built) return cholmod("this build has no petsc engine");
  const nlohmann::json& mesh = scene.at("mesh");
  if (mesh.at("type") != "box") return cholmod("not a generated 3D box (its size is known only once the mesh is made)");
  if (adaptive) return cholmod("adaptive refinement runs in the cholmod engine");
  // What the user set that only the cholmod engine has wins over the size.
  const std::string backend = scene.at("solver").at("backend").get<std::string>();
  if (backend != "auto" && backend != "ssn" && backend.rfind("tao:", 0) != 0)
    return cholmod("solver.backend = " + backend + " runs in the cholmod engine");
  if (scene.at("solver").at("formulation") != "auto") return cholmod("solver.formulation is the cholmod engine's (given)");
  if (scene.at("material").at("model") != "linear_elastic") return cholmod("a nonlinear material (the petsc engine's ssn needs K)");
  const double unknowns = 3.0 * (mesh.at("nx").get<double>() + 1) * (mesh.at("ny").get<double>() + 1) *
                          (mesh.at("nz").get<double>() + 1);
  const double above = scene.at("solver").at("method_choice").at("petsc_above").get<double>();
  const std::string size = fmt(unknowns, 3) + " unknowns";
  if (unknowns < above) return cholmod("3D box of " + size + " < solver.method_choice.petsc_above = " + fmt(above, 3));
  return {"petsc", true,
          "3D box of " + size + " >= solver.method_choice.petsc_above = " + fmt(above, 3) +
              ": the petsc engine in one process (ssn, CG + AMG: no factorization, no dense Gamma3 work)"};
}

nlohmann::json engine_choice_json(const EngineChoice& c) {
  return {{"engine", c.engine}, {"automatic", c.automatic}, {"reason", c.reason}};
}

}  // namespace hemicontact
