// The arguments of the scene commands (solve, converge, minima), apart from cli.cpp so that the
// PETSc engine's executable (hemicontact-mpi, src/petsc/) parses them with the same code.
#include "cli.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/text.hpp>
#include <hemicontact/scene/config.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace hemicontact::cli {

// Options every scene command takes (parse_scene_args).
std::string scene_options_help() {
  return "  --out DIR          output folder (default shown above); created if missing\n"
         "  --set path=value   override a scene entry by its dotted path, value in JSON (repeatable),\n"
         "                     e.g. --set mesh.n=128 --set solver.tol=1e-10; every key: docs/scene-format.md\n"
         "  --backend NAME     the same as --set solver.backend=NAME (default: the scene's, else " +
         schema_default("solver.backend").get<std::string>() +
         ");\n"
         "                     hemicontact backends lists them\n"
         "  --force            replace the results of an earlier run in DIR (only the files it wrote)\n"
         "  --quiet            warnings only on stderr (progress is on stderr by default)\n"
         "  -h, --help         this help\n";
}

// The ranks' count an MPI launcher sets: Open MPI's mpirun OMPI_COMM_WORLD_SIZE; MPICH, Intel MPI
// and Slurm's srun PMI_SIZE.
constexpr const char* MPI_SIZE_VARIABLES[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"};

bool started_by_mpi_launcher() {
  for (const char* var : MPI_SIZE_VARIABLES)
    if (std::getenv(var)) return true;
  return std::getenv("PMIX_RANK") || std::getenv("PMI_RANK");  // PMIx and PMI launchers' ranks
}

void refuse_mpi_ranks(const std::string& command) {
  for (const char* var : MPI_SIZE_VARIABLES) {
    const char* v = std::getenv(var);
    if (v == nullptr) continue;
    char* end = nullptr;
    const long ranks = std::strtol(v, &end, 10);
    if (end == v || ranks <= 1) continue;
    // Every rank would run the whole command on its own and race the others for --out.
    throw Error(command + ": this process is one of " + std::to_string(ranks) + " MPI ranks (" + var + " = " + v +
                    "), but the default engine (solver.engine = cholmod) runs in one process: every rank would "
                    "solve the same scene and write the same --out. Run it without mpirun, or, for `solve`, use the "
                    "distributed engine: mpirun -np N hemicontact solve SCENE --set solver.engine='\"petsc\"'",
                EXIT_USAGE);
  }
}

bool wants_help(const std::vector<std::string>& args) {
  // Options that take a value: their value is never a request for help (--set description=-h).
  static const std::vector<std::string> with_value = {
      "--out",  "--set", "--backend",  "--magnification", "--levels",          "--reference", "--starts",
      "--seed", "--box", "--backends", "--start",         "--load-path-steps", "--group-tol",
      "--graded-levels", "--graded-power"};
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "-h" || args[i] == "--help") return true;
    if (std::find(with_value.begin(), with_value.end(), args[i]) != with_value.end()) ++i;
  }
  return false;
}

void require_utf8_scene_name(const std::string& scene, const std::string& result) {
  if (invalid_utf8_at(scene) == std::string::npos) return;
  input_error("scene file name '" + printable(scene) + "' is not valid UTF-8 (" + describe_invalid_utf8(scene) +
              "): " + result + " records it, and JSON text is UTF-8; rename the file (or link it under a UTF-8 name)");
}

SceneArgs parse_scene_args(const std::vector<std::string>& args, const std::vector<std::string>& extra_keys) {
  SceneArgs a;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& s = args[i];
    // A value that is empty where a name is expected, or that is the next option ("--out --quiet"),
    // is the user forgetting the value: never taken as a path.
    const auto value = [&]() -> std::string {
      if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0)
        throw UsageError("option " + s + " needs a value");
      return args[++i];
    };
    if (s == "--out") {
      a.out = value();
      if (a.out.empty()) throw UsageError("--out: empty folder name");
    } else if (s == "--set")
      a.overrides.push_back(value());
    else if (s == "--backend")
      a.overrides.push_back("solver.backend=" + value());
    else if (s == "--force")
      a.force = true;
    else if (s == "--quiet")
      a.quiet = true;
    else if (s == "--plot")
      a.plot = true;
    else if (s.rfind("--", 0) == 0 && std::find(extra_keys.begin(), extra_keys.end(), s) != extra_keys.end())
      a.extra.emplace_back(s, value());
    else if (s.rfind("--", 0) == 0)
      throw UsageError("unknown option " + s);
    else if (a.scene.empty())
      a.scene = s;
    else
      throw UsageError("unexpected argument '" + s + "'");
  }
  if (a.scene.empty()) throw UsageError("missing SCENE.json");
  if (a.out.empty()) a.out = "out/" + std::filesystem::path(a.scene).stem().string();
  return a;
}

}  // namespace hemicontact::cli
