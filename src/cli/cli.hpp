#pragma once
// Command-line front end: argument parsing and the commands (private to the program).

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
  std::string scene;                   ///< SCENE.json
  std::string out;                     ///< --out DIR (default: out/<scene stem>)
  std::vector<std::string> overrides;  ///< --set path=value, in order; --backend NAME adds one
  bool force = false;                  ///< --force: overwrite existing results
  bool quiet = false;                  ///< --quiet: warnings only on stderr
  bool plot = false;                   ///< --plot: also write pictures
  std::vector<std::pair<std::string, std::string>> extra;  ///< command-specific --key value pairs
};

/// Parse `SCENE [--out DIR] [--set k=v]... [--backend NAME] [--force] [--quiet] [--plot]`;
/// @p extra_keys lists command-specific options that take a value.
SceneArgs parse_scene_args(const std::vector<std::string>& args, const std::vector<std::string>& extra_keys = {});

std::string usage();
std::string version();
int cmd_solve(const std::vector<std::string>& args);
int cmd_backends(const std::vector<std::string>& args);

}  // namespace hemicontact::cli
