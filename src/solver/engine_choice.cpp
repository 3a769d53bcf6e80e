#include <hemicontact/solver/engine_choice.hpp>

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/mesh/msh_peek.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/adapt.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <vector>

namespace hemicontact {
namespace {

// What auto decides on: the mesh's dimension and unknowns, known before it is made (a generated
// mesh from mesh.nx, ny, nz; a Gmsh file from its header, mesh/msh_peek.hpp), or why not.
struct SceneSize {
  int dim = 0;  // 0: not known before the mesh is made
  double unknowns = 0;
  std::string what;  // "3D box", "3D Gmsh mesh", ... or why the size is unknown
};

SceneSize gmsh_size(const nlohmann::json& mesh, const std::string& scene_dir) {
  if (mesh.at("file").is_null()) return {0, 0, "no mesh.file"};
  const std::optional<MshSize> s = peek_msh_size(scene_path_of(mesh.at("file").get<std::string>(), scene_dir));
  if (!s)
    return {0, 0,
            "a Gmsh file whose header does not give its size (MSH 4.1 has it; MSH 2 needs $PhysicalNames before "
            "$Nodes)"};
  return {s->dim, s->dim * s->nodes, std::to_string(s->dim) + "D Gmsh mesh"};
}

SceneSize scene_size(const nlohmann::json& mesh, const std::string& scene_dir) {
  const auto count = [&](const char* k) { return mesh.at(k).get<double>() + 1; };
  if (mesh.at("type") == "box") return {3, 3 * count("nx") * count("ny") * count("nz"), "3D box"};
  if (mesh.at("type") == "gmsh") return gmsh_size(mesh, scene_dir);
  return {2, 2 * count("nx") * count("ny"), "2D " + mesh.at("type").get<std::string>()};
}

// What the user set that only the cholmod engine has: it wins over the size ("" if nothing).
std::string cholmod_only_setting(const nlohmann::json& scene, bool adaptive) {
  if (adaptive)
    return "adaptive refinement: its loop runs in this process, each level on the engine solve would take for "
           "that level's mesh";
  const std::string backend = scene.at("solver").at("backend").get<std::string>();
  if (backend != "auto" && backend != "ssn" && backend.rfind("tao:", 0) != 0)
    return "solver.backend = " + backend + " runs in the cholmod engine";
  if (scene.at("solver").at("formulation") != "auto") return "solver.formulation is the cholmod engine's (given)";
  if (scene.at("material").at("model") != "linear_elastic") return "a nonlinear material (the petsc engine's ssn needs K)";
  return "";
}

// Where petsc_engine_program looks, in order (the environment's choice apart).
std::vector<std::filesystem::path> petsc_engine_places() {
  std::vector<std::filesystem::path> places;
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) places.push_back(self.parent_path() / "hemicontact-mpi");
#ifdef HEMICONTACT_MPI_BUILD_PATH
  places.emplace_back(HEMICONTACT_MPI_BUILD_PATH);
#endif
#ifdef HEMICONTACT_MPI_INSTALL_PATH
  places.emplace_back(HEMICONTACT_MPI_INSTALL_PATH);
#endif
  return places;
}

}  // namespace

std::string petsc_engine_program() {
  if (const char* given = std::getenv("HEMICONTACT_MPI"); given && *given) return given;
  const std::vector<std::filesystem::path> places = petsc_engine_places();
  std::error_code ec;
  for (const std::filesystem::path& p : places)
    if (std::filesystem::is_regular_file(p, ec)) return p.string();
  return places.empty() ? std::string("hemicontact-mpi") : places.back().string();
}

std::string petsc_engine_missing() {
  if (!HEMICONTACT_HAS_PETSC) return "this build has no petsc engine";
  const std::string program = petsc_engine_program();
  std::error_code ec;
  if (std::filesystem::is_regular_file(program, ec)) return "";
  return "the petsc engine's program " + program + " is not there (build the target hemicontact_mpi, or set HEMICONTACT_MPI)";
}

namespace {

// solver.engine = auto on a mesh of @p size (choose_engine's rule, file comment of the header),
// the petsc engine from solver.method_choice.@p threshold unknowns on.
EngineChoice choose_by_size(const nlohmann::json& scene, const SceneSize& size, bool petsc_built, bool adaptive,
                            const std::string& threshold = "petsc_above") {
  const auto cholmod = [](const std::string& why) { return EngineChoice{"cholmod", true, why}; };
  if (!petsc_built) {
    const std::string missing = petsc_engine_missing();
    return cholmod(missing.empty() ? "this build has no petsc engine" : missing);
  }
  if (size.dim == 0) return cholmod(size.what + ": its size is known only once the mesh is made");
  // In 2D the condensed path is one sparse factorization and a small dense Γ3 problem: faster
  // than the petsc engine at every size measured (docs/performance.md, method choice).
  if (size.dim != 3) return cholmod("a " + size.what + " (2D: the cholmod engine)");
  if (const std::string why = cholmod_only_setting(scene, adaptive); !why.empty()) return cholmod(why);
  const double above = scene.at("solver").at("method_choice").at(threshold).get<double>();
  const std::string desc = size.what + " of " + fmt(size.unknowns, 3) + " unknowns";
  const std::string key = "solver.method_choice." + threshold + " = " + fmt(above, 3);
  if (size.unknowns < above) return cholmod(desc + " < " + key);
  return {"petsc", true,
          desc + " >= " + key +
              ": the petsc engine in one process (ssn, CG + AMG: no factorization, no dense Gamma3 work)"};
}

}  // namespace

EngineChoice choose_engine(const nlohmann::json& scene, const std::string& scene_dir, bool petsc_built,
                           bool adaptive) {
  const std::string asked = scene.at("solver").at("engine").get<std::string>();
  if (asked != "auto") return {asked, false, "solver.engine = " + asked + " (given)"};
  return choose_by_size(scene, scene_size(scene.at("mesh"), scene_dir), petsc_built, adaptive);
}

EngineChoice choose_level_engine(const nlohmann::json& scene, const LevelNumbers& n, bool petsc_built) {
  const std::string asked = scene.at("solver").at("engine").get<std::string>();
  if (asked != "auto") return {asked, false, "solver.engine = " + asked + " (given)"};
  const auto cholmod = [](const std::string& why) { return EngineChoice{"cholmod", true, why}; };
  if (!petsc_built || n.dim != 3) return choose_by_size(scene, {n.dim, n.unknowns, "2D adaptive level"}, petsc_built, false);
  if (const std::string why = cholmod_only_setting(scene, false); !why.empty()) return cholmod(why);
  const std::string petsc = ": the petsc engine in one process (ssn, CG + AMG: no factorization)";
  if (n.previous_unknowns <= 0)  // the scene's own (uniform) mesh: as `solve` would take it
    return choose_by_size(scene, {n.dim, n.unknowns, "3D adaptive level 0 (the scene's mesh)"}, petsc_built, false);
  if (n.previous_petsc) return {"petsc", true, "the previous level went to the petsc engine" + petsc};
  if (n.previous_factor_nnz <= 0) return cholmod("this process (the previous level made no factorization to go by)");
  const double bytes = 8 * n.previous_factor_nnz * std::pow(n.unknowns / n.previous_unknowns, 4.0 / 3.0);
  const double budget = scene.at("solver").at("method_choice").at("memory_fraction").get<double>() * n.memory_bytes;
  const std::string numbers = "the factorization predicted from the previous level's (" + fmt(bytes / 1e9, 3) +
                              " GB) " + (bytes > budget ? ">" : "<=") +
                              " solver.method_choice.memory_fraction of the memory available (" +
                              fmt(budget / 1e9, 3) + " GB)";
  if (n.memory_bytes > 0 && bytes > budget) return {"petsc", true, numbers + petsc};
  return cholmod(numbers + ": this process (faster on graded meshes)");
}

EngineChoice in_process_engine(const nlohmann::json& scene, const std::string& scene_dir, bool petsc_built,
                               const std::string& command) {
  // As `solve` would decide for the same scene, its adaptive refinement included.
  const EngineChoice solve = choose_engine(scene, scene_dir, petsc_built, adapt_requested(scene));
  if (solve.engine != "petsc" || !solve.automatic) return solve;  // a given petsc is refused by the solver
  return {"cholmod", true,
          command + " runs in this process (it needs every field here): the cholmod engine. `hemicontact solve` "
                    "would take the petsc engine: " +
              solve.reason};
}

EngineChoice minima_engine(const nlohmann::json& scene, const std::string& scene_dir, bool petsc_built,
                           bool backends_named, bool barriers) {
  const std::string asked = scene.at("solver").at("engine").get<std::string>();
  const std::string why = backends_named ? "--backends names in-process backends"
                          : barriers     ? "--barriers needs the in-process solver's energy landscape"
                                         : "";
  if (asked == "petsc" && !why.empty()) input_error("minima: solver.engine = petsc, but " + why + "; drop one of them");
  if (asked == "petsc" && !petsc_built) input_error("minima: solver.engine = petsc: " + petsc_engine_missing());
  if (asked != "auto") return {asked, false, "solver.engine = " + asked + " (given)"};
  const EngineChoice c = choose_by_size(scene, scene_size(scene.at("mesh"), scene_dir), petsc_built,
                                        adapt_requested(scene), "petsc_restarts_above");
  if (c.engine != "petsc" || why.empty()) return c;
  return {"cholmod", true, "minima runs in this process (" + why + "); otherwise: " + c.reason};
}

std::string describe(const EngineChoice& c) { return c.engine + (c.automatic ? " (auto): " : ": ") + c.reason; }

void log_engine_choice(const EngineChoice& c) {
  if (c.automatic) log_info() << "engine " << describe(c);
}

nlohmann::json engine_choice_json(const EngineChoice& c) {
  return {{"engine", c.engine}, {"automatic", c.automatic}, {"reason", c.reason}};
}

}  // namespace hemicontact
