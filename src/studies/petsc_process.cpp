// The petsc engine for a command that holds the whole model (studies/petsc_process.hpp):
// hemicontact-mpi on one rank with --stream, the effective scene and the model's mesh on its
// stdin, report.json's content and the whole mesh's u back on its stdout, its log passed on
// through this process's; nothing is written to disk.
#include <hemicontact/studies/petsc_process.hpp>

#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/mesh/mesh_bytes.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/engine_choice.hpp>
#include <hemicontact/solver/method_choice.hpp>
#include <hemicontact/solver/solve.hpp>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <cerrno>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace hemicontact {
namespace {

namespace fs = std::filesystem;

// The scene the engine solves: the caller's effective scene with solver.engine = petsc, no
// adaptive refinement (an adaptive caller's loop sends each level's mesh), no files (the stream
// carries the results) and its mesh file's path absolute (the engine reads the scene
// from stdin, with no folder of its own to resolve a relative path from).
nlohmann::json engine_scene(nlohmann::json scene, const std::string& scene_dir) {
  scene["solver"]["engine"] = "petsc";
  scene["adapt"]["target_error"] = nullptr;  // the caller's loop refines; the engine solves one mesh
  for (const char* file : {"vtu", "csv", "plot"}) scene["output"][file] = false;
  nlohmann::json& file = scene["mesh"]["file"];
  if (file.is_string()) file = fs::absolute(scene_path_of(file.get<std::string>(), scene_dir)).string();
  return scene;
}

// A child's pipe end, closed once.
struct Fd {
  int fd = -1;
  ~Fd() { reset(); }
  void reset() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
};

// Write @p text whole to @p fd; false where the reader is gone (EPIPE: the engine stopped before
// it read its scene; its exit code says why). SIGPIPE is held back meanwhile, and a pending one
// taken, so that a stopped engine cannot end this process.
bool write_all(int fd, const std::string& text) {
  sigset_t pipe_set, old;
  sigemptyset(&pipe_set);
  sigaddset(&pipe_set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_set, &old);
  size_t at = 0;
  while (at < text.size()) {
    const ssize_t n = ::write(fd, text.data() + at, text.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    at += static_cast<size_t>(n);
  }
  const timespec none{0, 0};
  while (sigtimedwait(&pipe_set, nullptr, &none) > 0) {
  }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  return at == text.size();
}

struct EngineRun {
  int exit_code = 0;
  std::string out;     // its stdout: the report's line, then u
  std::string errors;  // its error lines ("hemicontact: error: ..."), for this process's message
};

// One line of the engine's stderr, passed on through this process's log (so that the Python
// module's logger gets it too) at the engine's level, without its own clock; its error lines are
// kept for the message of the Error this process throws.
void pass_on(const std::string& line, EngineRun& r) {
  if (line.rfind("hemicontact: ", 0) == 0) {  // "hemicontact: error: why", or an internal error
    const std::string why = line.substr(line.rfind("hemicontact: error: ", 0) == 0 ? 20 : 13);
    r.errors += (r.errors.empty() ? "" : "; ") + why;
    return;
  }
  std::string text = line;
  if (text.size() > 1 && text[0] == '[' && text.find("] ") != std::string::npos) text = text.substr(text.find("] ") + 2);
  if (text.rfind("warning: ", 0) == 0)
    log_warn() << "petsc engine: " << text.substr(9);
  else
    log_info() << "petsc engine: " << text;
}

// The engine's stdout (kept) and stderr (passed on line by line) until both end. Polled every
// 0.1 s for this thread's interrupt check (core/interrupt.hpp: the Python module's Ctrl-C): then
// the engine is stopped (SIGTERM) and Interrupted thrown.
void pump(int out_fd, int err_fd, pid_t pid, EngineRun& r) {
  std::string err_text;
  pollfd fds[2] = {{out_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
  char chunk[1 << 16];
  while (fds[0].fd >= 0 || fds[1].fd >= 0) {
    if (interrupt_requested()) {
      ::kill(pid, SIGTERM);
      int status = 0;
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      throw Interrupted();
    }
    if (::poll(fds, 2, 100) <= 0) continue;  // a timeout or EINTR: poll the interrupt again
    for (int q = 0; q < 2; ++q) {
      if (fds[q].fd < 0 || !(fds[q].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = ::read(fds[q].fd, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) fds[q].fd = -1;
      else (q == 0 ? r.out : err_text).append(chunk, static_cast<size_t>(n));
    }
    for (size_t eol; (eol = err_text.find('\n')) != std::string::npos; err_text.erase(0, eol + 1))
      pass_on(err_text.substr(0, eol), r);
  }
  if (!err_text.empty()) pass_on(err_text, r);
}

// hemicontact-mpi solve - --stream --mesh-follows [--start-follows] [--quiet], @p input (the
// scene's line, [the start,] the mesh) on its stdin, its stdout and stderr read here (pump).
EngineRun run_engine(const std::string& program, const std::string& input, bool start) {
  int in[2], out[2], err[2];
  if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0 || ::pipe2(err, O_CLOEXEC) != 0)
    throw Error(std::string("the petsc engine: no pipe: ") + std::strerror(errno), EXIT_INTERNAL);
  Fd write_in{in[1]}, read_out{out[0]}, read_err{err[0]}, child_in{in[0]}, child_out{out[1]}, child_err{err[1]};
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, in[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&fa, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&fa, err[1], STDERR_FILENO);
  std::vector<std::string> args{program, "solve", "-", "--stream", "--mesh-follows"};
  if (start) args.push_back("--start-follows");
  if (log_level() < LogLevel::INFO) args.push_back("--quiet");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int failed = posix_spawn(&pid, program.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (failed != 0) throw Error("the petsc engine: cannot run " + program + ": " + std::strerror(failed), EXIT_INPUT);
  child_in.reset();
  child_out.reset();
  child_err.reset();
  write_all(write_in.fd, input);
  write_in.reset();
  EngineRun r;
  pump(read_out.fd, read_err.fd, pid, r);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  check_interrupt();  // a Ctrl-C that reached the engine too (one process group) is this process's
  if (WIFSIGNALED(status))
    throw Error("the petsc engine (" + program + ") was ended by signal " + std::to_string(WTERMSIG(status)), EXIT_INTERNAL);
  r.exit_code = WEXITSTATUS(status);
  return r;
}

}  // namespace

PetscProcess::PetscProcess(nlohmann::json scene, const std::string& scene_dir)
    : scene_(engine_scene(std::move(scene), scene_dir)) {}

Solution PetscProcess::operator()(const Model& md, const SolveOptions& opt, const Vec* u_start) const {
  const std::string program = petsc_engine_program();
  log_info() << "petsc engine: " << program << " in one process (--stream), u judged here";
  // The model's own mesh goes with the scene: the engine solves on it, numbered as here (an
  // adaptive level's too, which no scene key describes); the start, where given, before it.
  const bool start = u_start && u_start->size() > 0;
  std::string input = scene_.dump() + "\n";
  if (start) {
    const auto count = static_cast<uint64_t>(u_start->size());
    input.append(reinterpret_cast<const char*>(&count), sizeof count);
    input.append(reinterpret_cast<const char*>(u_start->data()), count * sizeof(double));
  }
  const EngineRun run = run_engine(program, input + mesh_to_bytes(md.mesh), start);
  // 0, 3 (not converged) and 4 (not certified) end with an answer; anything else is an error,
  // whose message the engine's error lines give.
  if (run.exit_code != EXIT_OK && run.exit_code != EXIT_NOT_CONVERGED && run.exit_code != EXIT_CERTIFICATE)
    throw Error("the petsc engine (" + program + ") stopped with exit code " + std::to_string(run.exit_code) + ": " +
                    (run.errors.empty() ? std::string("no message") : run.errors),
                static_cast<ExitCode>(run.exit_code));
  const size_t eol = run.out.find('\n');
  const size_t bytes = static_cast<size_t>(md.mesh.num_nodes()) * static_cast<size_t>(md.dim()) * sizeof(double);
  if (eol == std::string::npos || run.out.size() - eol - 1 != bytes)
    throw Error("the petsc engine's stream is not a report and " + std::to_string(bytes) + " bytes of u (" +
                    std::to_string(run.out.size()) + " bytes came)",
                EXIT_INTERNAL);
  try {
    *report_ = nlohmann::json::parse(run.out.substr(0, eol));
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("the petsc engine's report line is not JSON: ") + e.what(), EXIT_INTERNAL);
  }
  Solution sol;
  read_solve_records(*report_, sol);
  sol.u.resize(md.mesh.num_nodes() * md.dim());
  std::memcpy(sol.u.data(), run.out.data() + eol + 1, bytes);
  sol.x = md.dofs.to_reduced(sol.u);
  for (const auto& [name, seconds] : report_->at("timings").items()) sol.timings["petsc_" + name] = seconds.get<double>();
  evaluate_solution(md, opt, sol);  // this model's judge: certificate, statuses, energies
  if (sol.certificate.passed != report_->at("certificate").at("passed").get<bool>())
    log_warn() << "petsc engine: its certificate " << (sol.certificate.passed ? "failed" : "passed")
               << " where this model's judge says " << (sol.certificate.passed ? "passed" : "failed")
               << " (max residual " << sol.certificate.max_residual << "): this judge's verdict stands";
  return sol;
}

SceneEngine scene_engine(const nlohmann::json& scene, const std::string& scene_dir, bool petsc_available,
                         const std::string& what) {
  const EngineChoice e = choose_engine(scene, scene_dir, petsc_available, false);
  if (e.engine == "petsc" && !petsc_available) {  // given (auto never takes it then)
    const std::string missing = petsc_engine_missing();
    input_error("solver.engine = petsc: " + (missing.empty() ? std::string("the caller runs the cholmod engine only") : missing));
  }
  if (e.engine != "petsc") return [](const Model& md, const SolveOptions& o) { return solve(md, o); };
  log_info() << what << ": the petsc engine (" << e.reason << ")";
  return PetscProcess(scene, scene_dir);
}

AdaptLevelEngine petsc_level_engine(const nlohmann::json& scene, const std::string& scene_dir) {
  return [scene, scene_dir](const Model& md, const SolveOptions& opt, const Solution* previous,
                            const Vec& u_start) -> std::optional<Solution> {
    LevelNumbers n;
    n.dim = md.dim();
    n.unknowns = static_cast<double>(md.dim()) * static_cast<double>(md.mesh.num_nodes());
    if (previous) {
      n.previous_unknowns = static_cast<double>(previous->u.size());
      const auto nnz = previous->method_choice.numbers.find("factor_nnz");
      n.previous_factor_nnz = nnz == previous->method_choice.numbers.end() ? 0 : nnz->second;
      n.previous_petsc = previous->method_choice.chosen == PETSC_ENGINE_METHOD;
    }
    n.memory_bytes = available_memory_bytes();
    const EngineChoice e = choose_level_engine(scene, n, petsc_engine_available());
    log_info() << "adapt: this level's engine " << e.engine << (e.automatic ? " (auto)" : "") << ": " << e.reason;
    if (e.engine != "petsc") return std::nullopt;
    // ssn (the engine's default) starts from the previous level's u, as a level solved here does.
    Solution sol = PetscProcess(scene, scene_dir)(md, opt, petsc_engine_runs_ssn(opt.backend) ? &u_start : nullptr);
    sol.method_choice.chosen = PETSC_ENGINE_METHOD;
    sol.method_choice.automatic = e.automatic;
    sol.method_choice.reason = e.reason;
    return sol;
  };
}

void petsc_minima_starts(const nlohmann::json& scene, const std::string& scene_dir, const SolveOptions& opt,
                         MinimaOptions& mo) {
  const nlohmann::json& loads = scene.at("loads");
  const double scale = loads.contains("scale") ? loads.at("scale").get<double>() : 1.0;
  mo.engine_name = "petsc engine";
  mo.engine = [scene, scene_dir, scale, opt](const Model& scaled, double load_scale, const Vec* u_start) {
    nlohmann::json s = scene;
    s["loads"]["scale"] = scale * load_scale;
    return PetscProcess(s, scene_dir)(scaled, opt, u_start);
  };
}

}  // namespace hemicontact
