#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and builds tests/consumer against it, with
# -Werror=unused-result; then checks that a program ignoring a pm::Status does not build.
# Usage: run.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$source/tests/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/consumer"
"$work/consumer/render_loop"
if cmake --build "$work/consumer" --target ignored_status >"$work/ignored.log" 2>&1; then
  echo "ignored_status.cpp built: an ignored pm::Status is not an error" >&2
  exit 1
fi
if ! grep -q "unused-result\|nodiscard\|ignoring return value" "$work/ignored.log"; then
  echo "ignored_status.cpp failed to build for another reason:" >&2
  cat "$work/ignored.log" >&2
  exit 1
fi
echo "an ignored pm::Status does not build (-Werror=unused-result)"
