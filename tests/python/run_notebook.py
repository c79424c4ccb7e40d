#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Executes tests/python/notebook/inline.ipynb headless with `jupyter nbconvert --execute` (a kernel of this
interpreter, with the build tree's module on PYTHONPATH) in a scratch folder, then checks its outputs: the
rendered image and dtfabric.show() carry image/png of the right size, dtfabric.web() carries text/html with
an iframe onto the page it wrote. Exits 77 (ctest's skip) when nbconvert or ipykernel is missing, unless
DTF_REQUIRE_TOOLS=1."""
import json
import os
import shutil
import struct
import subprocess
import sys
import base64

here = os.path.dirname(os.path.abspath(__file__))
scratch = os.path.join(os.environ.get("DTF_SCRATCH", os.getcwd()), "python_notebook")
require = os.environ.get("DTF_REQUIRE_TOOLS", "") not in ("", "0")


def missing(what):
    print(what + " is missing (Debian: jupyter-nbconvert, python3-ipykernel)", file=sys.stderr)
    sys.exit(1 if require else 77)


try:
    import ipykernel  # noqa: F401
    import nbconvert  # noqa: F401
except ImportError as e:
    missing(str(e))

shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
# A kernel of this very interpreter (the one the module was built for), whatever python3 is first on PATH.
kernels = os.path.join(scratch, "jupyter", "kernels", "dtfabric-test")
os.makedirs(kernels)
with open(os.path.join(kernels, "kernel.json"), "w") as f:
    json.dump({"argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
               "display_name": "dtfabric test", "language": "python"}, f)
env = dict(os.environ, JUPYTER_PATH=os.path.join(scratch, "jupyter"), JUPYTER_DATA_DIR=os.path.join(scratch, "data"),
           JUPYTER_RUNTIME_DIR=os.path.join(scratch, "runtime"), IPYTHONDIR=os.path.join(scratch, "ipython"))
notebook = os.path.join(scratch, "inline.ipynb")
shutil.copy(os.path.join(here, "notebook", "inline.ipynb"), notebook)
cmd = [sys.executable, "-m", "nbconvert", "--to", "notebook", "--execute", "--output", "executed.ipynb",
       "--ExecutePreprocessor.kernel_name=dtfabric-test", "--ExecutePreprocessor.timeout=300", notebook]
run = subprocess.run(cmd, cwd=scratch, env=env, capture_output=True, text=True)
if run.returncode != 0:
    print(run.stdout, run.stderr, file=sys.stderr)
    sys.exit("the notebook did not execute: " + " ".join(cmd))

executed = json.load(open(os.path.join(scratch, "executed.ipynb")))
code = [c for c in executed["cells"] if c["cell_type"] == "code"]


def data(cell):
    return [o.get("data", {}) for o in cell["outputs"] if o["output_type"] in ("execute_result", "display_data")]


def png_size(b64):
    png = base64.b64decode(b64)
    assert png[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    return struct.unpack(">II", png[16:24])


failures = []
for c in code:
    for o in c["outputs"]:
        if o["output_type"] == "error":
            failures.append("cell raised %s: %s" % (o["ename"], o["evalue"]))
render, show, web = data(code[1]), data(code[2]), data(code[3])
if not render or "image/png" not in render[0]:
    failures.append("render() shows no image/png: %s" % render)
elif png_size(render[0]["image/png"]) != (96, 80):
    failures.append("render()'s PNG is %s, not 96 x 80" % (png_size(render[0]["image/png"]),))
if not show or "image/png" not in show[0] or png_size(show[0]["image/png"]) != (10, 6):
    failures.append("show() carries no 10 x 6 image/png: %s" % show)
if not web or "text/html" not in web[0]:
    failures.append("web() shows no text/html: %s" % web)
else:
    html = "".join(web[0]["text/html"])
    if '<iframe src="page/index.html"' not in html:
        failures.append("web()'s HTML is not an iframe onto page/index.html: " + html)
    if not os.path.exists(os.path.join(scratch, "page", "index.html")):
        failures.append("the page's folder was not written beside the notebook")
if failures:
    sys.exit("\n".join(failures))
print("notebook executed: image/png %s, show %s, text/html %s" %
      (png_size(render[0]["image/png"]), png_size(show[0]["image/png"]), "".join(web[0]["text/html"])))
