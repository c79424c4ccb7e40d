# SPDX-License-Identifier: GPL-3.0-or-later
"""Bad files and arrays raise dtfabric's exceptions (ValueError or OSError subclasses) naming the file or
array and the problem; nothing crashes."""

import gzip

import numpy as np
import pytest

import dtfabric


def test_exception_classes():
    assert issubclass(dtfabric.FormatError, ValueError) and issubclass(dtfabric.FileError, OSError)
    assert issubclass(dtfabric.UsageError, ValueError) and issubclass(dtfabric.GlError, RuntimeError)
    for cls in (dtfabric.FormatError, dtfabric.FileError, dtfabric.UsageError, dtfabric.GlError):
        assert issubclass(cls, dtfabric.Error)


def test_missing_file(tmp_path):
    missing = tmp_path / "nothing.nii.gz"
    for call in (dtfabric.load, dtfabric.render, dtfabric.check, dtfabric.track,
                 lambda p: dtfabric.surface(p, "fa=0.3")):
        with pytest.raises(dtfabric.FileError, match="nothing.nii.gz: file does not exist"):
            call(missing)
    with pytest.raises(OSError, match="is a directory"):
        dtfabric.load(tmp_path)


def test_truncated_and_garbage_files(derived, tmp_path):
    data = open(derived("dti_tensor.nii.gz"), "rb").read()
    truncated = tmp_path / "truncated.nii.gz"
    truncated.write_bytes(data[: len(data) // 3])
    with pytest.raises(dtfabric.FormatError, match="truncated.nii.gz: .*truncated"):
        dtfabric.load(truncated)
    garbage = tmp_path / "garbage.nii"
    garbage.write_bytes(b"not a nifti file at all" * 40)
    with pytest.raises(ValueError, match="garbage.nii"):
        dtfabric.load(garbage)
    header_only = tmp_path / "header_only.nii.gz"
    raw = gzip.decompress(data)
    header_only.write_bytes(gzip.compress(raw[:352]))
    with pytest.raises(dtfabric.FormatError, match="header_only.nii.gz"):
        dtfabric.render(header_only, size=(64, 64))
    with pytest.raises(dtfabric.FormatError, match="garbage.nii"):
        dtfabric.check(garbage)


def test_bad_arrays():
    affine = np.diag([2.0, 2.0, 2.0, 1.0])
    good = np.zeros((4, 4, 4, 6), np.float32)
    good[..., 0] = good[..., 3] = good[..., 5] = 1e-3
    with pytest.raises(dtfabric.FormatError, match=r"shape \(4, 4, 4, 5\)"):
        dtfabric.TensorField(np.zeros((4, 4, 4, 5)), affine)
    with pytest.raises(dtfabric.FormatError, match="shape"):
        dtfabric.TensorField(np.zeros(6), affine)
    with pytest.raises(dtfabric.FormatError, match="NaN"):
        dtfabric.TensorField(good, np.full((4, 4), np.nan))
    with pytest.raises(dtfabric.FormatError, match="singular"):
        dtfabric.TensorField(good, np.zeros((4, 4)))
    with pytest.raises(dtfabric.FormatError, match="4x4"):
        dtfabric.TensorField(good, np.eye(3))
    with pytest.raises(dtfabric.FormatError, match="affine"):
        dtfabric.TensorField(good)
    with pytest.raises(dtfabric.FormatError, match="NaN"):
        dtfabric.TensorField(np.full((4, 4, 4, 6), np.nan), affine, layout="fsl")
    with pytest.raises(dtfabric.UsageError, match="layout"):
        dtfabric.TensorField(good, affine, layout="upside-down")
    with pytest.raises((TypeError, ValueError)):
        dtfabric.TensorField("not an array", affine)
    field = dtfabric.TensorField(good, affine, layout="fsl")
    assert field.valid.all() and field.shape == (4, 4, 4)


def test_wrong_layout_for_the_file(derived):
    with pytest.raises(dtfabric.FormatError, match="mask.nii.gz: is not a tensor volume"):
        dtfabric.load(derived("mask.nii.gz"))
    with pytest.raises(dtfabric.UsageError, match="layout"):
        dtfabric.load(derived("dti_tensor.nii.gz"), layout="sideways")


def test_file_system_failures_are_file_errors(tmp_path, cli, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "b").symlink_to("a")
    (tmp_path / "a").symlink_to("b")
    with pytest.raises(dtfabric.FileError, match="a: too many levels of symbolic links"):
        dtfabric.load("a")
    r = cli("info", "a", check=False)
    assert r.returncode == 2
    assert "dtfabric info: a: too many levels of symbolic links" in r.stderr
    assert "unexpected error" not in r.stderr


def test_paths_as_bytes_and_with_nul(derived):
    import os

    path = derived("dti_tensor.nii.gz")
    assert dtfabric.load(os.fsencode(path)).shape == dtfabric.load(path).shape
    with pytest.raises(dtfabric.UsageError, match="NUL character"):
        dtfabric.load(path + "\0.nii")


def test_arguments_of_the_wrong_type_are_usage_errors(derived):
    tensor, tracts = derived("dti_tensor.nii.gz"), derived("tracks_det.tck")
    with pytest.raises(dtfabric.UsageError, match="view must be .*got 5"):
        dtfabric.render(tensor, view=5, size=32)
    for bad in ((5, 1), (2, 2), (0, float("nan")), (float("-inf"), 1)):
        with pytest.raises(dtfabric.UsageError, match="tracts_range must be .*lo < hi"):
            dtfabric.render(tensor, tracts=tracts, tracts_range=bad, size=32)
    with pytest.raises(dtfabric.UsageError, match="seeds must be an integer"):
        dtfabric.track(tensor, seeds="many")
