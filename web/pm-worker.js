// The decoder's worker: runs pm-core.js off the page's thread for pm.js. Messages are
// { id, op, args }; replies { id, result } or { id, error: { code, codeNumber, message } }.
// Every typed array of a result is transferred to the page, not copied. Runs as a module
// worker in browsers and as a worker_threads worker in node.
import { CoreDecoder, PmError, loadPmModule } from './pm-core.js';

const port = typeof self !== 'undefined' && typeof self.postMessage === 'function'
  ? { post: (message, transfer) => self.postMessage(message, transfer),
      listen: (handler) => { self.onmessage = (event) => handler(event.data); } }
  : await (async () => {
    const { parentPort } = await import('node:worker_threads');
    return { post: (message, transfer) => parentPort.postMessage(message, transfer),
             listen: (handler) => parentPort.on('message', handler) };
  })();

let decoder = null;

function transferables(value, list = []) {
  if (ArrayBuffer.isView(value)) list.push(value.buffer);
  else if (Array.isArray(value)) value.forEach((item) => transferables(item, list));
  else if (value && typeof value === 'object') Object.values(value).forEach((item) => transferables(item, list));
  return list;
}

const operations = {
  async create(options) {
    decoder = new CoreDecoder(await loadPmModule(options.wasmBinary), options);
    return decoder.state();
  },
  append: (bytes) => decoder.append(new Uint8Array(bytes)),
  finish: () => decoder.finish(),
  state: () => decoder.state(),
  level: (request) => decoder.level(request),
  runtime: (request) => decoder.runtime(request),
  geomorph: (request, alphas) => decoder.geomorph(request, alphas),
  close() { decoder?.destroy(); decoder = null; return null; },
};

port.listen(async ({ id, op, args }) => {
  try {
    if (!operations[op]) throw new PmError('invalid-argument', `unknown operation ${op}`, 1);
    if (op !== 'create' && !decoder) throw new PmError('invalid-argument', 'the decoder is closed', 1);
    const result = await operations[op](...args);
    port.post({ id, result }, transferables(result));
  } catch (error) {
    const known = error instanceof PmError;
    port.post({ id, error: { code: known ? error.code : 'internal', codeNumber: known ? error.codeNumber : 11,
                             message: String(error && error.message ? error.message : error) } });
  }
});
