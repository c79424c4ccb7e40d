// SPDX-License-Identifier: GPL-3.0-or-later
// PNG files for rendered images and baselines.
#pragma once

#include "io/model/image.h"

#include <string>

namespace dtf::io {

// Writes an RGBA8 PNG atomically (temporary file renamed into place). Throws InputError on failure.
void writePng(const std::string& path, const Image& image);
// Reads any PNG as RGBA8. Throws InputError naming the file on failure.
Image readPng(const std::string& path);

} // namespace dtf::io
