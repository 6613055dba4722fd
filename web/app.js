// The spheremap page: submit a mesh, follow the job's events, show what came back.
// Contract kept for tests: one <input type="file">; when a job ends,
// document.body.dataset.status is its final status; the viewer draws into the <canvas>.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { STLLoader } from 'three/addons/loaders/STLLoader.js';
import { PLYLoader } from 'three/addons/loaders/PLYLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

const $ = (id) => document.getElementById(id);
const state = {
  files: [], extraOptions: {}, events: null, poll: null, models: {}, view: null,
  compare: null,  // a wrapped job: { original, envelope } drawn side by side (either may be null)
  submission: 0,  // counts submissions: a late answer to an earlier one is ignored
  newJob: true,  // the next view framed picks its own direction (side-on), not the current one
  fitted: null,  // the last fit's box, redone when the canvas changes shape
  touched: false,  // the person moved the camera since that fit: a resize keeps their view
};

// A service started with API keys wants `Authorization: Bearer KEY` on every /v1 call; the
// key is asked for after the first 401 and kept for this tab only.
const apiKey = () => $('api-key').value || sessionStorage.getItem('spheremap-key') || '';
function api(path, init = {}) {
  const headers = { ...(init.headers ?? {}) };
  if (apiKey()) headers.Authorization = `Bearer ${apiKey()}`;
  return fetch(path, { ...init, headers });
}
$('api-key').addEventListener('change', () => sessionStorage.setItem('spheremap-key', $('api-key').value));
if (sessionStorage.getItem('spheremap-key')) {
  $('api-key').value = sessionStorage.getItem('spheremap-key');
  $('key-field').hidden = false;
}

// ---- viewer -------------------------------------------------------------------------
const canvas = $('canvas');
// preserveDrawingBuffer: the canvas can be read back (tests check it is not blank).
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x20242b);
const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
camera.position.set(0, 0.4, 2.4);
const controls = new OrbitControls(camera, canvas);
controls.enableDamping = true;
scene.add(new THREE.HemisphereLight(0xffffff, 0x303040, 1.6));
const headlight = new THREE.DirectionalLight(0xffffff, 1.6);
headlight.position.set(1, 2, 3);
camera.add(headlight);
scene.add(camera);

controls.addEventListener('start', () => { state.touched = true; });

// The drawing buffer and the camera's aspect follow the canvas's size on the page; true
// when they changed.
function resize() {
  const { clientWidth: w, clientHeight: h } = canvas;
  if (canvas.width === Math.floor(w * renderer.getPixelRatio()) &&
      canvas.height === Math.floor(h * renderer.getPixelRatio())) return false;
  renderer.setSize(w, h, false);
  setAspect();
  return true;
}
// The side-by-side view draws each half of the canvas with the one camera.
function setAspect() {
  const { clientWidth: w, clientHeight: h } = canvas;
  camera.aspect = (state.view === 'compare' ? 0.5 : 1) * w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
// The original on the left half, the envelope on the right, seen by the same camera and
// controls, so both turn together.
function renderCompare() {
  const { clientWidth: w, clientHeight: h } = canvas;
  const half = Math.floor(w / 2);
  const { original, envelope } = state.compare;
  renderer.setScissorTest(true);
  for (const [shown, x, width] of [[original, 0, half], [envelope, half, w - half]]) {
    if (original) original.visible = shown === original;
    if (envelope) envelope.visible = shown === envelope;
    renderer.setViewport(x, 0, width, h);
    renderer.setScissor(x, 0, width, h);
    renderer.render(scene, camera);
  }
  renderer.setScissorTest(false);
  renderer.setViewport(0, 0, w, h);
}
renderer.setAnimationLoop(() => {
  // A canvas of a new shape frames the object again, unless the person moved the camera.
  if (resize() && state.fitted && !state.touched) fit(state.fitted);
  controls.update();
  if (state.view === 'compare' && state.compare) renderCompare();
  else renderer.render(scene, camera);
});

const draco = new DRACOLoader().setDecoderPath('/web/three/examples/jsm/libs/draco/');
function gltfLoader(manager) {
  return new GLTFLoader(manager).setDRACOLoader(draco).setMeshoptDecoder(MeshoptDecoder);
}

// Centres an object on the origin and scales it into the unit ball (the sphere and the
// remesh are already there), so the views of one job are alike in size.
function framed(object) {
  const box = new THREE.Box3().setFromObject(object);
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  const holder = new THREE.Group();
  object.position.sub(sphere.center);
  holder.add(object);
  holder.scale.setScalar(sphere.radius > 0 ? 1 / sphere.radius : 1);
  return holder;
}

// ---- framing: each view fits its object to the canvas ----------------------------------
const MARGIN = 1.2;  // the object spans at most 1 / 1.2 = 83% of the canvas either way
const FRONT = new THREE.Vector3(0, 0.4, 2.4).normalize();  // a little from above, +y up
const SIDE = new THREE.Vector3(2.4, 0.4, 0).normalize();

// An elongated object is seen side-on: the camera looks across its longer horizontal extent.
function sideOn(box) {
  const size = box.getSize(new THREE.Vector3());
  return size.z > 1.2 * size.x ? SIDE : FRONT;
}

// The camera on `direction` from the box's centre, as near as keeps the object whole in
// the frustum with the margin, at the canvas's aspect: the nearer of two fits that both
// hold it, every corner of its box inside, or its sphere (`radius` about the box's centre)
// inside. Near/far, the orbit target and the zoom limits follow the object's size.
function fit(shape, direction = camera.position.clone().sub(controls.target)) {
  resize();
  state.fitted = shape;
  state.touched = false;
  const { box } = shape;
  const center = box.getCenter(new THREE.Vector3());
  const radius = Math.max(shape.radius, 1e-6);
  const back = direction.clone().normalize();
  const right = new THREE.Vector3().crossVectors(camera.up, back);
  if (right.lengthSq() < 1e-12) right.set(1, 0, 0);  // looking straight down or up
  right.normalize();
  const up = new THREE.Vector3().crossVectors(back, right);
  const tanV = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) / MARGIN;
  const tanH = tanV * camera.aspect;
  const tanMin = Math.min(tanV, tanH);
  const sphereDistance = radius * Math.sqrt(1 + 1 / (tanMin * tanMin));  // r / sin(half angle)
  let boxDistance = 0;
  const corner = new THREE.Vector3();
  for (let i = 0; i < 8; ++i) {
    corner.set(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
      i & 4 ? box.max.z : box.min.z).sub(center);
    const depthNeeded = Math.max(Math.abs(corner.dot(right)) / tanH, Math.abs(corner.dot(up)) / tanV);
    boxDistance = Math.max(boxDistance, corner.dot(back) + Math.max(depthNeeded, 0.01 * radius));
  }
  const distance = Math.min(sphereDistance, boxDistance);
  camera.position.copy(center).addScaledVector(back, distance);
  camera.near = 0.01 * radius;
  camera.far = 8 * distance + 2 * radius;
  camera.updateProjectionMatrix();
  controls.target.copy(center);
  controls.minDistance = 0.05 * radius;
  controls.maxDistance = 6 * distance;
  camera.lookAt(center);
  controls.update();
}

// The exact box of what a model shows: its vertices as morphed now (three's own box of a
// morphed mesh is the union over every target).
function boxOf(object) {
  object.updateMatrixWorld(true);
  return new THREE.Box3().setFromObject(object, true);
}

// The distance from `center` to the model's farthest vertex, as morphed now.
function radiusAbout(object, center) {
  let farthest = 0;
  const vertex = new THREE.Vector3();
  object.traverse((o) => {
    const position = o.isMesh ? o.geometry?.attributes.position : null;
    for (let i = 0; i < (position?.count ?? 0); ++i) {
      o.getVertexPosition(i, vertex).applyMatrix4(o.matrixWorld);
      farthest = Math.max(farthest, vertex.distanceToSquared(center));
    }
  });
  return Math.sqrt(farthest);
}

function setInfluence(value) {
  state.models.morph?.traverse((o) => {
    if (o.morphTargetInfluences) o.morphTargetInfluences[0] = value;
  });
}

function disposeModel(object) {
  object.traverse((o) => {
    o.geometry?.dispose();
    for (const m of [o.material, o.userData.plain].flat()) m?.dispose?.();
  });
}

// A new job: the last one's models go, and its first view picks a direction of its own.
function clearModels() {
  for (const object of Object.values(state.models)) {
    scene.remove(object);
    disposeModel(object);
  }
  state.models = {};
  for (const object of Object.values(state.compare ?? {})) {
    if (!object) continue;
    scene.remove(object);
    disposeModel(object);
  }
  state.compare = null;
  const compare = document.querySelector('#views [data-view="compare"]');
  compare.hidden = true;
  $('compare-labels').hidden = $('distance-legend').hidden = true;
  state.view = null;
  state.newJob = true;
  for (const button of document.querySelectorAll('#views button')) {
    button.disabled = true;
    button.setAttribute('aria-selected', 'false');
  }
  $('morph-control').hidden = true;
  $('morph').value = '0';
  updateHeatToggle();
}

function setModel(name, object) {
  if (state.models[name]) {
    scene.remove(state.models[name]);
    disposeModel(state.models[name]);
  }
  state.models[name] = object;
  object.visible = false;
  scene.add(object);
  document.querySelector(`#views [data-view="${name}"]`).disabled = false;
  $('hint').hidden = true;
  updateHeatToggle();
}

// The heat map is the distortion of the map, per triangle of the morph (mesh and sphere in
// one): with it on, the input view shows the morph held at the mesh, the sphere view the
// morph held at the sphere. The remesh is a resampling with triangles of its own: no heat.
const HEAT_SHAPE = { input: 0, sphere: 1 };
const heatPossible = (view) => !!state.models.morph && (view === 'morph' || view in HEAT_SHAPE);

function updateHeatToggle() {
  const possible = heatPossible(state.view);
  $('heat').disabled = !possible;
  $('heat-toggle').title = possible ? 'Colour each triangle by how much the map grows or shrinks it'
    : !state.models.morph ? 'Map a mesh with the mesh-to-sphere morph output first'
    : state.view === 'compare' ? 'This view colours the envelope by its distance to the original'
    : 'The remesh resamples the sphere on a grid of its own: the distortion shows in the other views';
}

function show(name) {
  state.view = name;
  setAspect();
  const heat = $('heat').checked && heatPossible(name);
  const shown = heat ? 'morph' : name;
  for (const [key, object] of Object.entries(state.models)) object.visible = key === shown;
  for (const button of document.querySelectorAll('#views button'))
    button.setAttribute('aria-selected', String(button.dataset.view === name));
  $('morph-control').hidden = name !== 'morph';
  $('compare-labels').hidden = $('distance-legend').hidden = name !== 'compare';
  for (const object of Object.values(state.compare ?? {})) if (object) object.visible = false;
  updateHeatToggle();
  applyHeat(heat);
  if (name === 'compare') return showCompare();
  const object = state.models[shown];
  if (!object) return;
  // The morph view fits its mesh and its sphere at once, so the slider never leaves the
  // canvas; the heat map's input and sphere views hold the morph at one end.
  const influences = name === 'morph' ? [0, 1] : shown === 'morph' ? [HEAT_SHAPE[name]] : [null];
  const box = new THREE.Box3();
  for (const t of influences) {
    if (t !== null) setInfluence(t);
    box.union(boxOf(object));
  }
  if (box.isEmpty()) return;
  const center = box.getCenter(new THREE.Vector3());
  let radius = 0;
  for (const t of influences) {
    if (t !== null) setInfluence(t);
    radius = Math.max(radius, radiusAbout(object, center));
  }
  if (name === 'morph') setInfluence(Number($('morph').value));
  fit({ box, radius }, state.newJob ? sideOn(box) : undefined);
  state.newJob = false;
}

// Both halves framed alike: each model is already centred in the unit ball (framed()), and
// the camera fits the larger.
function showCompare() {
  const objects = Object.values(state.compare ?? {}).filter((o) => o);
  if (!objects.length) return;
  const box = new THREE.Box3();
  for (const object of objects) box.union(boxOf(object));
  const center = box.getCenter(new THREE.Vector3());
  const radius = Math.max(...objects.map((object) => radiusAbout(object, center)));
  fit({ box, radius }, state.newJob ? sideOn(box) : undefined);
  state.newJob = false;
}

for (const button of document.querySelectorAll('#views button'))
  button.addEventListener('click', () => show(button.dataset.view));
$('morph').addEventListener('input', () => {
  if (state.view === 'morph') setInfluence(Number($('morph').value));
});

// Our outputs keep a textured input's own material (the duck stays a duck on its sphere);
// anything else gets a plain surface, so the map's shape is what one sees. Triangle edges
// too, except on the morph (a wireframe would not follow its target) and on meshes of more
// than 50,000 triangles (a 256 x 256 remesh): their edges, denser than the canvas's pixels,
// only darken the surface, and they cost software WebGL seconds a frame.
function surface(object, color, edges = true) {
  object.traverse((o) => {
    if (!o.isMesh) return;
    const own = [o.material].flat().find((m) => m?.map);
    o.userData.plain = new THREE.MeshStandardMaterial({
      color, roughness: 0.65, metalness: 0.0, side: THREE.DoubleSide, flatShading: false });
    if (own) own.side = THREE.DoubleSide;
    o.userData.own = own ? o.material : null;
    o.material = o.userData.own ?? o.userData.plain;
    if (!edges || !o.geometry.index || o.geometry.index.count > 3 * 50000) return;
    o.add(new THREE.LineSegments(new THREE.WireframeGeometry(o.geometry),
      new THREE.LineBasicMaterial({ color: 0x000000, transparent: true, opacity: 0.12 })));
  });
  return object;
}

// ---- distortion heat map: log(area on the sphere / area on the mesh), each as a share
// of its total, per triangle of the morph (its base is the mesh, its target the sphere),
// averaged at the vertices; blue = shrunk, grey = even, red = grown.
function heatColors(geometry) {
  const base = geometry.attributes.position;
  const delta = geometry.morphAttributes.position?.[0];
  const index = geometry.index;
  if (!delta || !index) return null;
  const relative = geometry.morphTargetsRelative;
  const p = [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()];
  const q = [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()];
  const triangles = index.count / 3;
  const meshArea = new Float64Array(triangles), sphereArea = new Float64Array(triangles);
  let meshTotal = 0, sphereTotal = 0;
  const area = (a, b, c) => new THREE.Vector3().subVectors(b, a).cross(new THREE.Vector3().subVectors(c, a)).length() / 2;
  for (let t = 0; t < triangles; ++t) {
    for (let k = 0; k < 3; ++k) {
      const v = index.getX(3 * t + k);
      p[k].fromBufferAttribute(base, v);
      q[k].fromBufferAttribute(delta, v);
      if (relative) q[k].add(p[k]);
    }
    meshTotal += meshArea[t] = area(p[0], p[1], p[2]);
    sphereTotal += sphereArea[t] = area(q[0], q[1], q[2]);
  }
  const sum = new Float64Array(base.count), count = new Float64Array(base.count);
  for (let t = 0; t < triangles; ++t) {
    const ratio = (sphereArea[t] / sphereTotal) / Math.max(meshArea[t] / meshTotal, 1e-30);
    const value = Math.log(Math.max(ratio, 1e-12));
    for (let k = 0; k < 3; ++k) {
      const v = index.getX(3 * t + k);
      sum[v] += value;
      count[v] += 1;
    }
  }
  const colors = new Float32Array(base.count * 3);
  const shrunk = new THREE.Color(0x3b4cc0), even = new THREE.Color(0xdddddd), grown = new THREE.Color(0xb40426);
  const c = new THREE.Color();
  for (let v = 0; v < base.count; ++v) {
    const x = Math.max(-1, Math.min(1, (count[v] ? sum[v] / count[v] : 0) / 2));  // |log| 2 = 7.4x
    c.copy(even).lerp(x < 0 ? shrunk : grown, Math.abs(x));
    colors.set([c.r, c.g, c.b], 3 * v);
  }
  return new THREE.BufferAttribute(colors, 3);
}

function applyHeat(on) {
  $('heat-legend').hidden = !on;
  state.models.morph?.traverse((o) => {
    if (!o.isMesh) return;
    if (on && !o.geometry.attributes.color) {
      const colors = heatColors(o.geometry);
      if (colors) o.geometry.setAttribute('color', colors);
    }
    const heat = on && !!o.geometry.attributes.color;
    o.material = heat ? o.userData.plain : (o.userData.own ?? o.userData.plain);
    o.userData.plain.vertexColors = heat;
    o.userData.plain.color.set(heat ? 0xffffff : 0xd8b06a);
    o.userData.plain.needsUpdate = true;
  });
}
$('heat').addEventListener('change', () => { if (state.view) show(state.view); });

// ---- distance heat map of a wrapped job: each envelope vertex's distance to the original
// (the morph's _DISTANCE attribute, a share of the original's bounding-box diagonal);
// blue = on it, yellow = 1%, red = 2% or more.
const DISTANCE_SCALE = 0.02;
const NEAR = new THREE.Color(0x2c7bb6), MID = new THREE.Color(0xffffbf), FAR = new THREE.Color(0xd7191c);

// Colours `object` (a copy of the morph, at its mesh end) by distance; returns the largest.
// A part mapped as it is has no _DISTANCE: it is the original there (distance 0).
function distanceColored(object) {
  let max = 0;
  const c = new THREE.Color();
  object.traverse((o) => {
    if (!o.isMesh) return;
    const distance = o.geometry.attributes._distance;
    const count = o.geometry.attributes.position.count;
    const colors = new Float32Array(3 * count);
    for (let v = 0; v < count; ++v) {
      const d = distance ? distance.getX(v) : 0;
      max = Math.max(max, d);
      const t = Math.min(d / DISTANCE_SCALE, 1);
      if (t < 0.5) c.copy(NEAR).lerp(MID, 2 * t); else c.copy(MID).lerp(FAR, 2 * t - 1);
      colors.set([c.r, c.g, c.b], 3 * v);
    }
    o.geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    // The mesh end only: without its sphere target the model is framed as the envelope.
    o.geometry.morphAttributes = {};
    o.geometry.boundingBox = o.geometry.boundingSphere = null;
    delete o.morphTargetInfluences;
    delete o.morphTargetDictionary;
    o.material = new THREE.MeshStandardMaterial({
      vertexColors: true, roughness: 0.65, metalness: 0, side: THREE.DoubleSide });
  });
  return max;
}

// The asset as uploaded, read by three.js's own loaders from the chosen files; throws
// with the reason when the browser cannot show it.
async function originalModel() {
  const main = state.files.find((f) => MESH_FILE.test(f.name));
  if (!main) throw new Error('no file chosen');
  const type = main.name.split('.').pop().toLowerCase();
  if (type === 'glb' || type === 'gltf') {
    const urls = new Map(state.files.map((f) => [f.name, URL.createObjectURL(f)]));
    const manager = new THREE.LoadingManager();
    manager.setURLModifier((url) => urls.get(decodeURIComponent(url.split('/').pop())) ?? url);
    try {
      return (await gltfLoader(manager).parseAsync(await main.arrayBuffer(), '')).scene;
    } finally {
      setTimeout(() => urls.forEach((u) => URL.revokeObjectURL(u)), 60000);
    }
  }
  if (type === 'obj') return new OBJLoader().parse(await main.text());
  let geometry;
  if (type === 'stl') geometry = new STLLoader().parse(await main.arrayBuffer());
  else if (type === 'ply') geometry = new PLYLoader().parse(await main.arrayBuffer());
  else throw new Error(`the browser has no reader for .${type} files`);
  if (!geometry.attributes.normal) geometry.computeVertexNormals();
  return new THREE.Mesh(geometry);
}

// A wrapped job: the original and the envelope (a second copy of the morph) for the side
// by side view, and its button.
async function prepareCompare(morph, ticket) {
  const envelope = await loadGlb(morph.href);
  let original = null, note = '';
  try {
    original = framed(surface(await originalModel(), 0xc8c8c8));
  } catch (error) {
    note = `Not shown: ${error.message}.`;
  }
  if (ticket !== state.submission) return;
  const max = distanceColored(envelope);
  state.compare = { original, envelope: framed(envelope) };
  for (const object of Object.values(state.compare)) {
    if (!object) continue;
    object.visible = false;
    scene.add(object);
  }
  $('compare-note').hidden = !note;
  $('compare-note').textContent = note;
  $('distance-max').textContent = `${(100 * max).toFixed(2)}%`;
  $('distance-legend').dataset.max = String(max);
  $('canvas-box').dataset.compareModels = String(Object.values(state.compare).filter((o) => o).length);
  const button = document.querySelector('#views [data-view="compare"]');
  button.hidden = button.disabled = false;
}

async function loadGlb(url) {
  const bytes = await (await api(url)).arrayBuffer();
  return (await gltfLoader().parseAsync(bytes, '')).scene;
}

// The input as the browser reads it, with the selected files as its resources.
async function previewInput(main, ticket) {
  const urls = new Map(state.files.map((f) => [f.name, URL.createObjectURL(f)]));
  const manager = new THREE.LoadingManager();
  manager.setURLModifier((url) => {
    const name = decodeURIComponent(url.split('/').pop());
    return urls.get(name) ?? url;
  });
  try {
    const gltf = await gltfLoader(manager).parseAsync(await main.arrayBuffer(), '');
    if (ticket !== state.submission) return;  // another file was chosen meanwhile
    setModel('input', framed(gltf.scene));
    if (!state.view) show('input');  // unless a result came back first
  } catch (error) {
    console.warn('no preview of the input:', error.message);
  } finally {
    setTimeout(() => urls.forEach((u) => URL.revokeObjectURL(u)), 60000);
  }
}

// ---- jobs ---------------------------------------------------------------------------
function setStatus(status) { document.body.dataset.status = status; }

function showError(text, fix) {
  const box = $('error');
  box.hidden = !text;
  box.textContent = text || '';
  if (fix) {
    const button = document.createElement('button');
    button.type = 'button';
    button.textContent = fix.option === 'largest_component' ? 'Map the largest part'
      : `Map with ${fix.option} = ${JSON.stringify(fix.value)}`;
    button.addEventListener('click', () => {
      if (fix.option === 'largest_component') $('largest').checked = true;
      else state.extraOptions[fix.option] = fix.value;
      submit();
    });
    box.append(document.createElement('br'), button);
  }
}

function showProgress(p) {
  $('progress').hidden = false;
  // Several parts: each part's levels count from 0 again, so the bar runs over the parts.
  const within = p.levels > 0 ? p.level / p.levels : 0;
  const fraction = p.status === 'succeeded' ? 1
    : p.parts > 1 ? (p.part - 1 + within) / p.parts : p.levels > 0 ? within : 0.02;
  $('bar-fill').style.width = `${Math.round(100 * Math.min(1, Math.max(fraction, 0.02)))}%`;
  const parts = [p.status === 'queued' ? 'queued' : p.stage];
  if (p.parts > 1) parts.push(`part ${p.part}/${p.parts}`);
  if (p.levels) parts.push(`level ${p.level}/${p.levels}`);
  if (p.vertices) parts.push(`${p.vertices.toLocaleString()} vertices`);
  if (p.iteration) parts.push(`iteration ${p.iteration}`);
  if (p.folds) parts.push(`${p.folds} folds`);
  if (p.energy) parts.push(`energy ${p.energy.toFixed(3)}`);
  $('stage').textContent = parts.join(' · ');
}

function options() {
  const outputs = ['sphere'];
  for (const name of ['remesh', 'morph', 'uv']) if ($(`out-${name}`).checked) outputs.push(name);
  const chosen = { quality: $('quality').value, outputs, ...state.extraOptions };
  if ($('largest').checked) chosen.largest_component = true;
  if ($('prepare').value !== 'auto') chosen.prepare = $('prepare').value;
  return chosen;
}

// The file that is the mesh; the others are a .gltf's resources.
const MESH_FILE = /\.(glb|gltf|obj|stl|ply|off|drc)$/i;

async function submit() {
  stopFollowing();
  const ticket = ++state.submission;
  const main = state.files.find((f) => MESH_FILE.test(f.name));
  if (!main) {
    showError('Choose a .glb, .obj, .stl, .ply, .off or .drc file, or a .gltf with the .bin files it names.');
    return;
  }
  showError('');
  $('results').hidden = true;
  $('run').disabled = false;
  $('hint').hidden = true;
  setStatus('submitting');
  clearModels();
  // The browser previews glTF itself; other formats show once mapped (the morph's start).
  if (/\.(glb|gltf)$/i.test(main.name)) previewInput(main, ticket);
  const form = new FormData();
  form.append('mesh', main, main.name);
  // A .gltf's files go along as parts named by their file name (the service matches URIs).
  for (const f of state.files) if (f !== main) form.append(f.name, f, f.name);
  form.append('options', new Blob([JSON.stringify(options())], { type: 'application/json' }));
  let response, body;
  try {
    response = await api('/v1/jobs', { method: 'POST', body: form });
    body = await response.json();
  } catch (error) {
    if (ticket !== state.submission) return;
    setStatus('error');
    showError(`The service did not answer: ${error.message}`);
    return;
  }
  // Submitted again while this one was on its way (a second file, a fix button): the
  // newer submission owns the page; this job runs on, unwatched.
  if (ticket !== state.submission) return;
  if (response.status === 401) $('key-field').hidden = false;
  if (response.status !== 202) {
    setStatus('rejected');
    $('progress').hidden = true;
    showError(`${body.title ?? 'Refused'}: ${body.detail ?? response.status}`, body.fix);
    return;
  }
  setStatus(body.status);
  showProgress({ ...body.progress, status: body.status });
  follow(body.id, ticket);
}

function stopFollowing() {
  state.events?.close();
  clearInterval(state.poll);
  state.events = state.poll = null;
}

// Server-Sent Events while they work; polling when they cannot (too many streams, a proxy).
function follow(id, ticket) {
  if (apiKey()) return poll(id, ticket);  // EventSource cannot send the key
  const events = new EventSource(`/v1/jobs/${id}/events`);
  state.events = events;
  events.addEventListener('progress', (e) => {
    const p = JSON.parse(e.data);
    if (['queued', 'running'].includes(p.status)) setStatus(p.status);  // the end: finished()
    showProgress(p);
  });
  events.addEventListener('status', (e) => {
    stopFollowing();
    finished(JSON.parse(e.data), ticket);
  });
  events.onerror = () => {
    if (state.events !== events) return;
    stopFollowing();
    poll(id, ticket);
  };
}

function poll(id, ticket) {
  const timer = setInterval(async () => {
    const job = await (await api(`/v1/jobs/${id}`)).json();
    if (state.poll !== timer) return;  // stopped while this request was out
    showProgress({ ...job.progress, status: job.status });
    if (!['queued', 'running'].includes(job.status)) {
      stopFollowing();
      finished(job, ticket);
    }
  }, 500);
  state.poll = timer;
}

// With a key, a plain link cannot download (it carries no header): fetch, then save.
async function download(event, href, name) {
  if (!apiKey()) return;
  event.preventDefault();
  const url = URL.createObjectURL(await (await api(href)).blob());
  Object.assign(document.createElement('a'), { href: url, download: name }).click();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

const number = (x, digits = 3) => (typeof x === 'number' ? x.toFixed(digits) : '–');

async function finished(job, ticket) {
  showProgress({ ...job.progress, status: job.status });
  const metrics = job.metrics ?? {};
  const artifacts = job.artifacts ?? {};
  $('results').hidden = false;
  const verdict = $('verdict');
  if (job.status === 'succeeded') {
    verdict.textContent = 'Bijective: no folded or degenerate triangle (certified in float32)';
    verdict.className = 'ok';
  } else {
    verdict.textContent = job.status === 'failed' ? `Not certified: ${job.error?.title ?? 'failed'}` : 'Cancelled';
    verdict.className = 'bad';
    if (job.error) showError(job.error.detail);
  }
  const seconds = Object.values(metrics.seconds ?? {}).reduce((a, b) => a + b, 0);
  const rows = [
    ['vertices / triangles', `${metrics.vertices ?? '–'} / ${metrics.triangles ?? '–'}`],
    ['stretch L2 (1 = even)', number(metrics.stretch?.l2)],
    ['mean |log area ratio|', number(metrics.area_distortion?.mean_abs_log)],
    ['folds as written', metrics.folds_as_written ?? '–'],
    ['quality', metrics.quality ?? '–'],
    ['map time (s)', number(seconds, 2)],
  ];
  const prepared = metrics.preparation;
  if (prepared) {
    const changes = [
      [prepared.duplicate_faces_dropped, 'duplicate faces dropped'],
      [prepared.collapsed_faces_dropped, 'collapsed faces dropped'],
      [prepared.faces_shortened, 'polygons shortened'],
      [prepared.t_junctions_zipped, 'T-junctions zipped'],
      [prepared.faces_flipped, 'faces flipped'],
      [prepared.non_manifold_vertices_split, 'non-manifold vertices split'],
      [prepared.non_manifold_edges_split, 'non-manifold edges split'],
      [prepared.holes_filled, 'holes filled'],
      [prepared.handles_closed, 'handles closed'],
      [prepared.open_parts_cut, 'open parts cut into discs (then closed by their back)'],
      [prepared.sheets_doubled, 'open sheets closed by their own back'],
      [prepared.faces_added, 'faces added by the fills and backs'],
      [prepared.vertices_added, 'vertices added inside the fills and backs'],
      [prepared.holes_left, 'holes left open'],
    ].filter(([count]) => count > 0).map(([count, what]) => `${count.toLocaleString()} ${what}`);
    // A wrapped whole: the envelope is the change (its repairs above are the envelope's own).
    if (prepared.envelope_faces !== undefined)
      changes.unshift(`replaced by an envelope of ${prepared.envelope_faces.toLocaleString()} faces ` +
        `(handles cut ${prepared.handles_cut ?? 0}, filled ${prepared.handles_filled ?? 0}; ` +
        `within ${number(100 * prepared.envelope_hausdorff, 2)}% of the diagonal of the original)`);
    const method = prepared.decided ? `${prepared.method}: ${prepared.decided}` : prepared.method;
    rows.push([`preparation (${method})`, changes.length ? changes.join(', ') : 'none needed']);
  }
  if (metrics.parts) {
    const left = metrics.parts.filter((part) => !part.mapped);
    const reasons = left.slice(0, 3).map((part) => `part ${part.part} (${part.faces.toLocaleString()} faces): ${part.check}`);
    if (left.length > 3) reasons.push(`${left.length - 3} more`);
    const wrapped = metrics.parts.filter((part) => part.wrapped).length;
    rows.push(['parts mapped', `${metrics.parts_mapped} of ${metrics.parts.length}` +
      (wrapped ? ` (${wrapped} as envelopes)` : '') +
      (left.length ? `; left out: ${reasons.join(', ')}` : '')]);
  }
  const distance = metrics.remesh?.distance;
  if (distance?.asset_hausdorff !== undefined)
    // An asset of parts: over the asset's diagonal (a tiny part far off by its own diagonal
    // is not what the asset looks like), the largest part's own figure beside it.
    rows.push(['remesh Hausdorff (% of the asset\'s diagonal)',
      number(100 * distance.asset_hausdorff, 2) +
      ` (the farthest part by its own diagonal: ${number(100 * distance.hausdorff, 2)})`]);
  else if (distance?.hausdorff !== undefined)
    // A search that ran out of budget says how far the maximum could still be.
    rows.push(['remesh Hausdorff (% of diagonal)', number(100 * distance.hausdorff, 2) +
      (distance.hausdorff_settled === false
        ? ` (search unsettled: at most ${number(100 * distance.hausdorff_at_most, 2)})` : '')]);
  $('metrics').replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    for (const text of [k, String(v)]) tr.append(Object.assign(document.createElement('td'), { textContent: text }));
    return tr;
  }));
  $('metrics-json').textContent = JSON.stringify(metrics, null, 2);
  $('downloads').replaceChildren(...Object.entries(artifacts).map(([name, a]) => {
    const li = document.createElement('li');
    const link = Object.assign(document.createElement('a'), { href: a.href, download: name, textContent: name });
    link.addEventListener('click', (e) => download(e, a.href, name));
    li.append(link, ` (${(a.bytes / 1024).toFixed(1)} KiB)`);
    return li;
  }));
  // Each model arrives after an await: a submission made meanwhile owns the views.
  const load = async (name) => {
    const model = await loadGlb(artifacts[name].href);
    if (ticket !== state.submission) throw new Error('superseded by a newer submission');
    return model;
  };
  try {
    if (artifacts['sphere.glb']) setModel('sphere', surface(await load('sphere.glb'), 0x8fb3e8));
    if (artifacts['remesh.glb']) setModel('remesh', surface(await load('remesh.glb'), 0x9ad0a1));
    if (artifacts['morph.glb']) {
      setModel('morph', framed(surface(await load('morph.glb'), 0xd8b06a, false)));
      // An input the browser cannot preview (OBJ, STL, PLY, OFF): the morph at its mesh end
      // is that input, welded.
      if (!state.models.input)
        setModel('input', framed(surface(await load('morph.glb'), 0xc8c8c8)));
    }
    // A wrapped job (its morph carries _DISTANCE): the original beside the envelope.
    if (artifacts['morph.glb'] && metrics.morph?.vertex_distances)
      await prepareCompare(artifacts['morph.glb'], ticket);
    if (state.models.sphere) show('sphere');
  } catch (error) {
    console.warn('could not show a result:', error.message);
    if (ticket !== state.submission) return;
  }
  // Last: the status is what tests wait for, once everything is drawn.
  requestAnimationFrame(() => setStatus(job.status));
}

// ---- file choice ----------------------------------------------------------------------
function choose(fileList) {
  state.files = [...fileList];
  state.extraOptions = {};
  if (state.files.length) submit();
}
$('file').addEventListener('change', (e) => choose(e.target.files));

// The example (examples/spot.glb, built into the service) goes in as a chosen file would.
async function tryExample() {
  try {
    const response = await fetch('/examples/spot.glb');
    if (!response.ok) throw new Error(`GET /examples/spot.glb answered ${response.status}`);
    const file = new File([await response.blob()], 'spot.glb', { type: 'model/gltf-binary' });
    const chosen = new DataTransfer();
    chosen.items.add(file);
    $('file').files = chosen.files;  // the file input names it, as if it had been chosen
    choose(chosen.files);
  } catch (error) {
    showError(`Could not load the example: ${error.message}`);
  }
}
for (const button of document.querySelectorAll('button.example'))
  button.addEventListener('click', tryExample);
$('run').addEventListener('click', submit);
const drop = $('drop');
drop.addEventListener('dragover', (e) => { e.preventDefault(); drop.classList.add('over'); });
drop.addEventListener('dragleave', () => drop.classList.remove('over'));
drop.addEventListener('drop', (e) => {
  e.preventDefault();
  drop.classList.remove('over');
  choose(e.dataTransfer.files);
});
