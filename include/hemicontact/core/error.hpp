#pragma once
/// @file error.hpp  Error type and exit codes shared by the library and the CLI.

#include <stdexcept>
#include <string>

namespace hemicontact {

/// Process exit codes of the `hemicontact` program (documented in README.md).
enum ExitCode : int {
  EXIT_OK = 0,             ///< solved, certificate passed
  EXIT_USAGE = 1,          ///< bad command line
  EXIT_INPUT = 2,          ///< bad input: scene, mesh, parameters, output directory; or too big for the memory
  EXIT_NOT_CONVERGED = 3,  ///< a solver or the outer fixed point did not converge; a requested target not met
  EXIT_CERTIFICATE = 4,    ///< converged, but the certificate (docs/model.md §4) failed
  EXIT_INTERNAL = 5,       ///< anything else (a bug)
  EXIT_OUTPUT = 6          ///< the results could not be written (disk full, permissions, file-size limit)
};

/// An error with a one-line message that names what is wrong, and the exit code it maps to.
class Error : public std::runtime_error {
 public:
  /// @param message one line naming the problem (e.g. "mesh: no Γ1 (clamped) facets")
  /// @param code    exit code the CLI returns for it
  explicit Error(const std::string& message, ExitCode code = EXIT_INPUT) : std::runtime_error(message), m_code(code) {}
  /// @return the exit code for this error.
  ExitCode code() const { return m_code; }

 private:
  ExitCode m_code;
};

/// Input error (exit code 2). @param message names the offending key, element or value.
[[noreturn]] inline void input_error(const std::string& message) { throw Error(message, EXIT_INPUT); }

/// The one wording of "an allocation failed" (CHOLMOD's out-of-memory status, std::bad_alloc):
/// a problem too big for the memory this process may use is an input problem (exit code 2, as
/// the memory estimate's refusal before the solve), never a crash or an "internal error".
/// @param what what ran out, e.g. "the sparse Cholesky factorization of K (525 312 unknowns)".
inline std::string out_of_memory_message(const std::string& what) {
  return "out of memory in " + what +
         "; solve a smaller problem (mesh.n, mesh.nx, ..., or fewer Γ3 nodes) or allow more memory "
         "(ulimit -v, the cgroup's memory.max)";
}
/// @copydoc out_of_memory_message
[[noreturn]] inline void memory_error(const std::string& what) { throw Error(out_of_memory_message(what), EXIT_INPUT); }

}  // namespace hemicontact
