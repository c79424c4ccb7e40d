# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric.bootstrap and dtfabric.uncertainty: the cone of uncertainty as numpy arrays, equal to what
`dtfabric fit --bootstrap N --cone FILE` writes (read back with nibabel when present), and render(uncertainty=)
giving the pixels of `dtfabric render --uncertainty`."""

from pathlib import Path

import numpy as np
import pytest

import dtfabric
from conftest import read_png, render_or_skip


def sample_dwi():
    import os
    return Path(os.environ.get("DTF_SOURCE_DIR", Path(__file__).resolve().parents[2])) / "sample_data" / "dwi.nii.gz"


def test_bootstrap_and_cone_file_agree(cli, tmp_path):
    dwi = sample_dwi()
    cone_path = tmp_path / "cone.nii.gz"
    cli("fit", dwi, "--bootstrap", "20", "--cone", cone_path, "--fa-sd", tmp_path / "fasd.nii.gz",
        "-o", tmp_path / "tensor.nii.gz", "--threads", "2")
    result = dtfabric.bootstrap(dwi, resamples=20, threads=2)
    cone = result["cone"]
    assert cone.dtype == np.float32 and cone.ndim == 3
    inside = np.isfinite(cone)
    assert 0.05 < inside.mean() < 0.9
    assert np.all((cone[inside] >= 0) & (cone[inside] <= 90))
    assert np.all(np.isfinite(result["fa_sd"]) == inside)
    read, affine = dtfabric.uncertainty(cone_path)
    np.testing.assert_array_equal(np.isfinite(read), inside)
    np.testing.assert_allclose(read[inside], cone[inside], atol=1e-5)
    np.testing.assert_allclose(affine, result["affine"], atol=1e-5)
    assert result["tensors"].tensor.shape[:3] == cone.shape


def test_render_with_uncertainty_equals_cli(cli, tmp_path):
    dwi = sample_dwi()
    cone_path = tmp_path / "cone.nii.gz"
    cli("fit", dwi, "--bootstrap", "10", "--cone", cone_path, "-o", tmp_path / "t.nii.gz", "--threads", "2")
    ours = render_or_skip(tmp_path / "t.nii.gz", surface="slice=axial", size=(192, 192), uncertainty=cone_path)
    out = tmp_path / "cli.png"
    cli("render", tmp_path / "t.nii.gz", "--surface", "slice=axial", "--size", "192x192", "--uncertainty", cone_path,
        "-o", out)
    np.testing.assert_array_equal(ours, read_png(out))
    plain = render_or_skip(tmp_path / "t.nii.gz", surface="slice=axial", size=(192, 192))
    assert np.any(ours != plain)


def test_bad_cone_map_is_an_exception(tmp_path):
    with pytest.raises(dtfabric.Error) as e:
        dtfabric.uncertainty(tmp_path / "missing.nii.gz")
    assert "missing.nii.gz" in str(e.value)
