// libFuzzer target: MRtrix .tck or TrackVis .trk reader (io/tracts.h), chosen at build time by
// DTF_FUZZ_TRACT_EXT (".tck" or ".trk"). Any dtf::Error is an accepted outcome.
#include "fuzz_file.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/tracts.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = (dtf::setLogSink([](dtf::LogLevel, const std::string&) {}), true);
  (void)quiet;
  static const std::string ext = DTF_FUZZ_TRACT_EXT;
  static const std::string path = dtf::fuzz::scratchPath("tracts", ext);
  dtf::fuzz::writeInput(path, data, size);
  try {
    const dtf::Polylines lines = ext == ".tck" ? dtf::io::readTck(path) : dtf::io::readTrk(path);
    // What a reader returns must be a consistent polyline set.
    if (lines.offsets.empty() || lines.offsets.front() != 0 || lines.offsets.back() != lines.points.size())
      std::abort();
    for (std::size_t i = 1; i < lines.offsets.size(); ++i)
      if (lines.offsets[i] < lines.offsets[i - 1]) std::abort();
  } catch (const dtf::Error&) {
  }
  return 0;
}
