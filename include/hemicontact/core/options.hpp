#pragma once
/// @file options.hpp  Command-line values shared by the programs: `hemicontact` (src/cli), the
/// petsc engine's hemicontact-mpi and the bench programs check their options and end on an error
/// with the same words and exit codes (README: 1 usage, 2 bad input, 5 internal).

#include <functional>
#include <string>
#include <vector>

namespace hemicontact {

/// @return @p value of option @p key as an integer in [lo, hi]
/// @throws Error (EXIT_USAGE) "KEY: expected an integer from LO to HI, got 'VALUE'" otherwise
///         (not a number, trailing text, out of range: never std::stoi's abort)
long parse_integer_option(const std::string& key, const std::string& value, long lo, long hi);

/// @return @p value of option @p key as a positive finite number
/// @throws Error (EXIT_USAGE) "KEY: expected a positive number, got 'VALUE'" otherwise
double parse_positive_option(const std::string& key, const std::string& value);

/// @return @p text as one word of a POSIX shell command: unchanged when it holds only characters
/// the shell takes literally, else in single quotes (a recorded command reruns as written).
std::string shell_quote(const std::string& text);

/// @return the words of @p argv joined by spaces, each shell_quote'd.
std::string shell_command(const std::vector<std::string>& argv);

/// @brief Run a program's body and turn what it throws into the documented exit codes with a
/// message naming @p program: Error: "PROGRAM: error: MESSAGE" and its code; std::bad_alloc: the
/// memory message, EXIT_INPUT; any other exception: "PROGRAM: internal error: ...", EXIT_INTERNAL.
/// @return the body's exit code, or the error's
int run_program(const std::string& program, const std::function<int()>& body);

}  // namespace hemicontact
