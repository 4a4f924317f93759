#!/usr/bin/env python3
"""pmesh against the C++ library on one mesh (issue 30's goal: within 1.1 times the C++ time
on nefertiti, no hidden copies): pmesh.encode of the mesh's arrays against pm::encode, and
ProgressiveMesh.level(ratio=R) against pm::extract_level. Runs alternate between the two
(pm_bench_python_peer, then Python, RUNS times) so that the machine's load falls on both
alike; each time is the median of its runs (a level: of 21 extractions a run). Prints a
markdown table with the machine, the date and the load average.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/bench.py [--mesh M] [--runs N]
"""

import argparse
import datetime
import os
import pathlib
import platform
import statistics
import subprocess
import time

import pmesh

SOURCE = pathlib.Path(__file__).resolve().parent.parent.parent


def machine():
    model = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
                 platform.processor())
    return f"{model}, {os.cpu_count()} cores, Python {platform.python_version()}, numpy via pmesh {pmesh.__version__}"


def commit():
    try:
        return subprocess.run(["git", "-C", SOURCE, "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def python_run(mesh, ratio, extractions):
    start = time.perf_counter()
    pm = pmesh.encode(mesh)
    encode = time.perf_counter() - start
    times = []
    for _ in range(extractions):
        start = time.perf_counter()
        level = pm.level(ratio=ratio)
        times.append(time.perf_counter() - start)
    return encode, statistics.median(times), len(level.faces)


def cpp_run(peer, path, ratio, extractions):
    out = subprocess.run([peer, path, str(ratio), str(extractions)], capture_output=True, text=True, check=True).stdout
    values = dict(line.split(" ", 1) for line in out.splitlines())
    level, faces = values["level"].split()
    return float(values["encode"]), float(level), int(faces)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mesh", default=str(SOURCE.parent / "shared" / "meshes" / "nefertiti.obj"))
    parser.add_argument("--peer", default=str(SOURCE / "build" / "python" / "pm_bench_python_peer"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--ratio", type=float, default=0.1)
    args = parser.parse_args()
    extractions = 21
    # The arrays as a numpy user has them (new arrays, not the library's views of a mesh it
    # read): encode() checks them and hands them to the library, copy included if it makes one.
    read = pmesh.read(args.mesh)
    attributes = ("uvs", "uv_indices", "normals", "normal_indices", "colors", "face_materials")
    mesh = pmesh.Mesh(read.positions.copy(), read.faces.copy(),
                      **{name: getattr(read, name).copy() for name in attributes if getattr(read, name) is not None},
                      material_names=list(read.material_names), material_libraries=list(read.material_libraries))
    load_before = os.getloadavg()[0]
    cpp, python = [], []
    for _ in range(args.runs):
        cpp.append(cpp_run(args.peer, args.mesh, args.ratio, extractions))
        python.append(python_run(mesh, args.ratio, extractions))
    assert {r[2] for r in cpp} == {r[2] for r in python}, (cpp, python)  # the same level
    load_after = os.getloadavg()[0]
    faces = len(mesh.faces)
    rows = [(f"encode ({faces:,} faces)", 0), (f"level at ratio {args.ratio:g} ({cpp[0][2]:,} faces)", 1)]
    print(f"- machine: {machine()}")
    print(f"- date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, commit {commit()}")
    print(f"- load average (1 min): {load_before:.2f} before, {load_after:.2f} after")
    print(f"- mesh: {args.mesh}; {args.runs} runs each, alternating; medians")
    print()
    print("| step | C++ (s) | Python (s) | Python / C++ | goal |")
    print("|---|---|---|---|---|")
    for name, k in rows:
        c = statistics.median(r[k] for r in cpp)
        p = statistics.median(r[k] for r in python)
        print(f"| {name} | {c:.4f} | {p:.4f} | {p / c:.3f} | {'holds' if p / c <= 1.1 else 'does not hold'} (1.1) |")


if __name__ == "__main__":
    main()
