#!/usr/bin/env bash
# Builds pm::codec alone, with OpenMesh and CLI11 hidden from CMake, installs it, builds
# decode_levels against the install and decodes a golden stream with it; the face count must
# be the one pmdec reports for the same file.
# Usage: run.sh SOURCE_DIR PMDEC
set -euo pipefail
source=$1 pmdec=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake -S "$source" -B "$work/codec" -DPM_CODEC_ONLY=ON -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenMesh=ON -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON \
  -Wno-dev --no-warn-unused-cli >/dev/null
cmake --build "$work/codec" -j2 >/dev/null
if [[ -e "$work/codec/lib/libpm.a" || -e "$work/codec/apps" ]]; then
  echo "a codec-only build built more than pm::codec" >&2
  exit 1
fi
cmake --install "$work/codec" --prefix "$work/prefix" >/dev/null
cmake -S "$source/tests/codec_only" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/consumer" >/dev/null
golden="$source/tests/data/golden/generated-v2.4.pm"
read -r faces vertices splits < <("$work/consumer/decode_levels" "$golden")
expected=$("$pmdec" "$golden" --info | sed -n 's/^full detail: *[0-9]* vertices, \([0-9]*\) faces.*/\1/p')
echo "decode_levels: $faces faces, $vertices vertices, $splits splits; pmdec --info: $expected faces"
[[ -n "$expected" && "$faces" == "$expected" ]]
