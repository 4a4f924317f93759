#!/usr/bin/env bash
# Writes the manifest that the SharedMeshStreams tests (test_shared_mesh_streams.cpp) check:
# the SHA-256 of pmenc's .pm of every shared mesh (*.obj, *.off, *.ply in MESHES, sorted),
# lossless with the default options and with --quantize 14. Run it when a change of the
# encoder is meant to change the bytes (and say so in the commit message):
#
#   tests/shared_mesh_streams.sh build/apps/pmenc ../shared/meshes > tests/data/shared_mesh_streams.sha256
#
# COMMIT (default: this checkout's HEAD) names the commit pmenc was built from in the header.
# Usage: shared_mesh_streams.sh PMENC MESHES [COMMIT]
set -euo pipefail
if [[ $# -lt 2 || $# -gt 3 ]]; then
  echo "usage: $0 PMENC MESHES [COMMIT]" >&2
  exit 2
fi
pmenc=$1 meshes=$2
commit=${3:-$(git -C "$(dirname "${BASH_SOURCE[0]}")" rev-parse --short HEAD)}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat <<HEADER
# SHA-256 of pmenc's .pm of each shared mesh (../shared/meshes), as the
# SharedMeshStreams tests (tests/test_shared_mesh_streams.cpp) re-encode them:
# "HASH  MESH [OPTIONS]" for \`pmenc MESH [OPTIONS] -o X.pm\`, lossless (default options)
# and --quantize 14. Made by pmenc built from commit $commit. When an encoder change is
# meant to change the bytes, regenerate it (and say so in the commit message):
#   tests/shared_mesh_streams.sh build/apps/pmenc ../shared/meshes > tests/data/shared_mesh_streams.sha256
HEADER
mapfile -t names < <(cd "$meshes" && LC_ALL=C ls -1 -- *.obj *.off *.ply 2>/dev/null | LC_ALL=C sort)
if [[ ${#names[@]} -eq 0 ]]; then
  echo "$0: no meshes in $meshes" >&2
  exit 1
fi
for name in "${names[@]}"; do
  for options in "" "--quantize 14"; do
    # shellcheck disable=SC2086  # the options are words
    "$pmenc" "$meshes/$name" $options -o "$work/x.pm" >/dev/null
    hash=$(sha256sum "$work/x.pm" | cut -d' ' -f1)
    echo "$hash  $name${options:+ $options}"
  done
done
