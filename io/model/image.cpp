// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/model/image.h"

#include "io/model/error.h"

#include <cstring>

namespace dtf {

Image sideBySide(const Image& left, const Image& right) {
  if (left.height != right.height) throw Error("sideBySide: panes of different heights");
  Image out(left.width + right.width, left.height);
  const std::size_t ls = static_cast<std::size_t>(left.width) * 4;
  const std::size_t rs = static_cast<std::size_t>(right.width) * 4;
  for (int y = 0; y < out.height; ++y) {
    std::memcpy(out.pixel(0, y), left.pixel(0, y), ls);
    std::memcpy(out.pixel(left.width, y), right.pixel(0, y), rs);
  }
  return out;
}

} // namespace dtf
