// hemicontact-mpi — the petsc engine (solver.engine = "petsc"): `hemicontact solve` execs it with
// its own arguments, on every MPI rank:
//
//   mpirun -np 2 build/hemicontact solve problems/sofonea2017-fig2.json --set solver.engine='"petsc"' --out out/p2
//   mpirun -np 2 build/hemicontact-mpi solve problems/sofonea2017-3d.json --backend tao:bntr --out out/p3d
//
// A program of its own because `hemicontact` links Ipopt, whose MUMPS (Debian's libdmumps_seq)
// defines stub MPI_Init and MPI_Comm_rank that would take the real MPI's place in one process;
// this one links MPI and PETSc and never Ipopt. Same scene keys, same report.json (written once,
// by rank 0, with a "petsc" record added), same exit codes.
//
// Every rank parses the scene. A generated box or rectangle (ssn or TAO) is made per rank, in slabs
// of cell layers (a box on more ranks than layers: in blocks of cell columns), and any other mesh
// (a Gmsh file, a perturbed or crossed one) is made by rank 0 and distributed by DMPlex
// (solver.petsc.mesh = "auto", the default): no rank holds the whole mesh
// (rank 0 frees it once distributed), each writes its own piece of the results, and rank 0 gathers
// only the Γ3 rows for report.json. Rank 0 alone locks the output folder and broadcasts how that
// went, so that the ranks always leave together with one exit code.
#include "cli/cli.hpp"
#include "petsc_engine.hpp"
#include "petsc_slab_output.hpp"

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/process.hpp>
#include <hemicontact/mesh/boundary.hpp>
#include <hemicontact/mesh/mesh_bytes.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/studies/scene_solve.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/scene/slab_mesh.hpp>
#include <hemicontact/solver/engine_choice.hpp>

#include <malloc.h>
#include <petscsys.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <numeric>
#include <string_view>
#include <new>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace {

// report.json's engine_choice (solver/method_choice.hpp): why this engine runs.
nlohmann::json engine_choice;


using namespace hemicontact;

const char* const HELP =
    "usage: hemicontact-mpi solve SCENE.json [--out DIR] [--set path=value]... [--backend ssn|tao:bnls|tao:bntr|tao:bntl]\n"
    "                             [--force] [--quiet] [--plot [--magnification M]]\n"
    "       hemicontact-mpi solve SCENE.json|- --stream [--mesh-follows [--start-follows]] [--set path=value]... [--quiet]\n"
    "The petsc engine of `hemicontact solve` (solver.engine = petsc), normally run through it:\n"
    "  mpirun -np P hemicontact solve SCENE.json --set solver.engine='\"petsc\"' --out DIR\n"
    "Same scene keys, results and exit codes as `hemicontact solve --help` describes; settings of the\n"
    "engine under solver.petsc (docs/scene-format.md). PETSc options: solver.petsc.options or PETSC_OPTIONS.\n"
    "  --stream   write no files: report.json's content as one line on stdout, then the whole mesh's\n"
    "             displacement as raw float64 (native byte order, node-major, the report's node\n"
    "             numbering); PETSc's own printing goes to stderr. For a program that holds the whole\n"
    "             model (`hemicontact converge`, the Python module): it judges u itself. SCENE '-':\n"
    "             the scene's JSON from stdin (its relative paths from the current folder).\n"
    "  --mesh-follows  (one rank, SCENE '-') stdin holds the scene as one line, then the mesh to solve\n"
    "             on (the caller's, mesh/mesh_bytes.hpp) instead of the scene's own.\n"
    "  --start-follows  (with --mesh-follows; ssn) between the scene's line and the mesh, ssn's start:\n"
    "             a uint64 count, then that many float64, the whole mesh's displacement (node-major).\n";

// An error every rank holds, agreed on in a collective step (share, on_every_rank): the ranks can
// leave together through PetscFinalize. Any other error may be one rank's alone while the others
// wait in a collective for it, so main() ends the whole job on it (MPI_Abort).
struct SharedError : Error {
  using Error::Error;
};

// How long a rank other than 0 that met an error waits before it prints the message and ends the
// job itself: where every rank met the same error, rank 0 prints it and aborts first (the message
// once); where only this rank did, rank 0 is waiting in a collective and never will. Each rank
// waits a step longer than the one below it (up to a cap), so that of several failing ranks the
// lowest speaks and its MPI_Abort ends the others before their turn (measured: mpirun's kill takes
// a few ms). At most 2 + 4 s: well inside the 10 s in which every rank must stop after a failure.
constexpr std::chrono::milliseconds OTHER_RANKS_ABORT_GRACE{2000};
constexpr std::chrono::milliseconds ABORT_STAGGER_PER_RANK{100};
constexpr int ABORT_STAGGER_MAX_RANKS = 40;

// Rank 0's outcome of a step only it does (the output folder), shared with every rank: the code
// (0: fine) and the message.
void share(int& code, std::string& message, MPI_Comm comm) {
  MPI_Bcast(&code, 1, MPI_INT, 0, comm);
  int len = static_cast<int>(message.size());
  MPI_Bcast(&len, 1, MPI_INT, 0, comm);
  message.resize(static_cast<size_t>(len));
  if (len > 0) MPI_Bcast(message.data(), len, MPI_CHAR, 0, comm);
}

// The distributed layout for the scene: "slabs" (a generated box or rectangle that the slabs cover),
// "blocks" (a box on more ranks than cell layers, or asked for), "dmplex" (anything else: a Gmsh
// file, a perturbed or crossed mesh, a rectangle on more ranks than cell layers; rank 0 makes the
// whole mesh as build_mesh does and DMPlex distributes it).
std::string distributed_layout(const nlohmann::json& scene, const SolveOptions& opt, MPI_Comm comm) {
  const bool box = scene.at("mesh").at("type") == "box";
  if (opt.petsc.mesh == "blocks") {  // asked for: what blocks cannot make is refused (make_block), not sent elsewhere
    if (!box) input_error("solver.petsc.mesh = \"blocks\": only a generated box is made in blocks (mesh.type = box)");
    return "blocks";
  }
  const std::string refusal = slab_refusal(scene);
  if (!refusal.empty()) {
    log_info() << "petsc: not in slabs: " << refusal;
    return "dmplex";
  }
  int size = 1;
  MPI_Comm_size(comm, &size);
  const SlabCut cut = slab_cut(scene);
  if (cut.layers < size) {
    // Beyond one rank per layer: a box's blocks, made per rank as the slabs are (no rank makes the
    // whole mesh); else rank 0 makes it and DMPlex distributes it.
    if (box && petsc_engine::block_grid(scene.at("mesh").at("nx").get<int>(), scene.at("mesh").at("ny").get<int>(), size).px > 0) {
      log_info() << "petsc: in blocks: " << size << " ranks for " << cut.layers << " cell layers along " << "xyz"[cut.axis];
      return "blocks";
    }
    log_info() << "petsc: not in slabs: " << size << " ranks for " << cut.layers << " cell layers along "
               << "xyz"[cut.axis];
    return "dmplex";
  }
  return "slabs";
}

// A step that may fail on some ranks only (their slab's input checks): the ranks agree on the
// worst code, a failing rank other than 0 prints its own message, and all leave together.
template <class F>
void on_every_rank(MPI_Comm comm, const F& fn) {
  int code = 0, worst = 0, rank = 0;
  std::string message;
  try {
    fn();
  } catch (const Error& e) {
    code = e.code();
    message = e.what();
  }
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, comm);
  if (worst == 0) return;
  MPI_Comm_rank(comm, &rank);
  // Rank 0's message is printed by main(); another rank's only where rank 0 had none (an error
  // every rank met is printed once).
  int code0 = code;
  MPI_Bcast(&code0, 1, MPI_INT, 0, comm);
  if (code != 0 && rank != 0 && code0 == 0) std::fprintf(stderr, "hemicontact: error (rank %d): %s\n", rank, message.c_str());
  throw SharedError(code != 0 ? message : "another rank stopped (its message is above)", static_cast<ExitCode>(worst));
}

// The free (not clamped) nodes on Γ3 facets of a mesh.
long free_gamma3_nodes(const Mesh& mesh) {
  const std::vector<bool> clamped = clamped_nodes(mesh);
  std::vector<Index> on;
  for (Index f = 0; f < mesh.num_facets(); ++f)
    if (mesh.facet_part[static_cast<size_t>(f)] == Part::GAMMA3)
      for (int a = 0; a < mesh.dim; ++a)
        if (!clamped[static_cast<size_t>(mesh.facets(f, a))]) on.push_back(mesh.facets(f, a));
  std::sort(on.begin(), on.end());
  return static_cast<long>(std::unique(on.begin(), on.end()) - on.begin());
}

// --mesh-follows (one rank): the caller's whole mesh as this rank's piece, every node and cell
// owned and numbered as the caller numbers them.
petsc_engine::Piece whole_piece(const Mesh& mesh) {
  petsc_engine::Piece p;
  p.owned_node.assign(static_cast<size_t>(mesh.num_nodes()), 1);
  p.owned_cell.assign(static_cast<size_t>(mesh.num_cells()), 1);
  p.global_node.resize(static_cast<size_t>(mesh.num_nodes()));
  std::iota(p.global_node.begin(), p.global_node.end(), 0L);
  p.owner.assign(static_cast<size_t>(mesh.num_nodes()), 0);
  p.global_nodes = mesh.num_nodes();
  p.global_cells = mesh.num_cells();
  p.layout = "given";
  return p;
}

// The distributed path: each rank makes its piece of the mesh (@p layout: "slabs" of the generated
// mesh, or the Gmsh file distributed by "dmplex") and its model, solves, and writes its piece;
// report.json (rank 0) holds reductions and the gathered Γ3 rows.
int run_slabs(const cli::SceneArgs& a, const std::vector<std::string>& plot_args, const nlohmann::json& scene,
              const SolveOptions& opt, MPI_Comm comm, std::chrono::steady_clock::time_point t0,
              const std::string& layout, bool stream, std::optional<Mesh> given_mesh, const std::optional<Vec>& start) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  log_info() << "petsc: "
             << (given_mesh ? "the caller's mesh, whole" : "the mesh distributed over the ranks (" +
                                                          std::string(layout == "slabs"    ? "slabs of cell layers"
                                                                      : layout == "blocks" ? "blocks of cell columns"
                                                                                           : "DMPlex") + ")")
             << ", " << size << " rank(s)";
  Mesh mesh;
  petsc_engine::Piece slab;
  Model md;
  const auto tm = std::chrono::steady_clock::now();
  on_every_rank(comm, [&] {
    if (given_mesh) {
      mesh = std::move(*given_mesh);
      slab = whole_piece(mesh);
    } else {
      slab = layout == "slabs"    ? petsc_engine::make_slab(scene, comm, mesh)
             : layout == "blocks" ? petsc_engine::make_block(scene, comm, mesh)
                                  : petsc_engine::make_plex_piece(scene, scene_directory(a.scene), comm, mesh);
    }
  });
  const double t_mesh = std::chrono::duration<double>(std::chrono::steady_clock::now() - tm).count();
  // A piece may hold no free Γ3 node where others have some (Γ3 on part of the slabs' cut axis, or
  // away from a part DMPlex made): the model's check that a contact law has Γ3 nodes is then made
  // over the ranks (none anywhere: build_model's own error, on every rank alike).
  long g3 = free_gamma3_nodes(mesh), g3_all = 0;
  MPI_Allreduce(&g3, &g3_all, 1, MPI_LONG, MPI_SUM, comm);
  const GivenBoundary given = petsc_engine::ghost_boundary_from_owners(mesh, slab, comm);
  on_every_rank(comm, [&] {
    md = build_model(scene, std::move(mesh), /*stiffness=*/false, /*piece=*/g3_all > 0, &given);
    md.timings["mesh"] = t_mesh;
  });
  malloc_trim(0);
  log_info() << "piece built: " << md.mesh.num_nodes() << " nodes, memory " << petsc_engine::current_rss_kb() / 1024
             << " MB (rank 0)";
  petsc_engine::EngineReport er;
  er.json["engine_choice"] = engine_choice;
  petsc_engine::SlabResult out;
  // The caller's start (--start-follows, the whole mesh: this rank's piece is all of it) in the
  // model's reduced unknowns.
  const std::optional<Vec> x0 = start ? std::optional(md.dofs.to_reduced(*start)) : std::nullopt;
  Solution sol = petsc_engine::solve_slabs(md, slab, opt, comm, er, out, x0 ? &*x0 : nullptr);
  sol.timings["wall_total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stream) {
    petsc_engine::stream_slab_results(scene, md, slab, sol, out, opt, er, comm);
    return solve_exit_code(sol, opt);
  }
  // The picture reads the pieces (scripts/plot_fig2.py the .pvtu's, plot_status3d.py the CSVs).
  petsc_engine::write_slab_results(a.out, scene, md, slab, sol, out, opt, er, comm,
                                   [&] { cli::draw_solve_picture(a, plot_args, scene, md.dim()); });
  log_info() << "petsc: " << size << " rank(s), " << er.json.value("newton_iterations", 0L) << " Newton and "
             << er.json.value("krylov_iterations", 0L) << " Krylov iterations, peak memory "
             << er.json.value("peak_rss_mb_sum", 0.0) << " MB over the ranks, certificate "
             << sol.certificate.max_residual;
  return solve_exit_code(sol, opt);
}

// The output folder: rank 0 locks it (held until the end, the returned lock) and tells the others
// how that went; a refusal is every rank's error.
std::optional<OutputLock> lock_output(const cli::SceneArgs& a, int rank, MPI_Comm comm) {
  std::optional<OutputLock> lock;
  int code = 0;
  std::string message;
  if (rank == 0) {
    try {
      std::vector<std::string> names = solve_output_names();
      names.push_back("solution.pvtu");
      lock.emplace(prepare_output_dir(a.out, a.force, names, petsc_engine::slab_output_patterns()));
    } catch (const Error& e) {
      code = e.code();
      message = e.what();
    }
  }
  share(code, message, comm);
  if (code != 0) throw SharedError(message, static_cast<ExitCode>(code));
  return lock;
}

// SCENE "-" (--stream): the scene's text from rank 0's stdin, to every rank (collective). Read to
// its end: up to MAX_SCENE_BYTES for a scene alone (one byte more tells "too long"); under
// --mesh-follows (one rank) the caller's mesh and start follow its line, as large as the caller's
// own (an adaptive level of 122k nodes: 17 MB with its start), so no cap but the memory there
// (read_scene caps the scene's line).
std::string scene_from_stdin(MPI_Comm comm, bool mesh_follows) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const size_t cap = mesh_follows ? std::numeric_limits<size_t>::max() / 2 : MAX_SCENE_BYTES;
  std::string text;
  long size = 0;
  if (rank == 0) {
    char chunk[1 << 16];
    for (size_t got; text.size() <= cap && (got = std::fread(chunk, 1, sizeof chunk, stdin)) > 0;)
      text.append(chunk, got);
    size = text.size() > cap ? -1 : static_cast<long>(text.size());
  }
  MPI_Bcast(&size, 1, MPI_LONG, 0, comm);
  if (size < 0) throw SharedError("the scene on stdin is longer than MAX_SCENE_BYTES", EXIT_INPUT);
  text.resize(static_cast<size_t>(size));
  if (size > 0 && ranks > 1) MPI_Bcast(text.data(), static_cast<int>(size), MPI_CHAR, 0, comm);
  return text;
}

// The stream's flags (stream_flags below).
struct StreamFlags {
  bool stream = false, mesh_follows = false, start_follows = false;
  std::vector<std::string> rest;
};

// --start-follows: a uint64 count and that many float64 from the front of @p rest (which then holds
// what follows them).
Vec start_from_bytes(std::string_view& rest) {
  uint64_t count = 0;
  if (rest.size() < sizeof count) throw SharedError("--start-follows: no start after the scene's line", EXIT_INPUT);
  std::memcpy(&count, rest.data(), sizeof count);
  rest.remove_prefix(sizeof count);
  if (count > rest.size() / sizeof(double))
    throw SharedError("--start-follows: a start of " + std::to_string(count) + " values beyond the input's end", EXIT_INPUT);
  Vec u(static_cast<Index>(count));
  if (count > 0) std::memcpy(u.data(), rest.data(), count * sizeof(double));
  rest.remove_prefix(count * sizeof(double));
  return u;
}

// The scene and its options, read by every rank alike: an error in them (a bad key, a non-TAO
// backend) is every rank's and is agreed on, so that the ranks leave together through
// PetscFinalize with the message once, rather than by MPI_Abort.
void read_scene(const cli::SceneArgs& a, const StreamFlags& f, MPI_Comm comm, nlohmann::json& scene, SolveOptions& opt,
                std::optional<Mesh>& given, std::optional<Vec>& start) {
  std::optional<std::string> text = a.scene == "-" ? std::optional(scene_from_stdin(comm, f.mesh_follows)) : std::nullopt;
  if (f.mesh_follows) {  // one rank (stream_flags checked): the scene's line, [the start], then mesh_to_bytes's
    const size_t eol = text->find('\n');
    if (eol == std::string::npos) throw SharedError("--mesh-follows: no mesh after the scene's line on stdin", EXIT_INPUT);
    if (eol > MAX_SCENE_BYTES) throw SharedError("the scene on stdin is longer than MAX_SCENE_BYTES", EXIT_INPUT);
    std::string_view rest = std::string_view(*text).substr(eol + 1);
    if (f.start_follows) start = start_from_bytes(rest);
    given = mesh_from_bytes(rest);
    if (start && start->size() != given->num_nodes() * given->dim)
      throw SharedError("--start-follows: " + std::to_string(start->size()) + " values for a mesh of " +
                            std::to_string(given->num_nodes()) + " nodes in " + std::to_string(given->dim) + "D",
                        EXIT_INPUT);
    text->resize(eol);
  }
  on_every_rank(comm, [&] {
    scene = text ? load_scene_text(*text, "<stdin>", a.overrides) : load_scene(a.scene, a.overrides);
    refuse_adaptive_outside_cholmod(scene);  // as the CLI does before it runs this program
    const EngineChoice ec = choose_engine(scene, scene_directory(a.scene), true, false);
    engine_choice = engine_choice_json(
        ec.engine == "petsc" ? ec
                             : EngineChoice{"petsc", ec.automatic, "hemicontact-mpi is the petsc engine (" + ec.reason + ")"});
    if (scene.at("solver").at("engine").get<std::string>() != "petsc") {
      log_info() << "hemicontact-mpi is the petsc engine: solver.engine = petsc";
      scene["solver"]["engine"] = "petsc";
    }
    opt = solve_options_from_scene(scene);
    petsc_engine::install_error_handler(opt.petsc.options);
    if (!opt.petsc.options.empty()) {
      if (PetscOptionsInsertString(nullptr, opt.petsc.options.c_str()))
        input_error("solver.petsc.options: PETSc could not read '" + opt.petsc.options + "'");
    }
    (void)petsc_engine::tao_type(opt.backend);  // a non-TAO backend is refused before any work
  });
}

// --stream and --mesh-follows, taken out of the command line (the rest for parse_scene_args) and
// checked: --stream writes no files, so what acts on files is refused; the scene '-' (stdin) needs
// it; --mesh-follows (the caller's mesh after the scene's line) needs both, on one rank, and
// --start-follows (ssn's start before that mesh) needs --mesh-follows. Under --stream PETSc's own
// printing goes to stderr: stdout carries the stream alone.
StreamFlags stream_flags(const std::vector<std::string>& args, int ranks) {
  StreamFlags f;
  for (const std::string& s : args) {
    if (s == "--stream") f.stream = true;
    else if (s == "--mesh-follows") f.mesh_follows = true;
    else if (s == "--start-follows") f.start_follows = true;
    else f.rest.push_back(s);
  }
  const bool from_stdin = !f.rest.empty() && f.rest[0] == "-";
  if (f.mesh_follows && (!f.stream || !from_stdin || ranks != 1))
    throw cli::UsageError("--mesh-follows: one rank, with --stream and the scene '-' (stdin)");
  if (f.start_follows && !f.mesh_follows) throw cli::UsageError("--start-follows: with --mesh-follows only");
  if (!f.stream && from_stdin) throw cli::UsageError("the scene '-' (stdin) is read with --stream only");
  for (const char* files : {"--out", "--force", "--plot", "--magnification"})
    if (f.stream && std::find(f.rest.begin(), f.rest.end(), files) != f.rest.end())
      throw cli::UsageError(std::string("--stream writes no files: ") + files + " has nothing to act on");
  if (f.stream) PETSC_STDOUT = stderr;  // -ksp_monitor and the like print here
  return f;
}

int run(const std::vector<std::string>& args, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    if (rank == 0) std::fputs(HELP, args.empty() ? stderr : stdout);
    return args.empty() ? EXIT_USAGE : EXIT_OK;
  }
  if (args[0] != "solve") throw cli::UsageError("hemicontact-mpi runs `solve` only, not '" + args[0] + "'");
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (cli::wants_help(rest)) {
    if (rank == 0) std::fputs(HELP, stdout);
    return EXIT_OK;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const StreamFlags f = stream_flags(rest, size);
  const cli::SceneArgs a = cli::parse_scene_args(f.rest, {"--magnification"});
  // OpenBLAS maps this thread's work buffer at its first BLAS call (PETSc's GAMG, late in the
  // solve) and retries a mapping that fails for ever: under a memory limit one rank spun there
  // while the others waited. Mapped now, or this rank ends the job with the memory message.
  reserve_blas_buffers(1);
  if (a.quiet || rank != 0) set_log_level(LogLevel::WARN);  // one rank reports progress
  const std::vector<std::string> plot_args = cli::solve_plot_args(a);
  nlohmann::json scene;
  SolveOptions opt;
  std::optional<Mesh> given;
  std::optional<Vec> start;
  read_scene(a, f, comm, scene, opt, given, start);

  const std::optional<OutputLock> lock = f.stream ? std::nullopt : lock_output(a, rank, comm);
  const std::string layout = given ? "given" : distributed_layout(scene, opt, comm);
  return run_slabs(a, plot_args, scene, opt, comm, t0, layout, f.stream, std::move(given), start);
}

// The end of a job after an error that may be this rank's alone: the message printed once (rank
// 0's; another rank's only if rank 0 has not ended the job within the grace period), then
// MPI_Abort, which stops every rank; Open MPI's mpirun exits with @p code.
[[noreturn]] void abort_job(int rank, int size, const std::string& line, int code) {
  if (rank != 0 && size > 1)
    std::this_thread::sleep_for(OTHER_RANKS_ABORT_GRACE +
                                ABORT_STAGGER_PER_RANK * std::min(rank, ABORT_STAGGER_MAX_RANKS));
  std::fflush(stdout);
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);  // MPI_Abort does not return; should it, this rank still ends with the code
}

// A process that no launcher started (cli::started_by_mpi_launcher) is an MPI singleton, as
// `hemicontact solve` runs this engine in one process. Open MPI 4.1 then starts a helper daemon
// (orted) and probes UCX's network devices, 0.3 s of a 0.38 s solve of 3D n = 4 on the 2-core
// machine; one process needs neither: ess_singleton_isolated (no daemon: this program never
// spawns processes) and the ob1 messaging layer, which has its "self" transport, cut it to
// 0.07 s. The user's own settings win (setenv's overwrite = 0); other MPIs ignore the variables.
void prefer_a_fast_singleton_start() {
  if (cli::started_by_mpi_launcher()) return;
  ::setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  ::setenv("OMPI_MCA_pml", "ob1", 0);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hemicontact;
  const std::vector<std::string> args(argv + 1, argv + argc);
  prefer_a_fast_singleton_start();
  // PETSc reads its options from PETSC_OPTIONS and solver.petsc.options, never from our command
  // line (whose --set would look like a PETSc option to it).
  if (PetscInitializeNoArguments()) {
    std::fprintf(stderr, "hemicontact-mpi: internal error: PETSc/MPI could not be initialized\n");
    return EXIT_INTERNAL;
  }
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  install_interrupt_handlers();
  // Usage errors (every rank parses the same arguments before any communication) and shared ones
  // are collective: rank 0 prints it and every rank returns the same code. Any other error may be
  // one rank's alone (its piece of the mesh, its memory): abort_job ends every rank.
  int code = EXIT_INTERNAL;
  const std::string where = size > 1 ? " (rank " + std::to_string(rank) + ")" : std::string();
  try {
    code = run(args, PETSC_COMM_WORLD);
  } catch (const cli::UsageError& e) {
    if (rank == 0) std::fprintf(stderr, "hemicontact: %s (see hemicontact solve --help)\n", e.what());
    code = EXIT_USAGE;
  } catch (const SharedError& e) {
    if (rank == 0) std::fprintf(stderr, "hemicontact: error: %s\n", e.what());
    code = e.code();
  } catch (const Error& e) {
    if (size == 1) {
      std::fprintf(stderr, "hemicontact: error: %s\n", e.what());
      code = e.code();
    } else {
      abort_job(rank, size, "hemicontact: error" + where + ": " + e.what() + "\n", e.code());
    }
  } catch (const std::bad_alloc&) {
    // The memory message and code 2 as in `hemicontact`.
    abort_job(rank, size,
              "hemicontact: error" + where + ": " +
                  out_of_memory_message("an allocation of the petsc engine (std::bad_alloc)") + "\n",
              EXIT_INPUT);
  } catch (const std::exception& e) {
    abort_job(rank, size, "hemicontact: internal error" + where + ": " + e.what() + "\n", EXIT_INTERNAL);
  }
  // PetscFinalize stops at its first error (with the engine's error handler it returns it) before
  // MPI_Finalize, and mpirun then reports the rank as "exiting improperly" with exit code 1 after
  // a complete report (-log_view given after PetscInitialize did so).
  if (PetscFinalize() != 0) {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
  }
  return code;
}
