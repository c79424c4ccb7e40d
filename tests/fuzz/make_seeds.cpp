// Writes the fuzzers' seed corpora with dtfabric's own writers: small phantoms in every tensor layout
// (.nii and .nii.gz, NIfTI-1 and -2), a DWI-shaped 4D volume, gradient tables, .tck/.trk tracts and viewer
// scripts. Usage: dtf_fuzz_seeds DIR (creates DIR/nifti, DIR/gradients, DIR/tck, DIR/trk, DIR/trkgz, DIR/trx,
// DIR/view_script, DIR/formats).
#include "io/diffusion/dwi.h"
#include "io/phantoms.h"
#include "io/formats/tensor_io.h"
#include "io/formats/tracts.h"
#include "io/formats/trx.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>

namespace fs = std::filesystem;
using namespace dtf;

namespace {
void text(const fs::path& p, const std::string& s) {
  std::ofstream(p, std::ios::binary) << s;
}
} // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 1;
  }
  const fs::path dir = argv[1];
  for (const char* sub : {"nifti", "gradients", "tck", "trk", "trkgz", "trx", "view_script", "formats"})
    fs::create_directories(dir / sub);

  io::PhantomOptions small;
  small.size = 4;
  small.spacing = 2.0;
  const io::TensorLayout layouts[] = {io::TensorLayout::Fsl, io::TensorLayout::Mrtrix,
                                      io::TensorLayout::Symmatrix, io::TensorLayout::Dtitk};
  for (const char* name : {"constant", "crossing", "sphere"}) {
    const io::Phantom p = io::makePhantom(name, small);
    for (io::TensorLayout l : layouts)
      for (int version : {1, 2})
        for (const char* ext : {".nii", ".nii.gz"}) {
          if (version == 2 && l != io::TensorLayout::Fsl) continue;
          const std::string stem =
              std::string(name) + "_" + io::layoutName(l) + "_v" + std::to_string(version);
          io::writeTensorVolume((dir / "nifti" / (stem + ext)).string(), p.tensors, l, version);
        }
    io::writeScalarVolume((dir / "nifti" / (std::string(name) + "_scalar.nii")).string(), p.scalar);
  }
  // fuzz_formats: one selector byte (the extension index of fuzz_formats.cpp), then the file.
  {
    const io::Phantom p = io::makePhantom("crossing", small);
    const std::pair<const char*, int> outs[] = {{"t.mif", 0}, {"t.mif.gz", 1}, {"t.nrrd", 3}};
    for (const auto& [name, selector] : outs) {
      const fs::path tmp = dir / "formats" / name;
      io::writeTensorVolume(tmp.string(), p.tensors, io::TensorLayout::Mrtrix);
      std::ifstream in(tmp, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      in.close();
      fs::remove(tmp);
      text(dir / "formats" / (std::string(name) + ".seed"),
           std::string(1, static_cast<char>(selector)) + bytes);
    }
  }
  // A DWI-shaped volume: 4x4x4 with 7 components.
  ScalarVolume dwi(io::makePhantom("constant", small).tensors.grid, 7, 100.0f);
  io::writeScalarVolume((dir / "nifti" / "dwi.nii").string(), dwi);
  io::writeScalarVolume((dir / "nifti" / "dwi.nii.gz").string(), dwi, 2);

  text(dir / "gradients" / "bval", "0 1000 1000 1000 1000 1000 1000\n");
  text(dir / "gradients" / "bvec_fsl",
       "0 1 0 0 0.7071 0.7071 0\n0 0 1 0 0.7071 0 0.7071\n0 0 0 1 0 0.7071 0.7071\n");
  text(dir / "gradients" / "bvec_rows",
       "0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.7071 0.7071 0\n0.7071 0 0.7071\n0 nan nan\n");
  text(dir / "gradients" / "bval_lines", "0\n1000\n2000e0\n3.0E3\n");

  Polylines lines;
  lines.offsets = {0};
  for (int l = 0; l < 3; ++l) {
    for (int i = 0; i <= l + 1; ++i)
      lines.points.emplace_back(static_cast<float>(i), static_cast<float>(l), 1.5f * static_cast<float>(i));
    lines.offsets.push_back(static_cast<std::uint32_t>(lines.points.size()));
  }
  io::writeTck((dir / "tck" / "three.tck").string(), lines);
  io::writeTck((dir / "tck" / "none.tck").string(), Polylines{{}, {0}});
  const Grid grid = io::makePhantom("constant", small).tensors.grid;
  io::writeTrk((dir / "trk" / "three.trk").string(), lines, grid);
  io::writeTrk((dir / "trk" / "none.trk").string(), Polylines{{}, {0}}, grid);
  Polylines rich = lines;
  rich.perLine = {{"w", 1, {1, 2, 3}}};
  rich.perPoint = {{"v", 1, std::vector<float>(lines.points.size(), 0.5f)}};
  rich.groups = {{"g", {0, 2}}};
  io::writeTrk((dir / "trkgz" / "three.trk.gz").string(), rich, grid);
  io::writeTrx((dir / "trx" / "three.trx").string(), rich, grid);
  io::writeTrx((dir / "trx" / "none.trx").string(), Polylines{{}, {0}}, grid);

  text(dir / "view_script" / "tour.dtfs",
       "# a tour\nload brain.nii.gz\nsurface fa=0.3\nfa 0.25\nslice axial 20\nkey PgUp\nrotate 10 -5\npan 3 "
       "4\n"
       "zoom 2\nview anterior\nsplit on\nlinked off\nneurological on\nset lod 1.5\nset colour engineering\n"
       "set lighting off\nwait 3\nscreenshot a.png\nscreenshot-scene b.png\ncamera-save c.json\n"
       "camera-load c.json\nscreenshot --force a.png\ncamera-save --force c.json\ntracts t.tck\nquit\n");
  text(dir / "view_script" / "surfaces.dtfs",
       "surface slice=coronal:3\nsurface plane=0,0,0:0,0,1\nsurface iso=f.nii:0.5\nsurface mesh=m.vtk\n");
  std::printf("seeds written to %s\n", dir.c_str());
  return 0;
}
