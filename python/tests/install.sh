#!/usr/bin/env bash
# cmake --install puts pmesh in the interpreter's site directory under the prefix, and it
# imports from there with nothing else on the path (the build tree is not).
# Usage: install.sh BUILD_DIR PYTHON SITE_DIR_RELATIVE_TO_PREFIX
set -euo pipefail
build=$1 python=$2 site=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
module=$(ls "$work/prefix/$site"/pmesh*.so)
cd "$work"
PYTHONPATH="$work/prefix/$site" "$python" -c '
import sys, pmesh, numpy
assert pmesh.__file__ == sys.argv[1], (pmesh.__file__, sys.argv[1])
positions = numpy.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], numpy.float32)
faces = numpy.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], numpy.uint32)
pm = pmesh.encode(positions, faces)
assert len(pm) == pm.split_count + 1 and pm.level(len(pm) - 1).faces.shape == (4, 3)
print("installed pmesh", pmesh.__version__, "at", sys.argv[1])
' "$module"
