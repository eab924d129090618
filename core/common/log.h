// Marvin's log: one process-wide sink for human-readable events.
//
// Every area logs through marvin::log() so the carer reads one stream: the console of
// `marvin run`, a file, or a test's capture. The default sink writes to stderr.
// Thread-safe: log() and set_log_sink() may be called from any thread; the sink is
// called under a mutex, so a sink never runs on two threads at once.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace marvin {

enum class LogLevel { kDebug, kInfo, kWarning, kError };

// "debug", "info", "warning", "error".
const char* to_string(LogLevel level);

// Receives each record. `component` names the area ("graph", "skills", "skill:dice", ...).
using LogSink = std::function<void(LogLevel level, std::string_view component,
                                   std::string_view message)>;

// Replaces the sink and returns the previous one. An empty function restores stderr.
LogSink set_log_sink(LogSink sink);

// Records below this level are discarded before reaching the sink. Default: kInfo.
void set_log_level(LogLevel minimum);

void log(LogLevel level, std::string_view component, std::string_view message);

}  // namespace marvin
