#include "app/scene/tract_files.h"

#include "io/model/error.h"
#include "io/tracts.h"
#include "surfaces/polyline_io.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace dtf::app {

namespace {
std::string lowerExt(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}
} // namespace

bool isTractFileName(const std::string& path) {
  const std::string e = lowerExt(path);
  return e == ".tck" || e == ".trk" || e == ".vtk";
}

Polylines readTracts(const std::string& path) {
  const std::string e = lowerExt(path);
  if (e == ".tck") return io::readTck(path);
  if (e == ".trk") return io::readTrk(path);
  if (e == ".vtk") return surfaces::readVtkPolylines(path);
  throw InputError(path + ": unknown tract file extension (use .tck, .trk or .vtk)");
}

void writeTracts(const std::string& path, const Polylines& lines, const Grid* reference) {
  const std::string e = lowerExt(path);
  if (e == ".tck") return io::writeTck(path, lines);
  if (e == ".trk") {
    if (!reference) throw UsageError("writing " + path + ": a .trk file needs a reference grid");
    return io::writeTrk(path, lines, *reference);
  }
  if (e == ".vtk") return surfaces::writeVtkPolylines(path, lines);
  throw InputError("cannot write " + path + ": unknown tract file extension (use .tck, .trk or .vtk)");
}

} // namespace dtf::app
