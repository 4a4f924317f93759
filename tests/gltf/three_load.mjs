// three.js's GLTFLoader (npm three) in node on a file pmdec wrote: prints the faces of each
// level, finest first (the scene's node, then the nodes its MSFT_lod extension names), as
// JSON: {"levels":[faces, ...]}. three.js does not implement MSFT_lod, so the scene shows the
// finest level and the coarser ones are loaded as the file's other nodes.
// Usage: node three_load.mjs FILE.glb
import { readFileSync } from 'node:fs';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';

const bytes = readFileSync(process.argv[2]);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const loader = new GLTFLoader();
const gltf = await new Promise((resolve, reject) => loader.parse(buffer, '', resolve, reject));
const json = gltf.parser.json;
const root = json.scenes[json.scene ?? 0].nodes[0];
const lod = json.nodes[root].extensions?.MSFT_lod?.ids ?? [];
const faces = [];
for (const index of [root, ...lod]) {
  const node = await gltf.parser.getDependency('node', index);
  let count = 0;
  node.traverse((object) => {
    if (object.isMesh) count += (object.geometry.index ? object.geometry.index.count : object.geometry.attributes.position.count) / 3;
  });
  faces.push(count);
}
// The finest level is also what the loaded scene shows.
let shown = 0;
gltf.scene.traverse((object) => {
  if (object.isMesh) shown += object.geometry.index.count / 3;
});
console.log(JSON.stringify({ levels: faces, scene: shown }));
