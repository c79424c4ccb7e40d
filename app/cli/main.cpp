// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/cli/commands.h"

#ifdef __SANITIZE_ADDRESS__
#include <filesystem>
#include <iterator>
#include <system_error>

// Sanitizer builds only (DTF_SANITIZE). LeakSanitizer's exit check stops every thread through a tracer that
// now and then crashes ("Tracer caught signal 11") beside threads still running at exit: Mesa's llvmpipe
// workers in any process that made a GL context. Such a process skips the leak check (ASan and UBSan stay
// on); a process whose other threads have all ended by exit keeps it.
extern "C" int __lsan_is_turned_off() {
  std::error_code ec;
  const auto tasks = std::filesystem::directory_iterator("/proc/self/task", ec);
  return !ec && std::distance(tasks, std::filesystem::directory_iterator()) > 1 ? 1 : 0;
}
#endif

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#include <csignal>
#include <cstring>
#include <execinfo.h>
#include <unistd.h>

namespace {

// A crash (a bug, here or in a library) prints the signal and the call stack on stderr before the process
// dies of the signal as before (its exit status unchanged), so a log shows where it happened. Only
// async-signal-safe calls in the handler; backtrace() is loaded before any crash (it loads libgcc lazily).
// Sanitizer builds keep their own reports.
void writeAll(const char* s) {
  for (std::size_t n = std::strlen(s); n > 0;) {
    const ssize_t w = ::write(STDERR_FILENO, s, n);
    if (w <= 0) return;
    s += w, n -= static_cast<std::size_t>(w);
  }
}

extern "C" void crashReport(int sig) {
  writeAll("dtfabric: fatal signal ");
  writeAll(sigabbrev_np(sig) ? sigabbrev_np(sig) : "?");
  writeAll(" (a bug: please report it with the lines below and the command)\n");
  void* frames[64];
  const int n = ::backtrace(frames, 64);
  ::backtrace_symbols_fd(frames, n, STDERR_FILENO);
  std::signal(sig, SIG_DFL);
  ::raise(sig);
}

void installCrashReport() {
  void* warm[1];
  ::backtrace(warm, 1);
  // Its own stack, so a stack overflow is reported too.
  static char altStack[64 * 1024];
  stack_t ss{};
  ss.ss_sp = altStack;
  ss.ss_size = sizeof altStack;
  ::sigaltstack(&ss, nullptr);
  struct sigaction sa{};
  sa.sa_handler = crashReport;
  sa.sa_flags = SA_ONSTACK | SA_RESETHAND;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::sigaction(sig, &sa, nullptr);
}

} // namespace
#else
namespace {
void installCrashReport() {}
} // namespace
#endif

int main(int argc, char** argv) {
  installCrashReport();
  return dtf::app::runCli(argc, argv);
}
