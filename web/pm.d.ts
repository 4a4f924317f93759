// Types of pm.js (the decoder in a Worker) and pm-core.js (the same decoder, synchronous).

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

/** The decoder in a Worker: every method resolves, or rejects with a PmError. Typed arrays
 *  are transferred from the worker (no copy on the way). */
export class PmDecoder {
  static create(options?: DecoderOptions & { workerUrl?: string | URL; wasmBinary?: ArrayBuffer }): Promise<PmDecoder>;
  state: PmState | null;
  /** The next bytes; their buffer is transferred (detached here) unless copy is set. */
  push(bytes: Uint8Array | ArrayBuffer, options?: { copy?: boolean }): Promise<PmState>;
  /** The end of the stream: rejects with 'truncated-stream' when it was cut short. */
  finish(): Promise<PmState>;
  level(request?: LevelRequest): Promise<PmLevel>;
  runtime(request?: LevelRequest): Promise<PmRuntimeLevel>;
  geomorph(request: GeomorphRequest, alphas?: number[]): Promise<PmGeomorph>;
  close(): void;
}

/** Pushes a ReadableStream (a fetch() Response's body) into the decoder chunk by chunk. */
export function pushStream(decoder: PmDecoder, stream: ReadableStream<Uint8Array>,
                           onProgress?: (state: PmState, bytesReceived: number) => void | Promise<void>): Promise<PmState>;

/** pm-core.js: the module, and the decoder without a worker (same methods, synchronous). */
export interface PmModule {}
export function loadPmModule(wasmBinary?: ArrayBuffer | Uint8Array): Promise<PmModule>;
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
