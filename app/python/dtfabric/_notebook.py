# SPDX-License-Identifier: GPL-3.0-or-later
"""What dtfabric shows inline in Jupyter: rendered images and the web page.

Image is a numpy array (an (H, W, 4) or (H, W, 3) uint8 array, as render() has always returned) that IPython
displays as a PNG through _repr_png_; code that takes the array keeps working with it. WebPage is what web()
returns: the folder's path and its figures, shown inline as an iframe onto the folder's index.html.
"""

import html
import os
import struct
import zlib

import numpy

__all__ = ["Image", "WebPage", "show", "png_bytes"]


def png_bytes(array):
    """The PNG file (bytes) of an (H, W, 4) RGBA or (H, W, 3) RGB uint8 array, or (H, W) grey."""
    a = numpy.asarray(array)
    if a.dtype != numpy.uint8:
        raise TypeError("an image is an array of uint8, not %s" % a.dtype)
    if a.ndim == 2:
        colour_type, channels = 0, 1
    elif a.ndim == 3 and a.shape[2] in (3, 4):
        colour_type, channels = (2, 3) if a.shape[2] == 3 else (6, 4)
    else:
        raise ValueError("an image is (H, W), (H, W, 3) or (H, W, 4), not %s" % (a.shape,))
    height, width = a.shape[0], a.shape[1]
    if height < 1 or width < 1:
        raise ValueError("an image needs at least one pixel")
    rows = numpy.ascontiguousarray(a).reshape(height, width * channels)
    raw = numpy.zeros((height, width * channels + 1), dtype=numpy.uint8)  # filter byte 0 per row
    raw[:, 1:] = rows

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    return (b"\x89PNG\r\n\x1a\n" +
            chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw.tobytes(), 6)) + chunk(b"IEND", b""))


class Image(numpy.ndarray):
    """A rendered image: a numpy uint8 array of shape (H, W, 4) that Jupyter shows as a picture.

    Everything an array does, it does (indexing, arithmetic, numpy functions, matplotlib's imshow);
    numpy.asarray(image) gives the plain array.
    """

    def __new__(cls, array):
        return numpy.asarray(array).view(cls)

    def _repr_png_(self):
        a = self.view(numpy.ndarray)
        if a.dtype != numpy.uint8 or not (a.ndim == 2 or (a.ndim == 3 and a.shape[2] in (3, 4))) or a.size == 0:
            return None  # not a picture (a slice of one, a sum): IPython falls back to the array's repr
        return png_bytes(a)


def show(array):
    """The array (an (H, W, 4) or (H, W, 3) uint8 image, e.g. from render() or movie()) as an Image, which
    Jupyter shows inline."""
    return Image(array)


class WebPage:
    """The folder dtfabric.web() wrote. Shown inline in Jupyter as an iframe onto its index.html (the path
    relative to the notebook's working directory, which Jupyter serves; a folder outside it opens through
    file://, which a browser may refuse inside a page served over http)."""

    def __init__(self, info, height=640):
        self.path = os.path.abspath(info["path"])
        self.index = os.path.join(self.path, "index.html")
        self.slices = tuple(info["slices"])
        self.frames_3d = info["frames_3d"]
        self.fa_frames = info["fa_frames"]
        self.images = info["images"]
        self.bytes = info["bytes"]
        self.seconds = info["seconds"]
        self.height = height

    def url(self):
        """The index.html's address as the notebook's page reaches it."""
        rel = os.path.relpath(self.index, os.getcwd())
        if rel.startswith(".."):
            return "file://" + self.index
        return rel.replace(os.sep, "/")

    def _repr_html_(self):
        return ('<iframe src="%s" width="100%%" height="%d" style="border:1px solid #444" '
                'title="dtfabric web page"></iframe>' % (html.escape(self.url(), quote=True), self.height))

    def __repr__(self):
        return ("WebPage(%r: %d axial, %d coronal, %d sagittal slices, %d 3D frames, %d FA thresholds, "
                "%.1f MB in %.1f s)" % (self.index, self.slices[0], self.slices[1], self.slices[2],
                                        self.frames_3d, self.fa_frames, self.bytes / 1e6, self.seconds))
