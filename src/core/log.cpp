#include <hemicontact/core/log.hpp>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <mutex>

namespace hemicontact {
namespace {
std::atomic<int> g_level{static_cast<int>(LogLevel::INFO)};
const auto g_start = std::chrono::steady_clock::now();
// The sink is replaced while solves in other threads may log: each line takes a reference under
// the mutex and calls the sink outside it (a sink may block, e.g. on Python's GIL).
std::mutex g_sink_mutex;
std::shared_ptr<const LogSink> g_sink;
}  // namespace

void set_log_level(LogLevel level) { g_level = static_cast<int>(level); }
LogLevel log_level() { return static_cast<LogLevel>(g_level.load()); }

void set_log_sink(LogSink sink) {
  auto next = sink ? std::make_shared<const LogSink>(std::move(sink)) : nullptr;
  const std::lock_guard<std::mutex> lock(g_sink_mutex);
  g_sink = std::move(next);
}

void log_line(LogLevel level, const std::string& line) {
  if (static_cast<int>(level) > g_level.load()) return;
  std::shared_ptr<const LogSink> sink;
  {
    const std::lock_guard<std::mutex> lock(g_sink_mutex);
    sink = g_sink;
  }
  if (sink) {
    (*sink)(level, line);
    return;
  }
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count();
  std::fprintf(stderr, "[%8.3fs] %s%s\n", t, level == LogLevel::WARN ? "warning: " : "", line.c_str());
}

}  // namespace hemicontact
