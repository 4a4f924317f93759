// Types of pm.js: the decoder in a Worker. The types it shares with pm-core.js (the same
// decoder, synchronous) are declared in pm-core.d.ts and re-exported here.
import type { LevelRequest, PmState, PmLevel, PmRuntimeLevel, PmGeomorph, GeomorphRequest, DecoderOptions } from './pm-core.js';

export { PmError } from './pm-core.js';
export type { LevelRequest, PmState, PmLevel, PmRuntimeLevel, PmGeomorph, GeomorphRequest, DecoderOptions } from './pm-core.js';

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
