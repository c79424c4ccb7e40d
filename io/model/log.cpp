// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/log.h"

#include <mutex>

namespace dtf {
namespace {
std::mutex& sinkMutex() {
  static std::mutex m;
  return m;
}
LogSink& sinkRef() {
  static LogSink s;
  return s;
}
} // namespace

void setLogSink(LogSink sink) {
  std::lock_guard lock(sinkMutex());
  sinkRef() = std::move(sink);
}

void log(LogLevel level, const std::string& message) {
  std::lock_guard lock(sinkMutex());
  if (sinkRef()) sinkRef()(level, message);
}

} // namespace dtf
