// The Khronos glTF-Validator (npm gltf-validator) on each file given: prints one line per file
// with its counts, every error and warning in full, and exits 1 if any file has one.
// Usage: node validate.mjs FILE.glb|FILE.gltf ...
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
import validator from 'gltf-validator';

let failed = false;
for (const file of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    uri: basename(file),
    maxIssues: 0,  // all of them
    externalResourceFunction: () => Promise.reject(new Error('pmdec writes single files')),
  });
  const { numErrors, numWarnings, numInfos, numHints } = report.issues;
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints`);
  for (const message of report.issues.messages)
    if (message.severity <= 1)
      console.log(`  ${message.severity === 0 ? 'error' : 'warning'} ${message.code} at ${message.pointer}: ${message.message}`);
  if (numErrors > 0 || numWarnings > 0) failed = true;
}
process.exit(failed ? 1 : 0);
