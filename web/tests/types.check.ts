// The TypeScript declarations (pm.d.ts, pm-core.d.ts) as a user's program meets them:
// Web.types compiles this with tsc --strict (tsconfig.types.json; nothing runs). Each public
// entry's exports are imported from the .js file, so tsc takes their types from the .d.ts
// beside it; the @ts-expect-error lines are what the declarations must refuse.
import { PmDecoder, PmError, pushStream } from '../pm.js';
import type { GeomorphRequest, LevelRequest, PmLevel, PmRuntimeLevel, PmState } from '../pm.js';
import { CoreDecoder, PmError as CorePmError, loadPmModule } from '../pm-core.js';
import type { DecoderOptions, PmGeomorph, PmModule } from '../pm-core.js';

async function streamed(url: string): Promise<PmLevel> {
  const decoder: PmDecoder = await PmDecoder.create({ maxMemory: 1 << 30 });
  const response = await fetch(url);
  if (!response.body) throw new Error('no body');
  const state: PmState = await pushStream(decoder, response.body, async (s, bytesReceived) => {
    if (s.hasBase && bytesReceived > 0) await decoder.runtime();
  });
  const request: LevelRequest = state.complete ? { ratio: 1 } : { faces: state.decodedFaces };
  const level = await decoder.level(request);
  const runtime: PmRuntimeLevel = await decoder.runtime({ error: 0.01 });
  const morph: GeomorphRequest = { faces: [1000, runtime.faces] };
  const frames = (await decoder.geomorph(morph, [0, 0.5, 1])).frames;
  const first: Float32Array = frames[0].positions;
  decoder.close();
  // @ts-expect-error: a level request is one kind, with a number
  await decoder.level({ faces: '10' });
  return first.length > 0 ? level : await decoder.level();
}

async function synchronous(bytes: Uint8Array, options: DecoderOptions): Promise<number> {
  const module: PmModule = await loadPmModule();
  const decoder = new CoreDecoder(module, options);
  try {
    const state: PmState = decoder.append(bytes);
    decoder.finish();
    const level: PmLevel = decoder.level({ vertices: state.splits });
    const indices: Uint32Array = level.indices;
    const uvs: Float32Array | null = level.uvs;
    const morph: PmGeomorph = decoder.geomorph({ level: [0, 1] });
    // @ts-expect-error: the synchronous decoder returns the level, not a promise
    await decoder.level().then(() => 0);
    return indices.length + (uvs?.length ?? 0) + morph.wedges + decoder.runtime().wedges;
  } catch (error) {
    // One class: pm.js re-exports pm-core.js's.
    const same: typeof PmError = CorePmError;
    if (error instanceof same) return error.codeNumber + error.code.length;
    throw error;
  } finally {
    decoder.destroy();
  }
}

export { streamed, synchronous };
