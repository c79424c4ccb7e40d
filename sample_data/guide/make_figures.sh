#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Makes every figure of the user guide (sample_data/guide/README.md) from the bundled real brain,
# sample_data/dwi.nii.gz, with the dtfabric command line and the viewer's --script under xvfb-run.
#
# usage: sample_data/guide/make_figures.sh [OUTDIR]     (default: sample_data/guide/figures)
# Environment (optional):
#   DTFABRIC=EXE          the executable (default build/app/dtfabric; build it first)
#   DTF_FIGURES_QUICK=1   small figures (256 px images, an 800x500 window, 20 bootstrap fits) for the test
#                         that runs this
set -euo pipefail
here=$(pwd)
repo=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:-$repo/sample_data/guide/figures}
[[ $out == /* ]] || out=$here/$out
exe=${DTFABRIC:-$repo/build/app/dtfabric}
[[ $exe == /* ]] || exe=$here/$exe
[ -x "$exe" ] || { echo "make_figures.sh: no dtfabric executable at $exe (build it, or set DTFABRIC)" >&2; exit 2; }
command -v xvfb-run >/dev/null || { echo "make_figures.sh: xvfb-run is missing (Debian package xvfb)" >&2; exit 2; }
if [ "${DTF_FIGURES_QUICK:-0}" = 1 ]; then
  size=256 win_w=800 win_h=500 boot=20
else
  size=512 win_w=1280 win_h=1000 boot=200
fi
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$repo"
dtf() { "$exe" "$@"; }
render() { dtf render "$@" --size "${size}x$size" --force; }

# Getting started: exactly what `.ci/demo` shows without a display.
env -u DISPLAY DTFABRIC="$exe" DTF_DEMO_OUT="$work/demo" DTF_DEMO_SIZE="$size" .ci/demo >"$work/demo.txt"
for f in axial_cc axial_cc_decfa coronal_cst fa_left axial_cc_tracts; do
  cp "$work/demo/$f.png" "$out/demo_$f.png"
done
tensor=$work/demo/dti_tensor.nii.gz

# render: medical | engineering colour on the same slice; the neurological display convention;
# the midline sagittal slice (colour from the 3D direction, threads along the slice).
render "$tensor" --surface slice=axial:22 --split colour -o "$out/render_colour_split.png"
render "$tensor" --surface slice=axial:22 --neurological -o "$out/render_neurological.png"
render "$tensor" --surface slice=sagittal:36 -o "$out/render_sagittal_cc.png"

# fit --bootstrap: the cone of uncertainty, shown as fraying threads.
dtf fit sample_data/dwi.nii.gz --bootstrap "$boot" --cone "$work/cone.nii.gz" -o "$work/dti_boot.nii.gz" --force \
  >"$work/bootstrap.txt" 2>&1
render "$tensor" --surface slice=axial:22 --uncertainty "$work/cone.nii.gz" --look plain \
  -o "$out/render_uncertainty.png"

# surface: a fibre-following surface through the right corticospinal tract, seen from the front.
dtf surface "$tensor" --fibre-surface-voxel 27,34,15:33,34,15 -o "$work/cst.ply" --force >"$work/surface.txt"
render "$tensor" --surface "mesh=$work/cst.ply" --view anterior -o "$out/surface_cst_fibre.png"

# track: streamlines from a 6 mm ball at the corticospinal voxel (30,34,15) = world (18, 3.72, 21.60) mm,
# drawn within 3 mm of the coronal slice through it.
dtf track "$tensor" --seed-sphere 18,3.72,21.6,6 --select 300 -o "$work/cst.tck" --force 2>"$work/track.txt"
render "$tensor" --surface slice=coronal:34 --tracts "$work/cst.tck" -o "$out/track_cst.png"

# web: the page of every slice, opened from the file system in headless Chromium at the corpus callosum.
dtf web "$tensor" --tracts "$work/cst.tck" -o "$work/web" --force >"$work/web.txt" 2>&1
command -v chromium >/dev/null || { echo "make_figures.sh: chromium is missing (Debian package chromium)" >&2; exit 2; }
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=${win_w},$((win_h * 7 / 10)) \
  --virtual-time-budget=10000 --screenshot="$out/web_page.png" "file://$work/web/index.html#axis=axial&slice=22" \
  >/dev/null 2>&1

# phantom: the synthetic brain the tests use.
dtf phantom brain -o "$work/phantom.nii.gz" --size 48 --spacing 3.5 --force >/dev/null
render "$work/phantom.nii.gz" -o "$out/phantom_brain.png"

# Troubleshooting: the sample's FSL-layout tensors read as if they were in MRtrix's layout.
render "$tensor" --layout mrtrix --surface slice=axial:22 -o "$out/troubleshoot_wrong_layout.png"

# Troubleshooting: the same DWI fitted with the x row of the gradient table negated (a common
# conversion error), beside the right fit, on the axial slice through the genu and the splenium.
awk 'NR == 1 { for (i = 1; i <= NF; ++i) $i = ($i == 0 ? 0 : -$i) } { print }' sample_data/dwi.bvec >"$work/flipped.bvec"
dtf fit sample_data/dwi.nii.gz --bval sample_data/dwi.bval --bvec "$work/flipped.bvec" -o "$work/flipped.nii.gz" \
  --force 2>/dev/null
render "$tensor" --surface slice=axial:20 --split "input=$work/flipped.nii.gz" -o "$out/troubleshoot_flipped_bvec.png"

# The viewer in a real window under Xvfb: the window as `.ci/demo` opens it (the cursor's readout
# probed at the centre of the scene), then tracking from the slice and the split "fabric | + tracts".
# The same script as the guide shows, with these paths and this window's centre.
cat >"$work/viewer.txt" <<END
probe $(((win_w - 300) / 2)) $(((win_h - 26) / 2))   # read the voxel at this point of the picture (the status bar)
screenshot --force $out/viewer_window.png         # the whole window; --force replaces an older file
track from=slice:axial:22 select=1000        # 1000 streamlines seeded in slice 22, as \`dtfabric track\`
split tracts                                 # two panes: fabric alone | fabric + tracts
screenshot-scene --force $out/viewer_tracts.png   # the picture only, without the panels
quit
END
cat >"$work/viewer.sh" <<END
'$exe' view sample_data/dwi.nii.gz --surface slice=axial:22 --size ${win_w}x$win_h --script '$work/viewer.txt' \
  >'$work/viewer.out' 2>&1
echo \$? >'$work/viewer.rc'
END
# xvfb-run's own exit code can be 5 when it fails to remove its temporary folder: dtfabric's is the one that counts.
xvfb-run -a -s "-screen 0 1600x1200x24" sh "$work/viewer.sh" || true
rc=$(cat "$work/viewer.rc" 2>/dev/null || echo 1)
if [ "$rc" != 0 ]; then
  echo "make_figures.sh: the viewer script failed (exit code $rc):" >&2
  cat "$work/viewer.out" >&2 || true
  exit "$rc"
fi

echo "figures in $out:"
ls -1 "$out"
