// SPDX-License-Identifier: GPL-3.0-or-later
// GLSL sources embedded into the binary at build time (cmake/embed_shaders.cmake). Files are looked up
// by their path relative to shaders/, e.g. "fabric/advection.frag". `#include "x.glsl"` directives and
// variant defines are resolved by render's ShaderProgram, which also maps compile errors back to the file
// and line.
#pragma once

#include <string_view>
#include <vector>

namespace dtf::shaders {

// Source text of an embedded file, or nullptr if there is none of that name.
const char* find(std::string_view name);
// All embedded file names.
std::vector<std::string_view> names();

} // namespace dtf::shaders
