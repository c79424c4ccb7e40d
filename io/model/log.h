// SPDX-License-Identifier: GPL-3.0-or-later
// The one logger. Libraries never print; they call dtf::log(), and the app decides where messages go
// (stderr for the CLI, the status panel for the GUI).
#pragma once

#include <functional>
#include <string>

namespace dtf {

enum class LogLevel { Debug, Info, Warning, Error };

using LogSink = std::function<void(LogLevel, const std::string&)>;

// Replaces the process-wide sink; an empty sink drops messages. Thread-safe.
void setLogSink(LogSink sink);
// Sends one message to the current sink. Thread-safe.
void log(LogLevel level, const std::string& message);
inline void logInfo(const std::string& m) { log(LogLevel::Info, m); }
inline void logWarning(const std::string& m) { log(LogLevel::Warning, m); }

} // namespace dtf
