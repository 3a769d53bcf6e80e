// The petsc engine for a command that holds the whole model (studies/petsc_process.hpp):
// hemicontact-mpi on one rank with --stream, the effective scene on its stdin, report.json's
// content and the whole mesh's u back on its stdout; nothing is written to disk.
#include <hemicontact/studies/petsc_process.hpp>

#include <hemicontact/check/evaluate.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/engine_choice.hpp>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <cerrno>
#include <fcntl.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace hemicontact {
namespace {

namespace fs = std::filesystem;

// The scene the engine solves: the caller's effective scene with solver.engine = petsc, no files
// (the stream carries the results) and its mesh file's path absolute (the engine reads the scene
// from stdin, with no folder of its own to resolve a relative path from).
nlohmann::json engine_scene(nlohmann::json scene, const std::string& scene_dir) {
  scene["solver"]["engine"] = "petsc";
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

std::string read_all(int fd) {
  std::string out;
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    out.append(chunk, static_cast<size_t>(n));
  }
  return out;
}

struct EngineRun {
  int exit_code = 0;
  std::string out;  // its stdout: the report's line, then u
};

// hemicontact-mpi solve - --stream [--quiet], @p scene on its stdin; its stderr is this process's
// (its progress and messages reach the user as they come).
EngineRun run_engine(const std::string& program, const std::string& scene) {
  int in[2], out[2];
  if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0)
    throw Error(std::string("the petsc engine: no pipe: ") + std::strerror(errno), EXIT_INTERNAL);
  Fd write_in{in[1]}, read_out{out[0]}, child_in{in[0]}, child_out{out[1]};
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, in[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&fa, out[1], STDOUT_FILENO);
  std::vector<std::string> args{program, "solve", "-", "--stream"};
  if (log_level() < LogLevel::INFO) args.push_back("--quiet");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int err = posix_spawn(&pid, program.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (err != 0)
    throw Error("the petsc engine: cannot run " + program + ": " + std::strerror(err) + " (build the target hemicontact_mpi)",
                EXIT_INPUT);
  child_in.reset();
  child_out.reset();
  write_all(write_in.fd, scene);
  write_in.reset();
  EngineRun r;
  r.out = read_all(read_out.fd);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status))
    throw Error("the petsc engine (" + program + ") was ended by signal " + std::to_string(WTERMSIG(status)), EXIT_INTERNAL);
  r.exit_code = WEXITSTATUS(status);
  return r;
}

}  // namespace

PetscProcess::PetscProcess(nlohmann::json scene, const std::string& scene_dir)
    : scene_(engine_scene(std::move(scene), scene_dir)) {}

Solution PetscProcess::operator()(const Model& md, const SolveOptions& opt) const {
  const std::string program = petsc_engine_program();
  log_info() << "petsc engine: " << program << " in one process (--stream), u judged here";
  const EngineRun run = run_engine(program, scene_.dump());
  // 0, 3 (not converged) and 4 (not certified) end with an answer; anything else is an error
  // whose message the engine printed on stderr.
  if (run.exit_code != EXIT_OK && run.exit_code != EXIT_NOT_CONVERGED && run.exit_code != EXIT_CERTIFICATE)
    throw Error("the petsc engine (" + program + ") stopped with exit code " + std::to_string(run.exit_code) +
                    " (its message is above)",
                static_cast<ExitCode>(run.exit_code));
  const size_t eol = run.out.find('\n');
  const size_t bytes = static_cast<size_t>(md.mesh.num_nodes()) * static_cast<size_t>(md.dim()) * sizeof(double);
  if (eol == std::string::npos || run.out.size() - eol - 1 != bytes)
    throw Error("the petsc engine's stream is not a report and " + std::to_string(bytes) + " bytes of u (" +
                    std::to_string(run.out.size()) + " bytes came)",
                EXIT_INTERNAL);
  *report_ = nlohmann::json::parse(run.out.substr(0, eol));
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

}  // namespace hemicontact
