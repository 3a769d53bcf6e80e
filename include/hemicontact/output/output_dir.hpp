#pragma once
/// @file output_dir.hpp  The `--out` folder: created on demand, never silently overwritten, and
/// replaced as a whole by --force.
///
/// Every file a run writes is listed in the folder's manifest, OUTPUT_MANIFEST (its first line
/// OUTPUT_MANIFEST_SIGNATURE, then one plain file name per line), as it is written
/// (write_text_file, record_output_file), so that even an interrupted run's files are known.
/// --force removes exactly the files a manifest with that signature lists, never anything else: a
/// report.json, or a manifest without the signature, proves nothing about who wrote a file. A file
/// of the user's with the name of one this run would write is refused before any work is done,
/// --force or not.
///
/// The folder is reached through one directory handle, so that nothing planted in it can redirect
/// or hang a run: every file in it is opened, created, renamed and removed relative to that handle,
/// never through a symbolic link (O_NOFOLLOW, fstatat without following), and only regular files
/// are read or written; a symbolic link, FIFO, device or folder under a name the run uses is
/// refused with a message naming it (a FIFO would hang the run, a link would redirect its writes).
/// The --out path itself may be a link to a folder: that is the user's choice of place.
///
/// Safety of a run's results (neither a second run, a full disk nor a kill may leave a half file):
/// - one run at a time: prepare_output_dir takes an exclusive lock (flock on OUTPUT_LOCK) that the
///   returned OutputLock holds until the run ends; a second run into the same folder is refused;
/// - every file is written atomically: to a temporary name beside it (".NAME.partial", created
///   exclusively), flushed and synced, then renamed, so a reader never sees half a file; the marker
///   that the set is complete (report.json, convergence.json, minima.json) is written last;
/// - a failed write (disk full, permissions, a file-size limit) throws Error(EXIT_OUTPUT) naming
///   the file and leaves neither the temporary nor a report;
/// - SIGINT/SIGTERM (install_interrupt_handlers) remove the temporary being written, pass the
///   signal on to a plotting process, and say which files of the set were kept, then end the
///   process as the signal would have.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace hemicontact {

/// The manifest's name in an output folder.
inline constexpr const char* OUTPUT_MANIFEST = ".hemicontact-files";

/// The first line of a manifest written by hemicontact. A manifest without it (another program's,
/// an older version's, a user's) lists nothing that --force may remove.
inline constexpr const char* OUTPUT_MANIFEST_SIGNATURE = "# hemicontact output manifest, format 1";

/// The most bytes a manifest may have (a run writes a few dozen names): a larger file is not one.
inline constexpr std::size_t MAX_MANIFEST_BYTES = 1 << 20;

/// Files a run writes whose names carry a number: PREFIX, decimal digits, SUFFIX (level_16.vtu,
/// solution_3.vtu), when how many is known only at the end. prepare_output_dir checks every entry
/// of the folder that has such a name (or is its temporary).
struct OutputNamePattern {
  std::string prefix, suffix;
};

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
/// Creates the folder and its parents, opens the folder's handle (kept for the writers below) and
/// locks it (OUTPUT_LOCK) for as long as the returned object lives: the caller keeps it for the
/// whole run. A folder whose manifest lists files still there (results, complete or not) is
/// refused unless @p overwrite; with it, those files (regular files only) and their temporaries
/// are removed first. Every name in @p will_write, and every entry matching @p patterns, that
/// exists (or whose temporary exists) must be a regular file listed in the manifest. Starts an
/// empty manifest, which also proves the folder writable.
/// @param dir        the output folder (the `--out` argument)
/// @param overwrite  true when the user passed `--force`
/// @param will_write the file names this run will write (checked before any work is done)
/// @param patterns   the numbered names this run may write (checked likewise)
/// @return the folder's lock
/// @throws Error (EXIT_INPUT): "--out 'x': another hemicontact run (pid N) is writing there ...",
///         "--out 'x': exists and is not a directory", "--out 'x' is a symbolic link to 'y', which
///         does not exist ...", "--out 'x' already holds results ...; pass --force to replace
///         them", "--out 'x': 'f' exists and was not written by hemicontact ...", "--out 'x':
///         'f' is a symbolic link (a FIFO, ...), not a file hemicontact wrote ...", "--out 'x':
///         .hemicontact-files is not a file list written by hemicontact ...", "--out 'x': cannot
///         create directory: ..."; Error (EXIT_OUTPUT): "--out 'x': directory is not writable
///         (reason)", "the lock file 'x/.hemicontact-lock' cannot be opened ...", "cannot create
///         directory" for want of permission or space
OutputLock prepare_output_dir(const std::string& dir, bool overwrite, const std::vector<std::string>& will_write = {},
                              const std::vector<OutputNamePattern>& patterns = {});

/// @return the names a manifest's text lists, in order and once each, keeping only plain file
/// names of the folder itself (no '/', ".", "..", the manifest, the lock, control characters);
/// std::nullopt when the text is not a hemicontact manifest (no OUTPUT_MANIFEST_SIGNATURE line
/// first, or longer than MAX_MANIFEST_BYTES).
std::optional<std::vector<std::string>> parse_manifest(const std::string& text);

/// @return true when @p name is a name a manifest may list and the tool may write, remove or
/// rename: a plain file name in the folder itself (see parse_manifest).
bool plain_output_name(const std::string& name);

/// @return "" when @p path does not exist or is a regular file (without following a final
/// symbolic link), else what it is ("a symbolic link", "a FIFO", "a directory", "a device", "a
/// socket"): a name the tool must not write through (the pictures, written by another program).
std::string non_regular_kind(const std::string& path);

/// @brief Pass SIGINT/SIGTERM on to the child process @p pid (a plotting script) while it runs;
/// 0 when there is none. The interrupt handler signals it before ending this process.
void set_interrupt_child(int pid);

/// @return the plain file names listed in @p dir's manifest (none if it has none or it is not a
/// hemicontact manifest), in order.
std::vector<std::string> output_files(const std::string& dir);

/// @brief List the file @p path in its folder's manifest (once), if that folder has one (a
/// folder prepared by prepare_output_dir); for files written by other programs (the pictures).
void record_output_file(const std::string& path);

/// @brief Write @p text to the file @p path atomically (file comment: a temporary beside it, created
/// exclusively and without following links, synced, then renamed over @p path, all relative to the
/// folder's handle), or fail naming the file; recorded in the folder's manifest (before the
/// temporary is created, so that --force can clean up after a crash) when it has one.
/// @throws Error (EXIT_OUTPUT): "cannot write 'path': <reason>" (No space left on device,
///         Permission denied, File too large, its temporary exists already, ...); the temporary
///         (when this call created it) is removed and @p path untouched
void write_text_file(const std::string& path, const std::string& text);

/// @brief The temporary name write_text_file uses for @p name: ".NAME.partial" in the same folder.
std::string partial_name(const std::string& name);

/// @brief Install SIGINT/SIGTERM handlers (the CLI does, once): on a signal, remove the temporary
/// file being written, print which files of the current output folder were completed (and that
/// the set is incomplete), then end with the signal's default action (the shell's 130/143).
void install_interrupt_handlers();

}  // namespace hemicontact
