"""splits() and vertex_parents(): the records a user builds a hierarchy from. Replayed in numpy
by their documented meaning, they give the levels pmdec writes."""

import numpy as np
import pytest

import pmesh
from conftest import pmdec

NO = pmesh.NO_VERTEX


def replay(pm, level):
    """The faces of a level as vertex ids, by applying the first `level` splits to the base
    mesh as splits() documents them (Hoppe 1996, §3)."""
    faces = [list(f) for f in pm.base_faces]
    splits, moved = pm.splits(), pm.moved_faces
    for i in range(level):
        s = splits[i]
        v, u = pm.base_vertex_count + i, s["u"]
        for f in moved[s["moved_begin"]: s["moved_begin"] + s["moved_count"]]:
            faces[f] = [v if x == u else x for x in faces[f]]
        if s["vl"] != NO:
            faces.append([v, u, s["vl"]])
        if s["vr"] != NO:
            faces.append([u, v, s["vr"]])
    return np.array(faces, np.uint32)


def corners(positions, faces):
    return np.asarray(positions)[np.asarray(faces)]


@pytest.mark.parametrize("name", ["sphere.obj", "terrain_holes.obj"])
def test_replaying_the_splits_gives_pmdecs_levels(encoded, tmp_path, name):
    pm_path, _ = encoded(name)
    pm = pmesh.load(pm_path)
    for faces in (300, 2000):
        level = pm.level_for(faces=faces)
        pmdec(pm_path, tmp_path / "pmdec.obj", "--faces", str(faces))
        expected = pmesh.read(tmp_path / "pmdec.obj")
        np.testing.assert_array_equal(corners(pm.positions, replay(pm, level)),
                                      corners(expected.positions, expected.faces))


def test_splits_are_a_view_of_the_records(encoded):
    pm = pmesh.load(encoded("sphere.obj")[0])
    splits = pm.splits()
    assert splits.dtype.names == ("u", "vl", "vr", "error", "moved_begin", "moved_count")
    assert splits.dtype.itemsize == 24 and len(splits) == pm.split_count
    assert np.shares_memory(splits, pm.splits()) and not splits.flags.writeable
    assert np.all(np.diff(splits["error"]) <= 0)  # non-increasing bounds, coarse to fine
    assert splits["moved_begin"][-1] + splits["moved_count"][-1] == len(pm.moved_faces)


def test_vertex_parents_are_the_collapse_tree(encoded):
    pm = pmesh.load(encoded("sphere.obj")[0])
    parents = pm.vertex_parents()
    base = pm.base_vertex_count
    assert len(parents) == pm.vertex_count
    assert np.all(parents["parent"][:base] == NO) and np.all(parents["level"][:base] == 0)
    np.testing.assert_array_equal(parents["parent"][base:], pm.splits()["u"])
    np.testing.assert_array_equal(parents["level"][base:], np.arange(1, pm.split_count + 1))
    # A level is full detail with each vertex replaced by its ancestor in that level (half-edge
    # collapses keep u), the faces that collapse away dropped.
    full = replay(pm, pm.split_count)
    for level in (0, 50, 1000):
        ancestor = np.arange(pm.vertex_count)
        for v in range(base + level, pm.vertex_count):
            ancestor[v] = ancestor[parents["parent"][v]]  # parents come first
        mapped = ancestor[full]
        kept = (mapped[:, 0] != mapped[:, 1]) & (mapped[:, 1] != mapped[:, 2]) & (mapped[:, 0] != mapped[:, 2])
        expected = replay(pm, level)

        def as_set(faces):
            rotated = [tuple(np.roll(f, -int(np.argmin(f)))) for f in faces]
            return sorted(rotated)

        assert as_set(mapped[kept]) == as_set(expected)
