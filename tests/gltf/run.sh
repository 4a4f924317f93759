#!/usr/bin/env bash
# pmdec's glTF output against real consumers (issue 29), registered in CTest as
# Gltf.ValidatorAndThree (label integration): a sample through pmenc, then pmdec writes one
# level (.glb and .gltf), a 4-level chain (.glb and .gltf) and the quantized chain; the
# Khronos glTF-Validator must report no error and no warning on any of them, and three.js's
# GLTFLoader in node must load the chains with the face counts pmdec reported.
# Usage: run.sh PMENC PMDEC REPO. Needs node and tests/gltf/node_modules (bash .ci/deps --test
# runs npm ci here). About 5 s.
set -euo pipefail
pmenc=$1 pmdec=$2 repo=$3
here="$repo/tests/gltf"
if [[ ! -d "$here/node_modules/gltf-validator" || ! -d "$here/node_modules/three" ]]; then
  echo "tests/gltf/node_modules is missing: run 'bash .ci/deps --test' (npm ci in tests/gltf)" >&2
  exit 1
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/pm-gltf.XXXXXX")
trap 'rm -rf "$work"' EXIT
# textured.obj: UV seams, normals and two materials; sphere.obj: plain geometry.
for name in textured sphere; do
  "$pmenc" -q "$repo/samples/$name.obj" -o "$work/$name.pm"
  "$pmdec" -q "$work/$name.pm" -o "$work/${name}_full.glb"
  "$pmdec" -q "$work/$name.pm" --ratio 0.5 -o "$work/${name}_half.gltf"
  "$pmdec" -q "$work/$name.pm" --lods 100%,50%,25%,12.5% -o "$work/${name}_chain.glb" --json > "$work/${name}_chain.json"
  "$pmdec" -q "$work/$name.pm" --lods 100%,50%,25%,12.5% -o "$work/${name}_chain.gltf"
  "$pmdec" -q "$work/$name.pm" --lods 100%,50%,25%,12.5% --quantize -o "$work/${name}_quantized.glb" --json > "$work/${name}_quantized.json"
done
cd "$here"
node validate.mjs "$work"/*.glb "$work"/*.gltf
status=0
for chain in "$work"/*_chain.glb "$work"/*_quantized.glb; do
  expected=$(node -e 'const r = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
                      console.log(JSON.stringify(r.outputs.map((o) => o.faces)))' "${chain%.glb}.json")
  loaded=$(node three_load.mjs "$chain")
  echo "$(basename "$chain"): pmdec reported $expected faces; three.js loaded $loaded"
  levels=$(node -e 'console.log(JSON.stringify(JSON.parse(process.argv[1]).levels))' "$loaded")
  scene=$(node -e 'console.log(JSON.parse(process.argv[1]).scene)' "$loaded")
  finest=$(node -e 'console.log(JSON.parse(process.argv[1])[0])' "$expected")
  if [[ "$levels" != "$expected" || "$scene" != "$finest" ]]; then
    echo "  MISMATCH" >&2
    status=1
  fi
done
exit $status
