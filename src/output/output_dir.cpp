#include <hemicontact/output/output_dir.hpp>

#include <hemicontact/core/error.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace hemicontact {

namespace fs = std::filesystem;

namespace {

// What the interrupt handler needs, prepared outside it: a signal handler may only call
// async-signal-safe functions (unlink, write, signal, raise), so the path of the temporary being
// written and the message naming the kept files are plain char buffers, each double-buffered
// behind an atomic index so that a signal taken (on any thread) while one is updated reads the
// other, complete one.
constexpr size_t BUFFER = 8192;
char g_partial[2][BUFFER];  // the temporary being written ("" when none)
char g_message[2][BUFFER];  // "hemicontact: interrupted ..." for the current output folder
std::atomic<int> g_partial_index{0};
std::atomic<int> g_message_index{-1};  // −1: no output folder prepared yet
std::string g_dir;                     // the output folder of this run (prepare_output_dir)

void copy_to(char (&buffer)[BUFFER], const std::string& text) {
  const size_t n = std::min(text.size(), BUFFER - 1);
  std::memcpy(buffer, text.data(), n);
  buffer[n] = '\0';
}

void set_partial(const std::string& path) {
  const int next = 1 - g_partial_index.load();
  copy_to(g_partial[next], path);
  g_partial_index.store(next);
}

// Rebuild the interrupt message from the folder's manifest: the files listed there that exist
// are complete (a file is renamed into place only when fully written).
void update_interrupt_message() {
  if (g_dir.empty()) return;
  std::string kept;
  std::error_code ec;
  for (const std::string& f : output_files(g_dir))
    if (fs::exists(fs::path(g_dir) / f, ec)) kept += (kept.empty() ? "" : ", ") + f;
  std::string text = "hemicontact: interrupted: the results in '" + g_dir + "' are incomplete (" +
                     (kept.empty() ? std::string("nothing was written yet") : "kept: " + kept) +
                     "); rerun with --force to replace them\n";
  if (text.size() >= BUFFER) text = text.substr(0, BUFFER - 5) + "...\n";
  const int next = g_message_index.load() == 0 ? 1 : 0;
  copy_to(g_message[next], text);
  g_message_index.store(next);
}

extern "C" void on_interrupt(int sig) {
  const char* partial = g_partial[g_partial_index.load()];
  if (partial[0] != '\0') ::unlink(partial);
  const int m = g_message_index.load();
  if (m >= 0) {
    const char* msg = g_message[m];
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

// A name the manifest may list: a plain file name in the folder itself. Anything else (a path, "..",
// the manifest) is never removed or trusted, whoever edited the manifest.
bool plain_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name != OUTPUT_MANIFEST &&
         name.find('/') == std::string::npos && name.find('\0') == std::string::npos;
}

}  // namespace

std::vector<std::string> output_files(const std::string& dir) {
  std::vector<std::string> names;
  std::ifstream in(fs::path(dir) / OUTPUT_MANIFEST);
  for (std::string line; std::getline(in, line);)
    if (plain_name(line) && std::find(names.begin(), names.end(), line) == names.end()) names.push_back(line);
  return names;
}

std::string partial_name(const std::string& name) { return "." + name + ".partial"; }

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

namespace {

// Take the folder's lock, or say who holds it. flock (not fcntl) locks: they belong to the open
// file description, so a second prepare in the same process is refused as well, and they are
// released by the kernel however the holder ends.
OutputLock lock_output_dir(const fs::path& p, const std::string& name) {
  const fs::path file = p / OUTPUT_LOCK;
  const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int err = errno;
    throw Error(name + ": directory is not writable (" + std::strerror(err) + ")", output_code(err));
  }
  OutputLock lock(fd);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    char pid[32] = {0};
    const ssize_t n = ::pread(fd, pid, sizeof pid - 1, 0);
    std::string holder = n > 0 ? std::string(pid, static_cast<size_t>(n)) : std::string();
    holder.erase(std::remove(holder.begin(), holder.end(), '\n'), holder.end());
    input_error(name + ": another hemicontact run" + (holder.empty() ? std::string() : " (pid " + holder + ")") +
                " is writing there; wait for it to finish or choose another --out");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    const int err = errno;
    throw Error(name + ": directory is not writable (" + std::strerror(err) + ")", output_code(err));
  }
  return lock;
}

}  // namespace

namespace {

std::string first_existing(const fs::path& p, const std::vector<std::string>& names) {
  std::error_code ec;
  for (const std::string& f : names)
    if (fs::exists(fs::symlink_status(p / f, ec))) return f;
  for (const std::string& f : names)
    if (fs::exists(fs::symlink_status(p / partial_name(f), ec))) return partial_name(f);
  return names.empty() ? std::string() : names.front();
}

}  // namespace

OutputLock prepare_output_dir(const std::string& dir, bool overwrite, const std::vector<std::string>& will_write) {
  const std::string name = "--out '" + dir + "'";
  if (dir.empty()) input_error("--out: empty directory name");
  std::error_code ec;
  const fs::path p(dir);
  const fs::path manifest = p / OUTPUT_MANIFEST;
  if (fs::exists(p, ec) && !fs::is_directory(p, ec)) input_error(name + ": exists and is not a directory");
  const bool existed = fs::exists(p, ec);
  if (!existed) {
    fs::create_directories(p, ec);
    if (ec) throw Error(name + ": cannot create directory: " + ec.message(), output_code(ec.value()));
  }
  // The lock first: the check for earlier results below and this run's writes are then one
  // step that no other run can come between.
  OutputLock lock = lock_output_dir(p, name);
  if (existed) {
    // Results: a report.json, or files an earlier run listed (an interrupted run leaves a manifest
    // with the files it got to write; one that failed before writing any left it empty).
    std::vector<std::string> ours = output_files(dir);
    // A result set of a version before the manifest: its marker file (report.json, or a study's
    // JSON) says an earlier run of the tool wrote there, and then the names this run writes are
    // the names that run wrote.
    if (!fs::exists(manifest, ec))
      for (const char* marker : {"report.json", "convergence.json", "minima.json"})
        if (fs::exists(p / marker, ec)) {
          for (const std::string& f : will_write)
            if (fs::exists(p / f, ec)) ours.push_back(f);
          break;
        }
    // Results are the listed files still there (or their temporaries): a run that failed before
    // its first file was complete left nothing to protect.
    const bool has_results =
        fs::exists(p / "report.json", ec) || std::any_of(ours.begin(), ours.end(), [&](const std::string& f) {
          return fs::exists(fs::symlink_status(p / f, ec)) || fs::exists(fs::symlink_status(p / partial_name(f), ec));
        });
    bool complete = false;
    for (const char* marker : {"report.json", "convergence.json", "minima.json"})
      complete = complete || fs::exists(p / marker, ec);
    if (!overwrite && has_results)
      input_error(name + " already holds results (" +
                  (fs::exists(p / "report.json", ec) ? std::string("report.json")
                                                     : first_existing(p, ours) + ", listed in " + OUTPUT_MANIFEST) +
                  (complete ? "" : "; an incomplete set: its run was interrupted or failed") +
                  "); pass --force to replace them");
    // The files this run will write must be ours to replace: a user's own file of the same name
    // is never overwritten, not even with --force.
    for (const std::string& f : will_write)
      if (fs::exists(p / f, ec) && f != "report.json" && std::find(ours.begin(), ours.end(), f) == ours.end())
        input_error(name + ": '" + f + "' exists and was not written by hemicontact (it is not listed in " +
                    OUTPUT_MANIFEST + "); move it away or choose another --out");
    if (overwrite) {
      // --force replaces the previous result set as a whole: exactly the files it listed.
      // With each file goes its temporary, left by a run that was killed while writing it.
      for (const std::string& f : ours)
        for (const fs::path& q : {p / f, p / partial_name(f)})
          if (fs::is_regular_file(fs::symlink_status(q, ec))) fs::remove(q, ec);
      if (has_results) fs::remove(p / "report.json", ec);
    }
  }
  // The interrupt message before the manifest: from the moment the manifest exists (what a watcher,
  // or the tests, take as "the run has started writing") a signal says that the results are
  // incomplete. Setting it after left a window in which SIGTERM ended the run without a word.
  g_dir = dir;
  update_interrupt_message();
  // A fresh, empty manifest; writing it also proves that the folder is writable (permission bits
  // do not tell about read-only mounts, ACLs or root).
  std::ofstream f(manifest, std::ios::trunc);
  if (!f || !f.flush()) throw Error(name + ": directory is not writable", EXIT_OUTPUT);
  update_interrupt_message();  // from the fresh manifest: nothing written yet
  return lock;
}

void record_output_file(const std::string& path) {
  const fs::path p(path);
  const fs::path manifest = p.parent_path().empty() ? fs::path(OUTPUT_MANIFEST) : p.parent_path() / OUTPUT_MANIFEST;
  std::error_code ec;
  if (!fs::exists(manifest, ec)) return;  // not a prepared output folder: nothing to record
  const std::string file = p.filename().string();
  const std::vector<std::string> listed = output_files(manifest.parent_path().string());
  if (!plain_name(file) || std::find(listed.begin(), listed.end(), file) != listed.end()) return;
  std::ofstream(manifest, std::ios::app) << file << '\n';
  update_interrupt_message();
}

void write_text_file(const std::string& path, const std::string& text) {
  const fs::path p(path);
  const fs::path partial = p.parent_path() / partial_name(p.filename().string());
  // Listed before the temporary exists: a run killed from here on leaves nothing unlisted.
  record_output_file(path);
  set_partial(partial.string());
  const auto fail = [&](int err, int fd) {
    if (fd >= 0) ::close(fd);
    ::unlink(partial.c_str());
    set_partial("");
    throw Error("cannot write '" + path + "': " + std::strerror(err), EXIT_OUTPUT);
  };
  const int fd = ::open(partial.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail(errno, -1);
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
  if (::rename(partial.c_str(), path.c_str()) != 0) fail(errno, -1);
  set_partial("");
  update_interrupt_message();
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
