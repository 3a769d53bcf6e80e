#include <hemicontact/core/log.hpp>

#include <atomic>
#include <chrono>
#include <cstdio>

namespace hemicontact {
namespace {
std::atomic<int> g_level{static_cast<int>(LogLevel::INFO)};
const auto g_start = std::chrono::steady_clock::now();
}  // namespace

void set_log_level(LogLevel level) { g_level = static_cast<int>(level); }
LogLevel log_level() { return static_cast<LogLevel>(g_level.load()); }

void log_line(LogLevel level, const std::string& line) {
  if (static_cast<int>(level) > g_level.load()) return;
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count();
  std::fprintf(stderr, "[%8.3fs] %s%s\n", t, level == LogLevel::WARN ? "warning: " : "", line.c_str());
}

}  // namespace hemicontact
