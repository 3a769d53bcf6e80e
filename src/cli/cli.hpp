#pragma once
// Command-line front end: argument parsing and the commands (private to the program).

#include <hemicontact/studies/scene_solve.hpp>
#include <hemicontact/output/solve_files.hpp>
#include <hemicontact/problem/minima_report.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/problem/solution.hpp>
#include <hemicontact/problem/solve_options.hpp>

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace hemicontact::cli {

/// A malformed command line (exit code 1).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Parsed common options of the commands that take a scene.
struct SceneArgs {
  std::string scene;                                       ///< SCENE.json
  std::string out;                                         ///< --out DIR (default: out/<scene stem>)
  std::vector<std::string> overrides;                      ///< --set path=value, in order; --backend NAME adds one
  bool force = false;                                      ///< --force: overwrite existing results
  bool quiet = false;                                      ///< --quiet: warnings only on stderr
  bool plot = false;                                       ///< --plot: also write pictures
  std::vector<std::pair<std::string, std::string>> extra;  ///< command-specific --key value pairs
};

/// Parse `SCENE [--out DIR] [--set k=v]... [--backend NAME] [--force] [--quiet] [--plot]`;
/// @p extra_keys lists command-specific options that take a value.
SceneArgs parse_scene_args(const std::vector<std::string>& args, const std::vector<std::string>& extra_keys = {});

/// @return the overview printed by `hemicontact --help`.
std::string usage();
/// @return the help of one command (`hemicontact COMMAND --help`): usage, options with defaults,
/// an example; the overview for an unknown command.
std::string command_help(const std::string& command);
/// Refuse (Error, EXIT_USAGE) to run @p command ("solve", "converge", "minima") on the cholmod
/// engine as one of several MPI ranks (mpirun -np N: OMPI_COMM_WORLD_SIZE or PMI_SIZE > 1), with
/// the hint to use solver.engine = petsc.
void refuse_mpi_ranks(const std::string& command);
/// @return true when an MPI launcher (mpirun, mpiexec, srun) started this process, false for a
/// process started alone (an MPI singleton).
bool started_by_mpi_launcher();
/// @return true when @p args (a command's arguments) ask for its help (-h or --help anywhere).
bool wants_help(const std::vector<std::string>& args);
std::string version();
int cmd_solve(const std::vector<std::string>& args);
/// solver.engine = petsc: run hemicontact-mpi (beside this program) on the same `solve` arguments in
/// this process's place; returns only by throwing (no PETSc in this build: EXIT_INPUT naming it).
int exec_petsc_engine(const std::vector<std::string>& args);
/// The plotting script's arguments of `solve` (its --magnification checked). @throws UsageError
std::vector<std::string> solve_plot_args(const SceneArgs& a);
/// Write @p r's files (write_scene_solve), the summary on stdout, the picture (--plot) and
/// @p report as report.json into the locked folder a.out.
void write_solve_results(const SceneArgs& a, const std::vector<std::string>& plot_args, const SceneSolve& r,
                         const nlohmann::json& report);
/// With --plot or output.plot: draw the solve's picture into a.out (2D fig2.png from the VTU, 3D
/// status3d.png from the Γ3 CSV; the petsc engine's slabs: from their pieces) and list it in the
/// folder's manifest; a picture that could not be drawn is a warning, not an error.
void draw_solve_picture(const SceneArgs& a, const std::vector<std::string>& plot_args, const nlohmann::json& scene,
                        int dim);
/// The options every scene command takes (args.cpp), for the commands' help texts; the defaults
/// it states come from the scene schema.
std::string scene_options_help();
/// Defaults of the study commands' own options, written once: the parsers start from them and the
/// help texts print them.
inline constexpr const char* CONVERGE_LEVELS = "4,8,...,128";  ///< the paper's Fig. 3 levels
inline constexpr const char* CONVERGE_REFERENCE = "256";       ///< the paper's reference h = 1/256
inline constexpr const char* ADAPTIVE_LEVELS = "4,8,...,64";   ///< uniform and graded levels of --adaptive
/// Most random starts `minima --starts` takes (problem/minima_report.hpp says why).
inline constexpr long MAX_STARTS = MINIMA_MAX_STARTS;
int cmd_backends(const std::vector<std::string>& args);
/// `converge SCENE --levels L1,L2,... --reference R`: mesh-convergence study (src/cli/converge.cpp).
int cmd_converge(const std::vector<std::string>& args);
/// `minima SCENE [--starts N] [--seed S] [--backends a,b]`: distinct solutions from many starts (src/cli/minima_command.cpp).
int cmd_minima(const std::vector<std::string>& args);
/// `path SCENE --load 0,2,0 [--steps N]`: a quasi-static load history (src/cli/path_command.cpp).
int cmd_path(const std::vector<std::string>& args);
/// @return `hemicontact path --help` (src/cli/path_command.cpp).
std::string path_help();

/// @brief Run scripts/@p script with /usr/bin/python3 (or $HEMICONTACT_PYTHON) and @p args
/// (src/cli/plot.cpp). The script is looked up in $HEMICONTACT_SCRIPTS, the installed
/// share/hemicontact/scripts, the source tree's scripts/ (configure time), then scripts/ above the
/// executable.
/// @return the script's exit code (0: picture written); non-zero after a message on stderr when
///         python3, the script or matplotlib is missing
/// @param picture the file the script writes: when it is a link, FIFO or other non-regular file
///        (planted during the run) the script is not run, so that it cannot write through it
int run_plot_script(const std::string& script, const std::vector<std::string>& args, const std::string& picture);

/// @brief Refuse (EXIT_INPUT) a scene file name that is not UTF-8 where @p result (a JSON file)
/// records it: JSON text is UTF-8, and the result could not be written at the end.
void require_utf8_scene_name(const std::string& scene, const std::string& result);

}  // namespace hemicontact::cli
