// Types of pm-core.js: the WebAssembly decoder, synchronous (node programs, tests, and
// pm-worker.js, which runs it for pm.js). pm.d.ts re-exports the shared types.

/** A failure as the library reports it (pm::Status), or 'internal' for a fault of the module. */
export class PmError extends Error {
  /** The library's stable name: 'corrupt-stream', 'truncated-stream', 'checksum-mismatch',
   *  'unsupported-version', 'resource-limit', 'invalid-argument', 'internal', ... */
  readonly code: string;
  /** pm::ErrorCode's number (lib/include/pm/status.h). */
  readonly codeNumber: number;
}

/** One of these, or nothing for the finest level decoded so far. ratio: of the full detail's
 *  faces; error: the coarsest level whose recorded error bound is at most this (model units). */
export type LevelRequest =
  | { level: number } | { faces: number } | { vertices: number } | { error: number } | { ratio: number };

export interface PmState {
  hasBase: boolean;      // the base mesh has arrived: levels can be asked for
  complete: boolean;     // the whole stream has been decoded
  decodedFaces: number;  // faces of the finest level decoded so far
  streamFaces: number;   // faces of the whole stream (0 before its header)
  splits: number;        // vertex splits decoded so far
}

/** A level as pmdec writes it: welded copies merged, unused vertices dropped, faces grouped
 *  by material. Attributes are null when the mesh has none. */
export interface PmLevel {
  level: number; splits: number; faces: number; vertices: number; error: number;
  positions: Float32Array;         // x, y, z per vertex
  indices: Uint32Array;            // 3 vertex indices per face, counter-clockwise
  colorComponents: number;         // 0, 3 or 4
  colors: Float32Array | null;     // per vertex
  uvs: Float32Array | null;        // table: u, v per entry
  uvIndices: Uint32Array | null;   // per corner, into uvs (0xFFFFFFFF: none)
  normals: Float32Array | null;    // table: x, y, z per entry
  normalIndices: Uint32Array | null;
  faceMaterials: Uint32Array | null;
}

/** The runtime at a level (Hoppe 1998): wedges are render vertices (one position, texture
 *  coordinate, normal and colour each): bind them as vertex attributes and draw `indices`. */
export interface PmRuntimeLevel {
  level: number; maxLevel: number; faces: number; wedges: number; error: number;
  colorComponents: number;
  indices: Uint32Array;            // 3 wedge indices per face of the level
  positions: Float32Array;         // 3 per wedge
  uvs: Float32Array | null; normals: Float32Array | null; colors: Float32Array | null;
}

/** A geomorph (Hoppe 1996, §4.2): the finer level's faces; each frame its wedges blended at
 *  alpha (0: the coarser level's shape, each new vertex at its ancestor; 1: the finer's). */
export interface PmGeomorph {
  from: number; to: number; faces: number; wedges: number; colorComponents: number;
  indices: Uint32Array;
  frames: Array<{ alpha: number; positions: Float32Array; uvs: Float32Array | null;
                  normals: Float32Array | null; colors: Float32Array | null }>;
}

/** A geomorph request: two levels of one kind, coarser first. */
export type GeomorphRequest =
  | { level: [number, number] } | { faces: [number, number] } | { vertices: [number, number] }
  | { error: [number, number] } | { ratio: [number, number] };

export interface DecoderOptions {
  /** Refuse a stream whose decoding needs more bytes ('resource-limit'); 0: no bound. */
  maxMemory?: number;
  /** finish() accepts a stream cut after its base mesh (the levels that arrived). */
  allowTruncated?: boolean;
}

/** The compiled module (pm_decoder.mjs and its .wasm), loaded once and shared by decoders. */
export interface PmModule {}
/** Loads the module; wasmBinary: the .wasm's bytes, by default read beside pm-core.js
 *  (fetch() in browsers and workers, the file system in node). */
export function loadPmModule(wasmBinary?: ArrayBuffer | Uint8Array): Promise<PmModule>;

/** The decoder without a worker: the same methods as pm.js's PmDecoder, synchronous; each
 *  throws a PmError. Arrays are fresh copies out of the module's memory. */
export class CoreDecoder {
  constructor(module: PmModule, options?: DecoderOptions);
  append(bytes: Uint8Array): PmState;
  finish(): PmState;
  state(): PmState;
  level(request?: LevelRequest): PmLevel;
  runtime(request?: LevelRequest): PmRuntimeLevel;
  geomorph(request: GeomorphRequest, alphas?: number[]): PmGeomorph;
  destroy(): void;
}
