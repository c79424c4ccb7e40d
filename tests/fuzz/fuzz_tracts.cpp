// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: MRtrix .tck, TrackVis .trk / .trk.gz (io/formats/tracts.h) or TRX zip (io/formats/trx.h) reader,
// chosen at build time by DTF_FUZZ_TRACT_EXT (".tck", ".trk", ".trk.gz" or ".trx"). Any dtf::Error is an
// accepted outcome.
#include "fuzz_file.h"
#include "io/model/error.h"
#include "io/model/log.h"
#include "io/formats/tracts.h"
#include "io/formats/trx.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = (dtf::setLogSink([](dtf::LogLevel, const std::string&) {}), true);
  (void)quiet;
  static const std::string ext = DTF_FUZZ_TRACT_EXT;
  static const std::string path = dtf::fuzz::scratchPath("tracts", ext);
  dtf::fuzz::writeInput(path, data, size);
  try {
    const dtf::Polylines lines = ext == ".tck"   ? dtf::io::readTck(path)
                                 : ext == ".trx" ? dtf::io::readTrx(path)
                                                 : dtf::io::readTrk(path);
    // What a reader returns must be a consistent polyline set, its data and groups included.
    if (lines.offsets.empty() || !lines.inconsistency().empty()) std::abort();
  } catch (const dtf::Error&) {
  }
  return 0;
}
