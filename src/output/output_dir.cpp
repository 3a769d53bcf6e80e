#include <hemicontact/output/output_dir.hpp>

#include <hemicontact/core/error.hpp>
#include <hemicontact/core/text.hpp>

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <system_error>

namespace hemicontact {

namespace fs = std::filesystem;

namespace {

// Flags of every open in an output folder: never through a final symbolic link, and never
// blocking (a FIFO opened for writing without a reader, or for reading, would hang the run; it is
// refused by the fstat that follows instead).
constexpr int SAFE_OPEN = O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC;

// What the interrupt handler needs, prepared outside it: a signal handler may only call
// async-signal-safe functions (unlinkat, kill, write, signal, raise), so the temporary being
// written (its folder's descriptor and its name) and the message naming the kept files are plain
// buffers, each double-buffered behind an atomic index so that a signal taken (on any thread)
// while one is updated reads the other, complete one.
constexpr size_t BUFFER = 8192;
char g_partial[2][BUFFER];  // the temporary being written, relative to g_partial_fd ("" when none)
int g_partial_fd[2] = {-1, -1};
char g_message[2][BUFFER];  // "hemicontact: interrupted ..." for the current output folder
// The message once the file being renamed into place is there, prepared before the rename: a
// signal between the rename and the rebuilt g_message names that file as kept (the handler tells
// the two moments apart by whether the temporary still exists).
char g_message_renamed[BUFFER];
std::atomic<bool> g_renaming{false};
std::atomic<int> g_partial_index{0};
std::atomic<int> g_message_index{-1};  // −1: no output folder prepared yet
std::atomic<int> g_child{0};           // a plotting process to pass the signal on to (0: none)
std::string g_dir;                     // the output folder of this run (prepare_output_dir)
int g_dir_fd = -1;                     // its handle, open for the rest of the process

void copy_to(char (&buffer)[BUFFER], const std::string& text) {
  const size_t n = std::min(text.size(), BUFFER - 1);
  std::memcpy(buffer, text.data(), n);
  buffer[n] = '\0';
}

void set_partial(int dir_fd, const std::string& name) {
  const int next = 1 - g_partial_index.load();
  copy_to(g_partial[next], name);
  g_partial_fd[next] = dir_fd;
  g_partial_index.store(next);
}

extern "C" void on_interrupt(int sig) {
  const int child = g_child.load();
  if (child > 0) ::kill(child, sig);  // the plotting script ends with us, not after us
  const int i = g_partial_index.load();
  // Renamed already: the temporary is gone (or no longer named), its file is whole and in place.
  const bool renamed = g_renaming.load() && (g_partial[i][0] == '\0' ||
                                             ::faccessat(g_partial_fd[i], g_partial[i], F_OK, AT_SYMLINK_NOFOLLOW) != 0);
  if (g_partial[i][0] != '\0') ::unlinkat(g_partial_fd[i], g_partial[i], 0);
  const int m = g_message_index.load();
  if (m >= 0) {
    const char* msg = renamed ? g_message_renamed : g_message[m];
    size_t n = 0;
    while (msg[n] != '\0') ++n;
    if (::write(STDERR_FILENO, msg, n) < 0) {
      // nothing more can be done about it in a signal handler
    }
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// Errors of the file system that are about the output (space, permissions, a read-only mount, a
// file-size limit), as opposed to a bad --out path: exit code EXIT_OUTPUT.
ExitCode output_code(int err) {
  switch (err) {
    case EACCES:
    case EPERM:
    case EROFS:
    case ENOSPC:
    case EDQUOT:
    case EIO:
    case EFBIG:
      return EXIT_OUTPUT;
    default:
      return EXIT_INPUT;
  }
}

// What an entry of a folder is, without following a final link: NONE (absent), REGULAR, or
// something the tool never reads or writes (kind_text names it).
enum class Entry { NONE, REGULAR, OTHER };

std::string kind_text(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

Entry entry_at(int dir_fd, const std::string& name, std::string* kind = nullptr) {
  struct stat st {};
  if (::fstatat(dir_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) return Entry::NONE;
  if (S_ISREG(st.st_mode)) return Entry::REGULAR;
  if (kind) *kind = kind_text(st.st_mode);
  return Entry::OTHER;
}

// A descriptor closed when it goes out of scope (the folder handles opened for one call).
struct Fd {
  int fd = -1;
  Fd() = default;
  explicit Fd(int f) : fd(f) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// "a" and "a/" and "./a" are one folder: the writers name files as (fs::path(out) / name).
std::string folder_key(const std::string& dir) {
  std::string k = fs::path(dir.empty() ? "." : dir).lexically_normal().string();
  while (k.size() > 1 && k.back() == '/') k.pop_back();
  return k;
}

// The handle of the folder holding @p path: the prepared folder's own when it is that folder,
// else one opened for this call (owned by @p scratch). −1 with errno set when it cannot be opened.
int folder_of(const fs::path& path, Fd& scratch) {
  const std::string parent = path.parent_path().empty() ? "." : path.parent_path().string();
  if (g_dir_fd >= 0 && folder_key(parent) == folder_key(g_dir)) return g_dir_fd;
  scratch.fd = ::open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  return scratch.fd;
}

// The manifest of the folder @p dir_fd: absent, ours (the names it lists), or foreign (why).
struct Manifest {
  bool present = false;
  std::optional<std::vector<std::string>> names;  // nullopt when present but not ours
  std::string why_foreign;
};

Manifest read_manifest(int dir_fd) {
  Manifest m;
  const int fd = ::openat(dir_fd, OUTPUT_MANIFEST, O_RDONLY | SAFE_OPEN);
  if (fd < 0) {
    if (errno == ENOENT) return m;
    m.present = true;
    m.why_foreign = errno == ELOOP ? "it is a symbolic link" : std::string("it cannot be read: ") + std::strerror(errno);
    return m;
  }
  const Fd guard(fd);
  m.present = true;
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    m.why_foreign = "it is " + kind_text(st.st_mode);
    return m;
  }
  std::string text;
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      m.why_foreign = std::string("it cannot be read: ") + std::strerror(errno);
      return m;
    }
    if (n == 0) break;
    text.append(buf, static_cast<size_t>(n));
    if (text.size() > MAX_MANIFEST_BYTES) break;  // not a manifest: no need to read on
  }
  m.names = parse_manifest(text);
  if (!m.names)
    m.why_foreign = text.size() > MAX_MANIFEST_BYTES ? "it is larger than any file list hemicontact writes"
                                                    : std::string("its first line is not '") +
                                                          OUTPUT_MANIFEST_SIGNATURE + "'";
  return m;
}

// The names the manifest of @p dir_fd lists when it is ours, else none.
std::vector<std::string> listed_names(int dir_fd) {
  Manifest m = read_manifest(dir_fd);
  return m.names ? std::move(*m.names) : std::vector<std::string>{};
}

// The interrupt message from the folder's manifest: the files listed there that exist are complete
// (a file is renamed into place only when fully written), and @p renaming, about to be.
std::string interrupt_message(const std::string& renaming = "") {
  std::string kept;
  for (const std::string& f : listed_names(g_dir_fd))
    if (f == renaming || entry_at(g_dir_fd, f) == Entry::REGULAR) kept += (kept.empty() ? "" : ", ") + f;
  std::string text = "hemicontact: interrupted: the results in '" + printable(g_dir) + "' are incomplete (" +
                     (kept.empty() ? std::string("nothing was written yet") : "kept: " + kept + ", each file whole") +
                     "); rerun with --force to replace them\n";
  if (text.size() >= BUFFER) text = text.substr(0, BUFFER - 5) + "...\n";
  return text;
}

// Rebuild the interrupt message (after each file of the output folder is in place).
void update_interrupt_message() {
  if (g_dir.empty() || g_dir_fd < 0) return;
  const int next = g_message_index.load() == 0 ? 1 : 0;
  copy_to(g_message[next], interrupt_message());
  g_message_index.store(next);
}

// Whether @p name is PREFIX digits SUFFIX of @p p.
bool matches(const std::string& name, const OutputNamePattern& p) {
  if (name.size() <= p.prefix.size() + p.suffix.size()) return false;
  if (name.compare(0, p.prefix.size(), p.prefix) != 0) return false;
  if (name.compare(name.size() - p.suffix.size(), p.suffix.size(), p.suffix) != 0) return false;
  const size_t b = p.prefix.size(), e = name.size() - p.suffix.size();
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(b), name.begin() + static_cast<std::ptrdiff_t>(e),
                     [](unsigned char c) { return std::isdigit(c); });
}

// The entries of the folder @p dir_fd with a name of @p patterns, or the temporary of one (as the
// name itself): the numbered files this run may write over.
std::vector<std::string> numbered_entries(int dir_fd, const std::vector<OutputNamePattern>& patterns) {
  std::vector<std::string> found;
  if (patterns.empty()) return found;
  const int fd = ::openat(dir_fd, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return found;
  DIR* d = ::fdopendir(fd);
  if (!d) {
    ::close(fd);
    return found;
  }
  const std::string tail = ".partial";
  while (const dirent* e = ::readdir(d)) {
    std::string name = e->d_name;
    if (name.size() > 1 + tail.size() && name[0] == '.' && name.compare(name.size() - tail.size(), tail.size(), tail) == 0)
      name = name.substr(1, name.size() - 1 - tail.size());
    for (const OutputNamePattern& p : patterns)
      if (matches(name, p) && std::find(found.begin(), found.end(), name) == found.end()) found.push_back(name);
  }
  ::closedir(d);
  return found;
}

// Take the folder's lock, or say who holds it. flock (not fcntl) locks: they belong to the open
// file description, so a second prepare in the same process is refused as well, and they are
// released by the kernel however the holder ends.
OutputLock lock_output_dir(int dir_fd, const std::string& dir, const std::string& name) {
  const std::string file = (fs::path(dir) / OUTPUT_LOCK).string();
  const int fd = ::openat(dir_fd, OUTPUT_LOCK, O_RDWR | O_CREAT | SAFE_OPEN, 0666);
  if (fd < 0) {
    const int err = errno;
    std::string kind;
    const Entry there = entry_at(dir_fd, OUTPUT_LOCK, &kind);
    if (there == Entry::OTHER || err == ELOOP)
      input_error(name + ": the lock file '" + printable(file) + "' is " + (kind.empty() ? "a symbolic link" : kind) +
                  ", not a regular file: remove it (no hemicontact run uses it) or choose another --out");
    if (there == Entry::REGULAR)
      throw Error(name + ": the lock file '" + printable(file) + "' cannot be opened (" + std::strerror(err) +
                      "): a stale lock of another user or of a run with other permissions; if no hemicontact run "
                      "is writing there, remove it, or choose another --out",
                  output_code(err));
    throw Error(name + ": directory is not writable (cannot create '" + printable(file) + "': " + std::strerror(err) +
                    ")",
                output_code(err));
  }
  OutputLock lock(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
    input_error(name + ": the lock file '" + printable(file) + "' is " + kind_text(st.st_mode) +
                ", not a regular file: remove it (no hemicontact run uses it) or choose another --out");
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    char pid[32] = {0};
    const ssize_t n = ::pread(fd, pid, sizeof pid - 1, 0);
    std::string holder = n > 0 ? std::string(pid, static_cast<size_t>(n)) : std::string();
    holder.erase(std::remove(holder.begin(), holder.end(), '\n'), holder.end());
    // (Under mpirun the default engine is refused before any folder is touched: cli.cpp.)
    input_error(name + ": another hemicontact run" + (holder.empty() ? std::string() : " (pid " + printable(holder) + ")") +
                " is writing there; wait for it to finish or choose another --out");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    const int err = errno;
    throw Error(name + ": the lock file '" + printable(file) + "' cannot be written (" + std::strerror(err) + ")",
                output_code(err));
  }
  return lock;
}

// Open the --out folder, creating it (and its parents) when missing. The path itself may pass
// through links (the user's choice of place); a dangling one is named as such.
int open_output_dir(const std::string& dir, const std::string& name) {
  struct stat st {};
  if (::lstat(dir.c_str(), &st) == 0 && S_ISLNK(st.st_mode) && ::stat(dir.c_str(), &st) != 0) {
    std::error_code ec;
    const fs::path target = fs::read_symlink(dir, ec);
    input_error(name + " is a symbolic link to '" + printable(target.string()) +
                "', which does not exist; create that folder, or remove the link, or choose another --out");
  }
  std::error_code ec;
  const fs::path p(dir);
  if (fs::exists(p, ec) && !fs::is_directory(p, ec)) input_error(name + ": exists and is not a directory");
  if (!fs::exists(p, ec)) {
    fs::create_directories(p, ec);
    if (ec) throw Error(name + ": cannot create directory: " + ec.message(), output_code(ec.value()));
  }
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    throw Error(name + ": cannot open the directory (" + std::string(std::strerror(err)) + ")", output_code(err));
  }
  return fd;
}

}  // namespace

bool plain_output_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name != OUTPUT_MANIFEST && name != OUTPUT_LOCK &&
         name.find('/') == std::string::npos && printable(name) == name;
}

std::optional<std::vector<std::string>> parse_manifest(const std::string& text) {
  if (text.size() > MAX_MANIFEST_BYTES) return std::nullopt;
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != OUTPUT_MANIFEST_SIGNATURE) return std::nullopt;
  std::vector<std::string> names;
  while (std::getline(in, line))
    if (plain_output_name(line) && std::find(names.begin(), names.end(), line) == names.end()) names.push_back(line);
  return names;
}

std::vector<std::string> output_files(const std::string& dir) {
  Fd scratch;
  const int fd = folder_of(fs::path(dir) / OUTPUT_MANIFEST, scratch);
  return fd < 0 ? std::vector<std::string>{} : listed_names(fd);
}

std::string partial_name(const std::string& name) { return "." + name + ".partial"; }

std::string non_regular_kind(const std::string& path) {
  Fd scratch;
  const fs::path p(path);
  const int fd = folder_of(p, scratch);
  std::string kind;
  if (fd >= 0 && entry_at(fd, p.filename().string(), &kind) == Entry::OTHER) return kind;
  return "";
}

void set_interrupt_child(int pid) { g_child.store(pid); }

OutputLock& OutputLock::operator=(OutputLock&& o) noexcept {
  if (this != &o) {
    if (m_fd >= 0) ::close(m_fd);
    m_fd = o.m_fd;
    o.m_fd = -1;
  }
  return *this;
}

OutputLock::~OutputLock() {
  if (m_fd >= 0) ::close(m_fd);  // closing the descriptor releases the flock
}

OutputLock prepare_output_dir(const std::string& dir, bool overwrite, const std::vector<std::string>& will_write,
                              const std::vector<OutputNamePattern>& patterns) {
  if (dir.empty()) input_error("--out: empty directory name");
  const std::string name = "--out '" + printable(dir) + "'";
  // The system calls end a name at its first NUL byte: "dir/a\0b" would be written as dir/a.
  if (dir.find('\0') != std::string::npos) input_error(name + ": the folder name holds a NUL byte");
  Fd handle(open_output_dir(dir, name));
  const int dfd = handle.fd;
  // The lock first: the check for earlier results below and this run's writes are then one
  // step that no other run can come between.
  OutputLock lock = lock_output_dir(dfd, dir, name);

  const Manifest manifest = read_manifest(dfd);
  if (manifest.present && !manifest.names)
    input_error(name + ": " + OUTPUT_MANIFEST + " is not a file list written by hemicontact (" + manifest.why_foreign +
                "); hemicontact replaces only files its own list names: move the folder's files away (or remove " +
                OUTPUT_MANIFEST + " if they are yours) or choose another --out");
  const std::vector<std::string> ours = manifest.names ? *manifest.names : std::vector<std::string>{};
  const auto is_ours = [&](const std::string& f) { return std::find(ours.begin(), ours.end(), f) != ours.end(); };

  // Every name this run will write, and its temporary, must be free or a regular file of ours:
  // refused here, before any work, naming it; --force does not change that.
  std::vector<std::string> names = will_write;
  for (const std::string& f : numbered_entries(dfd, patterns))
    if (std::find(names.begin(), names.end(), f) == names.end()) names.push_back(f);
  for (const std::string& f : names)
    for (const std::string& q : {f, partial_name(f)}) {
      std::string kind;
      const Entry e = entry_at(dfd, q, &kind);
      if (e == Entry::OTHER)
        input_error(name + ": '" + printable(q) + "' is " + kind +
                    ", not a file hemicontact wrote; hemicontact writes only regular files and never through a "
                    "link: remove it or choose another --out");
      if (e == Entry::REGULAR && !is_ours(f))
        input_error(name + ": '" + printable(q) + "' exists and was not written by hemicontact (it is not listed in " +
                    OUTPUT_MANIFEST + "); move it away or choose another --out");
    }

  // Results: the listed files still there (or their temporaries): a run that failed before its
  // first file was complete left nothing to protect.
  std::string first;
  for (const std::string& f : ours) {
    if (entry_at(dfd, f) != Entry::NONE) first = f;
    else if (entry_at(dfd, partial_name(f)) != Entry::NONE) first = partial_name(f);
    if (!first.empty()) break;
  }
  std::string marker;  // the file that marks a set complete, when there is one
  for (const char* m : {"report.json", "convergence.json", "minima.json", "work_precision.json"})
    if (marker.empty() && is_ours(m) && entry_at(dfd, m) == Entry::REGULAR) marker = m;
  if (!overwrite && !first.empty())
    input_error(name + " already holds results (" +
                (marker.empty() ? printable(first) + ", listed in " + OUTPUT_MANIFEST +
                                      "; an incomplete set: its run was interrupted or failed"
                                : marker) +
                "); pass --force to replace them");
  if (overwrite) {
    // --force replaces the previous result set as a whole: exactly the files it listed, as long
    // as they are regular files (a link is not followed, nor removed). With each file goes its
    // temporary, left by a run that was killed while writing it.
    for (const std::string& f : ours)
      for (const std::string& q : {f, partial_name(f)})
        if (entry_at(dfd, q) == Entry::REGULAR && ::unlinkat(dfd, q.c_str(), 0) != 0 && errno != ENOENT) {
          const int err = errno;
          throw Error(name + ": cannot remove the earlier run's '" + printable(q) + "' (" + std::strerror(err) + ")",
                      output_code(err));
        }
  }

  // This folder's handle serves the writers from now on.
  if (g_dir_fd >= 0) ::close(g_dir_fd);
  g_dir_fd = handle.fd;
  handle.fd = -1;
  g_dir = dir;
  // The interrupt message before the manifest: from the moment the manifest exists (what a watcher,
  // or the tests, take as "the run has started writing") a signal says that the results are
  // incomplete. Setting it after left a window in which SIGTERM ended the run without a word.
  update_interrupt_message();
  // A fresh manifest with only its signature; writing it also proves that the folder is writable
  // (permission bits do not tell about read-only mounts, ACLs or root). It is ours or absent here.
  const int mfd = ::openat(g_dir_fd, OUTPUT_MANIFEST, O_WRONLY | O_CREAT | O_TRUNC | SAFE_OPEN, 0666);
  const std::string head = std::string(OUTPUT_MANIFEST_SIGNATURE) + "\n";
  if (mfd < 0) {
    const int err = errno;
    throw Error(name + ": directory is not writable (" + std::strerror(err) + ")", output_code(err));
  }
  const Fd mguard(mfd);
  if (::write(mfd, head.data(), head.size()) != static_cast<ssize_t>(head.size())) {
    const int err = errno;
    throw Error(name + ": directory is not writable (" + std::strerror(err) + ")", output_code(err));
  }
  update_interrupt_message();  // from the fresh manifest: nothing written yet
  return lock;
}

namespace {

// List @p file in the manifest of the folder @p dfd (once), when the folder has a manifest of ours.
void record_name(int dfd, const std::string& file) {
  if (!plain_output_name(file)) return;
  const Manifest m = read_manifest(dfd);
  if (!m.names) return;  // not a prepared output folder: nothing to record
  if (std::find(m.names->begin(), m.names->end(), file) != m.names->end()) return;
  const int fd = ::openat(dfd, OUTPUT_MANIFEST, O_WRONLY | O_APPEND | SAFE_OPEN);
  if (fd < 0) return;
  const Fd guard(fd);
  struct stat st {};
  const std::string line = file + "\n";
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && ::write(fd, line.data(), line.size()) < 0) {
    // the file itself is still written; only --force after a crash would not know it
  }
  if (dfd == g_dir_fd) update_interrupt_message();
}

}  // namespace

void record_output_file(const std::string& path) {
  const fs::path p(path);
  Fd scratch;
  const int dfd = folder_of(p, scratch);
  // Another program's file (a picture) is listed only as a regular file: --force never removes
  // what is listed unless it is one, and a link there is not the program's output.
  if (dfd < 0 || entry_at(dfd, p.filename().string()) == Entry::OTHER) return;
  record_name(dfd, p.filename().string());
}

void write_text_file(const std::string& path, const std::string& text) {
  const fs::path p(path);
  const std::string file = p.filename().string();
  const std::string partial = partial_name(file);
  const auto error = [&](const std::string& why) { return Error("cannot write '" + printable(path) + "': " + why, EXIT_OUTPUT); };
  Fd scratch;
  const int dfd = folder_of(p, scratch);
  if (dfd < 0) throw error(std::strerror(errno));
  // Listed before the temporary exists: a run killed from here on leaves nothing unlisted.
  record_name(dfd, file);
  // Created exclusively and never through a link: a name planted where the temporary goes is
  // refused, not written through (prepare_output_dir refuses it before the run in the first place).
  // Named to the interrupt handler before it exists: an interrupt between the creation and the
  // naming left the temporary behind (seen once in 40 interrupted runs). A name that is not there
  // yet costs the handler a failed unlinkat; one planted there (refused by prepare_output_dir
  // before the run, so only a race with another process) is cleared from the handler first.
  set_partial(dfd, partial);
  const int fd = ::openat(dfd, partial.c_str(), O_WRONLY | O_CREAT | O_EXCL | SAFE_OPEN, 0666);
  if (fd < 0) {
    const int err = errno;
    set_partial(-1, "");
    if (err == EEXIST || err == ELOOP)
      throw error("its temporary '" + printable(partial) + "' exists already (left by a killed run, or not " +
                  "hemicontact's); remove it and run again");
    throw error(std::strerror(err));
  }
  const auto fail = [&](int err, int open_fd) {
    if (open_fd >= 0) ::close(open_fd);
    ::unlinkat(dfd, partial.c_str(), 0);
    set_partial(-1, "");
    throw error(std::strerror(err));
  };
  for (size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(n < 0 ? errno : EIO, fd);
    done += static_cast<size_t>(n);
  }
  // On the disk before the rename: otherwise a crash of the machine could leave the new name
  // with no content. (File systems that cannot sync, EINVAL, have nothing to sync.)
  if (::fsync(fd) != 0 && errno != EINVAL) fail(errno, fd);
  if (::close(fd) != 0) fail(errno, -1);
  const bool in_run_folder = dfd == g_dir_fd && !g_dir.empty();
  if (in_run_folder) {
    copy_to(g_message_renamed, interrupt_message(file));
    g_renaming.store(true);
  }
  // renameat replaces the name itself: a link planted there since the check is replaced, not followed.
  if (::renameat(dfd, partial.c_str(), dfd, file.c_str()) != 0) {
    g_renaming.store(false);
    fail(errno, -1);
  }
  if (in_run_folder) update_interrupt_message();
  g_renaming.store(false);
  set_partial(-1, "");
}

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  // A file-size limit (ulimit -f) then fails the write with EFBIG, which names the file, instead
  // of killing the process without a word.
  std::signal(SIGXFSZ, SIG_IGN);
}

}  // namespace hemicontact
