#!/usr/bin/python3
"""vtkDecimatePro as a peer of the quality benchmark (quality_bench.cpp runs this script).

Usage: vtk_decimate.py IN.obj TARGET_FACES OUT.obj

Reads a triangle mesh from an OBJ file of v and f lines, decimates it with vtkDecimatePro
(Schroeder, Zarge and Lorensen 1992, "Decimation of triangle meshes", the algorithm pmenc's
schroeder metric also follows) towards TARGET_FACES faces with the topology preserved, writes
the result as an OBJ of v and f lines, and prints the seconds spent in the decimation's
Update() alone (not reading or writing) on standard output. Errors go to standard error, with
exit status 1; a missing VTK is exit status 3, so the caller can say "n/a" rather than fail.

Settings (see README.md): PreserveTopologyOn, SplittingOff, BoundaryVertexDeletionOn,
TargetReduction = 1 - TARGET_FACES / input faces; everything else at VTK's defaults
(FeatureAngle 15, MaximumError unbounded, AccumulateError off, Degree 25, PreSplitMesh off).
"""

import sys
import time

try:
    from vtkmodules.vtkFiltersCore import vtkDecimatePro
    from vtkmodules.vtkIOGeometry import vtkOBJReader
except ImportError as error:
    print(f"vtk_decimate.py: VTK is not available ({error})", file=sys.stderr)
    sys.exit(3)


def write_obj(poly_data, path):
    """Writes points and triangles only: no normals or texture coordinates, so the reader on
    the other side sees exactly the surface VTK produced."""
    points = poly_data.GetPoints()
    polys = poly_data.GetPolys()
    lines = []
    for i in range(poly_data.GetNumberOfPoints()):
        x, y, z = points.GetPoint(i)
        lines.append(f"v {x!r} {y!r} {z!r}\n")
    # The cell array holds, per cell, a count followed by that many point ids.
    ids = polys.GetData()
    position = 0
    total = ids.GetNumberOfValues()
    while position < total:
        count = int(ids.GetValue(position))
        corners = [int(ids.GetValue(position + 1 + k)) + 1 for k in range(count)]
        lines.append("f " + " ".join(map(str, corners)) + "\n")
        position += 1 + count
    with open(path, "w", encoding="ascii") as out:
        out.writelines(lines)


def main(argv):
    if len(argv) != 4:
        print("usage: vtk_decimate.py IN.obj TARGET_FACES OUT.obj", file=sys.stderr)
        return 2
    input_path, target_faces, output_path = argv[1], int(argv[2]), argv[3]

    reader = vtkOBJReader()
    reader.SetFileName(input_path)
    reader.Update()
    mesh = reader.GetOutput()
    input_faces = mesh.GetNumberOfPolys()
    if input_faces == 0:
        print(f"vtk_decimate.py: {input_path}: no faces", file=sys.stderr)
        return 1

    decimate = vtkDecimatePro()
    # SetInputData, not a pipeline connection: Update() then runs the decimation alone.
    decimate.SetInputData(mesh)
    decimate.SetTargetReduction(max(0.0, 1.0 - target_faces / input_faces))
    decimate.PreserveTopologyOn()
    decimate.SplittingOff()
    decimate.BoundaryVertexDeletionOn()

    start = time.perf_counter()
    decimate.Update()
    seconds = time.perf_counter() - start

    write_obj(decimate.GetOutput(), output_path)
    print(f"{seconds:.6f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
