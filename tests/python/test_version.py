# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric.__version__ is the project's version: `project(dtfabric VERSION X.Y.Z)` in CMakeLists.txt, which
`dtfabric --version` prints too."""

import os
import re
from pathlib import Path

import dtfabric


def project_version():
    root = Path(os.environ.get("DTF_SOURCE_DIR", Path(__file__).resolve().parents[2]))
    m = re.search(r"^project\(dtfabric VERSION ([0-9]+\.[0-9]+\.[0-9]+)[ )]",
                  (root / "CMakeLists.txt").read_text(), re.M)
    assert m, "no `project(dtfabric VERSION X.Y.Z` in CMakeLists.txt"
    return m.group(1)


def test_version_is_the_projects():
    assert isinstance(dtfabric.__version__, str)
    assert dtfabric.__version__ == project_version()


def test_version_is_what_the_command_prints(cli):
    assert cli("--version").stdout == f"dtfabric {dtfabric.__version__}\n"
