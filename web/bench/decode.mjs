// Full decode in node (the WebAssembly decoder) against the native pmdec, on one .pm: prints a
// Markdown table, the median of RUNS runs each. Native: pmdec decoding to a binary PLY in
// /dev/shm (read_pm + extract_level + writing the file); WebAssembly: append + finish (read_pm)
// + level() (extract_level, copied out of the module's memory).
// Usage: node web/bench/decode.mjs BUILD_DIR STREAM.pm [RUNS]
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';

const [build, stream, runs = '5'] = process.argv.slice(2);
const { loadPmModule, CoreDecoder } = await import(join(build, 'web/dist/pm-core.js'));
const module = await loadPmModule();
const bytes = readFileSync(stream);
const median = (values) => values.sort((a, b) => a - b)[Math.floor(values.length / 2)];

const wasm = [], wasmRead = [], native = [];
let faces = 0;
for (let r = 0; r < Number(runs); ++r) {
  const start = performance.now();
  const decoder = new CoreDecoder(module);
  decoder.append(bytes);
  decoder.finish();
  const read = performance.now();
  faces = decoder.level().faces;
  wasm.push(performance.now() - start);
  wasmRead.push(read - start);
  decoder.destroy();
  const nativeStart = performance.now();
  execFileSync(join(build, 'apps/pmdec'), [stream, '-o', '/dev/shm/pm-bench.ply', '-q']);
  native.push(performance.now() - nativeStart);
}
const [w, wr, n] = [median(wasm), median(wasmRead), median(native)];
console.log(`| stream | faces | bytes | wasm read_pm (ms) | wasm full decode (ms) | native pmdec (ms) | wasm / native |`);
console.log(`|---|---|---|---|---|---|---|`);
console.log(`| ${stream.split('/').pop()} | ${faces} | ${bytes.length} | ${wr.toFixed(0)} | ${w.toFixed(0)} | ${n.toFixed(0)} | ${(w / n).toFixed(2)} |`);
