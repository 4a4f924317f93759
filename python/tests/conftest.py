"""What the pmesh tests share: the tools they are checked against (pmenc, pmdec, as CTest
passes them), the meshes (the project's samples; the shared meshes, skipped loudly when
absent) and the way pmdec writes a level (faces grouped by material)."""

import json
import os
import pathlib
import subprocess
import sys

import pytest

import pmesh

HERE = pathlib.Path(__file__).resolve().parent
SOURCE = HERE.parent.parent
SAMPLES = pathlib.Path(os.environ.get("PM_SAMPLES_DIR", SOURCE / "samples"))
SHARED = pathlib.Path(os.environ.get("PM_SHARED_MESHES_DIR", SOURCE.parent / "shared" / "meshes"))
PMENC = os.environ.get("PM_PMENC", str(SOURCE / "build" / "apps" / "pmenc"))
PMDEC = os.environ.get("PM_PMDEC", str(SOURCE / "build" / "apps" / "pmdec"))
README = pathlib.Path(os.environ.get("PM_README", SOURCE / "README.md"))

# Samples that cover the library's cases: closed, open with holes, sharp features, welds,
# carried faces and loose vertices (nonmanifold), every OBJ attribute (textured).
SAMPLE_NAMES = ["sphere.obj", "terrain_holes.obj", "block_features.obj", "nonmanifold.obj", "textured.obj"]
# Shared meshes small enough to encode in a second or two: texture seams (spot), a pinched
# vertex (cow), sharp CAD features (fandisk).
SHARED_NAMES = ["spot.obj", "cow.obj", "fandisk.obj"]


def sample(name):
    return SAMPLES / name


def shared(name):
    """A shared mesh's path, or a skip that says why (pytest -rs lists it)."""
    path = SHARED / name
    if not path.exists():
        print(f"NOTE: {path} not found: skipping the tests on it", file=sys.stderr)
        pytest.skip(f"shared mesh {path} not found")
    return path


def mesh_path(name):
    return sample(name) if name in SAMPLE_NAMES else shared(name)


def run(*command):
    """Runs a tool; its stdout. A failure fails the test with the tool's stderr."""
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True)
    assert result.returncode == 0, f"{command}: exit {result.returncode}: {result.stderr}"
    return result.stdout


def pmenc(source, output, *options):
    run(PMENC, source, "-o", output, "-q", *options)
    return output


def pmdec(pm_path, output, *options):
    """pmdec's output file's bytes."""
    return pmdec_report(pm_path, output, *options)[0]


def pmdec_report(pm_path, output, *options):
    """pmdec's output file's bytes and its --json report."""
    report = json.loads(run(PMDEC, pm_path, "-o", output, "-q", "--json", *options))
    return pathlib.Path(output).read_bytes(), report


def written(mesh, path):
    """The bytes pmesh writes for a level as pmdec writes it (faces grouped by material)."""
    pmesh.write(path, pmesh.group_faces_by_material(mesh))
    return pathlib.Path(path).read_bytes()


@pytest.fixture(scope="session")
def encoded(tmp_path_factory):
    """name -> (pmenc's .pm path, the mesh as pmesh read it): each mesh encoded once."""
    cache = {}
    folder = tmp_path_factory.mktemp("pmenc")

    def get(name):
        if name not in cache:
            source = mesh_path(name)
            cache[name] = (pmenc(source, folder / (pathlib.Path(name).stem + ".pm")), pmesh.read(source))
        return cache[name]

    return get
