#pragma once
/// @file cli_runner.hpp  Running the built `hemicontact` program from tests: stdout/stderr captured
/// in files of a scratch directory, exit code decoded. Shared by the tests/cli/*_test.cpp files.

#include <sys/wait.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace hemicontact::test {

/// What one run of the program did.
struct CliOutcome {
  int code = -1;    ///< exit code (-1 if killed by a signal)
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// @return the whole text of file @p p (empty if missing).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// @return the lines of @p text.
inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> r;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) r.push_back(l);
  return r;
}

/// @return true if Debian's python3 can import matplotlib (picture tests skip otherwise).
/// The files a ParaView collection (.pvd) lists, in order (its DataSet file="..." attributes).
inline std::vector<std::string> pvd_files(const std::filesystem::path& pvd) {
  std::vector<std::string> files;
  const std::string text = slurp(pvd);
  for (size_t p = text.find("file=\""); p != std::string::npos; p = text.find("file=\"", p + 1)) {
    const size_t b = p + 6;
    files.push_back(text.substr(b, text.find('"', b) - b));
  }
  return files;
}

inline bool matplotlib_available() {
  return std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") == 0;
}

/// Run `hemicontact ARGS` (with optional leading environment assignments @p env) in the folder
/// @p dir, capturing its output in @p dir/out.txt and @p dir/err.txt. The working folder is the
/// test's own: a run without --out writes out/<scene> there, not into a folder that tests running
/// in parallel (ctest -j) share and whose output lock they would contend for.
inline CliOutcome run_cli(const std::filesystem::path& dir, const std::string& args, const std::string& env = "") {
  const std::string cmd = "cd '" + dir.string() + "' && " + env + " " + std::string(HEMICONTACT_CLI_PATH) + " " +
                          args + " >" + (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string();
  const int status = std::system(cmd.c_str());
  CliOutcome r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(dir / "out.txt");
  r.err = slurp(dir / "err.txt");
  return r;
}

}  // namespace hemicontact::test
