// Writes a big mesh for the browser test: an OBJ subdivided `rounds` times by splitting each
// triangle into four at its edges' midpoints (the 1:4 split of Loop subdivision, without its
// smoothing, which the test does not need). Usage: node subdivide.mjs IN.obj ROUNDS OUT.obj
import { readFileSync, writeFileSync } from 'node:fs';

const [input, rounds, output] = process.argv.slice(2);
let positions = [];
let faces = [];
for (const line of readFileSync(input, 'utf8').split('\n')) {
  const words = line.trim().split(/\s+/);
  if (words[0] === 'v') positions.push(Number(words[1]), Number(words[2]), Number(words[3]));
  if (words[0] === 'f') faces.push(...words.slice(1, 4).map((w) => parseInt(w, 10) - 1));
}
for (let r = 0; r < Number(rounds); ++r) {
  const midpoints = new Map();
  const midpoint = (a, b) => {
    const key = a < b ? a * 0x4000000 + b : b * 0x4000000 + a;
    let m = midpoints.get(key);
    if (m === undefined) {
      m = positions.length / 3;
      for (let k = 0; k < 3; ++k) positions.push((positions[3 * a + k] + positions[3 * b + k]) / 2);
      midpoints.set(key, m);
    }
    return m;
  };
  const next = [];
  for (let f = 0; f < faces.length; f += 3) {
    const [a, b, c] = [faces[f], faces[f + 1], faces[f + 2]];
    const [ab, bc, ca] = [midpoint(a, b), midpoint(b, c), midpoint(c, a)];
    next.push(a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca);
  }
  faces = next;
}
const lines = [];
for (let v = 0; v < positions.length; v += 3) lines.push(`v ${positions[v]} ${positions[v + 1]} ${positions[v + 2]}`);
for (let f = 0; f < faces.length; f += 3) lines.push(`f ${faces[f] + 1} ${faces[f + 1] + 1} ${faces[f + 2] + 1}`);
writeFileSync(output, lines.join('\n') + '\n');
