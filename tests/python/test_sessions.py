# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric.surface, track and check on known anatomy, and track/check against the command-line tool."""

import numpy as np
import pytest

import dtfabric
from conftest import read_tck

CC = (33, 42, 22)
CST = (30, 34, 15)


def world(field, ijk):
    return (field.affine @ np.array([*ijk, 1.0]))[:3]


def test_surface_arrays(derived):
    field = dtfabric.load(derived("dti_tensor.nii.gz"))
    s = dtfabric.surface(field, "fa=0.3")
    v, f, n = s.vertices, s.faces, s.normals
    assert v.dtype == np.float32 and v.shape[1] == 3 and n.shape == v.shape
    assert f.shape[1] == 3 and len(f) > 1000 and f.min() >= 0 and f.max() < len(v)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1, atol=1e-3)
    # Within the grid (voxel centres, plus the isosurface's reach of one voxel beyond them).
    lo, hi = world(field, (0, 0, 0)), world(field, np.array(field.shape) - 1)
    assert (v.min(axis=0) >= np.minimum(lo, hi) - 3).all() and (v.max(axis=0) <= np.maximum(lo, hi) + 3).all()
    # The white matter of a brain, not a box: well inside the field of view.
    assert np.ptp(v[:, 0]) > 60 and np.ptp(v[:, 2]) > 40

    axial = dtfabric.surface(derived("dti_tensor.nii.gz"), "slice=axial:22")
    np.testing.assert_allclose(axial.vertices[:, 2], world(field, (0, 0, 22))[2], atol=1e-3)
    np.testing.assert_allclose(np.abs(axial.normals[:, 2]), 1, atol=1e-3)


def test_track_equals_cli_and_runs_with_the_anatomy(derived, cli, tmp_path):
    path = derived("dti_tensor.nii.gz")
    field = dtfabric.load(path)
    for ijk, axis in ((CC, 0), (CST, 2)):
        x, y, z = world(field, ijk)
        lines = dtfabric.track(field, seed_sphere=(x, y, z, 3.0), select=40, seed=7, threads=2)
        assert len(lines) == 40 and all(l.dtype == np.float32 and l.shape[1] == 3 for l in lines)
        # Where they pass the seed region, the streamlines run along the tract.
        along = []
        for l in lines:
            near = np.linalg.norm(l[:-1] - (x, y, z), axis=1) < 6
            step = np.diff(l, axis=0)[near]
            along.append(np.mean(np.abs(step[:, axis]) / np.linalg.norm(step, axis=1)))
        assert np.median(along) > 0.8, (axis, np.median(along))
        out = tmp_path / f"t{axis}.tck"
        cli("track", path, "-o", out, "--seed-sphere", f"{x!r},{y!r},{z!r},3", "--select", 40, "--seed", 7,
            "--threads", 2, "--force")
        theirs = read_tck(out)
        assert len(theirs) == len(lines)
        for a, b in zip(lines, theirs):
            np.testing.assert_array_equal(a, b)


def test_track_options(derived):
    field = dtfabric.load(derived("dti_tensor.nii.gz"))
    lines = dtfabric.track(field, seed_slice="axial:22", seeds=200, min_length=20, rk4=False)
    assert 0 < len(lines) <= 200
    assert all(np.linalg.norm(np.diff(l, axis=0), axis=1).sum() >= 20 - 1e-3 for l in lines)
    with pytest.raises(dtfabric.UsageError):
        dtfabric.track(field, seeds_per_voxel=2)
    with pytest.raises(dtfabric.UsageError):
        dtfabric.track(field, select=10, seeds=10)


def test_check_equals_cli(shared, cli_json):
    dwi = shared("iu_prisma_dwi/dwi.nii.gz")
    ours = dtfabric.check(dwi)
    theirs = cli_json("check", dwi, "--json")
    assert set(ours) == set(theirs)
    assert ours["verdict"] == theirs["verdict"] == "ok"
    for key, value in theirs.items():
        if key == "seconds":
            continue
        if key == "candidates":
            assert [c["name"] for c in ours[key]] == [c["name"] for c in value]
            np.testing.assert_allclose([c["score"] for c in ours[key]], [c["score"] for c in value], atol=2e-6)
            assert [c["matrix"] for c in ours[key]] == [c["matrix"] for c in value]
        elif isinstance(value, float):
            assert ours[key] == pytest.approx(value, abs=2e-6), key
        elif key != "input":
            assert ours[key] == value, key


def test_check_finds_a_flipped_table(shared, tmp_path):
    bvec = np.loadtxt(shared("iu_prisma_dwi/dwi.bvec"))
    bvec[0] = -bvec[0]
    flipped = tmp_path / "flipped.bvec"
    np.savetxt(flipped, bvec, fmt="%.6f")
    r = dtfabric.check(shared("iu_prisma_dwi/dwi.nii.gz"), bval=shared("iu_prisma_dwi/dwi.bval"), bvec=flipped)
    assert r["verdict"] == "corrected"
    assert r["correction"] == [[-1, 0, 0], [0, 1, 0], [0, 0, 1]]
