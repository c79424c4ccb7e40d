// libFuzzer target: the readers of other tools' formats behind io/formats/formats.h (MRtrix images, NRRD, DSI
// Studio SRC/FIB, AFNI .HEAD). The first input byte picks the file name's extension (the readers detect by
// content first, by name second); the rest is the file. Any dtf::Error is an accepted outcome; a crash, a
// sanitizer report, a leak or an allocation beyond -rss_limit_mb is a finding.
#include "fuzz_file.h"
#include "io/formats/dsi_studio.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/formats/tensor_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = (dtf::setLogSink([](dtf::LogLevel, const std::string&) {}), true);
  (void)quiet;
  if (size < 1) return 0;
  static const char* kExt[] = {".mif",  ".mif.gz", ".mih",    ".nrrd",
                               ".nhdr", ".src.gz", ".fib.gz", "+orig.HEAD"};
  const std::size_t pick = data[0] % (sizeof kExt / sizeof kExt[0]);
  const std::string path = dtf::fuzz::scratchPath("fmt", kExt[pick]);
  dtf::fuzz::writeInput(path, data + 1, size - 1);
  if (pick == 6) {
    try {
      dtf::io::readDsiStudioFib(path);
    } catch (const dtf::Error&) {
    }
    return 0;
  }
  try {
    dtf::io::readHeader(path);
  } catch (const dtf::Error&) {
    return 0;
  }
  try {
    dtf::io::readScalarVolume(path);
  } catch (const dtf::Error&) {
  }
  try {
    dtf::io::readTensorVolume(path);
  } catch (const dtf::Error&) {
  }
  return 0;
}
