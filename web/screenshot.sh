#!/usr/bin/env bash
# Regenerates web/images/viewer.png: the browser test (a 1.3M-face stream, throttled) in a build
# made by .ci/test or .ci/build --test. Usage: bash web/screenshot.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
ctest --test-dir "$build" -R '^Web\.(Build|browser)$' --output-on-failure
mkdir -p "$root/web/images"
cp "$build/web/work/viewer.png" "$root/web/images/viewer.png"
