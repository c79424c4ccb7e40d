// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target: the region set file (ui/session/region_spec.h), JSON text in, a region set or an
// InputError out; a set that parses is written back and read again, and must give the same regions.
#include "io/model/error.h"
#include "ui/session/region_spec.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // Image paths resolve against a folder that holds none, so only spheres and boxes parse.
    const dtf::surfaces::RegionSet set = dtf::session::parseRegionSet(text, "fuzz.json", "/nonexistent");
    const dtf::surfaces::RegionSet again =
        dtf::session::parseRegionSet(dtf::session::regionSetText(set), "again.json", "/nonexistent");
    if (again.regions.size() != set.regions.size() || again.endsOnly != set.endsOnly ||
        again.precise != set.precise)
      std::abort();
    for (std::size_t i = 0; i < set.regions.size(); ++i)
      if (again.regions[i].kind != set.regions[i].kind || again.regions[i].shape != set.regions[i].shape ||
          again.regions[i].centre != set.regions[i].centre || again.regions[i].radius != set.regions[i].radius ||
          again.regions[i].lo != set.regions[i].lo || again.regions[i].hi != set.regions[i].hi ||
          again.regions[i].name != set.regions[i].name)
        std::abort();
  } catch (const dtf::Error&) {
  }
  return 0;
}
