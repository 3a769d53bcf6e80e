#pragma once
/// @file output_dir.hpp  The `--out` folder: created on demand, never silently overwritten, and
/// replaced as a whole by --force.
///
/// Every file a run writes is listed in the folder's manifest, OUTPUT_MANIFEST (one plain file
/// name per line), as it is written (write_text_file, record_output_file), so that even an
/// interrupted run's files are known. --force removes exactly the files the manifest lists (and
/// report.json), never anything else; a file of the user's with the name of one this run would
/// write is refused, --force or not.

#include <string>
#include <vector>

namespace hemicontact {

/// The manifest's name in an output folder.
inline constexpr const char* OUTPUT_MANIFEST = ".hemicontact-files";

/// @brief Make @p dir ready to receive a run's result files.
///
/// Creates the folder and its parents. A folder that holds results (report.json or a manifest)
/// is refused unless @p overwrite; with it, the files the manifest lists and report.json are
/// removed first. Every name in @p will_write that exists must be one of ours (listed in the
/// manifest, or report.json). Starts an empty manifest, which also proves the folder writable.
/// @param dir        the output folder (the `--out` argument)
/// @param overwrite  true when the user passed `--force`
/// @param will_write the file names this run will write (checked before any work is done)
/// @throws Error (EXIT_INPUT): "--out 'x': exists and is not a directory", "--out 'x' already holds
///         results ...; pass --force to replace them", "--out 'x': 'f' exists and was not written by
///         hemicontact ...", "--out 'x': cannot create directory: ...", "--out 'x': directory is not
///         writable"
void prepare_output_dir(const std::string& dir, bool overwrite, const std::vector<std::string>& will_write = {});

/// @return the plain file names listed in @p dir's manifest (none if it has none), in order.
std::vector<std::string> output_files(const std::string& dir);

/// @brief List the file @p path in its folder's manifest (once), if that folder has one (a
/// folder prepared by prepare_output_dir); for files written by other programs (the pictures).
void record_output_file(const std::string& path);

/// @brief Write @p text to the file @p path (binary mode, replacing it), or fail naming the file;
/// recorded in the folder's manifest when it has one.
/// @throws Error (EXIT_INPUT): "cannot write 'path'" or "cannot write 'path' (disk full?)"
void write_text_file(const std::string& path, const std::string& text);

}  // namespace hemicontact
