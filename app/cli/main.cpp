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

int main(int argc, char** argv) { return dtf::app::runCli(argc, argv); }
