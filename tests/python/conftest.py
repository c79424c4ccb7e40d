# SPDX-License-Identifier: GPL-3.0-or-later
"""Fixtures of the dtfabric Python tests: the shared real data (skip when missing, fail under
DTF_REQUIRE_SHARED_DATA=1), the built command-line tool (DTF_EXE) and readers of its outputs that do not use
dtfabric (PNG through zlib, MRtrix .tck)."""

import json
import os
import struct
import subprocess
import zlib
from pathlib import Path

import numpy as np
import pytest

import dtfabric


def _flag(name):
    v = os.environ.get(name, "")
    return v not in ("", "0")


def shared_data_dir():
    if os.environ.get("DTF_SHARED_DATA"):
        return Path(os.environ["DTF_SHARED_DATA"])
    return Path(os.environ.get("DTF_SOURCE_DIR", Path(__file__).resolve().parents[2])).parent / "shared" / "data"


@pytest.fixture
def shared():
    """shared("iu_prisma_dwi/dwi.nii.gz") -> the path as str; skips (or fails) when missing."""

    def get(rel):
        p = shared_data_dir() / rel
        if not p.exists():
            if _flag("DTF_REQUIRE_SHARED_DATA"):
                pytest.fail(f"shared data missing: {p}")
            pytest.skip(f"shared data missing: {p}")
        return str(p)

    return get


@pytest.fixture
def derived(shared):
    return lambda rel: shared("iu_prisma_dwi/derived/" + rel)


@pytest.fixture
def cli():
    """cli("info", FILE, ...) -> CompletedProcess of the built dtfabric executable (text)."""
    exe = os.environ.get("DTF_EXE")
    if not exe or not Path(exe).exists():
        pytest.fail(f"DTF_EXE does not name the built dtfabric executable: {exe!r}")

    def run(*args, check=True):
        r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"dtfabric {' '.join(map(str, args))} exited {r.returncode}: {r.stderr}")
        return r

    return run


@pytest.fixture
def cli_json(cli):
    return lambda *args: json.loads(cli(*args).stdout)


def render_or_skip(*args, **kwargs):
    """dtfabric.render, skipping when no GL context can be made (failing under DTF_REQUIRE_GL=1)."""
    try:
        return dtfabric.render(*args, **kwargs)
    except dtfabric.GlError as e:
        if _flag("DTF_REQUIRE_GL"):
            raise
        pytest.skip(f"no GL context: {e}")


def read_png(path):
    """A minimal PNG decoder (8-bit RGB/RGBA, non-interlaced: what dtfabric writes) -> (H, W, 4) uint8."""
    data = Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"IDAT":
            idat += chunk
        elif kind == b"IEND":
            break
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (2, 6) and interlace == 0, f"{path}: unsupported PNG {header}"
    channels = 4 if colour == 6 else 3
    raw = zlib.decompress(idat)
    stride = width * channels
    out = np.zeros((height, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=y * (stride + 1) + 1).astype(np.int32)
        cur = np.zeros(stride, dtype=np.int32)
        if f in (0, 2):
            cur = (line + (prev if f == 2 else 0)) & 0xFF
        else:  # sub, average, Paeth depend on the pixel to the left: per pixel
            for x in range(stride):
                a = cur[x - channels] if x >= channels else 0
                b = prev[x]
                c = prev[x - channels] if x >= channels else 0
                if f == 1:
                    pred = a
                elif f == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[x] = (line[x] + pred) & 0xFF
        out[y] = cur
        prev = cur
    img = out.reshape(height, width, channels).astype(np.uint8)
    if channels == 3:
        img = np.concatenate([img, np.full((height, width, 1), 255, np.uint8)], axis=2)
    return img


def read_tck(path):
    """MRtrix .tck (Float32LE) -> list of (N, 3) float32 arrays."""
    data = Path(path).read_bytes()
    end = data.index(b"\nEND\n")
    header = data[:end].decode().splitlines()
    fields = dict(line.split(": ", 1) for line in header[1:] if ": " in line)
    assert fields["datatype"] == "Float32LE"
    offset = int(fields["file"].split()[1])
    pts = np.frombuffer(data, dtype="<f4", offset=offset)
    pts = pts[: len(pts) // 3 * 3].reshape(-1, 3)
    lines, start = [], 0
    for i, p in enumerate(pts):
        if np.isinf(p).all():
            break
        if np.isnan(p).all():
            lines.append(pts[start:i])
            start = i + 1
    return lines
