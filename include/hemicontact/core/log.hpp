#pragma once
/// @file log.hpp  Minimal progress logger: everything goes to stderr, results go to files.

#include <functional>
#include <sstream>
#include <string>

namespace hemicontact {

/// Verbosity levels, lowest first.
enum class LogLevel : int { QUIET = 0, WARN = 1, INFO = 2, DEBUG = 3 };

/// Set the global verbosity (default INFO; the CLI's --quiet sets WARN).
void set_log_level(LogLevel level);
/// @return the global verbosity.
LogLevel log_level();
/// Write one line to stderr if @p level is enabled; prefixed with the elapsed wall time. With a
/// sink set (set_log_sink), the enabled line goes to the sink instead, without the prefix.
void log_line(LogLevel level, const std::string& line);
/// Receives each enabled line (without "warning: " or the time: the host adds its own), on the
/// thread that logged it.
using LogSink = std::function<void(LogLevel level, const std::string& line)>;
/// Send the log lines to @p sink instead of stderr (an empty sink: stderr again). For a host
/// that has its own logging (the Python module forwards to Python's `logging`).
void set_log_sink(LogSink sink);

/// Stream-style helpers: `log_info() << "outer " << k;` writes on destruction.
class LogStream {
 public:
  /// @param level the level the finished line is written at
  explicit LogStream(LogLevel level) : m_level(level) {}
  ~LogStream() { log_line(m_level, m_out.str()); }
  LogStream(const LogStream&) = delete;
  LogStream& operator=(const LogStream&) = delete;
  /// Append a value to the line.
  template <class T>
  LogStream& operator<<(const T& v) {
    m_out << v;
    return *this;
  }

 private:
  LogLevel m_level;
  std::ostringstream m_out;
};

/// @return a stream that logs at INFO.
inline LogStream log_info() { return LogStream(LogLevel::INFO); }
/// @return a stream that logs at WARN (prefix "warning: ").
inline LogStream log_warn() { return LogStream(LogLevel::WARN); }
/// @return a stream that logs at DEBUG.
inline LogStream log_debug() { return LogStream(LogLevel::DEBUG); }

}  // namespace hemicontact
