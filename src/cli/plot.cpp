// Pictures: the CLI runs the Python scripts in scripts/ (Debian's /usr/bin/python3 with
// python3-matplotlib) rather than linking a plotting library. A script is looked up, in order, in
//   1. $HEMICONTACT_SCRIPTS (a directory; set it to use modified scripts),
//   2. the installed copy, <exe dir>/../share/hemicontact/scripts (cmake --install),
//   3. the source tree the program was built from (HEMICONTACT_SCRIPTS_DIR, baked in at configure
//      time, so a build folder anywhere finds them),
//   4. scripts/ in the parent directories of the executable (a moved source tree with its build).
// HEMICONTACT_PYTHON replaces /usr/bin/python3 (tests use it to exercise the "no matplotlib" path).
#include "cli.hpp"

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/text.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <sys/wait.h>
#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace hemicontact::cli {
namespace {

namespace fs = std::filesystem;

const char* const INSTALL_HINT = "Debian: apt-get install python3-matplotlib";

// The script's path, or "" after printing why it was not found.
std::string find_script(const std::string& script) {
  if (const char* env = std::getenv("HEMICONTACT_SCRIPTS"); env && *env) {
    const fs::path p = fs::path(env) / script;
    if (fs::is_regular_file(p)) return p.string();
    std::fprintf(stderr, "hemicontact: --plot: %s not found (HEMICONTACT_SCRIPTS=%s)\n", p.c_str(), env);
    return "";
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> dirs;
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "share" / "hemicontact" / "scripts");
  dirs.push_back(HEMICONTACT_SCRIPTS_DIR);
  if (!ec)
    for (fs::path dir = exe.parent_path(); !dir.empty(); dir = dir.parent_path()) {
      dirs.push_back(dir / "scripts");
      if (dir == dir.root_path()) break;
    }
  for (const fs::path& dir : dirs) {
    std::error_code missing;
    if (fs::is_regular_file(dir / script, missing)) return (dir / script).string();
  }
  std::fprintf(stderr,
               "hemicontact: --plot: cannot find %s in the installed share/hemicontact/scripts, in %s, or in a "
               "scripts/ directory above the executable %s; set HEMICONTACT_SCRIPTS to a directory holding it\n",
               script.c_str(), HEMICONTACT_SCRIPTS_DIR, ec ? "(unknown)" : exe.c_str());
  return "";
}

}  // namespace

int run_plot_script(const std::string& script, const std::vector<std::string>& args, const std::string& picture) {
  // The script renames its temporary over the picture (scripts/plotutil.py): a link, FIFO or
  // folder planted under either name since the folder was checked is refused here.
  const fs::path pic(picture);
  for (const fs::path& p : {pic, pic.parent_path() / partial_name(pic.filename().string())})
    if (const std::string kind = non_regular_kind(p.string()); !kind.empty()) {
      std::fprintf(stderr, "hemicontact: --plot: '%s' is %s, not a regular file; the picture is not drawn (remove it)\n",
                   printable(p.string()).c_str(), kind.c_str());
      return EXIT_INPUT;
    }
  // Listed in the folder's manifest before the script creates its temporary (as write_text_file
  // lists its files): a run killed while the script draws leaves .NAME.partial, which the --force
  // rerun then removes as this run's, instead of refusing it as a file of someone else's.
  record_output_file(picture);
  const char* env_python = std::getenv("HEMICONTACT_PYTHON");
  const std::string python = env_python && *env_python ? env_python : "/usr/bin/python3";
  if (::access(python.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "hemicontact: --plot needs %s with matplotlib (%s): %s not found\n", python.c_str(),
                 INSTALL_HINT, python.c_str());
    return EXIT_INPUT;
  }
  const std::string path = find_script(script);
  if (path.empty()) return EXIT_INPUT;

  std::vector<std::string> argv_s{python, path};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : argv_s) argv.push_back(s.data());
  argv.push_back(nullptr);

  std::fflush(nullptr);  // or the child would inherit (and print again) our buffered output
  const pid_t pid = ::fork();
  if (pid < 0) {
    std::fprintf(stderr, "hemicontact: --plot: fork failed: %s\n", std::strerror(errno));
    return EXIT_INTERNAL;
  }
  if (pid == 0) {
    ::execv(python.c_str(), argv.data());
    std::fprintf(stderr, "hemicontact: --plot: cannot run %s: %s\n", python.c_str(), std::strerror(errno));
    ::_exit(127);
  }
  // SIGINT/SIGTERM while it draws end it too (output_dir.cpp's handler): no plotting process
  // left running after this one is gone.
  set_interrupt_child(static_cast<int>(pid));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      set_interrupt_child(0);
      return EXIT_INTERNAL;
    }
  set_interrupt_child(0);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  // The scripts exit with 2 when matplotlib is missing, after saying so themselves.
  if (code != 0)
    std::fprintf(stderr, "hemicontact: --plot: %s %s failed (exit code %d)\n", python.c_str(), path.c_str(), code);
  return code;
}

}  // namespace hemicontact::cli
