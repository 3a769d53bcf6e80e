#pragma once
/// @file output_dir.hpp  The `--out` folder: created on demand, never silently overwritten, and
/// replaced as a whole by --force.
///
/// Every file a run writes is listed in the folder's manifest, OUTPUT_MANIFEST (one plain file
/// name per line), as it is written (write_text_file, record_output_file), so that even an
/// interrupted run's files are known. --force removes exactly the files the manifest lists (and
/// report.json), never anything else; a file of the user's with the name of one this run would
/// write is refused, --force or not.
///
/// Safety of a run's results (issue 12):
/// - one run at a time: prepare_output_dir takes an exclusive lock (flock on OUTPUT_LOCK) that the
///   returned OutputLock holds until the run ends; a second run into the same folder is refused;
/// - every file is written atomically: to a temporary name beside it (".NAME.partial"), flushed
///   and synced, then renamed, so a reader never sees half a file; the marker that the set is
///   complete (report.json, convergence.json, minima.json) is written last;
/// - a failed write (disk full, permissions, a file-size limit) throws Error(EXIT_OUTPUT) naming
///   the file and leaves neither the temporary nor a report;
/// - SIGINT/SIGTERM (install_interrupt_handlers) remove the temporary being written and say which
///   files of the set were kept, then end the process as the signal would have.

#include <string>
#include <vector>

namespace hemicontact {

/// The manifest's name in an output folder.
inline constexpr const char* OUTPUT_MANIFEST = ".hemicontact-files";

/// The lock file of an output folder: held (flock, exclusive) by the run writing there. It stays
/// behind when the run ends (removing it would race with the next run taking it) and is empty
/// but for the holder's process id.
inline constexpr const char* OUTPUT_LOCK = ".hemicontact-lock";

/// The exclusive lock of an output folder for the life of this object (move-only). The kernel
/// releases it when the process ends, however it ends.
class OutputLock {
 public:
  OutputLock() = default;
  explicit OutputLock(int fd) : m_fd(fd) {}
  OutputLock(OutputLock&& o) noexcept : m_fd(o.m_fd) { o.m_fd = -1; }
  OutputLock& operator=(OutputLock&& o) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();
  /// @return true while the lock is held.
  bool held() const { return m_fd >= 0; }

 private:
  int m_fd = -1;
};

/// @brief Make @p dir ready to receive a run's result files.
///
/// Creates the folder and its parents and locks it (OUTPUT_LOCK) for as long as the returned
/// object lives: the caller keeps it for the whole run. A folder that holds results (report.json or a manifest)
/// is refused unless @p overwrite; with it, the files the manifest lists and report.json are
/// removed first. Every name in @p will_write that exists must be one of ours (listed in the
/// manifest, or report.json). Starts an empty manifest, which also proves the folder writable.
/// @param dir        the output folder (the `--out` argument)
/// @param overwrite  true when the user passed `--force`
/// @param will_write the file names this run will write (checked before any work is done)
/// @return the folder's lock
/// @throws Error (EXIT_INPUT): "--out 'x': another hemicontact run (pid N) is writing there ...",
///         "--out 'x': exists and is not a directory", "--out 'x' already holds
///         results ...; pass --force to replace them", "--out 'x': 'f' exists and was not written by
///         hemicontact ...", "--out 'x': cannot create directory: ..." (a path that cannot be a
///         folder); Error (EXIT_OUTPUT): "--out 'x': directory is not writable (reason)", "cannot
///         create directory" for want of permission or space
OutputLock prepare_output_dir(const std::string& dir, bool overwrite, const std::vector<std::string>& will_write = {});

/// @return the plain file names listed in @p dir's manifest (none if it has none), in order.
std::vector<std::string> output_files(const std::string& dir);

/// @brief List the file @p path in its folder's manifest (once), if that folder has one (a
/// folder prepared by prepare_output_dir); for files written by other programs (the pictures).
void record_output_file(const std::string& path);

/// @brief Write @p text to the file @p path atomically (file comment: a temporary beside it, synced,
/// then renamed over @p path), or fail naming the file; recorded in the folder's manifest (before
/// the temporary is created, so that --force can clean up after a crash) when it has one.
/// @throws Error (EXIT_OUTPUT): "cannot write 'path': <reason>" (No space left on device,
///         Permission denied, File too large, ...); the temporary is removed and @p path untouched
void write_text_file(const std::string& path, const std::string& text);

/// @brief The temporary name write_text_file uses for @p name: ".NAME.partial" in the same folder.
std::string partial_name(const std::string& name);

/// @brief Install SIGINT/SIGTERM handlers (the CLI does, once): on a signal, remove the temporary
/// file being written, print which files of the current output folder were completed (and that
/// the set is incomplete), then end with the signal's default action (the shell's 130/143).
void install_interrupt_handlers();

}  // namespace hemicontact
