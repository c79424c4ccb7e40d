# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric.render gives the pixels `dtfabric render` writes with the same arguments (read back with a PNG
decoder that does not use dtfabric), from a path, a loaded field, a fibre set and a numpy array; from several
Python threads at once; and refuses bad options as the command does."""

import threading

import numpy as np
import pytest

import dtfabric
from conftest import read_png, render_or_skip


def cli_png(cli, tmp_path, *args):
    out = tmp_path / "cli.png"
    cli("render", *args, "-o", out, "--force")
    return read_png(out)


def test_path_equals_cli(derived, cli, tmp_path):
    path = derived("dti_tensor.nii.gz")
    ours = render_or_skip(path, surface="slice=axial:22", size=(256, 256))
    assert ours.shape == (256, 256, 4) and ours.dtype == np.uint8
    theirs = cli_png(cli, tmp_path, path, "--surface", "slice=axial:22", "--size", "256x256")
    np.testing.assert_array_equal(ours, theirs)
    np.testing.assert_array_equal(dtfabric.read_png(tmp_path / "cli.png"), theirs)
    # Not blank: the brain's slice covers a good part of the image, in colour.
    brain = ours[..., :3].max(axis=2) > 40
    assert 0.2 < brain.mean() < 0.9


def test_field_with_options_equals_cli(derived, cli, tmp_path):
    path = derived("dti_tensor.nii.gz")
    field = dtfabric.load(path)
    ours = render_or_skip(field, surface="slice=coronal:40", view="coronal", size=(256, 192),
                          colour="engineering", blend_k=0.2, lighting=False, fade_out_of_plane=0.5)
    theirs = cli_png(cli, tmp_path, path, "--surface", "slice=coronal:40", "--view", "coronal", "--size", "256x192",
                     "--color", "engineering", "--blend-k", "0.2", "--no-lighting", "--fade-out-of-plane", "0.5")
    assert ours.shape == (192, 256, 4)
    np.testing.assert_array_equal(ours, theirs)


def test_fibre_set_equals_cli(derived, cli, tmp_path):
    path = derived("fibres/peaks_mrtrix.nii.gz")
    ours = render_or_skip(dtfabric.load(path), surface="slice=axial:22", size=(256, 256))
    theirs = cli_png(cli, tmp_path, path, "--surface", "slice=axial:22", "--size", "256x256")
    np.testing.assert_array_equal(ours, theirs)


def test_dipy_array_equals_cli(derived, cli, tmp_path):
    """An array in DIPY's order renders as the file it came from."""
    import nibabel as nib

    path = derived("dti_tensor_symmatrix5d.nii.gz")
    img = nib.load(path)
    field = dtfabric.TensorField(np.asarray(img.dataobj)[:, :, :, 0, :], img.affine, layout="dipy")
    ours = render_or_skip(field, surface="slice=sagittal:36", size=(256, 256))
    theirs = cli_png(cli, tmp_path, path, "--surface", "slice=sagittal:36", "--size", "256x256")
    np.testing.assert_array_equal(ours, theirs)
    # The nibabel image itself as render's input.
    np.testing.assert_array_equal(render_or_skip(img, surface="slice=sagittal:36", size=(256, 256)), theirs)


def test_threads_render_the_same(derived):
    field = dtfabric.load(derived("dti_tensor.nii.gz"))
    ref = render_or_skip(field, surface="slice=axial:22", size=(128, 128))
    out, errors = [None] * 3, []

    def work(n):
        try:
            out[n] = dtfabric.render(field, surface="slice=axial:22", size=(128, 128))
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(n,)) for n in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for o in out:
        np.testing.assert_array_equal(o, ref)


def test_bad_options(derived):
    field = dtfabric.load(derived("dti_tensor.nii.gz"))
    with pytest.raises(dtfabric.UsageError, match="blend-k must lie in"):
        dtfabric.render(field, blend_k=5)
    with pytest.raises(ValueError, match="colour|color"):
        dtfabric.render(field, colour="purple")
    with pytest.raises(TypeError, match="no_such_option"):
        dtfabric.render(field, no_such_option=1)
    with pytest.raises(dtfabric.UsageError, match="size"):
        dtfabric.render(field, size=(8, 8))
    with pytest.raises(dtfabric.UsageError, match="size must be"):
        dtfabric.render(field, size="large")
    with pytest.raises(dtfabric.UsageError):
        dtfabric.render(field, surface="slice=diagonal")
    with pytest.raises(dtfabric.FormatError, match="FA"):
        dtfabric.render(field, surface="fa=0.999")


def test_forked_child_refuses_to_render(derived):
    """After a render, a forked child gets a clear GlError instead of hanging on the parent's context."""
    import multiprocessing

    field = dtfabric.load(derived("dti_tensor.nii.gz"))
    render_or_skip(field, size=(32, 32))
    ctx = multiprocessing.get_context("fork")
    queue = ctx.Queue()

    def child():
        try:
            dtfabric.render(field, size=(32, 32))
            queue.put("rendered")
        except dtfabric.GlError as e:
            queue.put("GlError: " + str(e))

    p = ctx.Process(target=child)
    p.start()
    p.join(60)
    assert p.exitcode == 0
    message = queue.get(timeout=5)
    assert message.startswith("GlError") and "spawn" in message


def test_tracts_split_equals_cli(derived, cli, tmp_path):
    path, tracts = derived("dti_tensor.nii.gz"), derived("tracks_det.tck")
    ours = render_or_skip(dtfabric.load(path), surface="slice=axial:22", size=(128, 128), tracts=tracts,
                          split="tracts", tract_width=3)
    theirs = cli_png(cli, tmp_path, path, "--surface", "slice=axial:22", "--size", "128x128", "--tracts", tracts,
                     "--split", "tracts", "--tract-width", "3")
    assert ours.shape == (128, 256, 4)
    np.testing.assert_array_equal(ours, theirs)
    assert not np.array_equal(ours[:, :128], ours[:, 128:])  # the right pane has the tracts


def test_fibres_with_paired_tensor_equal_cli(derived, cli, tmp_path):
    peaks, tensor = derived("fibres/peaks_dipy.nii.gz"), derived("dti_tensor.nii.gz")
    fibres = dtfabric.load(peaks, tensor=tensor)
    assert isinstance(fibres.tensor, dtfabric.TensorField) and fibres.fa is not None
    np.testing.assert_allclose(fibres.fa, dtfabric.load(tensor).fa())
    ours = render_or_skip(fibres, surface="slice=coronal:40", size=(128, 128), background="fa")
    theirs = cli_png(cli, tmp_path, peaks, "--tensor", tensor, "--surface", "slice=coronal:40", "--size", "128x128",
                     "--background", "fa")
    np.testing.assert_array_equal(ours, theirs)
