# SPDX-License-Identifier: GPL-3.0-or-later
"""ctest's entry to the pytest suite: fails rather than skips when pytest or numpy is missing under
DTF_REQUIRE_TOOLS=1 (CI); otherwise exits 77 (ctest's skip) in that case."""
import os
import sys

try:
    import numpy  # noqa: F401
    import pytest
except ImportError as e:
    print(f"python3-pytest/python3-numpy missing for {sys.executable}: {e}", file=sys.stderr)
    sys.exit(1 if os.environ.get("DTF_REQUIRE_TOOLS", "") not in ("", "0") else 77)

sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", os.path.dirname(os.path.abspath(__file__))] + sys.argv[1:]))
