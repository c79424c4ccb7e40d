// SPDX-License-Identifier: GPL-3.0-or-later
// Writes the fuzzers' seed corpora with dtfabric's own writers: small phantoms in every tensor layout
// (.nii and .nii.gz, NIfTI-1 and -2), a DWI-shaped 4D volume, gradient tables, .tck/.trk tracts and viewer
// scripts. Usage: dtf_fuzz_seeds DIR (creates DIR/nifti, DIR/gradients, DIR/tck, DIR/trk, DIR/trkgz, DIR/trx,
// DIR/view_script, DIR/formats, and one folder per format family: DIR/mrtrix, DIR/nrrd, DIR/afni, DIR/dsi,
// DIR/bids). A seed of a family target is its selector byte (fuzz_formats.cpp), the file, and optionally
// "\n@@data@@\n" and its companion file.
#include "io/diffusion/dwi.h"
#include "io/phantoms.h"
#include "io/formats/tensor_io.h"
#include "io/formats/tracts.h"
#include "io/formats/trx.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
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

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename T> void put(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

std::string floatBytes(std::size_t n, float first, float step) {
  std::string s;
  for (std::size_t i = 0; i < n; ++i)
    put(s, first + step * static_cast<float>(i % 7));
  return s;
}

// A MATLAB v4 numeric matrix as DSI Studio writes them (little-endian, float unless `type` says otherwise).
std::string matlab4(const std::string& name, int type, int rows, int cols, const std::string& payload) {
  std::string m;
  for (std::int32_t v : {type, rows, cols, 0, static_cast<std::int32_t>(name.size() + 1)})
    put(m, v);
  return m + name + '\0' + payload;
}

std::string gzipped(const fs::path& scratch, const std::string& raw) {
  const fs::path plain = scratch / "gz.tmp";
  text(plain, raw);
  const std::string cmd = "gzip -nf '" + plain.string() + "'";
  if (std::system(cmd.c_str()) != 0) return {};
  const std::string z = slurp(scratch / "gz.tmp.gz");
  fs::remove(scratch / "gz.tmp.gz");
  return z;
}

void seed(const fs::path& p, int selector, const std::string& file, const std::string& companion = "",
          bool withCompanion = false) {
  text(p, std::string(1, static_cast<char>(selector)) + file +
              (withCompanion ? "\n@@data@@\n" + companion : std::string()));
}
} // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 1;
  }
  const fs::path dir = argv[1];
  for (const char* sub : {"nifti", "gradients", "tck", "trk", "trkgz", "trx", "view_script", "regions", "formats", "mrtrix",
                          "nrrd", "afni", "dsi", "bids"})
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
  // Family targets (selector = index among the family's extensions in fuzz_formats.cpp).
  {
    const io::Phantom p = io::makePhantom("crossing", small);
    const fs::path tmp = dir / "mrtrix" / "t.mif";
    io::writeTensorVolume(tmp.string(), p.tensors, io::TensorLayout::Mrtrix);
    seed(dir / "mrtrix" / "tensor_mif", 0, slurp(tmp));
    io::writeTensorVolume((dir / "mrtrix" / "t.mif.gz").string(), p.tensors, io::TensorLayout::Mrtrix);
    seed(dir / "mrtrix" / "tensor_mif_gz", 1, slurp(dir / "mrtrix" / "t.mif.gz"));
    fs::remove(tmp);
    fs::remove(dir / "mrtrix" / "t.mif.gz");
    const std::string geom = "dim: 2,2,2,4\nvox: 2,2,2\nlayout: -0,+1,+2,+3\ntransform: 1,0,0,0\n"
                             "transform: 0,1,0,0\ntransform: 0,0,1,0\n";
    const std::string scheme =
        "dw_scheme: 0,0,0,0\ndw_scheme: 1,0,0,1000\ndw_scheme: 0,1,0,1000\ndw_scheme: 0,0,1,1000\n";
    seed(dir / "mrtrix" / "dwi_mih", 2,
         "mrtrix image\n" + geom + "datatype: Float32LE\n" + scheme + "scaling: 0,1\nfile: data.raw 0\nEND\n",
         floatBytes(32, 100, 10), true);
    std::string mif = "mrtrix image\n" + geom + "datatype: Int16BE\n" + scheme + "file: . 256\nEND\n";
    mif.resize(256, '\0');
    seed(dir / "mrtrix" / "dwi_int16be_mif", 0, mif + std::string(64, '\x01'));
    std::string bit = "mrtrix image\ndim: 4,4,4\nvox: 1,1,1\nlayout: +2,+1,+0\ndatatype: Bit\nfile: . 128\nEND\n";
    bit.resize(128, '\0');
    seed(dir / "mrtrix" / "mask_bit_mif", 0, bit + std::string(8, '\x5a'));

    io::writeTensorVolume((dir / "nrrd" / "t.nrrd").string(), p.tensors, io::TensorLayout::Mrtrix);
    seed(dir / "nrrd" / "tensor_nrrd_gzip", 0, slurp(dir / "nrrd" / "t.nrrd"));
    fs::remove(dir / "nrrd" / "t.nrrd");
    const std::string nhdr = "NRRD0004\ntype: float\ndimension: 4\nsizes: 7 2 2 2\n"
                             "kinds: 3D-masked-symmetric-matrix space space space\n"
                             "space: left-posterior-superior\nspace directions: none (2,0,0) (0,2,0) (0,0,2)\n"
                             "space origin: (1,2,3)\nmeasurement frame: (1,0,0) (0,1,0) (0,0,1)\n"
                             "endian: little\nencoding: raw\ndata file: data.raw\n";
    std::string tensors;
    for (int v = 0; v < 8; ++v)
      for (float c : {1.0f, 1e-3f, 0.0f, 0.0f, 1e-3f, 0.0f, 1e-3f})
        put(tensors, c);
    seed(dir / "nrrd" / "tensor_nhdr", 1, nhdr, tensors, true);
    seed(dir / "nrrd" / "scalar_ascii_nrrd", 0,
         "NRRD0005\ntype: short\ndimension: 3\nsizes: 2 2 2\nspacings: 1 1 1.5\nencoding: ascii\n\n"
         "1 2 3 4 5 6 7 8\n");

    const std::string head = "type = integer-attribute\nname = DATASET_RANK\ncount = 8\n 3 3 0 0 0 0 0 0\n\n"
                             "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 5\n 4 4 4 0 0\n\n"
                             "type = float-attribute\nname = IJK_TO_DICOM_REAL\ncount = 12\n"
                             " -2 0 0 3 0 -2 0 3 0 0 2 -3\n\n"
                             "type = integer-attribute\nname = BRICK_TYPES\ncount = 3\n 3 3 3\n\n"
                             "type = float-attribute\nname = BRICK_FLOAT_FACS\ncount = 3\n 0 0 0\n\n"
                             "type = string-attribute\nname = BYTEORDER_STRING\ncount = 10\n'LSB_FIRST~\n\n"
                             "type = string-attribute\nname = BRICK_LABS\ncount = 12\n'x~y~z~\n";
    seed(dir / "afni" / "vector_head_brik", 0, head, floatBytes(64 * 3, 0.1f, 0.1f), true);
    seed(dir / "afni" / "vector_head_brik_gz", 0, head, gzipped(dir / "afni", floatBytes(64 * 3, 0.1f, 0.1f)),
         true);
    seed(dir / "afni" / "orient_specific", 0,
         "type = integer-attribute\nname = DATASET_DIMENSIONS\ncount = 3\n 2 2 2\n\n"
         "type = integer-attribute\nname = ORIENT_SPECIFIC\ncount = 3\n 1 2 4\n\n"
         "type = float-attribute\nname = ORIGIN\ncount = 3\n 0 0 0\n\n"
         "type = float-attribute\nname = DELTA\ncount = 3\n 1 1 1\n\n"
         "type = integer-attribute\nname = BRICK_TYPES\ncount = 1\n 1\n",
         std::string(16, '\x02'), true);

    std::string dims, vox, btable;
    for (std::int16_t d : {2, 2, 2})
      put(dims, d);
    for (float v : {2.f, 2.f, 2.f})
      put(vox, v);
    for (float v : {0.f, 0.f, 0.f, 0.f, 1000.f, 1.f, 0.f, 0.f, 1000.f, 0.f, 1.f, 0.f, 1000.f, 0.f, 0.f, 1.f})
      put(btable, v);
    std::string src = matlab4("dimension", 30, 1, 3, dims) + matlab4("voxel_size", 10, 1, 3, vox) +
                      matlab4("b_table", 10, 4, 4, btable);
    for (int k = 0; k < 4; ++k) {
      std::string img;
      for (int i = 0; i < 8; ++i)
        put(img, static_cast<std::uint16_t>(1000 - 300 * (k > 0) + i));
      src += matlab4("image" + std::to_string(k), 40, 4, 2, img);
    }
    seed(dir / "dsi" / "src_gz", 0, gzipped(dir / "dsi", src));
    std::string verts;
    for (float v : {1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f})
      put(verts, v);
    std::string idx;
    for (int i = 0; i < 8; ++i)
      put(idx, static_cast<std::int16_t>(i % 3));
    const std::string fib = matlab4("dimension", 20, 1, 3, std::string("\x02\0\0\0\x02\0\0\0\x02\0\0\0", 12)) +
                            matlab4("voxel_size", 10, 1, 3, vox) + matlab4("odf_vertices", 10, 3, 3, verts) +
                            matlab4("fa0", 10, 1, 8, floatBytes(8, 0.0f, 0.1f)) +
                            matlab4("index0", 30, 1, 8, idx) + matlab4("dti_fa", 10, 1, 8, floatBytes(8, 0.2f, 0.1f)) +
                            matlab4("report", 51, 1, 4, "abcd");
    seed(dir / "dsi" / "fib_gz", 1, gzipped(dir / "dsi", fib));

    text(dir / "bids" / "one_subject",
         "dataset_description.json={\"Name\": \"demo\", \"BIDSVersion\": \"1.8.0\"}\n"
         "sub-01/dwi/sub-01_dwi.nii.gz\nsub-01/dwi/sub-01_dwi.bval=0 1000 1000\\n\n"
         "sub-01/dwi/sub-01_dwi.bvec=0 1 0\\n0 0 1\\n0 0 0\\n\nsub-01/anat/\n");
    text(dir / "bids" / "sessions",
         "dataset_description.json={\"Name\": \"two\"}\nsub-A/ses-1/dwi/sub-A_ses-1_acq-b1_run-1_dwi.nii\n"
         "sub-A/ses-1/dwi/sub-A_ses-1_acq-b1_run-1_dwi.bval=0\nsub-A/ses-2/dwi/sub-A_ses-2_dwi.nii.gz\n"
         "sub-B/dwi/sub-B_desc-x_dwi.nii\nsub-B/dwi/sub-C_dwi.nii\nsub-B/dwi/sub-B_dwi.bvec=1 2 3\n");
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

  text(dir / "regions" / "cst.json",
       R"({"format": "dtfabric-regions", "version": 1, "ends_only": false, "precise": true, "regions": [
  {"name": "internal capsule", "kind": "include", "shape": "sphere", "centre": [18, 3.7, 21.6], "radius": 6},
  {"kind": "include-ordered", "shape": "box", "min": [10, -5, 30], "max": [30, 10, 60], "visible": false},
  {"kind": "exclude", "shape": "mask", "image": "aparc.nii.gz", "labels": [1024, 2024]}]})");
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
