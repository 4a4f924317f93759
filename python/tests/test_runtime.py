"""ProgressiveMesh.runtime: levels changed in place (Hoppe 1998), views of the runtime's own
buffers, and geomorphs as pmdec --morph writes them."""

import numpy as np
import pytest

import pmesh
from conftest import pmdec, written


def corners(positions, faces):
    """Each face's three corner positions, (m, 3, 3): meshes compared face by face, whatever
    their vertex numbering."""
    return np.asarray(positions)[np.asarray(faces)]


def face_set(values, faces):
    """The faces' corner values, one row per face, rows sorted: the same faces in any order
    (the runtime lists the faces a level carries first; extract_level last)."""
    rows = corners(values, faces).reshape(len(faces), -1)
    return rows[np.lexsort(rows.T[::-1])]


@pytest.mark.parametrize("name", ["textured.obj", "nonmanifold.obj"])
def test_set_faces_gives_the_levels_faces(encoded, name):
    pm_path, mesh = encoded(name)
    for pm in (pmesh.load(pm_path), pmesh.encode(mesh)):
        runtime = pm.runtime()
        assert runtime.level == 0 and runtime.max_level == len(pm) - 1
        for n in (500, 60, 2000, 10**9, 0):  # finer and coarser, in place
            level = runtime.set_faces(n)
            assert level == runtime.level == pm.level_for(faces=n)
            expected = pm.level(level)
            assert runtime.face_count == len(expected.faces)
            assert runtime.vertex_count == len(expected.positions)
            # The active faces as wedge indices give the level's faces, corner by corner.
            np.testing.assert_array_equal(face_set(runtime.positions, runtime.indices),
                                          face_set(expected.positions, expected.faces))
            as_mesh = runtime.to_mesh()
            np.testing.assert_array_equal(face_set(as_mesh.positions, as_mesh.faces),
                                          face_set(expected.positions, expected.faces))
            if expected.uvs is not None:
                np.testing.assert_array_equal(corners(as_mesh.uvs, as_mesh.uv_indices),
                                              corners(expected.uvs, expected.uv_indices))


def test_other_setters_follow_level_for(encoded):
    pm = pmesh.load(encoded("sphere.obj")[0])
    runtime = pm.runtime()
    assert runtime.set_vertices(700) == pm.level_for(vertices=700)
    assert runtime.set_error(0.01) == pm.level_for(error=0.01, estimate=True)
    assert runtime.set_level(42) == 42 == runtime.level
    with pytest.raises(pmesh.Error):
        runtime.set_level(len(pm))


def test_views_are_the_runtimes_buffers(encoded):
    runtime = pmesh.load(encoded("textured.obj")[0]).runtime()
    runtime.set_faces(1000)
    indices = runtime.indices
    assert not indices.flags.writeable and not indices.flags.owndata
    assert not runtime.positions.flags.writeable
    assert runtime.uvs.shape == (runtime.wedge_count, 2) and runtime.colors.shape == (runtime.wedge_count, 3)
    before = indices.copy()
    runtime.set_faces(3000)  # the prefix is rewritten in place: the old view sees it
    assert np.shares_memory(indices, runtime.indices)
    assert not np.array_equal(indices, before)
    del runtime  # the views keep the runtime alive
    assert indices.sum() >= 0


@pytest.mark.parametrize("name, ends, alphas", [
    ("textured.obj", ("300", "2000"), ["0", "0.25", "1"]),
    ("terrain_holes.obj", ("5%", "50%"), ["0.5"]),
])
def test_geomorph_gives_pmdecs_morph(encoded, tmp_path, name, ends, alphas):
    pm_path, mesh = encoded(name)
    def level(end):
        return pm.level_for(ratio=float(end[:-1]) / 100) if end.endswith("%") else pm.level_for(faces=int(end))
    for pm in (pmesh.load(pm_path), pmesh.encode(mesh)):
        runtime = pm.runtime()
        a, b = level(ends[0]), level(ends[1])
        morph = runtime.geomorph(a, b)
        assert runtime.level == b and morph.levels == (a, b)
        for alpha in alphas:
            expected = pmdec(pm_path, tmp_path / "pmdec.obj", "--morph", f"{ends[0]}:{ends[1]}:{alpha}")
            assert written(morph(float(alpha)), tmp_path / "pmesh.obj") == expected, (pm, alpha)


def test_geomorph_ends_are_the_levels_exactly(encoded):
    pm = pmesh.load(encoded("textured.obj")[0])
    runtime = pm.runtime()
    morph = runtime.geomorph(100, 900)
    positions, uvs, normals, colors = morph.evaluate(1.0)
    np.testing.assert_array_equal(positions, runtime.positions)  # level 900's own wedges
    np.testing.assert_array_equal(uvs, runtime.uvs)
    start = morph(0.0)
    level_a = pm.level(100)
    # At alpha 0, level a's surface: the faces b adds have no area, the others are a's.
    start_corners = corners(start.positions, start.faces)
    area = np.linalg.norm(np.cross(start_corners[:, 1] - start_corners[:, 0],
                                   start_corners[:, 2] - start_corners[:, 0]), axis=1)
    assert np.count_nonzero(area) == len(level_a.faces)
    assert morph.indices.shape == (runtime.face_count, 3) and morph.wedge_count == runtime.wedge_count
    with pytest.raises(pmesh.Error):
        morph(1.5)
    with pytest.raises(pmesh.Error):
        runtime.geomorph(10, 5)
