# SPDX-License-Identifier: GPL-3.0-or-later
"""dtfabric.load agrees with `dtfabric info --json` on the real data, in every tensor format and layout, and
the fields carry the brain's anatomy (corpus callosum left-right, corticospinal tract superior-inferior)."""

import numpy as np
import pytest

import dtfabric

CC = (33, 42, 22)   # corpus callosum, voxel of the LAS NIfTI files
CST = (30, 34, 15)  # corticospinal tract
LAS_AFFINE = np.array([[-3, 0, 0, 108], [0, 3, 0, -98.279], [0, 0, 3, -23.3962], [0, 0, 0, 1]])


def voxel(field, ijk):
    """The voxel of `field` at the world position of the LAS files' voxel ijk (dti_tensor.mif.gz is stored
    RAS: the same place has another i)."""
    xyz = LAS_AFFINE @ np.array([*ijk, 1.0])
    return tuple(int(v) for v in np.rint(np.linalg.solve(field.affine, xyz)[:3]))

TENSOR_FILES = [
    ("dti_tensor.nii.gz", "fsl"),
    ("dti_tensor_mrtrix.nii.gz", "mrtrix"),
    ("dti_tensor_symmatrix5d.nii.gz", "symmatrix"),
    ("dti_tensor.mif.gz", "mrtrix"),
]


def canonical(m):
    """3x3 -> xx xy xz yy yz zz"""
    m = np.asarray(m)
    return np.array([m[0, 0], m[0, 1], m[0, 2], m[1, 1], m[1, 2], m[2, 2]])


@pytest.mark.parametrize("name,layout", TENSOR_FILES)
def test_load_agrees_with_info(derived, cli_json, name, layout):
    path = derived(name)
    field = dtfabric.load(path)
    assert isinstance(field, dtfabric.TensorField)
    assert field.layout == layout
    assert field.layout_reason
    assert field.tensor.shape == (72, 72, 39, 6) and field.tensor.dtype == np.float32
    header = cli_json("info", path, "--json")
    np.testing.assert_allclose(field.affine, np.array(header["affine"]), atol=1e-5)
    assert header["layout"] == layout
    for ijk in (voxel(field, CC), voxel(field, CST)):
        info = cli_json("info", path, "--voxel", ",".join(map(str, ijk)), "--json")
        assert info["layout"] == layout and info["valid"]
        np.testing.assert_allclose(field.tensor[ijk], canonical(info["tensor_world"]), rtol=1e-6, atol=1e-12)
        # The voxel's world position through .affine, as info computes it.
        np.testing.assert_allclose((field.affine @ np.array([*ijk, 1.0]))[:3], info["world"], atol=1e-4)


def test_invalid_voxels_are_nan(derived, cli_json):
    path = derived("dti_tensor_mrtrix.nii.gz")  # one NaN voxel where b0 = 0, zeros outside the mask
    field = dtfabric.load(path)
    t = field.tensor
    assert field.nan_voxels == 1
    assert np.isnan(t[0, 0, 0]).all()  # outside the mask
    nan_rows = np.isnan(t).any(axis=3)
    assert (nan_rows == np.isnan(t).all(axis=3)).all()  # a voxel is all-NaN or not at all
    assert (~nan_rows == field.valid).all()
    assert field.valid.sum() == cli_json("info", path, "--json")["valid_voxels"]


def principal(t6):
    xx, xy, xz, yy, yz, zz = t6
    w, v = np.linalg.eigh(np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]], dtype=np.float64))
    return v[:, np.argmax(w)]


@pytest.mark.parametrize("name,layout", TENSOR_FILES)
def test_anatomy_in_world_frame(derived, name, layout):
    field = dtfabric.load(derived(name))
    cc, cst = principal(field.tensor[voxel(field, CC)]), principal(field.tensor[voxel(field, CST)])
    assert abs(cc[0]) > 0.9, cc    # left-right
    assert abs(cst[2]) > 0.9, cst  # superior-inferior
    # The frame, not only the axis: the callosal direction at this voxel runs (x, z) with the same sign in
    # world RAS (the README's reference: V1 (-0.95, -0.08, 0.29) in the LAS voxel frame).
    assert cc[0] * cc[2] > 0
    fa = field.fa()
    assert fa.shape == (72, 72, 39) and fa[voxel(field, CC)] > 0.7 and fa[voxel(field, CST)] > 0.7


def test_load_dwi_fits(shared):
    field = dtfabric.load(shared("iu_prisma_dwi/dwi.nii.gz"))  # sibling .bval/.bvec
    assert field.layout == "fitted" and "dwi.bvec" in field.layout_reason
    assert abs(principal(field.tensor[CC])[0]) > 0.9
    assert abs(principal(field.tensor[CST])[2]) > 0.9
    ref = dtfabric.load(shared("iu_prisma_dwi/derived/dti_tensor.nii.gz"))
    # The same brain fitted by DIPY (WLS): the FA maps agree (not exactly: other masks and weights).
    assert np.corrcoef(field.fa()[ref.valid], ref.fa()[ref.valid])[0, 1] > 0.85


@pytest.mark.parametrize("name,layout", [
    ("fibres/peaks_mrtrix.nii.gz", "mrtrix-peaks"),
    ("fibres/peaks_dipy.nii.gz", "dipy-peaks"),
    ("fibres/bedpostx_layout", "bedpostx"),
])
def test_fibre_sets_agree_with_info(derived, cli_json, name, layout):
    path = derived(name)
    fibres = dtfabric.load(path)
    assert isinstance(fibres, dtfabric.FibreSet)
    assert fibres.layout == layout and fibres.layout_reason
    k = fibres.directions.shape[3]
    assert fibres.directions.shape == (72, 72, 39, k, 3) and fibres.amplitudes.shape == (72, 72, 39, k)
    for ijk in (CC, CST):
        info = cli_json("info", path, "--voxel", ",".join(map(str, ijk)), "--json")
        assert info["fibre_layout"] == layout
        listed = info["fibres"]
        got = [(fibres.directions[ijk][n], fibres.amplitudes[ijk][n]) for n in range(k) if fibres.amplitudes[ijk][n] > 0]
        assert len(got) == len(listed)
        for (d, a), ref in zip(got, listed):
            np.testing.assert_allclose(d, ref["direction"], atol=1e-6)
            np.testing.assert_allclose(a, ref["amplitude"], rtol=1e-6)
    absent = fibres.amplitudes == 0
    assert np.isnan(fibres.directions[absent]).all()
    # Unit directions in world RAS: the callosum runs left-right, the corticospinal tract superior-inferior.
    assert abs(fibres.directions[CC][0][0]) > 0.9 and abs(fibres.directions[CST][0][2]) > 0.9


def test_fibre_frames_agree(derived):
    """The world-frame MRtrix peaks and the voxel-frame DIPY peaks give the same world directions."""
    mrtrix = dtfabric.load(derived("fibres/peaks_mrtrix.nii.gz"))
    dipy = dtfabric.load(derived("fibres/peaks_dipy.nii.gz"))
    both = (mrtrix.amplitudes[..., 0] > 0.6) & (dipy.amplitudes[..., 0] > 0)
    cos = np.abs(np.sum(mrtrix.directions[both][:, 0] * dipy.directions[both][:, 0], axis=1))
    assert both.sum() > 1000 and np.median(cos) > 0.98
