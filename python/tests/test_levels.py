"""ProgressiveMesh.level, level_for and levels: the levels pmdec writes, bit for bit, chosen
by the same rules, from pmenc's file and from pmesh.encode alike."""

import numpy as np
import pytest

import pmesh
from conftest import PMDEC, SAMPLE_NAMES, SHARED_NAMES, pmdec_report, run, written

# Which level each option picks: the same pmdec options and pmesh keywords.
SELECTIONS = [
    (["--faces", "1000"], dict(faces=1000)),
    (["--faces", "1"], dict(faces=1)),  # below the base mesh: the base mesh
    (["--vertices", "300"], dict(vertices=300)),
    (["--ratio", "0.25"], dict(ratio=0.25)),
    # Full detail, the input exactly, loose vertices included (nonmanifold.obj has 2),
    # whether asked for by ratio 1 or by no level option.
    (["--ratio", "1"], dict(ratio=1.0)),
    ([], dict(ratio=1.0)),
    (["--error", "0.02", "--absolute", "--estimate"], dict(error=0.02, estimate=True)),
]


@pytest.mark.parametrize("name", SAMPLE_NAMES + SHARED_NAMES)
def test_each_selection_gives_pmdecs_level(encoded, tmp_path, name):
    pm_path, mesh = encoded(name)
    loaded = pmesh.load(pm_path)
    made = pmesh.encode(mesh)
    for options, keywords in SELECTIONS:
        expected, report = pmdec_report(pm_path, tmp_path / "pmdec.obj", *options)
        level = report["outputs"][0]["level"]
        for pm in (loaded, made):
            assert pm.level_for(**keywords) == level, (options, pm)
            assert written(pm.level(**keywords), tmp_path / "pmesh.obj") == expected, options
            assert written(pm.level(level), tmp_path / "pmesh.obj") == expected, options


def test_measured_error_selects_pmdecs_level(encoded, tmp_path):
    pm_path, _ = encoded("sphere.obj")
    pm = pmesh.load(pm_path)
    bound = 0.01  # model units: pmdec --error 0.01 --absolute measures levels as pmesh does
    options = ["--error", str(bound), "--absolute"]
    expected, report = pmdec_report(pm_path, tmp_path / "pmdec.ply", *options)
    level = pm.level_for(error=bound)
    assert level == report["outputs"][0]["level"]
    assert written(pm.level(error=bound), tmp_path / "pmesh.ply") == expected
    # The level measures within the bound (the recorded errors alone would pick another).
    assert pmesh.surface_distance(pm.level(len(pm) - 1), pm.level(level)).hausdorff <= bound


@pytest.mark.parametrize("name", ["textured.obj", "terrain_holes.obj"])
def test_levels_in_one_walk_are_pmdecs_lods(encoded, tmp_path, name):
    pm_path, _ = encoded(name)
    pm = pmesh.load(pm_path)
    run_dir = tmp_path / "lods"
    run(PMDEC, pm_path, "-q", "--lods", "100%,25%,5%,1000", "--out-dir", run_dir, "-o", "{lod}.obj")
    by_ratio = pm.levels(ratio=[1.0, 0.25, 0.05])
    by_faces = pm.levels(faces=[1000])
    for mesh, label in zip(by_ratio + by_faces, ["100", "25", "5", "1000"]):
        assert written(mesh, tmp_path / "pmesh.obj") == (run_dir / f"{label}.obj").read_bytes()
    # In the order asked, repeats included; the same meshes as one at a time.
    indices = [pm.level_for(ratio=0.05), 0, pm.level_for(ratio=0.05), len(pm) - 1]
    for mesh, level in zip(pm.levels(indices), indices):
        one = pm.level(level)
        np.testing.assert_array_equal(mesh.positions, one.positions)
        np.testing.assert_array_equal(mesh.faces, one.faces)
        np.testing.assert_array_equal(mesh.uv_indices, one.uv_indices)
    assert [len(m.faces) for m in pm.levels(vertices=[100, 200])] == \
        [pm.faces_at(pm.level_for(vertices=100)), pm.faces_at(pm.level_for(vertices=200))]


def test_counts_and_errors_per_level_follow_the_records(encoded):
    pm_path, _ = encoded("sphere.obj")
    pm = pmesh.load(pm_path)
    splits = pm.splits()
    assert pm.error_at(len(pm) - 1) == 0
    assert [pm.error_at(k) for k in (0, 10, 100)] == [splits["error"][0], splits["error"][10], splits["error"][100]]
    for k in (0, 10, len(pm) - 1):
        mesh = pm.level(k)
        assert (pm.faces_at(k), pm.vertices_at(k)) == (len(mesh.faces), len(mesh.positions))
    assert pm.full_faces == pm.faces_at(len(pm) - 1) == 5120


def test_level_arguments_are_checked(encoded):
    pm = pmesh.load(encoded("sphere.obj")[0])
    for call in (lambda: pm.level(), lambda: pm.level(3, faces=10), lambda: pm.level(len(pm)),
                 lambda: pm.level(-1), lambda: pm.level(ratio=1.5), lambda: pm.level(error=-1.0),
                 lambda: pm.level(faces=10, estimate=True), lambda: pm.levels(),
                 lambda: pm.levels([0], faces=[10]), lambda: pm.error_at(len(pm))):
        with pytest.raises(pmesh.Error) as error:
            call()
        assert error.value.code == "invalid-argument"
