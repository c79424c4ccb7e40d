// SPDX-License-Identifier: GPL-3.0-or-later
// Triangle meshes from and to files (PLY, OBJ, legacy VTK, VTP) through VTK's readers and writers.
// Coordinates are taken as world RAS mm.
#pragma once

#include "io/model/geometry.h"

#include <string>

namespace dtf::surfaces {

// Reads a mesh; polygons are triangulated and normals computed when the file has none.
// Throws InputError naming the file on failure or when it holds no triangles.
Mesh readMesh(const std::string& path);
// Writes .ply, .vtp or .obj (by extension), atomically. Throws InputError.
void writeMesh(const std::string& path, const Mesh& mesh);

} // namespace dtf::surfaces
