# Encodes a mesh, writes 4 levels of detail, prints how far each is from the input.
# Usage: python3 levels.py MESH (OBJ, PLY, OFF or STL); the levels go to the current folder.
import pathlib
import sys

import pmesh

path = sys.argv[1]
mesh = pmesh.read(path)  # numpy arrays: mesh.positions (n, 3) float32, mesh.faces (m, 3) uint32
pm = pmesh.encode(mesh)  # every level at once; texture coordinates, normals, materials kept
ratios = [1.0, 0.25, 0.05, 0.01]
for ratio, level in zip(ratios, pm.levels(ratio=ratios)):  # one walk over the splits
    out = f"{pathlib.Path(path).stem}_{ratio:g}.obj"
    pmesh.write(out, level)
    d = pmesh.surface_distance(mesh, level)  # measured both ways, as pmdec --compare does
    print(f"{out}: {len(level.faces)} faces, Hausdorff {d.hausdorff_percent:.3f}% "
          f"and RMS {d.rms_percent:.4f}% of the bounding-box diagonal")
