"""surface_distance: the numbers pmdec --compare prints, to the last bit."""

import json

import pytest

import pmesh
from conftest import PMDEC, mesh_path, run


@pytest.mark.parametrize("name, ratio", [("sphere.obj", "0.1"), ("textured.obj", "0.5"), ("spot.obj", "0.2")])
def test_surface_distance_is_pmdecs_compare(encoded, tmp_path, name, ratio):
    pm_path, original = encoded(name)
    level = pmesh.load(pm_path).level(ratio=float(ratio))
    d = pmesh.surface_distance(original, level)
    expected = json.loads(run(PMDEC, pm_path, "--ratio", ratio, "--compare", mesh_path(name), "--json", "-q"))
    # %.17g in pmdec's JSON gives back every bit of a double.
    assert (d.hausdorff, d.rms, d.diagonal, d.samples, d.faces) == (
        expected["hausdorff"], expected["rms"], expected["diagonal"], expected["samples"], expected["faces"])
    assert d.hausdorff_percent == expected["hausdorff_percent"] and d.rms_percent == expected["rms_percent"]
    line = run(PMDEC, pm_path, "--ratio", ratio, "--compare", mesh_path(name), "-q")
    assert str(d) == line.rstrip("\n")


def test_distance_is_both_ways_and_reproducible(encoded):
    _, original = encoded("sphere.obj")
    coarse = pmesh.encode(original).level(faces=200)
    d = pmesh.surface_distance(original, coarse)
    assert d.hausdorff == max(d.forward_max, d.backward_max) > 0
    assert d.rms > 0 and d.samples > 0
    same = pmesh.surface_distance(original, coarse, threads=1)
    assert (same.hausdorff, same.rms) == (d.hausdorff, d.rms)  # whatever the threads
    other_seed = pmesh.surface_distance(original, coarse, seed=7)
    assert other_seed.rms != d.rms
    assert pmesh.surface_distance(original, original).hausdorff == 0


def test_distance_arguments_are_checked(encoded):
    _, original = encoded("sphere.obj")
    with pytest.raises(pmesh.Error) as error:
        pmesh.surface_distance(original, original, samples_per_face=0.5)
    assert error.value.code == "invalid-argument"
