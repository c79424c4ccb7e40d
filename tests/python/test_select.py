# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric.select: the command's ROI selection from Python, on arrays with known answers and on the real
tracts beside `dtfabric select`."""

import numpy as np
import pytest

import dtfabric


def line(a, b, n):
    return np.linspace(np.asarray(a, np.float32), np.asarray(b, np.float32), n).astype(np.float32)


def test_spheres_boxes_and_order_on_arrays():
    lines = [line((-10, 0, 0), (10, 0, 0), 21),   # through both spheres, A first
             line((10, 0, 0), (-10, 0, 0), 21),   # B first
             line((-10, 5, 0), (10, 5, 0), 21)]   # misses both
    a, b = "-8,0,0,1.5", "8,0,0,1.5"
    r = dtfabric.select(lines, include=[a, b])
    assert r["indices"].tolist() == [0, 1]
    assert r["total"] == 3
    assert dtfabric.select(lines, include_ordered=[a, b])["indices"].tolist() == [0]
    assert dtfabric.select(lines, include_ordered=[b, a])["indices"].tolist() == [1]
    assert dtfabric.select(lines, exclude="0,5,0,1")["indices"].tolist() == [0, 1]
    kept = dtfabric.select(lines, include="box:-1,4,-1,1,6,1")
    assert kept["indices"].tolist() == [2]
    np.testing.assert_array_equal(kept["streamlines"][0], lines[2])
    # A sphere between two vertices 1 mm apart: only precise sees it.
    assert dtfabric.select(lines, include="0.5,0.5,0,0.6")["indices"].tolist() == []
    assert dtfabric.select(lines, include="0.5,0.5,0,0.6", precise=True)["indices"].tolist() == [0, 1]
    assert dtfabric.select(lines, include=a, ends_only=True)["indices"].tolist() == []


def test_bad_regions_raise_with_the_spec():
    lines = [line((0, 0, 0), (1, 0, 0), 2)]
    with pytest.raises(dtfabric.Error, match="radius"):
        dtfabric.select(lines, include="0,0,0,-1")
    with pytest.raises(dtfabric.Error, match="inverted"):
        dtfabric.select(lines, include="box:1,1,1,0,0,0")
    with pytest.raises(dtfabric.Error, match="no such file"):
        dtfabric.select(lines, include="/nonexistent/mask.nii.gz")


def test_file_selection_equals_the_command(shared, cli, tmp_path):
    tracks = shared("iu_prisma_dwi/derived/tracks_det.tck")
    spheres = ["18,3.7,21.6,6", "20,0,45,10"]
    out = tmp_path / "py.tck"
    r = dtfabric.select(tracks, include=spheres, output=out)
    cli("select", tracks, "-o", str(tmp_path / "cli.tck"), "--include", spheres[0], "--include", spheres[1])
    ours = dtfabric.select(str(tmp_path / "cli.tck"))
    assert len(r["streamlines"]) == len(ours["streamlines"]) > 20
    for x, y in zip(r["streamlines"], ours["streamlines"]):
        np.testing.assert_array_equal(x, y)
    assert out.exists()
    with pytest.raises(dtfabric.Error, match="force"):
        dtfabric.select(tracks, include=spheres, output=out)
