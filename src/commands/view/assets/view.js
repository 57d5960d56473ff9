// cellc view: draws the document `cellc view` computed (geometry, frames of forward
// kinematics, graphs as SVG). Nothing here computes kinematics or plans: it places
// meshes where the frames say, interpolating between neighbouring frames only.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const doc = JSON.parse(document.getElementById('cellc-data').textContent);
const $ = (id) => document.getElementById(id);
const BACKGROUND = 0xeef1f5;
const COLOURS = { link: 0x8796ad, hand: 0x3f4a5c, surface: 0xc8a27a, obstacle: 0x9c8f80, object: 0xe4572e };
const PALETTE = [0x2563eb, 0x16a34a, 0xd97706, 0x9333ea, 0x0891b2, 0xdb2777, 0x65a30d, 0x7c3aed];

const api = { ready: false, webgl: false };
window.cellcView = api;

$('cell').textContent = doc.cell;
$('title').textContent = doc.title;

// --- Renderer -----------------------------------------------------------------------
const host = $('scene');
let renderer = null;
try {
  renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  api.webgl = !!renderer.getContext();
} catch (e) {
  const n = $('notice');
  n.hidden = false;
  n.textContent = 'This browser gives no WebGL context, so the scene cannot be drawn: ' + e.message;
}
const scene = new THREE.Scene();
scene.background = new THREE.Color(BACKGROUND);
const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 200);
camera.up.set(0, 0, 1);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8f99, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(2, -3, 5);
scene.add(sun);

// --- Bodies -------------------------------------------------------------------------
function geometryOf(g) {
  switch (g.type) {
    case 'box': return new THREE.BoxGeometry(g.size[0], g.size[1], g.size[2]);
    case 'sphere': return new THREE.SphereGeometry(g.radius, 24, 16);
    case 'cylinder': return new THREE.CylinderGeometry(g.radius, g.radius, g.height, 24);
    default: {
      const b = new THREE.BufferGeometry();
      b.setAttribute('position', new THREE.Float32BufferAttribute(g.positions, 3));
      b.setIndex(g.indices);
      b.computeVertexNormals();
      return b;
    }
  }
}
const geoms = doc.geometry.geoms.map(geometryOf);
const materials = {};
for (const k of Object.keys(COLOURS)) {
  materials[k] = new THREE.MeshLambertMaterial({ color: COLOURS[k], flatShading: true });
}
function setPose(o, p) {
  o.position.set(p[0], p[1], p[2]);
  o.quaternion.set(p[3], p[4], p[5], p[6]);
}
const bodies = doc.geometry.bodies.map((b) => {
  const group = new THREE.Group();
  group.name = b.name;
  group.userData = b;
  for (const part of b.parts) {
    const mesh = new THREE.Mesh(geoms[part.geom], materials[b.kind]);
    setPose(mesh, part.local);
    group.add(mesh);
  }
  scene.add(group);
  return group;
});
for (const [b, p] of doc.fixed) setPose(bodies[b], p);

// --- Workspaces and reach boxes -----------------------------------------------------
function label(text, colour) {
  const c = document.createElement('canvas');
  const ctx = c.getContext('2d');
  ctx.font = 'bold 28px sans-serif';
  c.width = Math.ceil(ctx.measureText(text).width) + 16;
  c.height = 40;
  ctx.font = 'bold 28px sans-serif';
  ctx.fillStyle = 'rgba(255,255,255,0.8)';
  ctx.fillRect(0, 0, c.width, c.height);
  ctx.fillStyle = '#' + colour.toString(16).padStart(6, '0');
  ctx.fillText(text, 8, 29);
  const s = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(c), depthTest: false }));
  // Labels 4 cm tall, whatever their length.
  s.scale.set(0.04 * c.width / c.height, 0.04, 1);
  s.renderOrder = 10;
  return s;
}
const regions = doc.regions.map((r, i) => {
  const colour = r.kind === 'reach' ? 0x64748b : PALETTE[i % PALETTE.length];
  const group = new THREE.Group();
  const fill = new THREE.MeshBasicMaterial({ color: colour, transparent: true, opacity: r.kind === 'reach' ? 0.06 : 0.12, depthWrite: false });
  const edge = new THREE.LineBasicMaterial({ color: colour });
  let top = null;
  for (const [min, max] of r.boxes) {
    const size = [max[0] - min[0], max[1] - min[1], max[2] - min[2]];
    const box = new THREE.BoxGeometry(size[0], size[1], size[2]);
    const m = new THREE.Mesh(box, fill);
    const lines = new THREE.LineSegments(new THREE.EdgesGeometry(box), edge);
    for (const o of [m, lines]) {
      o.position.set((min[0] + max[0]) / 2, (min[1] + max[1]) / 2, (min[2] + max[2]) / 2);
      group.add(o);
    }
    if (!top || max[2] > top[2]) top = [(min[0] + max[0]) / 2, (min[1] + max[1]) / 2, max[2]];
  }
  const text = label(r.name + (r.label && r.kind === 'workspace' ? ' (' + r.label + ')' : ''), colour);
  if (top) text.position.set(top[0], top[1], top[2] + 0.04);
  group.add(text);
  group.visible = false;
  scene.add(group);
  return { region: r, group, edge, fill, colour, text };
});

// --- Controls of what is shown ------------------------------------------------------
function checkbox(parent, text, checked, onChange, colour) {
  const l = document.createElement('label');
  const c = document.createElement('input');
  c.type = 'checkbox';
  c.checked = checked;
  c.addEventListener('change', () => { onChange(c.checked); draw(); });
  l.append(c);
  if (colour !== undefined) {
    const s = document.createElement('span');
    s.className = 'swatch';
    s.style.background = '#' + colour.toString(16).padStart(6, '0');
    l.append(s);
  }
  l.append(text);
  parent.append(l);
  return c;
}
const kinds = [['link', 'robots'], ['hand', 'hands'], ['surface', 'surfaces'], ['obstacle', 'obstacles'], ['object', 'objects']];
for (const [kind, text] of kinds) {
  if (!doc.geometry.bodies.some((b) => b.kind === kind)) continue;
  checkbox($('layers'), text, true, (on) => {
    bodies.forEach((b) => { if (b.userData.kind === kind) b.userData.shown = on; });
    applyVisibility();
  }, COLOURS[kind]);
}
let labelsShown = true;
checkbox($('layers'), 'labels', true, (on) => { labelsShown = on; regions.forEach((r) => { r.text.visible = on; }); });
for (const r of regions) {
  const parent = r.region.kind === 'reach' ? $('reach') : $('workspaces');
  const on = r.region.kind === 'workspace';
  r.group.visible = on;
  r.checkbox = checkbox(parent, r.region.name, on, (v) => { r.group.visible = v; }, r.colour);
}
if (!regions.length) $('workspaces').textContent = 'none (an abstract cell has no geometry)';
bodies.forEach((b) => { b.userData.shown = true; });
let poses = null;
function applyVisibility() {
  const moving = doc.timeline.moving;
  bodies.forEach((b) => { b.visible = b.userData.shown; });
  if (poses) moving.forEach((b, i) => { if (!poses[i]) bodies[b].visible = false; });
}

// --- Frames -------------------------------------------------------------------------
const frames = doc.timeline.frames;
const duration = frames.length ? frames[frames.length - 1].t : 0;
const qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
function frameIndex(t) {
  let lo = 0, hi = frames.length - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (frames[mid].t <= t) lo = mid; else hi = mid - 1;
  }
  return lo;
}
function showPoses(list, next, f) {
  poses = list;
  doc.timeline.moving.forEach((b, i) => {
    const p = list[i];
    if (!p) return;
    const o = bodies[b];
    const q = next && next[i];
    if (q && f > 0) {
      o.position.set(p[0] + (q[0] - p[0]) * f, p[1] + (q[1] - p[1]) * f, p[2] + (q[2] - p[2]) * f);
      qa.set(p[3], p[4], p[5], p[6]);
      qb.set(q[3], q[4], q[5], q[6]);
      o.quaternion.slerpQuaternions(qa, qb, f);
    } else {
      setPose(o, p);
    }
  });
  applyVisibility();
}
let now = 0, playing = false, speed = 1, snapshot = null;
function setTime(t) {
  now = Math.max(0, Math.min(duration, t));
  snapshot = null;
  if (!frames.length) return;
  const i = frameIndex(now);
  const a = frames[i], b = frames[Math.min(i + 1, frames.length - 1)];
  const f = b.t > a.t ? (now - a.t) / (b.t - a.t) : 0;
  showPoses(a.poses, b.poses, Math.max(0, Math.min(1, f)));
  $('scrub').value = duration > 0 ? Math.round(1000 * now / duration) : 0;
  $('clock').textContent = now.toFixed(2) + ' / ' + duration.toFixed(2) + ' s';
  markStep(a.step);
}

// --- Plan panel ---------------------------------------------------------------------
const steps = doc.timeline.steps;
const stepItems = [];
const holderItems = [];
if (steps.length) {
  $('plan').hidden = false;
  doc.timeline.plans.forEach((p, k) => {
    const li = document.createElement('li');
    li.append(p.label + ' (' + p.object + '): ');
    p.holders.forEach((h, j) => {
      if (j) li.append(' → ');
      const span = document.createElement('span');
      span.className = 'holder';
      span.textContent = h;
      li.append(span);
    });
    $('holders').append(li);
    holderItems.push(li);
    void k;
  });
  steps.forEach((s, i) => {
    const li = document.createElement('li');
    li.textContent = s.text + (s.end > s.start ? ' [' + s.start.toFixed(1) + '–' + s.end.toFixed(1) + ' s]' : '');
    li.addEventListener('click', () => { pause(); setTime(s.start + 1e-6); draw(); });
    $('steps').append(li);
    stepItems.push(li);
    void i;
  });
}
let currentStep = undefined;
function markStep(i) {
  if (i === currentStep) return;
  currentStep = i;
  stepItems.forEach((li, k) => li.classList.toggle('current', k === i));
  const s = i === null || i === undefined ? null : steps[i];
  holderItems.forEach((li, k) => {
    const here = !!s && s.plan === k;
    li.classList.toggle('current', here);
    li.querySelectorAll('.holder').forEach((h) => h.classList.toggle('current', here && h.textContent === s.holder));
  });
  markGraph();
}
if (doc.timeline.truncated) {
  const n = $('notice');
  n.hidden = false;
  n.textContent = 'The plan is longer than a page shows; its end is cut.';
}

// --- Graph panel --------------------------------------------------------------------
const objectSelect = $('object');
doc.graphs.forEach((g, i) => {
  const o = document.createElement('option');
  o.value = i;
  o.textContent = g.object + ' (' + g.states.length + ' states' + (g.pruned ? ', ' + g.pruned + ' arcs pruned' : '') + ')';
  objectSelect.append(o);
});
let graphIndex = 0;
const firstPlan = doc.timeline.plans[0];
const wanted = doc.explanation ? doc.explanation.object : firstPlan ? firstPlan.object : null;
doc.graphs.forEach((g, i) => { if (g.object === wanted) graphIndex = i; });
objectSelect.value = graphIndex;
let selected = null;
function showGraph() {
  const g = doc.graphs[graphIndex];
  const box = $('graph');
  box.innerHTML = g ? g.svg : '';
  selected = null;
  box.querySelectorAll('.state').forEach((el) => {
    el.addEventListener('click', () => selectState(Number(el.dataset.state)));
  });
  markGraph();
}
function markGraph() {
  const g = doc.graphs[graphIndex];
  if (!g) return;
  const box = $('graph');
  const planStates = new Set();
  let current = null;
  doc.timeline.plans.forEach((p, k) => {
    if (p.object !== g.object) return;
    if (p.first !== null) planStates.add(p.first);
    steps.forEach((s, i) => {
      if (s.plan !== k || s.state === null) return;
      planStates.add(s.state);
      if (i === currentStep) current = s.state;
    });
  });
  const ex = doc.explanation && doc.explanation.object === g.object ? doc.explanation : null;
  const startSide = new Set(ex ? ex.start_side : []);
  const goalSide = new Set(ex ? ex.goal_side : []);
  box.querySelectorAll('.state').forEach((el) => {
    const n = Number(el.dataset.state);
    el.classList.toggle('plan', planStates.has(n));
    el.classList.toggle('current', n === current);
    el.classList.toggle('selected', n === selected);
    el.classList.toggle('start-side', startSide.has(n));
    el.classList.toggle('goal-side', goalSide.has(n) && !startSide.has(n));
  });
  if (ex) {
    const lost = new Set(ex.lost.map((l) => Math.min(l.from, l.to) + ',' + Math.max(l.from, l.to)));
    box.querySelectorAll('.arc.pruned').forEach((el) => {
      const a = Number(el.dataset.from), b = Number(el.dataset.to);
      el.classList.toggle('lost', lost.has(Math.min(a, b) + ',' + Math.max(a, b)));
    });
  }
}
function selectState(n) {
  const g = doc.graphs[graphIndex];
  const s = g.states[n];
  selected = n;
  markGraph();
  // The arcs verification pruned at this state, with their reasons (the SVG's titles).
  const reasons = [];
  $('graph').querySelectorAll('.arc.pruned').forEach((el) => {
    if (Number(el.dataset.from) === n || Number(el.dataset.to) === n) reasons.push(el.textContent);
  });
  const pruned = reasons.length ? ' Pruned here: ' + reasons.join('; ') + '.' : '';
  const text = 'S(' + s.end_effector + ', ' + s.grasp + ', ' + s.workspace + ')';
  if (s.snapshot === null || !doc.snapshots[s.snapshot]) {
    $('state').textContent = text + ': no witness configuration (no verified arc at this state).' + pruned;
    return;
  }
  pause();
  snapshot = n;
  showPoses(doc.snapshots[s.snapshot], null, 0);
  $('state').textContent = text + ': the witness configuration is shown; press Play or move the time to go back.' + pruned;
  draw();
}
objectSelect.addEventListener('change', () => { graphIndex = Number(objectSelect.value); showGraph(); });
showGraph();

// --- Unreachable request -------------------------------------------------------------
if (doc.failure) {
  $('why').hidden = false;
  $('failure').textContent = doc.failure;
  const ex = doc.explanation;
  if (ex) {
    for (const c of ex.cut) { const li = document.createElement('li'); li.textContent = 'cut: ' + c; $('cut').append(li); }
    for (const l of ex.lost) { const li = document.createElement('li'); li.textContent = 'lost: ' + l.text; $('lost').append(li); }
    const named = new Set(ex.workspaces);
    for (const r of regions) {
      if (r.region.kind === 'workspace' && named.has(r.region.name)) {
        r.group.visible = true;
        r.checkbox.checked = true;
        r.edge.color.set(0xdc2626);
        r.fill.color.set(0xdc2626);
        r.fill.opacity = 0.22;
      }
    }
  }
}

// --- Camera, timeline controls, loop -------------------------------------------------
const bounds = new THREE.Box3();
bodies.forEach((b) => bounds.expandByObject(b));
regions.forEach((r) => { if (r.region.kind === 'workspace') bounds.expandByObject(r.group); });
if (bounds.isEmpty()) bounds.set(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 1));
const centre = bounds.getCenter(new THREE.Vector3());
const size = Math.max(0.5, bounds.getSize(new THREE.Vector3()).length());
camera.position.set(centre.x + 0.75 * size, centre.y - 0.95 * size, centre.z + 0.65 * size);
let controls = null;
if (renderer) {
  host.append(renderer.domElement);
  controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();
  controls.addEventListener('change', () => draw());
}
function resize() {
  const w = host.clientWidth, h = Math.max(1, host.clientHeight);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  if (renderer) renderer.setSize(w, h);
  draw();
}
function draw() { if (renderer) renderer.render(scene, camera); }
function play() {
  if (!duration) return;
  if (now >= duration) setTime(0);
  playing = true;
  $('play').textContent = 'Pause';
}
function pause() { playing = false; $('play').textContent = 'Play'; }
$('play').addEventListener('click', () => (playing ? pause() : play()));
$('scrub').addEventListener('input', () => { pause(); setTime(duration * Number($('scrub').value) / 1000); draw(); });
$('speed').addEventListener('change', () => { speed = Number($('speed').value); });
document.addEventListener('keydown', (e) => {
  if (e.code === 'Space' && e.target.tagName !== 'INPUT' && e.target.tagName !== 'SELECT') { e.preventDefault(); playing ? pause() : play(); }
});
if (!duration) { $('play').disabled = true; $('scrub').disabled = true; }
let last = null;
function tick(ms) {
  if (playing && last !== null) {
    setTime(now + speed * (ms - last) / 1000);
    if (now >= duration) pause();
    draw();
  }
  last = ms;
  requestAnimationFrame(tick);
}
window.addEventListener('resize', resize);
setTime(0);
resize();
requestAnimationFrame(tick);

// --- For tests and scripts -----------------------------------------------------------
api.duration = duration;
api.background = [BACKGROUND >> 16, (BACKGROUND >> 8) & 255, BACKGROUND & 255];
api.bodies = () => bodies.map((b) => ({ name: b.name, kind: b.userData.kind, visible: b.visible }));
api.setTime = (t) => { pause(); setTime(t); draw(); return now; };
api.time = () => now;
api.play = play;
api.pause = pause;
api.selectState = (object, n) => {
  const i = doc.graphs.findIndex((g) => g.object === object);
  if (i < 0 || !(n >= 0 && n < doc.graphs[i].states.length)) return false;
  graphIndex = i; objectSelect.value = i; showGraph(); selectState(n);
  return snapshot === n;
};
// Where a body's centre is drawn, in CSS pixels of the page (null when hidden).
api.project = (name) => {
  const b = bodies.find((x) => x.name === name);
  if (!b || !b.visible || !b.children.length) return null;
  // The centroid of the first solid's vertices: inside it, as every solid is convex.
  const mesh = b.children[0];
  const pos = mesh.geometry.getAttribute('position');
  const c = new THREE.Vector3();
  for (let i = 0; i < pos.count; i++) c.add(new THREE.Vector3().fromBufferAttribute(pos, i));
  c.divideScalar(Math.max(1, pos.count));
  b.updateMatrixWorld(true);
  const p = mesh.localToWorld(c).project(camera);
  const r = host.getBoundingClientRect();
  return { x: r.left + (p.x + 1) / 2 * r.width, y: r.top + (1 - p.y) / 2 * r.height };
};
api.ready = true;
