#pragma once
/// @file output_dir.hpp  The `--out` directory: created on demand, never silently overwritten.

#include <string>

namespace hemicontact {

/// @brief Make @p dir ready to receive the result files (report.json, solution.vtu, ...).
///
/// Creates the directory and its parents. Results the user already has are not overwritten
/// without asking: a directory that holds a report.json is refused unless @p overwrite. Checks
/// that a file can be created in it, so that a solve is not wasted on an unwritable directory.
/// @param dir       the output directory (the `--out` argument)
/// @param overwrite true when the user passed `--force`
/// @throws Error (EXIT_INPUT): "--out 'x': exists and is not a directory",
///         "--out 'x' already holds results (report.json); pass --force to overwrite",
///         "--out 'x': cannot create directory: ...", "--out 'x': directory is not writable"
void prepare_output_dir(const std::string& dir, bool overwrite);

/// @brief Write @p text to the file @p path (binary mode, replacing it), or fail naming the file.
/// @throws Error (EXIT_INPUT): "cannot write 'path'" or "cannot write 'path' (disk full?)"
void write_text_file(const std::string& path, const std::string& text);

}  // namespace hemicontact
