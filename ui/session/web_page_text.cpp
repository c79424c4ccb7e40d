// SPDX-License-Identifier: GPL-3.0-or-later
// The static text of the web page: index.html and viewer.js. The page reads window.DTF_WEB (data.js) and
// window.DTF_WEB_VOXELS (voxels.js) and loads each slice's PNG through an <img>, so it works from file://.
//
// Pixel -> world: a slice image of axis A (W x H pixels) is an orthographic view whose centre pixel looks at
// `centre`; the point under pixel coordinates (px, py) (0..W, 0..H, y down) is
//   centre + right * (px - W/2) * mmPerPixel + up * (H/2 - py) * mmPerPixel
// and the ray from it along `forward` meets the slice's voxel plane (voxel index `voxelAxis` = slice) at the
// probed point. Images are rendered in the radiological convention; the neurological one mirrors them.
//
// The 3D view (id="view3d") shows one frame of window.DTF_WEB.view3d at a time: a drag across the image's
// width turns the surface once round (one frame per azimuth), a vertical drag moves between elevations; the
// FA sweep (id="viewfa") shows the frame of the threshold its slider picks and prints the threshold. Every
// frame is preloaded through an <img>, so turning needs no file access and works from file://.
#include "ui/session/web_page.h"
#include "io/bids/bids_report.h"

namespace dtf::session {

std::string webIndexHtml(const std::string& title) {
  const std::string t = io::htmlEscape(title);
  return R"HTML(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>)HTML" +
         t +
         R"HTML( - dtfabric</title>
<style>
html,body{margin:0;height:100%;background:#111;color:#ddd;font:13px/1.4 system-ui,sans-serif}
#app{display:flex;height:100%}
#view{position:relative;flex:1;min-width:0;overflow:hidden;cursor:crosshair}
#canvas{position:absolute;left:0;top:0;width:100%;height:100%;display:block}
.letter{position:absolute;font:bold 16px system-ui,sans-serif;color:#ffd54a;text-shadow:0 0 3px #000;pointer-events:none}
#lt{left:50%;top:6px;transform:translateX(-50%)} #lb{left:50%;bottom:6px;transform:translateX(-50%)}
#ll{left:8px;top:50%;transform:translateY(-50%)} #lr{right:8px;top:50%;transform:translateY(-50%)}
#note{position:absolute;left:8px;top:6px;color:#999;pointer-events:none}
.pane{position:relative;flex:1;min-width:0;overflow:hidden;display:flex;flex-direction:column;align-items:center;justify-content:center;background:#000}
.pane[hidden]{display:none}
.pane img{flex:1;min-height:0;max-width:100%;object-fit:contain;user-select:none;-webkit-user-drag:none}
#view3d img{cursor:grab} #view3d.dragging img{cursor:grabbing}
.caption{padding:6px 10px;color:#ccc;display:flex;gap:10px;align-items:center;width:calc(100% - 20px);justify-content:center}
#faslider{flex:1;max-width:420px}
#fathreshold{font-weight:bold;color:#ffd54a;min-width:80px}
#side{width:290px;padding:10px 12px;background:#1b1b1b;border-left:1px solid #333;overflow:auto}
h1{font-size:15px;margin:0 0 8px;word-break:break-all}
.row{margin:8px 0}
.axis{display:flex;align-items:center;gap:6px}
.axis label{width:70px} .axis input[type=range]{flex:1} .axis span{width:48px;text-align:right}
.axis.active label{color:#ffd54a;font-weight:bold}
button{background:#2a2a2a;color:#ddd;border:1px solid #444;padding:3px 8px;border-radius:3px;cursor:pointer}
button.on{background:#4a4020;border-color:#ffd54a}
#probe{font-family:ui-monospace,monospace;font-size:12px;white-space:pre;background:#151515;padding:6px;border:1px solid #333}
#swatch{display:inline-block;width:12px;height:12px;vertical-align:middle;border:1px solid #555}
.help{color:#999;font-size:12px}
</style>
</head>
<body>
<div id="app">
<div id="view"><canvas id="canvas"></canvas>
<div class="letter" id="lt"></div><div class="letter" id="lb"></div><div class="letter" id="ll"></div><div class="letter" id="lr"></div>
<div id="note"></div></div>
<div id="view3d" class="pane" hidden><img id="img3d" alt="3D view" draggable="false"><div class="caption" id="cap3d"></div></div>
<div id="viewfa" class="pane" hidden><img id="imgfa" alt="FA sweep" draggable="false"><div class="caption"><label for="faslider">FA threshold</label><input type="range" id="faslider" min="0" max="0" step="1"><span id="fathreshold"></span></div></div>
<div id="side">
<h1>)HTML" +
         t +
         R"HTML(</h1>
<div class="row" id="tabs"><button id="tab-slices" class="on" title="1">slices</button> <button id="tab-3d" title="2">3D</button> <button id="tab-fa" title="3">FA sweep</button></div>
<div class="row" id="axes"></div>
<div class="row" id="slicebuttons"><button id="conv" title="N">radiological</button> <button id="tracts" title="T">tracts</button> <button id="reset" title="R">reset view</button></div>
<div class="row" id="proberow">Probe <span id="swatch"></span><div id="probe">move the pointer over the slice</div></div>
<div class="row help">Up/Down: next/previous slice; PgUp/PgDn: 5 slices; A, C, S: axial, coronal, sagittal;
wheel: zoom; drag: pan; click: move the other slices to the point; N: radiological/neurological; T: tracts;
R: reset the view. Colour: red left-right, green anterior-posterior, blue superior-inferior.
1, 2, 3: slices, 3D view, FA sweep; in the 3D view drag (or Left/Right, Up/Down) to turn; in the FA sweep
Left/Right move the threshold.</div>
<div class="row help" id="info"></div>
</div>
</div>
<script src="data.js"></script>
<script src="voxels.js"></script>
<script src="viewer.js"></script>
</body>
</html>
)HTML";
}

const char* webViewerJs() {
  return R"JS(// dtfabric web page: slice fabric images, probe, navigation. Reads window.DTF_WEB and DTF_WEB_VOXELS.
'use strict';
(function () {
  const caught = [];
  window.addEventListener('error', e => caught.push(String(e.message || e.type) + (e.filename ? ' @ ' + e.filename : '')), true);
  window.addEventListener('unhandledrejection', e => caught.push('rejection: ' + e.reason));
  const origError = console.error;
  console.error = function () { caught.push(Array.from(arguments).join(' ')); origError.apply(console, arguments); };

  const D = window.DTF_WEB;
  if (!D || typeof window.DTF_WEB_VOXELS !== 'string') {
    console.error('dtfabric web: data.js or voxels.js did not load');
    return;
  }
  const raw = atob(window.DTF_WEB_VOXELS);
  const table = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; ++i) table[i] = raw.charCodeAt(i);
  const dims = D.dims, A = D.affine;
  // voxel -> world (3x4) and its inverse.
  const M = [[A[0][0], A[0][1], A[0][2]], [A[1][0], A[1][1], A[1][2]], [A[2][0], A[2][1], A[2][2]]];
  const T = [A[0][3], A[1][3], A[2][3]];
  const det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
              M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
  const Mi = [
    [(M[1][1] * M[2][2] - M[1][2] * M[2][1]) / det, (M[0][2] * M[2][1] - M[0][1] * M[2][2]) / det, (M[0][1] * M[1][2] - M[0][2] * M[1][1]) / det],
    [(M[1][2] * M[2][0] - M[1][0] * M[2][2]) / det, (M[0][0] * M[2][2] - M[0][2] * M[2][0]) / det, (M[0][2] * M[1][0] - M[0][0] * M[1][2]) / det],
    [(M[1][0] * M[2][1] - M[1][1] * M[2][0]) / det, (M[0][1] * M[2][0] - M[0][0] * M[2][1]) / det, (M[0][0] * M[1][1] - M[0][1] * M[1][0]) / det]];
  const mul = (m, v) => [0, 1, 2].map(r => m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2]);
  const toWorld = v => mul(M, v).map((x, r) => x + T[r]);
  const toVoxel = p => mul(Mi, [p[0] - T[0], p[1] - T[1], p[2] - T[2]]);

  const state = { axis: 0, slice: D.axes.map(a => a.slices.length ? a.slices[a.slices.length >> 1] : 0),
                  zoom: 1, panX: 0, panY: 0, neuro: false, tracts: false };
  const canvas = document.getElementById('canvas'), ctx = canvas.getContext('2d');
  const view = document.getElementById('view');
  const images = new Map();
  let drawn = 0, drawnSrc = '';

  function hasSlice(a, s) { return D.axes[a].slices.indexOf(s) >= 0; }
  function pad(s) { return String(s).padStart(3, '0'); }
  function imageSrc(a, s, tracts) {
    const ax = D.axes[a];
    return (tracts && ax.tractImage ? ax.tractImage : ax.image) + pad(s) + '.png';
  }
  function image(src) {
    let img = images.get(src);
    if (!img) {
      img = new Image();
      img.onload = () => { if (src === currentSrc()) draw(); };
      img.onerror = () => console.error('dtfabric web: cannot load ' + src);
      img.src = src;
      images.set(src, img);
    }
    return img;
  }
  function currentSrc() {
    const a = state.axis, s = state.slice[a];
    return hasSlice(a, s) ? imageSrc(a, s, state.tracts) : '';
  }

  // The image's placement on the canvas (CSS pixels): scale and top-left corner.
  function placement() {
    const ax = D.axes[state.axis];
    const cw = view.clientWidth, ch = view.clientHeight;
    const scale = Math.min(cw / ax.width, ch / ax.height) * 0.96 * state.zoom;
    return { scale: scale, x: (cw - ax.width * scale) / 2 + state.panX, y: (ch - ax.height * scale) / 2 + state.panY };
  }

  function letter(v, sign) {
    const a = v.map(Math.abs), i = a[0] >= a[1] && a[0] >= a[2] ? 0 : (a[1] >= a[2] ? 1 : 2);
    return (v[i] * sign > 0 ? 'RAS' : 'LPI')[i];
  }

  function draw() {
    const dpr = window.devicePixelRatio || 1;
    const cw = view.clientWidth, ch = view.clientHeight;
    if (canvas.width !== Math.round(cw * dpr) || canvas.height !== Math.round(ch * dpr)) {
      canvas.width = Math.round(cw * dpr);
      canvas.height = Math.round(ch * dpr);
    }
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = '#000';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    const a = state.axis, ax = D.axes[a], s = state.slice[a], p = placement();
    const src = currentSrc();
    const note = document.getElementById('note');
    if (!src) {
      note.textContent = ax.name + ' slice ' + s + ': no data';
    } else {
      const img = image(src);
      note.textContent = ax.name + ' slice ' + s + ' / ' + (ax.count - 1) + (state.neuro ? ', neurological' : ', radiological');
      if (img.complete && img.naturalWidth > 0) {
        ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
        ctx.imageSmoothingEnabled = p.scale < 6; // pixels show only when zoomed far in
        if (state.neuro) {
          ctx.translate(p.x + ax.width * p.scale, p.y);
          ctx.scale(-p.scale, p.scale);
        } else {
          ctx.translate(p.x, p.y);
          ctx.scale(p.scale, p.scale);
        }
        ctx.drawImage(img, 0, 0);
        ++drawn;
        drawnSrc = src;
      }
      // Neighbours, so stepping through slices does not wait for the file.
      for (const d of [-1, 1]) if (hasSlice(a, s + d)) image(imageSrc(a, s + d, state.tracts));
    }
    const sign = state.neuro ? -1 : 1;
    document.getElementById('lr').textContent = letter(ax.right, sign);
    document.getElementById('ll').textContent = letter(ax.right, -sign);
    document.getElementById('lt').textContent = letter(ax.up, 1);
    document.getElementById('lb').textContent = letter(ax.up, -1);
    document.getElementById('conv').textContent = state.neuro ? 'neurological' : 'radiological';
    document.getElementById('tracts').classList.toggle('on', state.tracts);
    D.axes.forEach((x, i) => {
      document.getElementById('row' + i).classList.toggle('active', i === a);
      document.getElementById('slider' + i).value = state.slice[i];
      document.getElementById('value' + i).textContent = state.slice[i];
    });
  }

  // The probe at canvas point (cx, cy) in CSS pixels: world mm, voxel, FA, principal direction.
  function probe(cx, cy) {
    const a = state.axis, ax = D.axes[a], p = placement();
    let px = (cx - p.x) / p.scale;
    const py = (cy - p.y) / p.scale;
    if (state.neuro) px = ax.width - px;
    if (px < 0 || py < 0 || px > ax.width || py > ax.height) return null;
    const s = ax.mmPerPixel, du = (px - ax.width / 2) * s, dv = (ax.height / 2 - py) * s;
    const p0 = [0, 1, 2].map(i => ax.centre[i] + ax.right[i] * du + ax.up[i] * dv);
    const v0 = toVoxel(p0), dir = mul(Mi, ax.forward), k = ax.voxelAxis;
    if (Math.abs(dir[k]) < 1e-12) return null;
    const t = (state.slice[a] - v0[k]) / dir[k];
    const v = v0.map((x, i) => x + t * dir[i]);
    const ijk = v.map(Math.round);
    const out = { world: toWorld(v), voxel: ijk, fa: null, dir: null };
    if (ijk.some((x, i) => x < 0 || x >= dims[i])) return out;
    const o = 4 * (ijk[0] + dims[0] * (ijk[1] + dims[1] * ijk[2]));
    if (table[o] > 0) {
      out.fa = (table[o] - 1) / 254;
      out.dir = [table[o + 1], table[o + 2], table[o + 3]].map(b => (b - 128) / 127);
    }
    return out;
  }
  const f1 = x => x.toFixed(1), f2 = x => x.toFixed(2);
  function showProbe(r) {
    const el = document.getElementById('probe'), sw = document.getElementById('swatch');
    if (!r) { el.textContent = 'outside the slice'; sw.style.background = 'none'; return; }
    let t = 'world  ' + r.world.map(f1).join(', ') + ' mm\nvoxel  ' + r.voxel.join(', ');
    if (r.fa === null) {
      t += '\nno tensor data';
      sw.style.background = 'none';
    } else {
      t += '\nFA     ' + r.fa.toFixed(3) + '\ne1     ' + r.dir.map(f2).join(', ') + ' (sign arbitrary)';
      const c = r.dir.map(x => Math.round(255 * Math.min(1, Math.abs(x) * Math.max(r.fa, 0.25))));
      sw.style.background = 'rgb(' + c.join(',') + ')';
    }
    el.textContent = t;
  }

  function setAxis(a) { state.axis = a; draw(); }
  function setSlice(a, s) {
    const ax = D.axes[a];
    const lo = ax.slices.length ? ax.slices[0] : 0, hi = ax.slices.length ? ax.slices[ax.slices.length - 1] : ax.count - 1;
    state.slice[a] = Math.max(lo, Math.min(hi, Math.round(s)));
    state.axis = a;
    draw();
  }

  // Controls: one slider per axis.
  const axesEl = document.getElementById('axes');
  D.axes.forEach((ax, i) => {
    const row = document.createElement('div');
    row.className = 'axis';
    row.id = 'row' + i;
    const lo = ax.slices.length ? ax.slices[0] : 0, hi = ax.slices.length ? ax.slices[ax.slices.length - 1] : ax.count - 1;
    row.innerHTML = '<label>' + ax.name + '</label><input type="range" id="slider' + i + '" min="' + lo + '" max="' + hi +
                    '" step="1"><span id="value' + i + '"></span>';
    axesEl.appendChild(row);
    const slider = row.querySelector('input');
    slider.addEventListener('input', () => setSlice(i, Number(slider.value)));
    row.querySelector('label').addEventListener('click', () => setAxis(i));
  });
  const tractButton = document.getElementById('tracts');
  if (!D.tracts) tractButton.style.display = 'none';
  tractButton.addEventListener('click', () => { state.tracts = !state.tracts && !!D.tracts; draw(); });
  document.getElementById('conv').addEventListener('click', () => { state.neuro = !state.neuro; draw(); });
  function resetView() { state.zoom = 1; state.panX = 0; state.panY = 0; draw(); }
  document.getElementById('reset').addEventListener('click', resetView);
  document.getElementById('info').textContent = D.input + ': ' + dims.join(' x ') + ' voxels (' + D.orientation + ')' +
      (D.tracts ? ', tracts ' + D.tracts : '') + '. Made by dtfabric web.';

  window.addEventListener('keydown', e => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    const a = state.axis, k = e.key;
    if (k === '1' || k === '2' || k === '3') { showTab(['slices', '3d', 'fa'][Number(k) - 1]); e.preventDefault(); return; }
    if (turn.tab === '3d') {
      const d = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] }[k];
      if (d) { setTurn(turn.az + d[0], turn.el + d[1]); e.preventDefault(); }
      return;
    }
    if (turn.tab === 'fa') {
      const d = { ArrowLeft: -1, ArrowRight: 1, ArrowDown: -1, ArrowUp: 1 }[k];
      if (d) { setFa(turn.fa + d); e.preventDefault(); }
      return;
    }
    const steps = { ArrowUp: 1, ArrowDown: -1, PageUp: 5, PageDown: -5 };
    if (k in steps) setSlice(a, state.slice[a] + steps[k]);
    else if (k === 'a' || k === 'A') setAxis(0);
    else if (k === 'c' || k === 'C') setAxis(1);
    else if (k === 's' || k === 'S') setAxis(2);
    else if (k === 'n' || k === 'N') { state.neuro = !state.neuro; draw(); }
    else if ((k === 't' || k === 'T') && D.tracts) { state.tracts = !state.tracts; draw(); }
    else if (k === 'r' || k === 'R') resetView();
    else return;
    e.preventDefault();
  });
  view.addEventListener('wheel', e => {
    e.preventDefault();
    const rect = view.getBoundingClientRect(), cx = e.clientX - rect.left, cy = e.clientY - rect.top;
    const f = Math.exp(-e.deltaY * 0.0015), zoom = Math.max(0.25, Math.min(32, state.zoom * f));
    const before = placement(), g = zoom / state.zoom;
    state.zoom = zoom;
    // Keep the point under the cursor fixed.
    const after = placement();
    state.panX += cx - (cx - before.x) * g - after.x;
    state.panY += cy - (cy - before.y) * g - after.y;
    draw();
  }, { passive: false });
  let drag = null;
  view.addEventListener('mousedown', e => { drag = { x: e.clientX, y: e.clientY, moved: false }; });
  window.addEventListener('mouseup', e => {
    if (drag && !drag.moved) {
      const rect = view.getBoundingClientRect(), r = probe(e.clientX - rect.left, e.clientY - rect.top);
      if (r) D.axes.forEach((ax, i) => { if (i !== state.axis) setSliceQuiet(i, r.voxel[ax.voxelAxis]); });
      draw();
    }
    drag = null;
  });
  function setSliceQuiet(a, s) {
    const ax = D.axes[a];
    if (ax.slices.length) state.slice[a] = Math.max(ax.slices[0], Math.min(ax.slices[ax.slices.length - 1], s));
  }
  view.addEventListener('mousemove', e => {
    const rect = view.getBoundingClientRect();
    if (drag) {
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
      if (drag.moved) { state.panX += dx; state.panY += dy; drag.x = e.clientX; drag.y = e.clientY; draw(); }
    }
    showProbe(probe(e.clientX - rect.left, e.clientY - rect.top));
  });
  window.addEventListener('resize', draw);

  // The 3D view and the FA sweep: one preloaded <img> per frame, the shown one's src copied to the pane's.
  const V = D.view3d, F = D.faSweep;
  const pad2 = x => String(x).padStart(2, '0');
  const frames = new Map();
  function frame(src) {
    let img = frames.get(src);
    if (!img) {
      img = new Image();
      img.onerror = () => console.error('dtfabric web: cannot load ' + src);
      img.src = src;
      frames.set(src, img);
    }
    return img;
  }
  const turn = { az: 0, el: 0, fa: 0, tab: 'slices' };
  const src3d = (e, a) => V.image + pad2(e) + '_' + pad(a) + '.png';
  const srcFa = i => F.image + pad2(i) + '.png';
  const img3d = document.getElementById('img3d'), imgFa = document.getElementById('imgfa');
  const faSlider = document.getElementById('faslider');
  function show3d() {
    if (!V) return;
    const src = src3d(turn.el, turn.az);
    frame(src);
    if (img3d.getAttribute('src') !== src) img3d.src = src;
    document.getElementById('cap3d').textContent = V.surface + ' - azimuth ' + Math.round(turn.az * 360 / V.azimuths) +
        '\u00b0, elevation ' + V.elevations[turn.el] + '\u00b0 - drag to turn';
  }
  function showFa() {
    if (!F || !F.thresholds.length) return;
    const src = srcFa(turn.fa);
    frame(src);
    if (imgFa.getAttribute('src') !== src) imgFa.src = src;
    faSlider.value = turn.fa;
    document.getElementById('fathreshold').textContent = 'FA \u2265 ' + F.thresholds[turn.fa].toFixed(2);
  }
  function setTurn(az, el) {
    turn.az = ((Math.round(az) % V.azimuths) + V.azimuths) % V.azimuths;
    turn.el = Math.max(0, Math.min(V.elevations.length - 1, Math.round(el)));
    show3d();
  }
  function setFa(i) { turn.fa = Math.max(0, Math.min(F.thresholds.length - 1, Math.round(i))); showFa(); }
  function showTab(name) {
    if ((name === '3d' && !V) || (name === 'fa' && !F)) name = 'slices';
    turn.tab = name;
    view.hidden = name !== 'slices';
    view.style.display = name === 'slices' ? '' : 'none';
    document.getElementById('view3d').hidden = name !== '3d';
    document.getElementById('viewfa').hidden = name !== 'fa';
    ['slices', '3d', 'fa'].forEach(t => document.getElementById('tab-' + t).classList.toggle('on', t === name));
    for (const el of [axesEl, document.getElementById('slicebuttons'), document.getElementById('proberow')])
      el.style.display = name === 'slices' ? '' : 'none';
    if (name === '3d') show3d();
    else if (name === 'fa') showFa();
    else draw();
  }
  ['slices', '3d', 'fa'].forEach(t => document.getElementById('tab-' + t).addEventListener('click', () => showTab(t)));
  if (!V) document.getElementById('tab-3d').style.display = 'none';
  if (!F) document.getElementById('tab-fa').style.display = 'none';
  if (V) {
    V.elevations.forEach((e, i) => { if (Math.abs(e - 20) < Math.abs(V.elevations[turn.el] - 20)) turn.el = i; });
    for (let e = 0; e < V.elevations.length; ++e) for (let a = 0; a < V.azimuths; ++a) frame(src3d(e, a));
    // A drag across the image's width turns the surface once round; 40 px up or down is one elevation.
    const pane = document.getElementById('view3d');
    let turning = null;
    pane.addEventListener('mousedown', e => {
      e.preventDefault();
      turning = { x: e.clientX, y: e.clientY, az: turn.az, el: turn.el };
      pane.classList.add('dragging');
    });
    window.addEventListener('mousemove', e => {
      if (!turning) return;
      const width = Math.max(1, img3d.clientWidth || pane.clientWidth);
      setTurn(turning.az - (e.clientX - turning.x) * V.azimuths / width, turning.el + (e.clientY - turning.y) / 40);
    });
    window.addEventListener('mouseup', () => { turning = null; pane.classList.remove('dragging'); });
  }
  if (F && F.thresholds.length) {
    F.thresholds.forEach((t, i) => frame(srcFa(i)));
    faSlider.max = F.thresholds.length - 1;
    let nearest = 0;
    F.thresholds.forEach((t, i) => { if (Math.abs(t - 0.25) < Math.abs(F.thresholds[nearest] - 0.25)) nearest = i; });
    turn.fa = nearest;
    faSlider.addEventListener('input', () => setFa(Number(faSlider.value)));
  }

  // The URL's hash sets the start: #axis=coronal&slice=30&neuro=1&tracts=1, #tab=3d&az=9&el=0,
  // #tab=fa&fa=3 (frame indices), and selfcheck or selfcheck3d for tests.
  const params = new Map(location.hash.slice(1).split('&').filter(x => x).map(x => {
    const i = x.indexOf('=');
    return i < 0 ? [x, ''] : [x.slice(0, i), decodeURIComponent(x.slice(i + 1))];
  }));
  const named = D.axes.findIndex(ax => ax.name === params.get('axis'));
  if (named >= 0) state.axis = named;
  if (params.has('slice')) setSliceQuiet(state.axis, Number(params.get('slice')));
  state.neuro = params.get('neuro') === '1';
  state.tracts = params.get('tracts') === '1' && !!D.tracts;
  draw();
  if (V && params.has('az')) setTurn(Number(params.get('az')), turn.el);
  if (V && params.has('el')) setTurn(turn.az, Number(params.get('el')));
  if (F && params.has('fa')) setFa(Number(params.get('fa')));
  if (params.has('tab')) showTab(params.get('tab'));

  window.dtfWeb = { state: state, setSlice: setSlice, setAxis: setAxis, probe: probe, placement: placement, draw: draw,
                    turn: turn, showTab: showTab, setTurn: setTurn, setFa: setFa };

  // Self-check of the 3D view and the FA sweep for headless tests: a drag on the 3D view and a slider move,
  // each with the frame shown and loaded before and after, in <pre id="dtf-selfcheck">.
  function whenLoaded(img, then) {
    const t0 = Date.now();
    (function poll() {
      if ((img.complete && img.naturalWidth > 0) || Date.now() - t0 > 5000) then();
      else setTimeout(poll, 20);
    })();
  }
  const shown = img => ({ src: img.getAttribute('src'), loaded: img.complete && img.naturalWidth > 0,
                          width: img.naturalWidth, visible: img.offsetWidth > 0 && img.offsetHeight > 0 });
  if (params.has('selfcheck3d')) {
    const out = { view3d: !!document.getElementById('view3d'), frames3d: V ? V.azimuths * V.elevations.length : 0,
                  thresholds: F ? F.thresholds.length : 0 };
    showTab('3d');
    whenLoaded(img3d, () => {
      out.before3d = shown(img3d);
      out.before3d.azimuth = turn.az;
      const pane = document.getElementById('view3d'), rect = img3d.getBoundingClientRect();
      const x = Math.round(rect.left + rect.width / 2), y = Math.round(rect.top + rect.height / 2);
      pane.dispatchEvent(new MouseEvent('mousedown', { clientX: x, clientY: y, bubbles: true, cancelable: true }));
      window.dispatchEvent(new MouseEvent('mousemove', { clientX: x + Math.round(rect.width / 4), clientY: y, bubbles: true }));
      window.dispatchEvent(new MouseEvent('mouseup', { clientX: x + Math.round(rect.width / 4), clientY: y, bubbles: true }));
      whenLoaded(img3d, () => {
        out.after3d = shown(img3d);
        out.after3d.azimuth = turn.az;
        showTab('fa');
        whenLoaded(imgFa, () => {
          out.beforeFa = shown(imgFa);
          out.beforeFa.text = document.getElementById('fathreshold').textContent;
          faSlider.value = F.thresholds.length - 1;
          faSlider.dispatchEvent(new Event('input'));
          whenLoaded(imgFa, () => {
            out.afterFa = shown(imgFa);
            out.afterFa.text = document.getElementById('fathreshold').textContent;
            // Every frame preloaded: loaded, or an error reported below.
            const t0 = Date.now();
            (function all() {
              const list = Array.from(frames.values());
              if (list.some(i => !i.complete) && Date.now() - t0 < 10000) { setTimeout(all, 20); return; }
              out.framesLoaded = list.filter(i => i.complete && i.naturalWidth > 0).length;
              out.framesTotal = list.length;
              const base = location.href.replace(/[#?].*$/, '').replace(/[^/]*$/, '');
              out.outside = list.map(i => i.src).filter(n => n.indexOf(base) !== 0);
              out.errors = caught;
              const pre = document.createElement('pre');
              pre.id = 'dtf-selfcheck';
              pre.textContent = JSON.stringify(out);
              document.body.appendChild(pre);
            })();
          });
        });
      });
    });
  }

  // Self-check for headless tests: waits for the slice shown, probes it, moves the slider and reports JSON
  // in <pre id="dtf-selfcheck">.
  function whenDrawn(src, then) {
    const t0 = Date.now();
    (function poll() {
      const img = images.get(src);
      if ((img && img.complete && drawnSrc === src) || Date.now() - t0 > 5000) then(img);
      else setTimeout(poll, 20);
    })();
  }
  // The viewer's keys, the wheel and a drag as a user gives them (events dispatched on the page), each with
  // what it changed; the view is restored after.
  function interact() {
    const key = k => window.dispatchEvent(new KeyboardEvent('keydown', { key: k, bubbles: true }));
    const a0 = state.axis, s0 = state.slice[a0], r = {};
    key('ArrowUp');
    r.up = state.slice[a0] - s0;
    key('ArrowDown');
    key('PageDown');
    r.pageDown = state.slice[a0] - s0;
    key('PageUp');
    r.axes = ['c', 's', 'a'].map(k => { key(k); return D.axes[state.axis].name; });
    state.axis = a0;
    setSlice(a0, s0);
    // Whole pixels: mouse events carry integer client coordinates.
    const rect = view.getBoundingClientRect();
    const cx = Math.round(rect.left + rect.width * 0.3), cy = Math.round(rect.top + rect.height * 0.4);
    const before = probe(cx - rect.left, cy - rect.top);
    view.dispatchEvent(new WheelEvent('wheel', { deltaY: -400, clientX: cx, clientY: cy, bubbles: true, cancelable: true }));
    const after = probe(cx - rect.left, cy - rect.top);
    r.zoom = state.zoom;
    // Zooming keeps the point under the pointer.
    r.zoomShiftMm = before && after ? Math.hypot(...before.world.map((x, i) => x - after.world[i])) : null;
    const pan0 = [state.panX, state.panY];
    view.dispatchEvent(new MouseEvent('mousedown', { clientX: cx, clientY: cy, bubbles: true }));
    view.dispatchEvent(new MouseEvent('mousemove', { clientX: cx + 30, clientY: cy - 20, bubbles: true }));
    window.dispatchEvent(new MouseEvent('mouseup', { clientX: cx + 30, clientY: cy - 20, bubbles: true }));
    r.pan = [state.panX - pan0[0], state.panY - pan0[1]];
    key('r');
    r.reset = [state.zoom, state.panX, state.panY];
    r.probeText = document.getElementById('probe').textContent;
    return r;
  }
  if (params.has('selfcheck')) {
    const out = { axis: D.axes[state.axis].name, before: {}, after: {} };
    const first = currentSrc();
    whenDrawn(first, img => {
      const p = placement(), ax = D.axes[state.axis];
      const at = fx => probe(p.x + ax.width * p.scale * fx, p.y + ax.height * p.scale * 0.5);
      out.before = { slice: state.slice[state.axis], src: first, loaded: !!(img && img.naturalWidth > 0),
                     width: img ? img.naturalWidth : 0, drawn: drawn, probeLeft: at(0.4), probeCentre: at(0.5), probeRight: at(0.6) };
      const slider = document.getElementById('slider' + state.axis);
      const target = ax.slices[Math.max(0, ax.slices.indexOf(state.slice[state.axis]) - 2)];
      slider.value = target;
      slider.dispatchEvent(new Event('input'));
      const second = currentSrc();
      whenDrawn(second, img2 => {
        out.after = { slice: state.slice[state.axis], src: second, loaded: !!(img2 && img2.naturalWidth > 0), drawn: drawn,
                      probeCentre: at(0.5) };
        // Every file the page refers to (scripts, slice images) lies in its folder.
        const base = location.href.replace(/[#?].*$/, '').replace(/[^/]*$/, '');
        const refs = Array.from(document.querySelectorAll('script[src],img[src],link[href]'))
                         .map(e => e.src || e.href).concat(Array.from(images.keys()).map(s => new URL(s, location.href).href));
        out.resources = refs.length;
        out.outside = refs.filter(n => n.indexOf(base) !== 0);
        out.letters = ['ll', 'lr', 'lt', 'lb'].map(id => document.getElementById(id).textContent).join('');
        out.interaction = interact();
        out.errors = caught;
        const pre = document.createElement('pre');
        pre.id = 'dtf-selfcheck';
        pre.textContent = JSON.stringify(out);
        document.body.appendChild(pre);
        // Back to the slice the URL asked for, so a screenshot shows it.
        setSlice(state.axis, out.before.slice);
      });
    });
  }
})();
)JS";
}

} // namespace dtf::session
