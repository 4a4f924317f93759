// The WebAssembly decoder, synchronous: pm::codec compiled by emscripten (web/src/pm_wasm.cpp)
// behind a small class. pm-worker.js runs it off the page's thread (what pm.js offers); node
// programs and tests may use it directly. Types: pm-core.d.ts.
//
// Arrays come out of the module's memory as fresh typed arrays (one copy, from the wasm heap
// into buffers of their own), so that a worker can transfer them to the page without another.
import createPmModule from './pm_decoder.mjs';

// A failure of the library (a pm::Status), or of the module itself ('internal').
export class PmError extends Error {
  constructor(code, message, codeNumber) {
    super(message);
    this.name = 'PmError';
    this.code = code;              // the library's stable name: 'corrupt-stream', ...
    this.codeNumber = codeNumber;  // pm::ErrorCode's number (status.h)
  }
}

const kInternal = 11;  // pm::ErrorCode::kInternal

// Loads the module. wasmBinary: the .wasm's bytes; by default read beside this file (fetch in
// browsers and workers, the file system in node).
export async function loadPmModule(wasmBinary) {
  if (!wasmBinary) {
    const url = new URL('./pm_decoder.wasm', import.meta.url);
    if (url.protocol === 'file:') {
      const { readFile } = await import('node:fs/promises');
      wasmBinary = await readFile(url);
    } else {
      const response = await fetch(url);
      if (!response.ok) throw new PmError('io-error', `${url}: HTTP ${response.status}`, 2);
      wasmBinary = await response.arrayBuffer();
    }
  }
  return createPmModule({ wasmBinary });
}

// Level requests: { level }, { faces }, { vertices }, { error }, { ratio } (one of them), or
// nothing for the finest level decoded so far.
const kRequestKinds = ['level', 'faces', 'vertices', 'error', 'ratio'];
function requestArguments(request) {
  if (request === undefined || request === null) return [4, 1];
  const kinds = kRequestKinds.filter((kind) => request[kind] !== undefined);
  if (kinds.length !== 1 || typeof request[kinds[0]] !== 'number') {
    throw new PmError('invalid-argument',
                      'a level request is one of { level | faces | vertices | error | ratio: number }', 1);
  }
  return [kRequestKinds.indexOf(kinds[0]), request[kinds[0]]];
}

export class CoreDecoder {
  // options: maxMemory (bytes, 0: no bound; ReadOptions::max_memory), allowTruncated (finish()
  // accepts a stream cut after its base mesh).
  constructor(module, options = {}) {
    this.module = module;
    this.handle = this.#call(() => module._pmw_create(options.maxMemory ?? 0, options.allowTruncated ? 1 : 0));
    if (!this.handle) throw new PmError('resource-limit', 'out of memory', 10);
    this.scratch = 0;
    this.scratchSize = 0;
  }

  // Runs a call into the module; a trap (which C++ cannot catch) becomes a PmError, and the
  // module is never called again: its memory may be half-updated.
  #call(body) {
    if (this.module.broken) throw new PmError('internal', 'the decoder stopped after an earlier failure', kInternal);
    try {
      return body();
    } catch (error) {
      if (error instanceof PmError) throw error;  // the library's own report
      this.module.broken = true;
      throw new PmError('internal', `the decoder failed: ${error && error.message ? error.message : error}`, kInternal);
    }
  }

  #check(code) {
    if (code === 0) return;
    const m = this.module;
    throw new PmError(m.UTF8ToString(m._pmw_error_code_name(code)),
                      m.UTF8ToString(m._pmw_error_message(this.handle)), code);
  }

  #checkedDescriptor(address, words) {
    if (address === 0) {
      const m = this.module;
      const message = m.UTF8ToString(m._pmw_error_message(this.handle));
      const code = m._pmw_error_code(this.handle);
      throw new PmError(m.UTF8ToString(m._pmw_error_code_name(code)), message, code);
    }
    return Array.from(this.module.HEAPU32.subarray(address >>> 2, (address >>> 2) + words));
  }

  // The next bytes of the stream (Uint8Array). Throws PmError on damage; the error is final.
  append(bytes) {
    if (bytes.length === 0) return this.state();
    this.#call(() => {
      const m = this.module;
      if (bytes.length > this.scratchSize) {
        if (this.scratch) m._free(this.scratch);
        this.scratchSize = Math.max(bytes.length, 65536);
        this.scratch = m._malloc(this.scratchSize);
        if (!this.scratch) this.scratchSize = 0;
      }
      if (!this.scratch) return this.#check(10);
      m.HEAPU8.set(bytes, this.scratch);
      return this.#check(m._pmw_append(this.handle, this.scratch, bytes.length));
    });
    return this.state();
  }

  // The end of the stream: throws 'truncated-stream' when it was cut short.
  finish() {
    this.#call(() => this.#check(this.module._pmw_finish(this.handle)));
    return this.state();
  }

  state() {
    return this.#call(() => {
      const s = (field) => this.module._pmw_state(this.handle, field);
      return { hasBase: s(0) === 1, complete: s(1) === 1, decodedFaces: s(2), streamFaces: s(3), splits: s(4) };
    });
  }

  #floats(address, length) {
    return address ? this.module.HEAPF32.slice(address >>> 2, (address >>> 2) + length) : null;
  }
  #uints(address, length) {
    return address ? this.module.HEAPU32.slice(address >>> 2, (address >>> 2) + length) : null;
  }
  #errorOf(bits) {
    return new Float32Array(new Uint32Array([bits]).buffer)[0];
  }

  // A level as pmdec writes it (extract_level: welded copies merged, unused vertices dropped):
  // positions (3 per vertex), indices (3 per face), colours per vertex, texture coordinates
  // and normals as tables with per-corner indices, a material per face.
  level(request) {
    const [by, value] = requestArguments(request);
    return this.#call(() => {
      const d = this.#checkedDescriptor(this.module._pmw_level(this.handle, by, value), 22);
      const field = (i, read) => read.call(this, d[6 + 2 * i], d[7 + 2 * i]);
      return {
        level: d[0], splits: d[1], faces: d[2], vertices: d[3], colorComponents: d[4],
        error: this.#errorOf(d[5]),
        positions: field(0, this.#floats), indices: field(1, this.#uints) ?? new Uint32Array(0),
        colors: field(2, this.#floats), uvs: field(3, this.#floats), uvIndices: field(4, this.#uints),
        normals: field(5, this.#floats), normalIndices: field(6, this.#uints),
        faceMaterials: field(7, this.#uints),
      };
    });
  }

  // The runtime at a level (Hoppe 1998): render vertices are wedges (position, texture
  // coordinate, normal, colour each), ready for a vertex buffer; indices hold the level's faces.
  runtime(request) {
    const [by, value] = requestArguments(request);
    return this.#call(() => {
      const d = this.#checkedDescriptor(this.module._pmw_runtime(this.handle, by, value), 11);
      const wedges = d[3], components = d[4];
      return {
        level: d[0], maxLevel: d[1], faces: d[2], wedges, colorComponents: components,
        error: this.#errorOf(d[5]),
        indices: this.#uints(d[6], 3 * d[2]) ?? new Uint32Array(0),
        positions: this.#floats(d[7], 3 * wedges) ?? new Float32Array(0),
        uvs: this.#floats(d[8], 2 * wedges), normals: this.#floats(d[9], 3 * wedges),
        colors: this.#floats(d[10], components * wedges),
      };
    });
  }

  // A geomorph (Hoppe 1996, §4.2) from one level to a finer one (requests as for runtime(),
  // of one kind: { faces: [from, to] } etc., or levels { level: [from, to] }): the finer
  // level's faces, and the wedges blended at each alpha in `alphas` (0: the coarser level's
  // geometry, new wedges at their ancestors; 1: the finer level's).
  geomorph(request, alphas = [0, 1]) {
    const kinds = kRequestKinds.filter((kind) => request && request[kind] !== undefined);
    const range = kinds.length === 1 ? request[kinds[0]] : null;
    if (!Array.isArray(range) || range.length !== 2 || !range.every((x) => typeof x === 'number')) {
      throw new PmError('invalid-argument', 'a geomorph request is { level | faces | vertices | error | ratio: [from, to] }', 1);
    }
    const by = kRequestKinds.indexOf(kinds[0]);
    return this.#call(() => {
      const d = this.#checkedDescriptor(this.module._pmw_geomorph(this.handle, by, range[0], range[1]), 8);
      const wedges = d[3], components = d[4];
      const morph = {
        from: d[0], to: d[1], faces: d[2], wedges, colorComponents: components,
        indices: this.#uints(d[7], 3 * d[2]) ?? new Uint32Array(0), frames: [],
      };
      for (const alpha of alphas) {
        const e = this.#checkedDescriptor(this.module._pmw_geomorph_evaluate(this.handle, alpha), 4);
        morph.frames.push({
          alpha, positions: this.#floats(e[0], 3 * wedges) ?? new Float32Array(0),
          uvs: this.#floats(e[1], 2 * wedges), normals: this.#floats(e[2], 3 * wedges),
          colors: this.#floats(e[3], components * wedges),
        });
      }
      return morph;
    });
  }

  destroy() {
    if (!this.handle || this.module.broken) return;
    if (this.scratch) this.module._free(this.scratch);
    this.module._pmw_destroy(this.handle);
    this.handle = 0;
  }
}
