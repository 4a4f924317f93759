#!/usr/bin/env python3
"""pmesh against the C++ library on one mesh (issue 30's goal: within 1.1 times the C++ time
on nefertiti, no hidden copies): pmesh.encode of the mesh's arrays against pm::encode, and
ProgressiveMesh.level(ratio=R) against pm::extract_level, for each ratio. Runs alternate between the two
(pm_bench_python_peer, then Python, RUNS times) so that the machine's load falls on both
alike; each time is the median of its runs. A level's time in a run is the median of 21
samples, each the mean of --calls calls timed together (50: a call of half a millisecond is
not timed alone, at the mercy of the clock, the interpreter and the scheduler). Prints a
markdown table with the machine, the date and the load average.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/bench.py [--mesh M] [--runs N] [--calls N]
        [--ratios 0.1,1]
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


def python_run(mesh, ratios, samples, calls):
    """Encode seconds, then (median seconds a call, faces) per ratio."""
    start = time.perf_counter()
    pm = pmesh.encode(mesh)
    results = [time.perf_counter() - start]
    for ratio in ratios:
        times = []
        for _ in range(samples):
            start = time.perf_counter()
            for _ in range(calls):
                level = pm.level(ratio=ratio)
            times.append((time.perf_counter() - start) / calls)
        results.append((statistics.median(times), len(level.faces)))
    return results


def cpp_run(peer, path, ratios, samples, calls):
    out = subprocess.run([peer, path, str(samples), str(calls), *map(str, ratios)], capture_output=True,
                         text=True, check=True).stdout.splitlines()
    results = [float(out[0].split()[1])]
    for line in out[1:]:
        _, _, seconds, faces = line.split()
        results.append((float(seconds), int(faces)))
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mesh", default=str(SOURCE.parent / "shared" / "meshes" / "nefertiti.obj"))
    parser.add_argument("--peer", default=str(SOURCE / "build" / "python" / "pm_bench_python_peer"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--calls", type=int, default=50, help="level calls timed together in a sample")
    parser.add_argument("--ratios", default="0.1,1", help="levels to extract, as ratios of the full faces")
    args = parser.parse_args()
    samples = 21
    # The arrays as a numpy user has them (new arrays, not the library's views of a mesh it
    # read): encode() checks them and hands them to the library, copy included if it makes one.
    read = pmesh.read(args.mesh)
    attributes = ("uvs", "uv_indices", "normals", "normal_indices", "colors", "face_materials")
    mesh = pmesh.Mesh(read.positions.copy(), read.faces.copy(),
                      **{name: getattr(read, name).copy() for name in attributes if getattr(read, name) is not None},
                      material_names=list(read.material_names), material_libraries=list(read.material_libraries))
    ratios = [float(r) for r in args.ratios.split(",")]
    load_before = os.getloadavg()[0]
    cpp, python = [], []
    for _ in range(args.runs):
        cpp.append(cpp_run(args.peer, args.mesh, ratios, samples, args.calls))
        python.append(python_run(mesh, ratios, samples, args.calls))
    load_after = os.getloadavg()[0]
    rows = [(f"encode ({len(mesh.faces):,} faces)", [r[0] for r in cpp], [r[0] for r in python])]
    for k, ratio in enumerate(ratios, 1):
        faces = {r[k][1] for r in cpp + python}
        assert len(faces) == 1, (cpp, python)  # the same level on both sides
        rows.append((f"level at ratio {ratio:g} ({faces.pop():,} faces)", [r[k][0] for r in cpp],
                     [r[k][0] for r in python]))
    print(f"- machine: {machine()}")
    print(f"- date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, commit {commit()}")
    print(f"- load average (1 min): {load_before:.2f} before, {load_after:.2f} after")
    print(f"- mesh: {args.mesh}; {args.runs} runs each, alternating; medians (a level: of {samples} samples "
          f"a run, each the mean of {args.calls} calls; both sides choose the level by ratio, then extract it)")
    print()
    print("| step | C++ (s) | Python (s) | Python / C++ | goal |")
    print("|---|---|---|---|---|")
    for name, cpp_times, python_times in rows:
        c, p = statistics.median(cpp_times), statistics.median(python_times)
        print(f"| {name} | {c:.4g} | {p:.4g} | {p / c:.3f} | {'holds' if p / c <= 1.1 else 'does not hold'} (1.1) |")


if __name__ == "__main__":
    main()
