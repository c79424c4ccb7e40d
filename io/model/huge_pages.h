// SPDX-License-Identifier: GPL-3.0-or-later
// Large buffers on transparent huge pages where the kernel grants them on request (THP "madvise" mode, as
// on Debian 12). A buffer of hundreds of MB otherwise takes a page fault per 4 KiB on first touch, which on
// some virtual machines costs more than the work done in it: an HCP-sized tensor .nii.gz took 1.3 s to
// load there against 0.2 s on huge pages, almost all of the difference in page faults.
#pragma once

#include <cstddef>
#include <vector>

namespace dtf {

// Asks the kernel to back [data, data + bytes) with huge pages; nothing for buffers below 4 MiB, off
// Linux, or where the kernel refuses (the pages stay ordinary). Call it before the buffer is first touched.
void adviseHugePages(void* data, std::size_t bytes);

// v = n copies of fill, its storage advised (adviseHugePages) before it is written.
template <typename T> void assignAdvised(std::vector<T>& v, std::size_t n, const T& fill) {
  if (v.capacity() < n) {
    std::vector<T>().swap(v);
    v.reserve(n);
    adviseHugePages(v.data(), n * sizeof(T));
  }
  v.assign(n, fill);
}

} // namespace dtf
