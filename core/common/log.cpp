#include "common/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace marvin {
namespace {

std::mutex g_mutex;
LogSink g_sink;  // guarded by g_mutex; empty means stderr
std::atomic<int> g_minimum{static_cast<int>(LogLevel::kInfo)};

}  // namespace

const char* to_string(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return "debug";
    case LogLevel::kInfo: return "info";
    case LogLevel::kWarning: return "warning";
    case LogLevel::kError: return "error";
  }
  return "?";
}

LogSink set_log_sink(LogSink sink) {
  std::lock_guard lock(g_mutex);
  LogSink previous = std::move(g_sink);
  g_sink = std::move(sink);
  return previous;
}

void set_log_level(LogLevel minimum) { g_minimum.store(static_cast<int>(minimum)); }

void log(LogLevel level, std::string_view component, std::string_view message) {
  if (static_cast<int>(level) < g_minimum.load()) return;
  std::lock_guard lock(g_mutex);
  if (g_sink) {
    g_sink(level, component, message);
    return;
  }
  std::fprintf(stderr, "[%s] %.*s: %.*s\n", to_string(level), static_cast<int>(component.size()),
               component.data(), static_cast<int>(message.size()), message.data());
}

}  // namespace marvin
