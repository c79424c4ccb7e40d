# SPDX-License-Identifier: GPL-3.0-or-later
"""The exceptions dtfabric raises. Each message names the file (or array) and the problem, in the words of
the command-line tool."""


class Error(Exception):
    """Base of dtfabric's errors."""


class FormatError(Error, ValueError):
    """The data is not what it should be: an unreadable, truncated or malformed file, a wrong shape or
    layout, a NaN or singular affine, a surface that comes out empty."""


class FileError(Error, OSError):
    """A file cannot be opened, read or written (missing, a directory, no permission)."""


class UsageError(Error, ValueError):
    """A bad argument or a combination of arguments that does not go together."""


class GlError(Error, RuntimeError):
    """No OpenGL 4.5 context could be made (headless EGL), or rendering failed."""


for _cls in (Error, FormatError, FileError, UsageError, GlError):
    _cls.__module__ = "dtfabric"
