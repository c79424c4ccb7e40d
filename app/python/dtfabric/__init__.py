# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric: fabric-like tensor LIC (Eichelbaum et al.) for diffusion MRI, from Python.

    import dtfabric
    field = dtfabric.load("dti_tensor.nii.gz")        # .tensor (X,Y,Z,6) world RAS mm^2/s, .affine
    rgba = dtfabric.render(field, surface="slice=axial:22", size=(512, 512))   # (H, W, 4) uint8

Everything runs the command-line tool's own code: load() reads what `dtfabric info` and `dtfabric render`
read, render() gives the pixels `dtfabric render` writes for the same arguments, track() and check() are
`dtfabric track` and `dtfabric check --json`. Rendering is headless (EGL) and needs no display; all GL work
runs on one thread of the module, so render() may be called from any Python thread (calls run one at a
time). Long work releases the GIL.
"""

from ._errors import Error, FileError, FormatError, GlError, UsageError
from ._core import (FibreSet, Surface, TensorField, bootstrap, check, fabric_options, load, movie, read_png,
                    render, select, surface, track, uncertainty)
from ._core import __version__  # the project's version (CMakeLists.txt), as `dtfabric --version` prints it

__all__ = [
    "Error", "FileError", "FormatError", "GlError", "UsageError",
    "FibreSet", "Surface", "TensorField",
    "load", "render", "movie", "surface", "track", "select", "check", "read_png", "fabric_options", "bootstrap", "uncertainty",
]
