# SPDX-License-Identifier: GPL-3.0-or-later
"""What Jupyter shows: render()'s Image is the array it always was and encodes itself as a PNG of the same
pixels; show() wraps any image array; WebPage's HTML is an iframe onto the page's index.html. (The notebook
executed headless is tests/python/run_notebook.py.)"""
import os
import struct

import numpy as np
import pytest

import dtfabric
from conftest import read_png


def test_an_image_is_the_array_and_its_png_holds_the_same_pixels(tmp_path):
    rng = np.random.default_rng(3)
    for shape in [(7, 11, 4), (5, 3, 3)]:
        a = rng.integers(0, 256, size=shape, dtype=np.uint8)
        img = dtfabric.show(a)
        assert isinstance(img, np.ndarray) and isinstance(img, dtfabric.Image)
        assert img.shape == shape and img.dtype == np.uint8 and np.array_equal(img, a)
        path = tmp_path / ("i%d.png" % len(shape))
        path.write_bytes(img._repr_png_())
        back = np.asarray(read_png(str(path)))  # RGBA
        assert np.array_equal(back[..., :shape[2]], a)
        if shape[2] == 3:
            assert (back[..., 3] == 255).all()
    # Grey: an 8-bit grey PNG (colour type 0) of that size.
    grey = dtfabric.show(np.zeros((4, 6), np.uint8))._repr_png_()
    assert grey[12:16] == b"IHDR" and struct.unpack(">IIBB", grey[16:26]) == (6, 4, 8, 0)
    # What is not a picture displays as an array.
    assert dtfabric.show(np.zeros((2, 3, 4, 4), np.uint8))._repr_png_() is None
    assert dtfabric.show(np.zeros((2, 3, 4), np.float32))._repr_png_() is None
    with pytest.raises(ValueError):
        dtfabric._notebook.png_bytes(np.zeros((2, 3, 5), np.uint8))


def test_render_returns_an_image_that_code_taking_the_array_keeps_working_with():
    f = dtfabric.TensorField(np.tile(np.array([2e-3, 0, 0, 5e-4, 0, 5e-4], np.float32), (8, 8, 8, 1)),
                             np.eye(4), layout="world")
    img = dtfabric.render(f, size=(48, 32))
    assert isinstance(img, dtfabric.Image) and img.shape == (32, 48, 4)
    plain = np.asarray(img)
    assert type(plain) is np.ndarray and plain[..., :3].max() > 0
    assert img._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_web_page_shows_as_an_iframe_onto_its_index(tmp_path, monkeypatch):
    info = {"path": str(tmp_path / "page"), "slices": (3, 4, 5), "frames_3d": 108, "fa_frames": 10,
            "images": 130, "bytes": 2_000_000, "seconds": 1.5}
    monkeypatch.chdir(tmp_path)
    page = dtfabric.WebPage(info, height=500)
    assert page._repr_html_() == ('<iframe src="page/index.html" width="100%" height="500" '
                                  'style="border:1px solid #444" title="dtfabric web page"></iframe>')
    assert "108 3D frames" in repr(page)
    # From the folder above: the path below it, quoted for HTML.
    monkeypatch.chdir(os.path.dirname(str(tmp_path)))
    inner = dtfabric.WebPage(dict(info, path=str(tmp_path / "a\"b")))
    assert 'src="%s/a&quot;b/index.html"' % os.path.basename(str(tmp_path)) in inner._repr_html_()
    # From a sibling folder Jupyter would not serve: the file's own address.
    os.makedirs(tmp_path / "elsewhere", exist_ok=True)
    monkeypatch.chdir(tmp_path / "elsewhere")
    assert dtfabric.WebPage(info).url() == "file://" + str(tmp_path / "page" / "index.html")


def test_web_refuses_bad_values_naming_them(tmp_path):
    f = dtfabric.TensorField(np.tile(np.array([2e-3, 0, 0, 5e-4, 0, 5e-4], np.float32), (8, 8, 8, 1)),
                             np.eye(4), layout="world")
    with pytest.raises(dtfabric.UsageError, match="azimuths"):
        dtfabric.web(f, str(tmp_path / "p"), azimuths=2)
    assert not (tmp_path / "p").exists()
