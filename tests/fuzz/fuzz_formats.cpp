// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: the readers of other tools' formats behind io/formats/formats.h (MRtrix images, NRRD, DSI
// Studio SRC/FIB, AFNI .HEAD/.BRIK). DTF_FUZZ_FAMILY picks the extensions a target tries (0: all, 1: MRtrix,
// 2: NRRD, 3: AFNI, 4: DSI Studio); the first input byte picks one of them (the readers detect by content
// first, by name second). The rest is the file; when it holds the line "@@data@@", what follows goes to a
// second file beside it: "data.raw" (named by a .mih's `file:` or an .nhdr's `data file:`) or the AFNI
// .BRIK (.BRIK.gz when it starts with the gzip magic). Any dtf::Error is an accepted outcome; a crash, a
// sanitizer report, a leak or an allocation beyond -rss_limit_mb/-malloc_limit_mb is a finding.
#include "fuzz_file.h"
#include "io/diffusion/dwi.h"
#include "io/formats/dsi_studio.h"
#include "io/formats/formats.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "io/model/log.h"

#include <cstring>
#include <vector>

#ifndef DTF_FUZZ_FAMILY
#define DTF_FUZZ_FAMILY 0
#endif

namespace {

struct Ext {
  const char* name;
  int family;
};
// The order is the selector byte of fuzz_formats (family 0): seeds rely on it.
constexpr Ext kExt[] = {{".mif", 1},  {".mif.gz", 1}, {".mih", 1},    {".nrrd", 2},
                        {".nhdr", 2}, {".src.gz", 4}, {".fib.gz", 4}, {"+orig.HEAD", 3}};

const std::vector<int>& candidates() {
  static const std::vector<int> c = [] {
    std::vector<int> out;
    for (int i = 0; i < static_cast<int>(sizeof kExt / sizeof kExt[0]); ++i)
      if (DTF_FUZZ_FAMILY == 0 || kExt[i].family == DTF_FUZZ_FAMILY) out.push_back(i);
    return out;
  }();
  return c;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool quiet = (dtf::setLogSink([](dtf::LogLevel, const std::string&) {}), true);
  (void)quiet;
  if (size < 1) return 0;
  const int pick = candidates()[data[0] % candidates().size()];
  const std::string ext = kExt[pick].name;
  static const std::filesystem::path dir = dtf::fuzz::scratchDir("fmt");
  dtf::fuzz::clearDir(dir);
  const std::string path = (dir / ("in" + ext)).string();
  // Split at the first "@@data@@" line into the file and its companion.
  static const char kMark[] = "\n@@data@@\n";
  const std::uint8_t* end = data + size;
  const std::uint8_t* mark =
      static_cast<const std::uint8_t*>(memmem(data + 1, size - 1, kMark, sizeof kMark - 1));
  dtf::fuzz::writeInput(path, data + 1, static_cast<std::size_t>((mark ? mark : end) - (data + 1)));
  if (mark) {
    const std::uint8_t* rest = mark + sizeof kMark - 1;
    const std::size_t n = static_cast<std::size_t>(end - rest);
    const bool gz = n >= 2 && rest[0] == 0x1f && rest[1] == 0x8b;
    const std::string companion = kExt[pick].family == 3 ? (gz ? "in+orig.BRIK.gz" : "in+orig.BRIK") : "data.raw";
    dtf::fuzz::writeInput((dir / companion).string(), rest, n);
  }
  if (ext == ".fib.gz") {
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
  // A gradient table stored in the file (MRtrix dw_scheme, DSI Studio b_table) through the DWI reader.
  if (dtf::io::hasEmbeddedGradients(path)) {
    try {
      dtf::io::readDwi(path, "", "");
    } catch (const dtf::Error&) {
    }
  }
  return 0;
}
