# SPDX-License-Identifier: GPL-3.0-or-later
"""TensorField from numpy and nibabel: an array in each layout, built with numpy from the loaded field, gives
the same field as the file; nibabel images are taken directly; DIPY's lower-triangular order in the voxel
frame is accepted as "dipy"."""

import os

import numpy as np
import pytest

import dtfabric


@pytest.fixture
def nib():
    try:
        import nibabel
    except ImportError:
        if os.environ.get("DTF_REQUIRE_TOOLS", "") not in ("", "0"):
            pytest.fail("python3-nibabel is missing")
        pytest.skip("python3-nibabel is missing")
    return nibabel


def matrices(t):
    xx, xy, xz, yy, yz, zz = np.moveaxis(t.astype(np.float64), -1, 0)
    return np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1), np.stack([xz, yz, zz], -1)], -2)


def rotation(affine):
    a = affine[:3, :3]
    u, _, vt = np.linalg.svd(a)
    return u @ vt  # polar decomposition: the orthonormal part


def fsl_frame(affine):
    """Voxel axes, x negated when det(affine) > 0 (the bvec frame of FSL, DIPY and DTI-TK)."""
    r = rotation(affine)
    if np.linalg.det(affine[:3, :3]) > 0:
        r = r @ np.diag([-1.0, 1.0, 1.0])
    return r


def layout_array(field, layout):
    """The field's tensors as they would lie on disk in `layout`, made with numpy only."""
    world = matrices(field.tensor)
    if layout in ("world", "mrtrix"):
        m = world
    else:
        r = fsl_frame(field.affine)
        m = np.einsum("ji,...jk,kl->...il", r, world, r)  # R^T D R
    g = lambda a, b: m[..., a, b]
    order = {
        "world": [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)],
        "fsl": [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)],
        "mrtrix": [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)],
        "symmatrix": [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)],
        "dtitk": [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)],
        "dipy": [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)],
    }[layout]
    a = np.stack([g(*ij) for ij in order], axis=-1)
    if layout == "dtitk":
        a = a * 1000.0
    if layout in ("symmatrix", "dtitk"):
        a = a[:, :, :, None, :]
    return np.where(np.isnan(a), 0.0, a)  # invalid voxels as zeros, as files store them


@pytest.mark.parametrize("layout", ["world", "fsl", "mrtrix", "symmatrix", "dtitk", "dipy"])
def test_each_layout_equals_file(derived, layout):
    field = dtfabric.load(derived("dti_tensor.nii.gz"))
    made = dtfabric.TensorField(layout_array(field, layout), field.affine, layout=layout)
    assert made.layout == layout
    assert (made.valid == field.valid).all()
    scale = np.nanmax(np.abs(field.tensor))
    np.testing.assert_allclose(made.tensor, field.tensor, rtol=0, atol=1e-6 * scale, equal_nan=True)
    np.testing.assert_allclose(made.affine, field.affine)


def test_world_round_trip_is_exact(derived):
    field = dtfabric.load(derived("dti_tensor_mrtrix.nii.gz"))
    again = dtfabric.TensorField(field.tensor, field.affine, layout="world")
    np.testing.assert_array_equal(again.tensor, field.tensor)  # NaN where invalid stays invalid


@pytest.mark.parametrize("name,layout", [
    ("dti_tensor.nii.gz", "fsl"),
    ("dti_tensor_mrtrix.nii.gz", "mrtrix"),
    ("dti_tensor_symmatrix5d.nii.gz", "symmatrix"),
])
def test_nibabel_image_equals_file(derived, nib, name, layout):
    path = derived(name)
    from_file = dtfabric.load(path)
    img = nib.load(path)
    for given in ("auto", layout):
        made = dtfabric.TensorField(img, layout=given)
        assert made.layout == layout
        np.testing.assert_array_equal(made.tensor, from_file.tensor)
        np.testing.assert_allclose(made.affine, from_file.affine, atol=1e-6)
    # The array and affine given separately.
    made = dtfabric.TensorField(np.asarray(img.dataobj), img.affine, layout=layout)
    np.testing.assert_array_equal(made.tensor, from_file.tensor)


def test_dipy_lower_triangular(derived, nib):
    """TensorFit.lower_triangular() is (X, Y, Z, 6) xx xy yy xz yz zz in the voxel frame: the SYMMATRIX file's
    values without its singleton 4th axis."""
    path = derived("dti_tensor_symmatrix5d.nii.gz")
    img = nib.load(path)
    lower = np.asarray(img.dataobj)[:, :, :, 0, :]
    field = dtfabric.TensorField(lower, img.affine, layout="dipy")
    np.testing.assert_array_equal(field.tensor, dtfabric.load(path).tensor)
    # And against the FSL file fitted by DIPY: the same tensors.
    fsl = dtfabric.load(derived("dti_tensor.nii.gz"))
    np.testing.assert_allclose(field.tensor, fsl.tensor, rtol=0, atol=1e-9, equal_nan=True)


def test_ras_grid_uses_fsl_frame(derived):
    """On a grid with det > 0 the dipy/FSL frame negates x: flipping the grid and the data along i gives the
    same world tensors."""
    field = dtfabric.load(derived("dti_tensor.nii.gz"))
    las = layout_array(field, "dipy")
    flip = np.diag([-1.0, 1.0, 1.0, 1.0])
    flip[0, 3] = field.shape[0] - 1
    ras_affine = field.affine @ flip  # voxel i' = X-1-i: det > 0
    assert np.linalg.det(ras_affine[:3, :3]) > 0
    ras = dtfabric.TensorField(las[::-1], ras_affine, layout="dipy")
    np.testing.assert_allclose(ras.tensor[::-1], field.tensor, rtol=0, atol=1e-9, equal_nan=True)
