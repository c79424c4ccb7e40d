#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Independent reference reader for the tract-format tests: writes the streamlines of IN as
OUT.points (float32 little-endian, N x 3, world RAS mm), OUT.offsets (int64, lines + 1) and, per data
array, OUT.<dps|dpv>.<index> (float32) with OUT.names listing "<dps|dpv> <name> <components>".
TrackVis and MRtrix files through nibabel; TRX through Python's zipfile and numpy (positions as stored,
which the TRX specification defines as RAS mm); legacy VTK 4.x binary POLYDATA LINES by a direct parse."""
import io, os, re, sys, zipfile
import numpy as np


def trx(path):
    def arrays():
        if os.path.isdir(path):
            for root, _, files in os.walk(path):
                for f in files:
                    full = os.path.join(root, f)
                    yield os.path.relpath(full, path).replace(os.sep, "/"), open(full, "rb").read()
        else:
            z = zipfile.ZipFile(path)
            for n in z.namelist():
                if not n.endswith("/"):
                    yield n, z.read(n)
    data = dict(arrays())
    import json
    header = json.loads(data["header.json"])
    pos_name = next(n for n in data if n.startswith("positions."))
    off_name = next(n for n in data if n.startswith("offsets."))
    pos = np.frombuffer(data[pos_name], dtype=np.dtype(pos_name.split(".")[-1]).newbyteorder("<")).reshape(-1, 3).astype(np.float32)
    off = np.frombuffer(data[off_name], dtype=np.dtype(off_name.split(".")[-1]).newbyteorder("<")).astype(np.int64)
    if len(off) == 0 or off[-1] != header["NB_VERTICES"]:  # offsets without the end entry
        off = np.append(off, header["NB_VERTICES"])
    extra = []
    for n, b in sorted(data.items()):
        m = re.match(r"(dps|dpv)/(.+?)(?:\.(\d+))?\.([a-z0-9]+)$", n)
        if m:
            comps = int(m.group(3) or 1)
            extra.append((m.group(1), m.group(2), comps, np.frombuffer(b, dtype=np.dtype(m.group(4)).newbyteorder("<")).astype(np.float32)))
    return pos, off, extra


def nib(path):
    import nibabel
    t = nibabel.streamlines.load(path)
    s = t.streamlines
    pos = np.asarray(s.get_data(), dtype=np.float32)
    off = np.append(np.asarray(s._offsets, dtype=np.int64), len(pos))
    extra = []
    for k, v in t.tractogram.data_per_point.items():
        arr = np.asarray(v.get_data(), dtype=np.float32)
        extra.append(("dpv", k, arr.shape[1], arr.ravel()))
    for k, v in t.tractogram.data_per_streamline.items():
        arr = np.asarray(v, dtype=np.float32)
        extra.append(("dps", k, arr.shape[1], arr.ravel()))
    return pos, off, extra


def vtk_legacy(path):
    raw = open(path, "rb").read()
    m = re.search(rb"POINTS (\d+) float\s?\n", raw)
    n = int(m.group(1))
    pos = np.frombuffer(raw[m.end():m.end() + 12 * n], dtype=">f4").reshape(-1, 3).astype(np.float32)
    m2 = re.search(rb"LINES (\d+) (\d+)\s?\n", raw)
    cells = np.frombuffer(raw[m2.end():m2.end() + 4 * int(m2.group(2))], dtype=">i4")
    pts, off, i = [], [0], 0
    for _ in range(int(m2.group(1))):
        k = cells[i]
        pts.extend(cells[i + 1:i + 1 + k])
        i += 1 + k
        off.append(len(pts))
    return pos[np.array(pts, dtype=np.int64)], np.array(off, dtype=np.int64), []


def main():
    src, out = sys.argv[1], sys.argv[2]
    low = src.lower().rstrip("/")
    if low.endswith(".trx") or os.path.isdir(src):
        pos, off, extra = trx(src)
    elif low.endswith(".vtk"):
        pos, off, extra = vtk_legacy(src)
    else:
        pos, off, extra = nib(src)
    pos.astype("<f4").tofile(out + ".points")
    off.astype("<i8").tofile(out + ".offsets")
    with open(out + ".names", "w") as f:
        for i, (kind, name, comps, values) in enumerate(extra):
            values.astype("<f4").tofile(out + ".%s.%d" % (kind, i))
            f.write("%s %d %d %s\n" % (kind, i, comps, name))


main()
