// What the web tests share: where the built decoder and the native tools are (from CTest's
// environment, see tests.cmake), the .pm streams to test (goldens, samples encoded by pmenc,
// the shared meshes when they are there), pmdec's levels read from its binary PLY output
// (float32 positions and int indices, written as they are: exact), and level checks.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';

export const dist = process.env.PM_WEB_DIST;
export const pmdec = process.env.PMDEC;
const pmenc = process.env.PMENC;
const makeSamples = process.env.PM_MAKE_SAMPLES;
const sourceDir = process.env.PM_SOURCE_DIR;
const work = process.env.PM_WEB_WORK;
const sharedDir = process.env.PM_SHARED_MESHES_DIR;

for (const [name, value] of Object.entries({ PM_WEB_DIST: dist, PMDEC: pmdec, PMENC: pmenc,
  PM_MAKE_SAMPLES: makeSamples, PM_SOURCE_DIR: sourceDir, PM_WEB_WORK: work })) {
  if (!value) throw new Error(`${name} is not set (the tests run from CTest: web/tests/tests.cmake)`);
}
// A fresh build has no work folder yet, and pmdec does not make the folders it writes into.
mkdirSync(work, { recursive: true });

export const { loadPmModule, CoreDecoder, PmError } = await import(join(dist, 'pm-core.js'));
export const { PmDecoder } = await import(join(dist, 'pm.js'));

// Encodes every mesh of `dir` (given extensions) into work/NAME once, with -j2; returns the
// .pm paths. Streams made by an earlier run of the same tests are reused.
function encodeAll(dir, name, extensions, options = []) {
  const out = join(work, name);
  const inputs = readdirSync(dir).filter((f) => extensions.some((e) => f.endsWith(e))).sort();
  const outputs = inputs.map((f) => join(out, f.replace(/\.[a-z]+$/, '.pm')));
  if (!outputs.every(existsSync)) {
    mkdirSync(out, { recursive: true });
    execFileSync(pmenc, [...inputs.map((f) => join(dir, f)), '--out-dir', out, '-o', '{stem}.pm', '-j', '2', '-q', ...options],
                 { stdio: ['ignore', 'ignore', 'inherit'] });
  }
  return outputs;
}

// The project's samples, made by pm_make_samples into the build (not the committed copies, so
// that the generator is what the tests exercise), lossless and 14-bit.
export function sampleStreams() {
  const samples = join(work, 'samples-obj');
  if (!existsSync(join(samples, 'textured.obj'))) {
    mkdirSync(samples, { recursive: true });
    execFileSync(makeSamples, [samples], { stdio: 'ignore' });
  }
  return [...encodeAll(samples, 'samples', ['.obj']),
          ...encodeAll(samples, 'samples-q14', ['.obj'], ['--quantize', '14'])];
}

export function goldenStreams() {
  const dir = join(sourceDir, 'tests/data/golden');
  return readdirSync(dir).filter((f) => f.endsWith('.pm')).sort().map((f) => join(dir, f));
}

// The shared meshes (../shared/meshes), or [] with a loud note when they are not there.
export function sharedStreams() {
  if (!sharedDir || !existsSync(sharedDir)) {
    console.log(`NOTE: shared meshes not found (${sharedDir}): the tests on real meshes are skipped`);
    return [];
  }
  return encodeAll(sharedDir, 'shared', ['.obj', '.off', '.ply'], ['--quantize', '14']);
}

export function fuzzCorpus() {
  const dir = join(sourceDir, 'tests/fuzz/corpus/pm_reader');
  return readdirSync(dir).sort().map((f) => join(dir, f));
}

// A binary little-endian PLY as pmdec writes it: { positions, indices } exactly as stored.
export function readPly(bytes) {
  const text = bytes.toString('latin1', 0, Math.min(bytes.length, 1 << 16));
  const end = text.indexOf('end_header\n') + 'end_header\n'.length;
  const elements = [];
  for (const line of text.slice(0, end).split('\n')) {
    const words = line.split(' ');
    if (words[0] === 'element') elements.push({ name: words[1], count: Number(words[2]), properties: [] });
    if (words[0] === 'property') elements.at(-1).properties.push(words.slice(1));
  }
  const size = { uchar: 1, char: 1, int: 4, uint: 4, float: 4 };
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let at = end;
  const vertex = elements.find((e) => e.name === 'vertex');
  const face = elements.find((e) => e.name === 'face');
  const positions = new Float32Array(3 * vertex.count);
  const stride = vertex.properties.reduce((sum, p) => sum + size[p[0]], 0);
  for (let v = 0; v < vertex.count; ++v, at += stride) {
    for (let k = 0; k < 3; ++k) positions[3 * v + k] = view.getFloat32(at + 4 * k, true);
  }
  const indices = new Uint32Array(3 * face.count);
  for (let f = 0; f < face.count; ++f) {
    for (const [kind, ...rest] of face.properties) {
      if (kind !== 'list') { at += size[kind]; continue; }
      const n = view.getUint8(at); at += 1;
      for (let i = 0; i < n; ++i, at += size[rest[1]]) {
        if (rest[2] === 'vertex_indices') indices[3 * f + i] = view.getUint32(at, true);
      }
    }
  }
  return { positions, indices };
}

// pmdec's level (extra arguments: --faces N, none for full detail), read back exactly.
export function nativeLevel(pmPath, args) {
  const out = join(work, `native-${process.pid}.ply`);
  execFileSync(pmdec, [pmPath, ...args, '-o', out, '-q'], { stdio: ['ignore', 'ignore', 'inherit'] });
  return readPly(readFileSync(out));
}

// Bit-for-bit equality of two typed arrays (floats compared as their bits: -0 and NaN too).
export function sameBits(a, b) {
  if (a.length !== b.length) return false;
  const x = new Uint32Array(a.buffer, a.byteOffset, a.length);
  const y = new Uint32Array(b.buffer, b.byteOffset, b.length);
  for (let i = 0; i < x.length; ++i) if (x[i] !== y[i]) return false;
  return true;
}

// The checks validate_attributes makes on a level (sizes, every index in range or none), and
// what a renderer needs: finite positions.
export function levelProblem(level) {
  const none = 0xFFFFFFFF;
  const { faces, vertices } = level;
  if (level.positions.length !== 3 * vertices) return 'positions: not 3 per vertex';
  if (level.indices.length !== 3 * faces) return 'indices: not 3 per face';
  if (!level.positions.every(Number.isFinite)) return 'a position is not finite';
  if (!level.indices.every((i) => i < vertices)) return 'a face uses a vertex out of range';
  if (level.colorComponents && level.colors.length !== level.colorComponents * vertices) return 'colours: wrong size';
  const tables = [['uvIndices', 'uvs', 2], ['normalIndices', 'normals', 3]];
  for (const [indices, values, dims] of tables) {
    if (!level[indices]) continue;
    if (level[indices].length !== 3 * faces) return `${indices}: not 3 per face`;
    const count = level[values].length / dims;
    if (!level[indices].every((i) => i === none || i < count)) return `${indices}: out of range`;
  }
  return null;
}

// A stream of over a million faces for the browser test: the sphere sample split 1:4 four
// times (1,310,720 faces), encoded at 14 bits (pmenc takes its fast loop: ~20 s).
export function bigStream() {
  const out = join(work, 'big.pm');
  if (!existsSync(out)) {
    sampleStreams();  // makes samples-obj/
    const obj = join(work, 'big.obj');
    execFileSync(process.execPath, [join(sourceDir, 'web/tests/subdivide.mjs'), join(work, 'samples-obj/sphere.obj'), '4', obj]);
    execFileSync(pmenc, [obj, '-o', out, '--quantize', '14', '-q'], { stdio: ['ignore', 'ignore', 'inherit'] });
  }
  return out;
}
