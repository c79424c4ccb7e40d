# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric.movie makes the frames `dtfabric movie` makes (the same pixels, read back from the command's PNG
frames), writes MP4/PNG outputs atomically, refuses to overwrite without force=True, and refuses bad motions."""

import os
import shutil

import numpy as np
import pytest

import dtfabric
from conftest import _flag, read_png


def movie_or_skip(*args, **kwargs):
    try:
        return dtfabric.movie(*args, **kwargs)
    except dtfabric.GlError as e:
        if _flag("DTF_REQUIRE_GL"):
            raise
        pytest.skip(f"no GL context: {e}")


def test_frames_equal_cli(derived, cli, tmp_path):
    path = derived("dti_tensor.nii.gz")
    frames = movie_or_skip(path, turntable=True, frames=4, size=(96, 80), surface="fa=0.3")
    assert frames.shape == (4, 80, 96, 4) and frames.dtype == np.uint8
    cli("movie", path, "--turntable", "--frames", "4", "--size", "96x80", "--surface", "fa=0.3",
        "-o", f"{tmp_path}/frames/")
    names = sorted(os.listdir(tmp_path / "frames"))
    assert names == [f"frame_{i:04d}.png" for i in range(4)]
    for i, name in enumerate(names):
        np.testing.assert_array_equal(frames[i], read_png(tmp_path / "frames" / name))
    # The turntable turns: consecutive frames differ, but not wholesale.
    assert 0 < np.abs(frames[1].astype(int) - frames[0].astype(int)).mean() < 60


def test_sweep_to_files_atomic_and_forced(derived, tmp_path):
    path = derived("dti_tensor.nii.gz")
    out = tmp_path / "sweep"
    got = movie_or_skip(path, str(out) + "/", sweep="coronal", frames=3, size=(64, 64))
    assert got == str(out) + "/"
    assert sorted(os.listdir(out)) == [f"frame_{i:04d}.png" for i in range(3)]
    with pytest.raises(dtfabric.Error, match="--force|exists"):
        dtfabric.movie(path, str(out) + "/", sweep="coronal", frames=2, size=(64, 64))
    assert len(os.listdir(out)) == 3
    movie_or_skip(path, str(out) + "/", sweep="coronal", frames=2, size=(64, 64), force=True)
    assert len(os.listdir(out)) == 2
    assert sorted(os.listdir(tmp_path)) == ["sweep"]  # no temporary left
    if shutil.which("ffmpeg"):
        mp4 = tmp_path / "fa.mp4"
        assert movie_or_skip(path, mp4, fa_sweep=(0.25, 0.35), frames=3, size=(64, 48)) == str(mp4)
        assert mp4.stat().st_size > 0


def test_bad_motions_are_usage_errors(derived):
    path = derived("dti_tensor.nii.gz")
    with pytest.raises(dtfabric.UsageError):
        dtfabric.movie(path)
    with pytest.raises(dtfabric.UsageError):
        dtfabric.movie(path, turntable=True, sweep="axial")
    with pytest.raises(dtfabric.UsageError):
        dtfabric.movie(path, sweep="oblique")
    with pytest.raises(dtfabric.UsageError):
        dtfabric.movie(path, "out.avi", turntable=True)
