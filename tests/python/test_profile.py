# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric.profile: the table of `dtfabric profile` as numpy columns, against the command-line tool on the
bundled brain, and a linear field along straight lines (closed form) written with nibabel."""

import csv

import nibabel as nib
import numpy as np
import pytest

import dtfabric

COLUMNS = ["bundle", "scalar", "node", "x", "y", "z", "mean", "sd", "ci_low", "ci_high", "streamlines"]


def read_table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f, delimiter="\t"))
    assert rows[0] == COLUMNS
    return rows[1:]


def test_profile_equals_the_cli(derived, cli, tmp_path):
    tracts, fa = derived("tracks_det.tck"), derived("dti_FA.nii.gz")
    p = dtfabric.profile(tracts, [f"fa={fa}"], nodes=50, weights="mean", bootstrap=100, seed=3)
    assert list(p) == COLUMNS
    assert all(len(v) == 50 for v in p.values())
    assert p["node"].dtype == np.int64 and p["mean"].dtype == np.float64
    assert set(p["bundle"]) == {"tracks_det"} and set(p["scalar"]) == {"fa"}
    np.testing.assert_array_equal(p["node"], np.arange(50))
    assert (p["streamlines"] == 2000).all()
    assert (p["ci_low"] <= p["mean"]).all() and (p["mean"] <= p["ci_high"]).all()

    out = tmp_path / "p.tsv"
    cli("profile", tracts, "--scalar", f"fa={fa}", "--nodes", 50, "--weights", "mean", "--bootstrap", 100,
        "--seed", 3, "-o", out)
    rows = read_table(out)
    for name in ("x", "y", "z", "mean", "sd", "ci_low", "ci_high"):
        col = np.array([float(r[COLUMNS.index(name)]) for r in rows])
        np.testing.assert_allclose(p[name], col, rtol=1e-6, atol=1e-3 if name in "xyz" else 1e-7)

    # The scalars as a dict; no bootstrap, no interval.
    q = dtfabric.profile(tracts, {"fa": fa}, nodes=50, weights="mean", bootstrap=0)
    np.testing.assert_allclose(q["mean"], p["mean"], atol=1e-12)
    assert np.isnan(q["ci_low"]).all()


def test_linear_field_and_plot(tmp_path):
    # value = 0.1 + 0.01 x on a 2 mm grid; lines along x from -20 to 20 at several y.
    affine = np.diag([2.0, 2.0, 2.0, 1.0])
    affine[:3, 3] = [-40, -40, -40]
    ijk = np.indices((41, 41, 41)).reshape(3, -1).T
    x = (ijk @ affine[:3, :3].T + affine[:3, 3])[:, 0]
    nib.save(nib.Nifti1Image((0.1 + 0.01 * x).reshape(41, 41, 41).astype(np.float32), affine),
             str(tmp_path / "lin.nii.gz"))
    lines = [np.stack([np.linspace(-20, 20, 15), np.full(15, y), np.zeros(15)], 1).astype(np.float32)
             for y in (-3.0, 0.0, 1.0, 5.0)]
    lines[1] = lines[1][::-1].copy()
    nib.streamlines.save(nib.streamlines.Tractogram(lines, affine_to_rasmm=np.eye(4)), str(tmp_path / "b.tck"))
    p = dtfabric.profile(tmp_path / "b.tck", f"lin={tmp_path / 'lin.nii.gz'}", nodes=9,
                         plot=tmp_path / "b.svg")
    np.testing.assert_allclose(p["x"], np.linspace(-20, 20, 9), atol=1e-4)
    np.testing.assert_allclose(p["mean"], 0.1 + 0.01 * np.linspace(-20, 20, 9), atol=1e-5)
    np.testing.assert_allclose(p["sd"], 0, atol=1e-6)
    assert (tmp_path / "b.svg").read_text().startswith("<?xml")
    # Started near x = 20 (a point, as a tuple): the same profile from the other end.
    r = dtfabric.profile(str(tmp_path / "b.tck"), [f"lin={tmp_path / 'lin.nii.gz'}"], nodes=9, start=(25, 0, 0))
    np.testing.assert_allclose(r["mean"], p["mean"][::-1], atol=1e-6)


def test_profile_errors(derived, tmp_path):
    tracts, fa = derived("tracks_det.tck"), derived("dti_FA.nii.gz")
    with pytest.raises(dtfabric.UsageError, match="give --tensor"):
        dtfabric.profile(tracts, "fa")
    with pytest.raises(dtfabric.UsageError, match="weights"):
        dtfabric.profile(tracts, {"fa": fa}, weights="trimmed")
    with pytest.raises(dtfabric.Error, match="missing.nii.gz"):
        dtfabric.profile(tracts, {"fa": str(tmp_path / "missing.nii.gz")})
    with pytest.raises(dtfabric.Error, match="has no groups"):
        dtfabric.profile(tracts, {"fa": fa}, groups="all")
    with pytest.raises(dtfabric.UsageError, match="png or .svg"):
        dtfabric.profile(tracts, {"fa": fa}, plot=tmp_path / "p.jpg")
