// Streaming (issue 28): a stream fed in pieces of 1 KB reports valid levels whose face counts
// never decrease, the last one full detail; cut and damaged streams, and the native fuzz
// corpus, give the library's errors (never a trap, which would be the code 'internal').
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
import test from 'node:test';

import { CoreDecoder, PmDecoder, PmError, fuzzCorpus, goldenStreams, levelProblem, loadPmModule,
         sameBits, sampleStreams, sharedStreams } from './fixtures.mjs';

const module = await loadPmModule();
const kLibraryCodes = ['invalid-argument', 'corrupt-stream', 'truncated-stream', 'unsupported-version',
                       'checksum-mismatch', 'resource-limit'];

function fullDetail(bytes) {
  const decoder = new CoreDecoder(module);
  decoder.append(bytes);
  decoder.finish();
  const level = decoder.level();
  decoder.destroy();
  return level;
}

function streamInPieces(path) {
  const bytes = readFileSync(path);
  const decoder = new CoreDecoder(module);
  let faces = 0, levels = 0;
  for (let at = 0; at < bytes.length; at += 1024) {
    const state = decoder.append(bytes.subarray(at, at + 1024));
    if (!state.hasBase || state.decodedFaces === faces) continue;
    const level = decoder.level();
    const problem = levelProblem(level);
    assert.equal(problem, null, `${basename(path)} at byte ${at}: ${problem}`);
    assert.ok(level.faces >= faces, `${basename(path)}: faces went down from ${faces} to ${level.faces}`);
    faces = level.faces;
    ++levels;
  }
  assert.ok(decoder.finish().complete);
  const last = decoder.level();
  const whole = fullDetail(bytes);
  assert.ok(sameBits(last.positions, whole.positions) && sameBits(last.indices, whole.indices),
            `${basename(path)}: the last level is not full detail`);
  decoder.destroy();
  return levels;
}

test('1 KB pieces give valid levels, growing, ending at full detail', (t) => {
  const streams = [...goldenStreams(), ...sampleStreams(), ...sharedStreams()];
  let refined = 0;
  for (const path of streams) refined += streamInPieces(path) > 1;
  // The samples' streams are longer than a chunk: they must refine more than once.
  assert.ok(refined >= 6, `only ${refined} streams refined more than once`);
});

function expectLibraryError(run, what) {
  try {
    run();
  } catch (error) {
    assert.ok(error instanceof PmError, `${what}: ${error}`);
    assert.ok(kLibraryCodes.includes(error.code), `${what}: code ${error.code}: ${error.message}`);
    assert.ok(error.message.length > 0);
    return error;
  }
  return null;
}

test('cut streams are truncated-stream errors; with allowTruncated, the levels that arrived', () => {
  const bytes = readFileSync(sampleStreams().find((p) => p.endsWith('samples/sphere.pm')));
  for (const cut of [10, 100, 1000, Math.floor(bytes.length / 2), bytes.length - 1]) {
    const decoder = new CoreDecoder(module);
    decoder.append(bytes.subarray(0, cut));
    const error = expectLibraryError(() => decoder.finish(), `cut at ${cut}`);
    assert.equal(error?.code, 'truncated-stream', `cut at ${cut}`);
    decoder.destroy();
  }
  const lenient = new CoreDecoder(module, { allowTruncated: true });
  lenient.append(bytes.subarray(0, Math.floor(bytes.length / 2)));
  const state = lenient.finish();
  assert.ok(state.hasBase && state.decodedFaces < fullDetail(bytes).faces);
  assert.equal(levelProblem(lenient.level()), null);
});

test('damaged streams and the fuzz corpus give errors, never traps', () => {
  const inputs = fuzzCorpus().map((path) => [basename(path), readFileSync(path)]);
  // Every sample stream with one byte changed at 40 places: an error or a valid mesh.
  for (const path of sampleStreams().slice(0, 4)) {
    const bytes = readFileSync(path);
    for (let k = 1; k <= 40; ++k) {
      const damaged = Buffer.from(bytes);
      const at = Math.floor((k * damaged.length) / 41);
      damaged[at] ^= 0x5a;
      inputs.push([`${basename(path)} byte ${at}`, damaged]);
    }
  }
  let refused = 0;
  for (const [what, bytes] of inputs) {
    for (const piece of [bytes.length || 1, 1024]) {
      const decoder = new CoreDecoder(module, { maxMemory: 256 << 20 });
      const error = expectLibraryError(() => {
        for (let at = 0; at < bytes.length; at += piece) decoder.append(bytes.subarray(at, at + piece));
        decoder.finish();
        assert.equal(levelProblem(decoder.level()), null, what);
      }, what);
      refused += error !== null;
      decoder.destroy();
    }
  }
  assert.ok(refused > inputs.length / 2, `only ${refused} of ${2 * inputs.length} refused`);
  assert.ok(!module.broken, 'the module trapped');
});

test('the worker: levels transferred, bad bytes a rejected promise with the library\'s code', async (t) => {
  const path = sampleStreams().find((p) => p.endsWith('samples/textured.pm'));
  const bytes = readFileSync(path);
  const decoder = await PmDecoder.create();
  t.after(() => decoder.close());
  let state;
  for (let at = 0; at < bytes.length; at += 1024) state = await decoder.push(bytes.slice(at, at + 1024));
  state = await decoder.finish();
  assert.ok(state.complete);
  const level = await decoder.level({ ratio: 0.5 });
  const direct = new CoreDecoder(module);
  direct.append(bytes);
  const expected = direct.level({ ratio: 0.5 });
  assert.ok(sameBits(level.positions, expected.positions) && sameBits(level.indices, expected.indices));
  assert.ok(level.uvs && level.uvIndices && level.normals && level.colors, 'textured.obj has every attribute');
  const runtime = await decoder.runtime({ faces: level.faces });
  assert.equal(runtime.faces, level.faces);
  assert.ok(runtime.indices.every((i) => i < runtime.wedges));
  assert.equal(runtime.positions.length, 3 * runtime.wedges);
  const morph = await decoder.geomorph({ faces: [1, level.faces] }, [0, 0.5, 1]);
  assert.equal(morph.faces, level.faces);
  assert.deepEqual(morph.frames.map((f) => f.alpha), [0, 0.5, 1]);
  // alpha 1 is the finer level's geometry exactly, as the runtime holds it.
  assert.ok(sameBits(morph.frames[2].positions, runtime.positions.subarray(0, 3 * morph.wedges)));

  const bad = await PmDecoder.create();
  t.after(() => bad.close());
  const garbage = new Uint8Array(4096).fill(0x41);
  await assert.rejects(bad.push(garbage), (error) => error instanceof PmError && error.code === 'corrupt-stream' &&
                       /magic/.test(error.message));
  assert.equal(garbage.byteLength, 0, 'the pushed buffer is transferred, not copied');
  await assert.rejects(bad.level(), (error) => error.code === 'corrupt-stream');  // the error is final
});
