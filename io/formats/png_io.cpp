// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/formats/png_io.h"

#include "io/formats/atomic_file.h"
#include "io/model/error.h"

#include <png.h>

#include <cstdio>
#include <memory>

namespace dtf::io {

namespace {
struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;
} // namespace

void writePng(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0) throw InputError("cannot write " + path + ": empty image");
  AtomicOutput out(path);
  {
    FilePtr f(std::fopen(out.tempPath().c_str(), "wb"));
    if (!f) throw InputError("cannot open " + path + " for writing");
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    img.width = static_cast<png_uint_32>(image.width);
    img.height = static_cast<png_uint_32>(image.height);
    img.format = PNG_FORMAT_RGBA;
    if (!png_image_write_to_stdio(&img, f.get(), 0, image.rgba.data(), 0, nullptr))
      throw InputError("cannot write " + path + ": " + img.message);
    if (std::fflush(f.get()) != 0) throw InputError("cannot write " + path + ": flush failed");
  }
  out.commit();
}

Image readPng(const std::string& path) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str()))
    throw InputError("cannot read PNG " + path + ": " + img.message);
  if (img.width > 16384 || img.height > 16384) {
    png_image_free(&img);
    throw InputError("cannot read PNG " + path + ": image too large");
  }
  img.format = PNG_FORMAT_RGBA;
  Image out(static_cast<int>(img.width), static_cast<int>(img.height));
  if (!png_image_finish_read(&img, nullptr, out.rgba.data(), 0, nullptr))
    throw InputError("cannot read PNG " + path + ": " + img.message);
  return out;
}

} // namespace dtf::io
