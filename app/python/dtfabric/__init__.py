# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric: fabric-like tensor LIC (Eichelbaum et al.) for diffusion MRI, from Python.

    import dtfabric
    field = dtfabric.load("dti_tensor.nii.gz")        # .tensor (X,Y,Z,6) world RAS mm^2/s, .affine
    rgba = dtfabric.render(field, surface="slice=axial:22", size=(512, 512))   # (H, W, 4) uint8
    page = dtfabric.web(field, "page")               # the web page's folder, inline in Jupyter

Everything runs the command-line tool's own code: load() reads what `dtfabric info` and `dtfabric render`
read, render() gives the pixels `dtfabric render` writes for the same arguments, track() and check() are
`dtfabric track` and `dtfabric check --json`, and profile() returns the table of `dtfabric profile` as numpy
columns (pandas.DataFrame(dtfabric.profile("cst.tck", "fa", tensor="dti_tensor.nii.gz")) is the table).
Rendering is headless (EGL) and needs no display; all GL work runs on one thread of the module, so render()
may be called from any Python thread (calls run one at a time). Long work releases the GIL.
"""

from ._errors import Error, FileError, FormatError, GlError, UsageError
from ._core import (FibreSet, Surface, TensorField, bootstrap, check, fabric_options, load, movie, profile,
                    read_png, select, surface, track, uncertainty)
from ._core import __version__  # the project's version (CMakeLists.txt), as `dtfabric --version` prints it
from . import _core
from ._notebook import Image, WebPage, show

__all__ = [
    "Error", "FileError", "FormatError", "GlError", "UsageError",
    "FibreSet", "Surface", "TensorField",
    "load", "render", "movie", "surface", "track", "select", "profile", "check", "read_png", "fabric_options",
    "bootstrap", "uncertainty", "Image", "WebPage", "show", "web",
]


def render(*args, **kwargs):
    return Image(_core.render(*args, **kwargs))


render.__doc__ = (_core.render.__doc__ or "") + """

Returns an Image: the (H, W, 4) uint8 array, which Jupyter shows inline."""


def web(input, output, height=640, **kwargs):
    """Writes the folder of `dtfabric web` (index.html; the slices, the 3D view of an FA isosurface and the
    FA sweep) and returns a WebPage, which Jupyter shows inline as an iframe onto it (`height` pixels tall).
    Keywords: size=512, surface="fa=0.25", slices_only=False, azimuths=36, fa_steps=10, background, tracts,
    title, force=False, layout, bval, bvec, mask (as the command's flags)."""
    return WebPage(_core.web(input, output, **kwargs), height)
