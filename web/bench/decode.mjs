// Full decode in node (the WebAssembly decoder) against the native library, on .pm streams:
// prints a Markdown table, the median of RUNS runs each. Both sides time the same work from
// the stream's bytes in memory to the full-detail mesh:
//   WebAssembly  CoreDecoder append + finish (read_pm), then level() (extract_level, and the
//                typed arrays copied out of the module's memory)
//   native       pm_bench_decode_stream (tests/bench/decode_stream.cpp): read_pm, then
//                extract_level, timed inside its process (the file read and the start left out)
// Each run times one of each, alternating, so that the machine's load hits both alike, after
// one unmeasured WebAssembly decode (V8 compiles the module's hot functions again, optimized,
// while they first run). Two measures: wall-clock time, and CPU time (the process's, node's
// and the native program's: on a loaded machine, the time each was given the CPU; node's
// includes its garbage collector's threads).
// Usage: node web/bench/decode.mjs DIST_DIR NATIVE_PROGRAM RUNS STREAM.pm...
// (web/bench/run_decode.sh runs it; DIST_DIR is web/build.sh's BUILD_DIR/dist.)
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { basename, join, resolve } from 'node:path';

const [dist, native, runsText, ...streams] = process.argv.slice(2);
const runs = Number(runsText);
if (!dist || !native || !(runs >= 1) || streams.length === 0) {
  console.error('usage: node decode.mjs DIST_DIR NATIVE_PROGRAM RUNS STREAM.pm...');
  process.exit(2);
}
const { loadPmModule, CoreDecoder } = await import(resolve(join(dist, 'pm-core.js')));
const module = await loadPmModule();
const median = (values) => {
  const sorted = [...values].sort((a, b) => a - b);
  const n = sorted.length;
  return n % 2 ? sorted[(n - 1) / 2] : (sorted[n / 2 - 1] + sorted[n / 2]) / 2;
};

const fmt = (ms) => ms.toFixed(0);
console.log('| stream | faces | bytes | runs | wasm wall (ms) | native wall (ms) | wasm / native, wall | wasm CPU (ms) | native CPU (ms) | wasm / native, CPU |');
console.log('|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|');
const decodeWasm = (bytes) => {
  const cpuStart = process.cpuUsage();
  const start = performance.now();
  const decoder = new CoreDecoder(module);
  decoder.append(bytes);
  decoder.finish();
  const faces = decoder.level().faces;
  const wall = performance.now() - start;
  const cpu = process.cpuUsage(cpuStart);
  decoder.destroy();
  return { faces, wall, cpu: (cpu.user + cpu.system) / 1000 };
};
for (const stream of streams) {
  const bytes = readFileSync(stream);
  const wasm = [], wasmCpu = [], nativeWall = [], nativeCpu = [];
  let faces = decodeWasm(bytes).faces;  // the warm-up
  for (let r = 0; r < runs; ++r) {
    console.error(`decode.mjs: ${basename(stream)}: run ${r + 1} of ${runs}`);
    const w = decodeWasm(bytes);
    wasm.push(w.wall);
    wasmCpu.push(w.cpu);
    const line = execFileSync(native, [stream], { encoding: 'utf8' });
    const field = (name) => Number(new RegExp(`${name}=([0-9.]+)`).exec(line)[1]);
    if (field('faces') !== w.faces) throw new Error(`native decoded ${field('faces')} faces, wasm ${w.faces}`);
    nativeWall.push(field('full_ms'));
    nativeCpu.push(field('cpu_ms'));
    faces = w.faces;
  }
  const [w, n, wc, nc] = [median(wasm), median(nativeWall), median(wasmCpu), median(nativeCpu)];
  console.log(`| ${basename(stream)} | ${faces.toLocaleString('en-US')} | ${bytes.length.toLocaleString('en-US')} | ${runs} | ` +
              `${fmt(w)} | ${fmt(n)} | ${(w / n).toFixed(2)} | ${fmt(wc)} | ${fmt(nc)} | ${(wc / nc).toFixed(2)} |`);
}
