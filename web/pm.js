// The progressive-mesh decoder for web pages (and node), as an ES module: pm::codec compiled
// to WebAssembly, running in a Worker. Push a .pm stream's bytes as they arrive; ask for the
// finest level so far, a level by faces, vertices, ratio or error, the runtime's wedge
// buffers, or a geomorph. Results are typed arrays, transferred from the worker, ready for
// WebGL or three.js. Every failure is a rejected promise with a PmError (code, message) as
// the library reports it. Types: pm.d.ts.
import { PmError } from './pm-core.js';

export { PmError };

async function startWorker(url) {
  if (typeof Worker !== 'undefined') {
    const worker = new Worker(url, { type: 'module' });
    return {
      post: (message, transfer) => worker.postMessage(message, transfer),
      onMessage: (handler) => { worker.onmessage = (event) => handler(event.data); },
      onFailure: (handler) => { worker.onerror = (event) => handler(event.message || 'the worker failed'); },
      terminate: () => worker.terminate(),
    };
  }
  const { Worker: NodeWorker } = await import('node:worker_threads');
  const worker = new NodeWorker(url);
  worker.unref();
  return {
    post: (message, transfer) => worker.postMessage(message, transfer),
    onMessage: (handler) => worker.on('message', handler),
    onFailure: (handler) => worker.on('error', (error) => handler(error.message)),
    terminate: () => worker.terminate(),
  };
}

export class PmDecoder {
  // options: maxMemory (bytes; a stream whose decoding needs more is refused with
  // 'resource-limit'), allowTruncated (finish() accepts a stream cut after its base mesh),
  // workerUrl (where pm-worker.js is; beside this module by default), wasmBinary (the .wasm's
  // bytes, when they are at hand; else fetched beside pm-core.js).
  static async create(options = {}) {
    const url = options.workerUrl ?? new URL('./pm-worker.js', import.meta.url);
    const decoder = new PmDecoder(await startWorker(url));
    const { workerUrl, ...settings } = options;
    decoder.state = await decoder.#request('create', [settings]);
    return decoder;
  }

  constructor(worker) {
    this.worker = worker;
    this.pending = new Map();
    this.nextId = 1;
    this.state = null;
    worker.onMessage(({ id, result, error }) => {
      const call = this.pending.get(id);
      if (!call) return;
      this.pending.delete(id);
      if (error) call.reject(new PmError(error.code, error.message, error.codeNumber));
      else call.resolve(result);
    });
    worker.onFailure((message) => {
      for (const call of this.pending.values()) call.reject(new PmError('internal', message, 11));
      this.pending.clear();
    });
  }

  #request(op, args, transfer = []) {
    return new Promise((resolve, reject) => {
      const id = this.nextId++;
      this.pending.set(id, { resolve, reject });
      this.worker.post({ id, op, args }, transfer);
    });
  }

  // The next bytes of the stream (a Uint8Array or ArrayBuffer). Its buffer is transferred to
  // the worker (detached here) unless copy is set. Resolves to the state: { hasBase,
  // complete, decodedFaces, streamFaces, splits }.
  async push(bytes, { copy = false } = {}) {
    let view = bytes instanceof ArrayBuffer ? new Uint8Array(bytes) : bytes;
    // A copy when asked, or when the bytes share their buffer with others (node's Buffer
    // slices, a view into a larger buffer): only a buffer of their own is transferred.
    if (copy || view.byteOffset !== 0 || view.byteLength !== view.buffer.byteLength) view = new Uint8Array(view);
    this.state = await this.#request('append', [view.buffer], [view.buffer]);
    return this.state;
  }

  // The end of the stream: rejects with 'truncated-stream' when it was cut short.
  async finish() {
    this.state = await this.#request('finish', []);
    return this.state;
  }

  // A level as pmdec writes it; request: { level | faces | vertices | error | ratio: n }, or
  // nothing for the finest level decoded so far.
  level(request) { return this.#request('level', [request]); }
  // The runtime (Hoppe 1998) set to a level: wedge buffers and the level's indices.
  runtime(request) { return this.#request('runtime', [request]); }
  // A geomorph between two levels ({ faces: [from, to] }, ...), blended at each alpha.
  geomorph(request, alphas = [0, 1]) { return this.#request('geomorph', [request, alphas]); }

  // Ends the worker; pending calls are rejected.
  close() {
    for (const call of this.pending.values()) call.reject(new PmError('invalid-argument', 'the decoder was closed', 1));
    this.pending.clear();
    this.worker.terminate();
  }
}

// Streams a .pm from a ReadableStream of bytes (a fetch() Response's body) into a decoder;
// calls onProgress(state, bytesSoFar) after each chunk. Resolves to the final state.
export async function pushStream(decoder, stream, onProgress = () => {}) {
  const reader = stream.getReader();
  let received = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    received += value.byteLength;
    await onProgress(await decoder.push(value), received);
  }
  return decoder.finish();
}
