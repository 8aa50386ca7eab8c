// millpath view.html: the program, the simulated stock and its deviation in 3D.
// Data: the JSON block #millpath-data written by millpath.report.viewer (program units,
// Z up, tool tip coordinates). Typed arrays arrive as base64 little-endian buffers.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls';

const D = JSON.parse(document.getElementById('millpath-data').textContent);
const $ = (id) => document.getElementById(id);
const api = (window.millpathViewer = { ready: false, timings: {} });
const T0 = performance.now();
function mark(name) { api.timings[name] = Math.round(performance.now() - T0); }
mark('start');

function decode(s, Type) {
  if (!s) return null;
  const bin = atob(s);
  const n = bin.length;
  const u8 = new Uint8Array(n);
  for (let i = 0; i < n; i++) u8[i] = bin.charCodeAt(i);
  return new Type(u8.buffer);
}
function fmt(v, d = 4) {
  if (v === null || v === undefined) return '-';
  if (typeof v !== 'number') return String(v);
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a >= 1e5 || a < 1e-3) return v.toExponential(2);
  return String(Number(v.toPrecision(d)));
}
function esc(s) {
  return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
}
function srgb(hex) { return new THREE.Color().setStyle(hex); }   // to the linear working space
function lerpColor(a, b, t) { return a.clone().lerp(b, Math.min(1, Math.max(0, t))); }
function ramp(stops, t) {
  t = Math.min(1, Math.max(0, t)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(t));
  return lerpColor(stops[i], stops[i + 1], t - i);
}
function upperBound(arr, k) {          // first index whose value is > k (arr sorted)
  let lo = 0, hi = arr.length;
  while (lo < hi) { const mid = (lo + hi) >> 1; if (arr[mid] <= k) lo = mid + 1; else hi = mid; }
  return lo;
}

// ---- data ------------------------------------------------------------------------------
const units = D.units;
const P = D.path;
const pts = decode(P.points, Float32Array);
const mFirst = decode(P.first, Int32Array);
const mLast = decode(P.last, Int32Array);
const mKind = decode(P.kind, Uint8Array);
const mFeed = decode(P.feed, Float32Array);
const mLine = decode(P.line, Int32Array);
const mOp = decode(P.op, Uint16Array);
const mTool = decode(P.tool, Uint32Array);
const M = mFirst.length;
mark('decoded');
const programLines = D.program.split(/\r?\n/);
const ops = D.operations;
const KIND = ['rapid', 'feed', 'arc', 'cubic', 'dwell', 'nurbs'];
const OP_COLOURS = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2',
  '#7f7f7f', '#bcbd22', '#17becf'].map(srgb);
const FEED_STOPS = ['#30123b', '#4686fb', '#1ae4b6', '#a2fc3c', '#fabb39', '#e4460a', '#7a0403'].map(srgb);

// ---- renderer, camera, controls -----------------------------------------------------
function softwareGL() {
  try {
    const gl = document.createElement('canvas').getContext('webgl2');
    if (!gl) return false;
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
    const lose = gl.getExtension('WEBGL_lose_context');
    if (lose) lose.loseContext();
    return /swiftshader|llvmpipe|softpipe|software/i.test(name);
  } catch (e) {
    return false;
  }
}
THREE.Object3D.DEFAULT_UP.set(0, 0, 1);
const host = $('view');
let renderer;
try {
  // multisampling costs a software renderer (SwiftShader, llvmpipe) about 4x per frame:
  // keep it for GPUs only
  api.softwareGL = softwareGL();
  renderer = new THREE.WebGLRenderer({ antialias: !api.softwareGL, preserveDrawingBuffer: true });
} catch (e) {
  $('status').textContent = 'WebGL is not available in this browser: ' + e.message;
  throw e;
}
renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
renderer.setSize(host.clientWidth, host.clientHeight);
host.appendChild(renderer.domElement);
mark('webgl');
const scene = new THREE.Scene();
scene.background = srgb('#eef0f3');
const camera = new THREE.PerspectiveCamera(35, host.clientWidth / host.clientHeight, 0.1, 1e5);
const controls = new OrbitControls(camera, renderer.domElement);
controls.screenSpacePanning = true;
controls.zoomToCursor = true;
scene.add(new THREE.HemisphereLight(0xffffff, 0x60646a, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
scene.add(sun);
scene.add(sun.target);

let renderPending = false;
function requestRender() {
  if (renderPending) return;
  renderPending = true;
  requestAnimationFrame(() => { renderPending = false; render(); });
}
controls.addEventListener('change', requestRender);

// ---- bounds -----------------------------------------------------------------------------
const [sx0, sy0, sz0, sx1, sy1, sz1] = D.stock;
const bounds = new THREE.Box3(new THREE.Vector3(sx0, sy0, sz0), new THREE.Vector3(sx1, sy1, sz1));
{
  const v = new THREE.Vector3();
  for (let i = 0; i < pts.length; i += 3) bounds.expandByPoint(v.set(pts[i], pts[i + 1], pts[i + 2]));
}
const size = bounds.getSize(new THREE.Vector3()).length() || 1;
mark('bounds');

// ---- toolpath ---------------------------------------------------------------------------
const feedMotions = [];
for (let k = 0; k < M; k++) if (mKind[k] !== 0 && mKind[k] !== 4 && mFeed[k] > 0) feedMotions.push(mFeed[k]);
let feedLo = Infinity, feedHi = -Infinity;
for (const f of feedMotions) { if (f < feedLo) feedLo = f; if (f > feedHi) feedHi = f; }
if (!isFinite(feedLo)) { feedLo = 0; feedHi = 1; }
function feedColour(f) { return ramp(FEED_STOPS, feedHi > feedLo ? (f - feedLo) / (feedHi - feedLo) : 0.5); }

const groups = [];            // {op, rapid, obj, segMotion, colOp, colFeed}: one per operation and kind
const opMoveCount = new Int32Array(ops.length);
{
  const nOps = ops.length;
  const count = new Int32Array(nOps * 2);     // segments of group op * 2 + (rapid ? 1 : 0)
  for (let k = 0; k < M; k++) {
    opMoveCount[mOp[k]]++;
    count[mOp[k] * 2 + (mKind[k] === 0 ? 1 : 0)] += mLast[k] - mFirst[k];
  }
  const opRGB = new Float32Array(nOps * 3);
  for (let o = 0; o < nOps; o++) {
    const c = OP_COLOURS[o % OP_COLOURS.length];
    opRGB[o * 3] = c.r; opRGB[o * 3 + 1] = c.g; opRGB[o * 3 + 2] = c.b;
  }
  const bufs = [];
  for (let g = 0; g < nOps * 2; g++) {
    const n = count[g], rapid = (g & 1) === 1;
    bufs.push(n === 0 ? null : {
      pos: new Float32Array(n * 6), segMotion: new Int32Array(n), s: 0,
      cOp: rapid ? null : new Float32Array(n * 6), cFeed: rapid ? null : new Float32Array(n * 6),
    });
  }
  mark('counted');
  const fc = new THREE.Color();
  for (let k = 0; k < M; k++) {
    const a = mFirst[k], b = mLast[k];
    if (b <= a) continue;
    const o = mOp[k], rapid = mKind[k] === 0;
    const B = bufs[o * 2 + (rapid ? 1 : 0)];
    const { pos, segMotion, cOp, cFeed } = B;
    let s = B.s;
    if (!rapid) fc.copy(feedColour(mFeed[k]));
    const or = opRGB[o * 3], og = opRGB[o * 3 + 1], ob = opRGB[o * 3 + 2];
    for (let p = a; p < b; p++, s++) {
      const i = p * 3, j = s * 6;
      pos[j] = pts[i]; pos[j + 1] = pts[i + 1]; pos[j + 2] = pts[i + 2];
      pos[j + 3] = pts[i + 3]; pos[j + 4] = pts[i + 4]; pos[j + 5] = pts[i + 5];
      segMotion[s] = k;
      if (!rapid) {
        cOp[j] = cOp[j + 3] = or; cOp[j + 1] = cOp[j + 4] = og; cOp[j + 2] = cOp[j + 5] = ob;
        cFeed[j] = cFeed[j + 3] = fc.r; cFeed[j + 1] = cFeed[j + 4] = fc.g; cFeed[j + 2] = cFeed[j + 5] = fc.b;
      }
    }
    B.s = s;
  }
  mark('filled');
  const rapidMat = new THREE.LineDashedMaterial({ color: srgb('#6d7178'), dashSize: size * 0.006,
    gapSize: size * 0.005, transparent: true, opacity: 0.85 });
  const feedMat = new THREE.LineBasicMaterial({ vertexColors: true });
  for (let g = 0; g < nOps * 2; g++) {
    const B = bufs[g];
    if (!B) continue;
    const rapid = (g & 1) === 1;
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(B.pos, 3));
    const colOp = B.cOp && new THREE.BufferAttribute(B.cOp, 3);
    const colFeed = B.cFeed && new THREE.BufferAttribute(B.cFeed, 3);
    if (colOp) geo.setAttribute('color', colOp);
    const obj = new THREE.LineSegments(geo, rapid ? rapidMat : feedMat);
    if (rapid) obj.computeLineDistances();
    obj.userData.segMotion = B.segMotion;
    scene.add(obj);
    groups.push({ op: g >> 1, rapid, obj, segMotion: B.segMotion, colOp, colFeed });
  }
}

mark('toolpath');
// ---- stock: box, simulated surface, design overlay, markers -----------------------------
// a bar (D.stock_cylinder = [cx, cy, r]) is drawn as its two end circles, else the box
const SC = D.stock_cylinder;
const stockBox = new THREE.LineSegments(
  SC ? new THREE.EdgesGeometry(new THREE.CylinderGeometry(SC[2], SC[2], sz1 - sz0, 96), 10)
    : new THREE.EdgesGeometry(new THREE.BoxGeometry(sx1 - sx0, sy1 - sy0, sz1 - sz0)),
  new THREE.LineBasicMaterial({ color: srgb('#3c4047') }));
if (SC) stockBox.rotation.x = Math.PI / 2;        // three.js cylinders run along Y
stockBox.position.set(SC ? SC[0] : (sx0 + sx1) / 2, SC ? SC[1] : (sy0 + sy1) / 2,
  (sz0 + sz1) / 2);
scene.add(stockBox);

const S = D.surface;
let surface = null, skirt = null, overlay = null;
const markers = [];
const NEUTRAL = srgb('#cfc9bf');
const RED_LO = srgb('#f4a09a'), RED_HI = srgb('#a50016');
const BLUE_LO = srgb('#9fc3ea'), BLUE_HI = srgb('#08306b');
const HEIGHT_STOPS = ['#3b4a6b', '#5f7fa8', '#9bb6c9', '#d8d2c4', '#efe6d2'].map(srgb);
let sHeights = null, sDev = null;
function gridGeometry(xs, ys, zs) {
  // a height field on the grid xs x ys; normals from central differences of the heights
  const nx = xs.length, ny = ys.length;
  const pos = new Float32Array(nx * ny * 3);
  const nrm = new Float32Array(nx * ny * 3);
  for (let j = 0; j < ny; j++) {
    const j0 = j > 0 ? j - 1 : j, j1 = j + 1 < ny ? j + 1 : j;
    for (let i = 0; i < nx; i++) {
      const v = j * nx + i, w = v * 3;
      pos[w] = xs[i]; pos[w + 1] = ys[j]; pos[w + 2] = zs[v];
      const i0 = i > 0 ? i - 1 : i, i1 = i + 1 < nx ? i + 1 : i;
      const gx = i1 > i0 ? (zs[j * nx + i1] - zs[j * nx + i0]) / (xs[i1] - xs[i0]) : 0;
      const gy = j1 > j0 ? (zs[j1 * nx + i] - zs[j0 * nx + i]) / (ys[j1] - ys[j0]) : 0;
      const inv = 1 / Math.sqrt(gx * gx + gy * gy + 1);
      nrm[w] = -gx * inv; nrm[w + 1] = -gy * inv; nrm[w + 2] = inv;
    }
  }
  const idx = new Uint32Array(Math.max(0, (nx - 1) * (ny - 1) * 6));
  let t = 0;
  for (let j = 0; j + 1 < ny; j++) for (let i = 0; i + 1 < nx; i++) {
    const a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
    idx[t++] = a; idx[t++] = b; idx[t++] = d; idx[t++] = a; idx[t++] = d; idx[t++] = c;
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  geo.setAttribute('normal', new THREE.BufferAttribute(nrm, 3));
  geo.setIndex(new THREE.BufferAttribute(idx, 1));
  return geo;
}
function put(a, v, c0, c1, t) {            // a[v] = c0 + (c1 - c0) * t, t clamped to [0, 1]
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  a[v] = c0.r + (c1.r - c0.r) * t; a[v + 1] = c0.g + (c1.g - c0.g) * t; a[v + 2] = c0.b + (c1.b - c0.b) * t;
}
function colourSurface(tol) {
  if (!surface) return;
  const col = surface.geometry.getAttribute('color');
  const a = col.array;
  const n = sHeights.length;
  if (sDev) {
    const g = S.max_gouge, l = S.max_left;
    const gs = g > tol ? 1 / (g - tol) : 0, ls = l > tol ? 1 / (l - tol) : 0;
    for (let v = 0; v < n; v++) {
      const d = sDev[v];
      if (d < -tol) put(a, v * 3, RED_LO, RED_HI, gs ? (-d - tol) * gs : 1);
      else if (d > tol) put(a, v * 3, BLUE_LO, BLUE_HI, ls ? (d - tol) * ls : 1);
      else put(a, v * 3, NEUTRAL, NEUTRAL, 0);
    }
  } else {
    let lo = Infinity, hi = -Infinity;
    for (let v = 0; v < n; v++) { if (sHeights[v] < lo) lo = sHeights[v]; if (sHeights[v] > hi) hi = sHeights[v]; }
    const m = HEIGHT_STOPS.length - 1;
    for (let v = 0; v < n; v++) {
      const t = (hi > lo ? (sHeights[v] - lo) / (hi - lo) : 1) * m;
      const i = Math.min(m - 1, Math.floor(t));
      put(a, v * 3, HEIGHT_STOPS[i], HEIGHT_STOPS[i + 1], t - i);
    }
  }
  col.needsUpdate = true;
  requestRender();
}
if (S) {
  const xs = decode(S.xs, Float32Array), ys = decode(S.ys, Float32Array);
  sHeights = decode(S.heights, Float32Array);
  sDev = decode(S.deviation, Float32Array);
  const geo = gridGeometry(xs, ys, sHeights);
  mark('grid');
  geo.setAttribute('color', new THREE.BufferAttribute(new Float32Array(sHeights.length * 3), 3));
  surface = new THREE.Mesh(geo, new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide }));
  scene.add(surface);
  // walls from the stock bottom up to the edge heights, so the block reads as a solid
  const nx = xs.length, ny = ys.length;
  const ring = [];
  for (let i = 0; i < nx; i++) ring.push([i, 0]);
  for (let j = 1; j < ny; j++) ring.push([nx - 1, j]);
  for (let i = nx - 2; i >= 0; i--) ring.push([i, ny - 1]);
  for (let j = ny - 2; j >= 0; j--) ring.push([0, j]);
  const wall = new Float32Array(ring.length * 18);
  for (let r = 0; r < ring.length; r++) {
    const [i0, j0] = ring[r], [i1, j1] = ring[(r + 1) % ring.length];
    const z0 = sHeights[j0 * nx + i0], z1 = sHeights[j1 * nx + i1];
    wall.set([xs[i0], ys[j0], S.zmin, xs[i1], ys[j1], S.zmin, xs[i1], ys[j1], z1,
      xs[i0], ys[j0], S.zmin, xs[i1], ys[j1], z1, xs[i0], ys[j0], z0], r * 18);
  }
  const wg = new THREE.BufferGeometry();
  wg.setAttribute('position', new THREE.BufferAttribute(wall, 3));
  wg.computeVertexNormals();
  skirt = new THREE.Mesh(wg, new THREE.MeshLambertMaterial({ color: srgb('#a9a398'), side: THREE.DoubleSide }));
  scene.add(skirt);
  if (S.design) {
    const og = gridGeometry(xs, ys, decode(S.design, Float32Array));
    overlay = new THREE.Mesh(og, new THREE.MeshLambertMaterial({ color: srgb('#37b26c'),
      transparent: true, opacity: 0.3, depthWrite: false, side: THREE.DoubleSide,
      polygonOffset: true, polygonOffsetFactor: -1, polygonOffsetUnits: -4 }));
    overlay.renderOrder = 2;
    scene.add(overlay);
  }
  // the worst points are the proof's (exact, on the design) when it ran, else the stock
  // model's cells
  const X = D.exact;
  const marks = X ? [[X.max_gouge > X.accuracy ? X.gouge_at : null, '#c00018', 'worst gouge', X.max_gouge],
    [X.max_left > X.accuracy ? X.left_at : null, '#0b3d91', 'worst leftover', X.max_left]]
    : [[S.gouge_at, '#c00018', 'worst gouge', S.max_gouge],
      [S.left_at, '#0b3d91', 'worst leftover', S.max_left]];
  for (const [at, colour, label, value] of marks) {
    if (!at) continue;
    const g = new THREE.Group();
    const mat = new THREE.MeshBasicMaterial({ color: srgb(colour), depthTest: false });
    const ball = new THREE.Mesh(new THREE.SphereGeometry(size * 0.006, 16, 12), mat);
    ball.renderOrder = 10;
    g.add(ball);
    const pin = new THREE.Line(new THREE.BufferGeometry().setFromPoints([
      new THREE.Vector3(0, 0, 0), new THREE.Vector3(0, 0, Math.max(sz1 - at[2], 0) + size * 0.05)]),
      new THREE.LineBasicMaterial({ color: srgb(colour), depthTest: false }));
    pin.renderOrder = 10;
    g.add(pin);
    g.position.set(at[0], at[1], at[2]);
    scene.add(g);
    const div = document.createElement('div');
    div.className = 'marker-label';
    div.style.borderColor = colour;
    div.textContent = `${label} ${fmt(value)} ${units}`;
    $('labels').appendChild(div);
    markers.push({ g, div, top: new THREE.Vector3(at[0], at[1], at[2] + Math.max(sz1 - at[2], 0) + size * 0.05) });
  }
}
mark('surface');
const axes = new THREE.AxesHelper(size * 0.08);
scene.add(axes);

// ---- tools ---------------------------------------------------------------------------------
const toolAnchor = new THREE.Group();        // at the tool tip of the current move
scene.add(toolAnchor);
const toolMeshes = new Map();
const cutterMat = new THREE.MeshLambertMaterial({ color: srgb('#e0a030') });
const shankMat = new THREE.MeshLambertMaterial({ color: srgb('#8c939c') });
const holderMat = new THREE.MeshLambertMaterial({ color: srgb('#59606a'), transparent: true, opacity: 0.45, depthWrite: false });
for (const [num, t] of Object.entries(D.tools)) {
  const g = new THREE.Group();
  const lathe = new THREE.LatheGeometry(t.profile.map(([r, z]) => new THREE.Vector2(r, z)), 40);
  lathe.rotateX(Math.PI / 2);                  // lathe axis Y -> tool axis Z
  g.add(new THREE.Mesh(lathe, cutterMat));
  for (const [r, z0, z1, part] of t.cylinders) {
    const cg = new THREE.CylinderGeometry(r, r, z1 - z0, 40);
    cg.rotateX(Math.PI / 2);
    cg.translate(0, 0, (z0 + z1) / 2);
    const mesh = new THREE.Mesh(cg, part === 'shank' ? shankMat : holderMat);
    if (part !== 'shank') mesh.renderOrder = 3;
    g.add(mesh);
  }
  g.visible = false;
  toolAnchor.add(g);
  toolMeshes.set(Number(num), g);
}
const tipDot = new THREE.Mesh(new THREE.SphereGeometry(size * 0.004, 12, 8),
  new THREE.MeshBasicMaterial({ color: srgb('#e0a030') }));
toolAnchor.add(tipDot);

// ---- selection highlight ---------------------------------------------------------------
const selMat = new THREE.LineBasicMaterial({ color: srgb('#ff00c8'), depthTest: false });
const selLine = new THREE.Line(new THREE.BufferGeometry(), selMat);
selLine.renderOrder = 20;
selLine.visible = false;
scene.add(selLine);
const selDot = new THREE.Mesh(new THREE.SphereGeometry(size * 0.005, 12, 8),
  new THREE.MeshBasicMaterial({ color: srgb('#ff00c8'), depthTest: false }));
selDot.renderOrder = 20;
selDot.visible = false;
scene.add(selDot);

// ---- state -------------------------------------------------------------------------------
let cur = M - 1;
let selected = -1;
let colourBy = 'operation';
const opVisible = ops.map(() => true);
const layer = { feeds: true, rapids: true, surface: true, design: false, box: true, tool: true, markers: true };

function motionText(k) {
  const line = mLine[k];
  const text = programLines[line - 1] ?? '';
  const kind = KIND[mKind[k]];
  const feed = mKind[k] === 0 ? 'rapid' : mKind[k] === 4 ? 'dwell' : `F ${fmt(mFeed[k], 6)} ${units}/min`;
  const op = ops[mOp[k]];
  return { line, text, kind, feed, op: op ? op.name : '', tool: mTool[k] };
}
function applyVisibility() {
  for (const g of groups) g.obj.visible = opVisible[g.op] && (g.rapid ? layer.rapids : layer.feeds);
  if (surface) { surface.visible = layer.surface; skirt.visible = layer.surface; }
  if (overlay) overlay.visible = layer.design;
  stockBox.visible = layer.box;
  axes.visible = layer.box;
  toolAnchor.visible = layer.tool;
  for (const m of markers) { m.g.visible = layer.markers; m.div.style.display = layer.markers ? '' : 'none'; }
  requestRender();
}
function setMove(k) {
  k = Math.max(0, Math.min(M - 1, Math.round(k)));
  cur = k;
  const whole = $('whole').checked;
  for (const g of groups) {
    const n = whole ? g.segMotion.length : upperBound(g.segMotion, k);
    g.obj.geometry.setDrawRange(0, n * 2);
  }
  const p = mLast[k] * 3;
  toolAnchor.position.set(pts[p], pts[p + 1], pts[p + 2]);
  let shown = 0;
  for (const [num, g] of toolMeshes) { g.visible = num === mTool[k]; if (g.visible) shown = num; }
  api.shownTool = shown;
  const slider = $('slider');
  if (Number(slider.value) !== k) slider.value = String(k);
  const t = motionText(k);
  $('move-no').textContent = `${k + 1} / ${M}`;
  $('line-no').textContent = String(t.line);
  $('line-text').textContent = t.text;
  $('move-info').textContent = `${t.kind}, ${t.feed}, T${t.tool}${t.op ? ', ' + t.op : ''}`;
  requestRender();
}
function select(k) {
  selected = k;
  if (k < 0) {
    selLine.visible = selDot.visible = false;
    $('selection').hidden = true;
    requestRender();
    return;
  }
  const a = mFirst[k], b = mLast[k];
  const arr = pts.slice(a * 3, (b + 1) * 3);
  selLine.geometry.dispose();
  selLine.geometry = new THREE.BufferGeometry();
  selLine.geometry.setAttribute('position', new THREE.BufferAttribute(arr, 3));
  selLine.visible = true;
  selDot.position.set(pts[b * 3], pts[b * 3 + 1], pts[b * 3 + 2]);
  selDot.visible = true;
  const t = motionText(k);
  $('sel-move').textContent = String(k + 1);
  $('sel-line').textContent = String(t.line);
  $('sel-text').textContent = t.text;
  $('sel-info').textContent = `${t.kind}, ${t.feed}, T${t.tool}${t.op ? ', ' + t.op : ''}`;
  $('selection').hidden = false;
  requestRender();
}
function setColourBy(mode) {
  colourBy = mode;
  for (const g of groups) if (!g.rapid) g.obj.geometry.setAttribute('color', mode === 'feed' ? g.colFeed : g.colOp);
  $('feed-legend').hidden = mode !== 'feed';
  requestRender();
}

// ---- views ---------------------------------------------------------------------------------
const VIEWS = { top: [0, -1e-4, 1], front: [0, -1, 0], iso: [1, -1, 0.9], right: [1, 0, 0] };
function freeLeft() {                       // pixels on the left covered by the panel
  const panel = $('panel');
  const w = host.clientWidth;
  if (!panel || panel.hidden || w < 700) return 0;
  return Math.min(panel.getBoundingClientRect().right + 8, w / 2);
}
function layoutCamera() {
  // centre the picture in the part of the window the panel leaves free
  const w = host.clientWidth, h = host.clientHeight;
  camera.aspect = w / h;
  const left = freeLeft();
  if (left > 0) camera.setViewOffset(w, h, -left / 2, 0, w, h); else camera.clearViewOffset();
  camera.updateProjectionMatrix();
}
function fit(dirArr) {
  // look along dir at the bounds' centre from the nearest distance that shows all eight
  // corners of the bounds in the free part of the window
  layoutCamera();
  const c = bounds.getCenter(new THREE.Vector3());
  const dir = dirArr ? new THREE.Vector3(...dirArr).normalize()
    : camera.position.clone().sub(controls.target).normalize();
  const right = new THREE.Vector3().crossVectors(camera.up, dir);
  if (right.lengthSq() < 1e-12) right.set(1, 0, 0);
  right.normalize();
  const up = new THREE.Vector3().crossVectors(dir, right).normalize();
  const w = host.clientWidth, h = host.clientHeight;
  const tanV = Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2) * 0.92;
  const tanH = tanV * Math.max(w - freeLeft(), 1) / h;
  let dist = 0;
  const p = new THREE.Vector3();
  for (let k = 0; k < 8; k++) {
    p.set(k & 1 ? bounds.max.x : bounds.min.x, k & 2 ? bounds.max.y : bounds.min.y,
      k & 4 ? bounds.max.z : bounds.min.z).sub(c);
    const x = p.dot(right), y = p.dot(up), z = p.dot(dir);
    dist = Math.max(dist, Math.abs(x) / tanH + z, Math.abs(y) / tanV + z);
  }
  dist = Math.max(dist, 1e-6);
  camera.position.copy(c).addScaledVector(dir, dist);
  controls.target.copy(c);
  controls.update();
  requestRender();
}

// ---- picking ------------------------------------------------------------------------------
const raycaster = new THREE.Raycaster();
function pickAt(clientX, clientY) {
  const rect = renderer.domElement.getBoundingClientRect();
  camera.updateMatrixWorld();               // the view may have changed since the last frame
  const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1,
    -((clientY - rect.top) / rect.height) * 2 + 1);
  raycaster.setFromCamera(ndc, camera);
  const dist = camera.position.distanceTo(controls.target);
  const worldPerPx = (2 * dist * Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2)) / rect.height;
  raycaster.params.Line = { threshold: 5 * worldPerPx };
  const objs = groups.filter((g) => g.obj.visible).map((g) => g.obj);
  const hits = raycaster.intersectObjects(objs, false);
  if (!hits.length) return -1;
  const h = hits[0];
  return h.object.userData.segMotion[Math.floor(h.index / 2)];
}
let downAt = null;
renderer.domElement.addEventListener('pointerdown', (e) => { downAt = [e.clientX, e.clientY]; });
renderer.domElement.addEventListener('pointerup', (e) => {
  if (!downAt || Math.hypot(e.clientX - downAt[0], e.clientY - downAt[1]) > 4) return;
  select(pickAt(e.clientX, e.clientY));
});

// ---- playing -------------------------------------------------------------------------------
let playing = false, lastT = 0, acc = 0;
function tick(t) {
  if (!playing) return;
  const dt = lastT ? (t - lastT) / 1000 : 0;
  lastT = t;
  acc += Number($('speed').value) * dt;
  const adv = Math.floor(acc);
  if (adv > 0) { acc -= adv; setMove(cur + adv); }
  if (cur >= M - 1) { setPlaying(false); return; }
  requestAnimationFrame(tick);
}
function setPlaying(on) {
  playing = on;
  $('play').textContent = on ? 'Pause' : 'Play';
  if (on) {
    if (cur >= M - 1) setMove(0);
    lastT = 0; acc = 0;
    requestAnimationFrame(tick);
  }
}

// ---- rendering ------------------------------------------------------------------------------
const tmp = new THREE.Vector3();
let frameWaiters = [];
function render() {
  // depth range from the camera's distance to the scene, so zooming never clips
  const d = camera.position.distanceTo(bounds.getCenter(tmp));
  camera.near = Math.max(d - size, d * 0.01, size * 1e-4);
  camera.far = d + size * 2;
  camera.updateProjectionMatrix();
  sun.position.copy(camera.position);
  sun.target.position.copy(controls.target);
  renderer.render(scene, camera);
  if (!api.ready) mark('first-render');
  const rect = renderer.domElement.getBoundingClientRect();
  for (const m of markers) {
    tmp.copy(m.top).project(camera);
    m.div.style.left = `${((tmp.x + 1) / 2) * rect.width}px`;
    m.div.style.top = `${((1 - tmp.y) / 2) * rect.height}px`;
  }
  api.frames = (api.frames || 0) + 1;
  const waiting = frameWaiters;
  frameWaiters = [];
  for (const resolve of waiting) resolve(api.frames);
  if (!api.ready) {
    api.ready = true;
    api.readyMs = performance.now();
    document.body.dataset.ready = '1';
  }
}
window.addEventListener('resize', () => {
  renderer.setSize(host.clientWidth, host.clientHeight);
  layoutCamera();
  requestRender();
});

// ---- panel ----------------------------------------------------------------------------------
function buildPanel() {
  $('title').textContent = D.title;
  const v = D.verification;
  const rows = [['program', `${D.program_name}, ${M} moves, ${units}`]];
  if (v) {
    // the proof's figures (report.json's), as the markers; the stock model's only when
    // the exact check did not run, and then said so
    const X = D.exact;
    if (X) {
      const how = `exact, normal to the design, ±${fmt(X.accuracy)}`;
      rows.push(['max gouge', `${fmt(X.max_gouge)} ${units} (${how})`]);
      rows.push(['max left', `${fmt(X.max_left)} ${units} (${how})`]);
    } else {
      const g = S && sDev ? S.max_gouge : v.max_gouge, l = S && sDev ? S.max_left : v.max_left;
      const how = `stock model, ${fmt(v.resolution)} ${units} cells`;
      if (g !== null && g !== undefined) rows.push(['max gouge', `${fmt(g)} ${units} (${how})`]);
      if (l !== null && l !== undefined) rows.push(['max left', `${fmt(l)} ${units} (${how})`]);
    }
    rows.push(['removed', `${fmt(v.removed_volume, 6)} ${units}³`]);
    rows.push(['rapids in material', String(v.rapids_through_material)]);
    rows.push(['holder contacts', String(v.holder_contacts)]);
    rows.push(['cycle time', `${fmt(v.cycle_time_s, 5)} s`]);
    rows.push(['stock model', `${fmt(v.resolution)} ${units} cells` + (S && S.step > 1 ? `, shown 1 in ${S.step}` : '')]);
  }
  $('summary').innerHTML = rows.map(([k, val]) => `<tr><th>${esc(k)}</th><td>${esc(val)}</td></tr>`).join('');
  const list = $('ops');
  ops.forEach((o, i) => {
    const c = OP_COLOURS[i % OP_COLOURS.length].clone().convertLinearToSRGB();
    const li = document.createElement('label');
    li.className = 'op';
    li.innerHTML = `<input type="checkbox" checked data-op="${i}"><span class="swatch" style="background:#${c.getHexString()}"></span>` +
      `<span>${esc(o.name)} <small>T${o.tool}, ${opMoveCount[i]} moves, line ${o.first_line}</small></span>`;
    li.querySelector('input').addEventListener('change', (e) => { opVisible[i] = e.target.checked; applyVisibility(); });
    list.appendChild(li);
  });
  $('feed-lo').textContent = `${fmt(feedLo, 5)}`;
  $('feed-hi').textContent = `${fmt(feedHi, 5)} ${units}/min`;
  if (S && sDev) {
    $('dev-legend').hidden = false;
    // the colours are the stock model's cells (display only); the figures the proof's
    $('gouge-max').textContent = `stock model: gouge ${fmt(S.max_gouge)}`;
    $('left-max').textContent = `left ${fmt(S.max_left)}`;
    $('tol').value = String(D.tolerance);
    $('tol').step = String(D.tolerance / 2);
    $('tol').addEventListener('input', () => { const t = Math.abs(Number($('tol').value)) || 0; colourSurface(t); });
  } else {
    $('tol-row').hidden = true;
    if (!S) $('surface-row').hidden = true;
  }
  if (!overlay) $('design-row').hidden = true;
  if (!markers.length) $('markers-row').hidden = true;
  for (const key of Object.keys(layer)) {
    const box = $('show-' + key);
    if (!box) continue;
    box.addEventListener('change', () => { layer[key] = box.checked; applyVisibility(); });
  }
  for (const r of document.querySelectorAll('input[name=colour]')) r.addEventListener('change', () => setColourBy(r.value));
  for (const name of Object.keys(VIEWS)) $('view-' + name).addEventListener('click', () => fit(VIEWS[name]));
  $('view-fit').addEventListener('click', () => fit(null));
  const slider = $('slider');
  slider.max = String(M - 1);
  slider.addEventListener('input', () => setMove(Number(slider.value)));
  $('whole').addEventListener('change', () => setMove(cur));
  $('play').addEventListener('click', () => setPlaying(!playing));
  $('step-back').addEventListener('click', () => setMove(cur - 1));
  $('step-fwd').addEventListener('click', () => setMove(cur + 1));
  $('sel-go').addEventListener('click', () => { if (selected >= 0) setMove(selected); });
  $('sel-close').addEventListener('click', () => select(-1));
  window.addEventListener('keydown', (e) => {
    // the slider, number fields and menus handle their own keys
    if (e.target instanceof HTMLSelectElement) return;
    if (e.target instanceof HTMLInputElement && (e.target.type === 'number' || e.target.type === 'range')) return;
    if (e.key === 'ArrowRight') setMove(cur + 1);
    else if (e.key === 'ArrowLeft') setMove(cur - 1);
    else if (e.key === ' ') { e.preventDefault(); setPlaying(!playing); }
  });
}

// ---- API for tests and scripts --------------------------------------------------------------
Object.assign(api, {
  moves: M,
  operations: ops.length,
  setMove, select, fit: (name) => fit(name ? VIEWS[name] : null), setColourBy, pickAt,
  toolTip: () => toolAnchor.position.toArray(),
  // milliseconds per frame while orbiting the camera about the target by n small steps
  // (each frame drawn and read back, so the GPU work is included)
  frameMs: (n = 10) => {
    const gl = renderer.getContext();
    const px = new Uint8Array(4);
    const t0 = performance.now();
    for (let i = 0; i < n; i++) {
      camera.position.sub(controls.target).applyAxisAngle(camera.up, 0.05).add(controls.target);
      camera.lookAt(controls.target);
      render();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    }
    return (performance.now() - t0) / n;
  },
  // a promise of the next frame drawn (with everything changed so far)
  nextFrame: () => new Promise((resolve) => { frameWaiters.push(resolve); requestRender(); }),
  // bounding boxes of the shown tool relative to its tip: the cutter, and everything
  toolBox: () => {
    const g = toolMeshes.get(api.shownTool);
    if (!g) return null;
    toolAnchor.updateMatrixWorld(true);
    const rel = (obj) => {
      const b = new THREE.Box3().setFromObject(obj);
      return [b.min.sub(toolAnchor.position).toArray(), b.max.sub(toolAnchor.position).toArray()];
    };
    return { cutter: rel(g.children[0]), all: rel(g) };
  },
  motionLine: (k) => mLine[k],
  motionEnd: (k) => Array.from(pts.slice(mLast[k] * 3, mLast[k] * 3 + 3)),
  // client pixel of the middle of motion k's polyline (for clicking it)
  screenOf: (k) => {
    const a = mFirst[k], b = mLast[k];
    const p = a + Math.floor((b - a) / 2);
    const q = Math.min(p + 1, b);
    camera.updateMatrixWorld();
    tmp.set((pts[p * 3] + pts[q * 3]) / 2, (pts[p * 3 + 1] + pts[q * 3 + 1]) / 2,
      (pts[p * 3 + 2] + pts[q * 3 + 2]) / 2).project(camera);
    const rect = renderer.domElement.getBoundingClientRect();
    return [rect.left + ((tmp.x + 1) / 2) * rect.width, rect.top + ((1 - tmp.y) / 2) * rect.height];
  },
});

Object.defineProperty(api, 'move', { get: () => cur });          // live, unlike Object.assign
Object.defineProperty(api, 'selected', { get: () => selected });
buildPanel();
colourSurface(D.tolerance);
setColourBy('operation');
applyVisibility();
fit(VIEWS.iso);
if (M > 0) setMove(M - 1);
$('status').textContent = '';
