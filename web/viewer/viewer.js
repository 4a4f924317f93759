// The viewer: streams a .pm with fetch() and a ReadableStream (or a dropped file), draws the
// base mesh as soon as it has arrived and refines as chunks arrive, each refinement a geomorph
// (Hoppe 1996, §4.2): the new vertices move out of their ancestors instead of popping in.
// Sliders pick a level by faces or by error bound. window.pmViewer holds the figures the
// browser test reads (bytes, faces drawn, frames).
import * as THREE from 'three';
import { OrbitControls } from './OrbitControls.js';
import { PmDecoder, PmError } from './pm.js';

const kMorphMilliseconds = 400;
const canvas = document.getElementById('view');
// preserveDrawingBuffer: the browser test reads the drawn pixels back.
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1d2026);
const camera = new THREE.PerspectiveCamera(40, 1, 0.001, 1000);
const controls = new OrbitControls(camera, canvas);
scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 1.2));
const light = new THREE.DirectionalLight(0xffffff, 1.6);
light.position.set(1, 2, 3);
scene.add(light);
const material = new THREE.MeshStandardMaterial({ color: 0xc9b48f, flatShading: true, roughness: 0.7 });
let mesh = null;

const viewer = window.pmViewer = {
  bytesReceived: 0, bytesTotal: 0, facesDrawn: 0, framesDrawn: 0, levelDrawn: -1,
  firstByteTime: null, firstFrameTime: null, frameMilliseconds: 0, done: false, error: null,
};
const ui = Object.fromEntries(['stats', 'follow', 'faces', 'facesValue', 'error', 'errorValue', 'message']
  .map((id) => [id, document.getElementById(id)]));

function resize() {
  const { clientWidth: w, clientHeight: h } = canvas;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();

// The geometry of one runtime level or geomorph: positions at the start, and, morphing, the
// end as a morph target that the frame loop blends in.
let morph = null;
function show({ indices, faces, start, end, colors, colorComponents }) {
  const geometry = new THREE.BufferGeometry();
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  geometry.setAttribute('position', new THREE.BufferAttribute(start, 3));
  if (colors) {
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, colorComponents));
  }
  if (end) {
    geometry.morphAttributes.position = [new THREE.BufferAttribute(end, 3)];
  }
  geometry.setDrawRange(0, 3 * faces);
  const first = !mesh;
  if (mesh) {
    mesh.geometry.dispose();
    mesh.geometry = geometry;
    mesh.updateMorphTargets();
  } else {
    mesh = new THREE.Mesh(geometry, material);
    scene.add(mesh);
  }
  material.vertexColors = Boolean(colors);
  material.needsUpdate = true;
  if (end) {
    mesh.morphTargetInfluences[0] = 0;
    morph = { startTime: performance.now() };
  } else {
    morph = null;
  }
  viewer.facesDrawn = faces;
  if (first) frame(geometry);
}

function frame(geometry) {
  geometry.computeBoundingSphere();
  const { center, radius } = geometry.boundingSphere;
  controls.target.copy(center);
  camera.position.copy(center).add(new THREE.Vector3(0.6, 0.5, 1).normalize().multiplyScalar(radius * 3.2));
  camera.near = radius / 100;
  camera.far = radius * 100;
  camera.updateProjectionMatrix();
}

let last = performance.now();
renderer.setAnimationLoop(() => {
  const now = performance.now();
  if (morph) {
    const alpha = Math.min(1, (now - morph.startTime) / kMorphMilliseconds);
    mesh.morphTargetInfluences[0] = alpha;
  }
  controls.update();
  renderer.render(scene, camera);
  viewer.frameMilliseconds = now - last;
  last = now;
  if (mesh) {
    viewer.framesDrawn += 1;
    if (viewer.firstFrameTime === null) viewer.firstFrameTime = now;
  }
  const state = decoderState ?? {};
  ui.stats.textContent =
    `bytes  ${viewer.bytesReceived.toLocaleString()}${viewer.bytesTotal ? ' / ' + viewer.bytesTotal.toLocaleString() : ''}\n` +
    `faces  ${viewer.facesDrawn.toLocaleString()} drawn, ${(state.decodedFaces ?? 0).toLocaleString()} decoded` +
    `${state.streamFaces ? ' of ' + state.streamFaces.toLocaleString() : ''}\n` +
    `frame  ${viewer.frameMilliseconds.toFixed(1)} ms` +
    (viewer.firstFrameTime !== null && viewer.firstByteTime !== null
      ? `\nfirst byte to first frame ${(viewer.firstFrameTime - viewer.firstByteTime).toFixed(0)} ms` : '');
});

let decoder = null;
let decoderState = null;
let busy = false;       // a level request is in flight
let wanted = null;      // the request to make when it is done

// Levels are asked for one at a time: a newer request replaces a waiting one.
async function request(kind) {
  wanted = kind;
  if (busy) return;
  busy = true;
  try {
    while (wanted) {
      const next = wanted;
      wanted = null;
      await draw(next);
    }
  } catch (error) {
    report(error);
  } finally {
    busy = false;
  }
}

async function draw(next) {
  const state = decoderState;
  if (!state?.hasBase) return;
  if (next.follow) {
    // A geomorph from the level drawn to the finest decoded: new wedges start at their
    // ancestors and move out over kMorphMilliseconds.
    const from = Math.max(0, Math.min(viewer.levelDrawn, state.splits));
    const m = await decoder.geomorph({ level: [from, state.splits] }, from === state.splits ? [1] : [0, 1]);
    const [start, end] = [m.frames[0], m.frames.at(-1)];
    show({ indices: m.indices, faces: m.faces, start: start.positions, end: m.frames.length > 1 ? end.positions : null,
           colors: end.colors, colorComponents: m.colorComponents });
    viewer.levelDrawn = m.to;
  } else {
    const level = await decoder.runtime(next.request);
    show({ indices: level.indices, faces: level.faces, start: level.positions, colors: level.colors,
           colorComponents: level.colorComponents });
    viewer.levelDrawn = level.level;
  }
}

function sliderRequest() {
  const state = decoderState;
  if (!state?.hasBase) return null;
  ui.follow.checked = false;
  return state;
}
ui.faces.addEventListener('input', () => {
  const state = sliderRequest();
  if (!state) return;
  const faces = Math.round(Math.pow(state.decodedFaces, ui.faces.value / 1000));  // log scale
  ui.facesValue.textContent = faces.toLocaleString();
  request({ request: { faces } });
});
ui.error.addEventListener('input', () => {
  if (!sliderRequest()) return;
  // Log scale over 1e-6 .. 1 of the bounding sphere's radius (0 at the left: full detail).
  const radius = mesh?.geometry.boundingSphere?.radius ?? 1;
  const error = ui.error.value === '0' ? 0 : radius * Math.pow(10, -6 + (6 * ui.error.value) / 1000);
  ui.errorValue.textContent = error.toPrecision(3);
  request({ request: { error } });
});
ui.follow.addEventListener('change', () => { if (ui.follow.checked) request({ follow: true }); });

function report(error) {
  viewer.error = error instanceof PmError ? `${error.code}: ${error.message}` : String(error?.message ?? error);
  ui.message.textContent = viewer.error;
}

// Streams a .pm from a ReadableStream into a fresh decoder, refining as chunks arrive.
async function load(name, stream, total) {
  decoder?.close();
  decoder = await PmDecoder.create();
  decoderState = null;
  Object.assign(viewer, { bytesReceived: 0, bytesTotal: total || 0, facesDrawn: 0, levelDrawn: -1,
                          firstByteTime: null, firstFrameTime: null, framesDrawn: 0, done: false, error: null });
  if (mesh) { scene.remove(mesh); mesh.geometry.dispose(); mesh = null; }
  ui.message.textContent = name;
  ui.follow.checked = true;
  try {
    const reader = stream.getReader();
    // Chunks go to the worker as they arrive, without waiting for its replies: a push never
    // waits behind a geomorph of a million faces, and the worker decodes the chunks that
    // came in while it was making one before the next (request() keeps one in flight).
    let pushed = Promise.resolve();
    let failure = null;
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      if (viewer.firstByteTime === null) viewer.firstByteTime = performance.now();
      viewer.bytesReceived += value.byteLength;
      pushed = decoder.push(value).then((state) => {
        const before = decoderState?.decodedFaces ?? -1;
        decoderState = state;
        if (state.hasBase && state.decodedFaces !== before && ui.follow.checked) request({ follow: true });
      }, (error) => { failure ??= error; });
      if (failure) throw failure;
    }
    await pushed;
    if (failure) throw failure;
    decoderState = await decoder.finish();
    if (ui.follow.checked) await request({ follow: true });
    viewer.done = true;
  } catch (error) {
    report(error);
  }
}

async function loadUrl(url) {
  try {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    await load(url, response.body, Number(response.headers.get('content-length')));
  } catch (error) {
    report(error);
  }
}

window.addEventListener('dragover', (event) => { event.preventDefault(); document.body.classList.add('dragging'); });
window.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
window.addEventListener('drop', (event) => {
  event.preventDefault();
  document.body.classList.remove('dragging');
  const file = event.dataTransfer.files[0];
  if (file) load(file.name, file.stream(), file.size);
});

const url = new URLSearchParams(location.search).get('url');
if (url) loadUrl(url);
