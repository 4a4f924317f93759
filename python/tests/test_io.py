"""pmesh.read and pmesh.write: every format, the same bytes as pmdec writes, arrays that are
the library's own memory."""

import numpy as np
import pytest

import pmesh
from conftest import pmdec, sample, written

NA = pmesh.NO_ATTRIBUTE

# A tetrahedron with every OBJ attribute, some corners and faces without them.
TETRAHEDRON_OBJ = """mtllib shapes.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1 0.5 0.25 1
vt 0 0
vt 1 0
vt 0 1
vn 0 0 -1
usemtl red
f 1/1/1 3/3/1 2/2/1
f 1/1 2/2 4/3
usemtl blue
f 1 4 3
f 2 3 4
"""


def test_read_gives_every_obj_attribute_as_arrays(tmp_path):
    path = tmp_path / "tetrahedron.obj"
    path.write_text(TETRAHEDRON_OBJ)
    mesh = pmesh.read(path)
    assert mesh.positions.dtype == np.float32 and mesh.faces.dtype == np.uint32
    np.testing.assert_array_equal(mesh.positions, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    np.testing.assert_array_equal(mesh.faces, [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    np.testing.assert_array_equal(mesh.uvs, [[0, 0], [1, 0], [0, 1]])
    np.testing.assert_array_equal(mesh.uv_indices, [[0, 2, 1], [0, 1, 2], [NA] * 3, [NA] * 3])
    np.testing.assert_array_equal(mesh.normals, [[0, 0, -1]])
    np.testing.assert_array_equal(mesh.normal_indices, [[0, 0, 0], [NA] * 3, [NA] * 3, [NA] * 3])
    # Vertices without a colour are given opaque white (README, "Input and output formats").
    np.testing.assert_array_equal(mesh.colors, [[1, 1, 1], [1, 1, 1], [1, 1, 1], [0.5, 0.25, 1]])
    np.testing.assert_array_equal(mesh.face_materials, [0, 0, 1, 1])
    assert mesh.material_names == ["red", "blue"]
    assert mesh.material_libraries == ["shapes.mtl"]


def test_a_mesh_without_attributes_has_none(tmp_path):
    path = tmp_path / "triangle.off"
    path.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    mesh = pmesh.read(path)
    assert mesh.uvs is None and mesh.uv_indices is None and mesh.normals is None
    assert mesh.colors is None and mesh.face_materials is None and mesh.material_names == []
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2]])


@pytest.mark.parametrize("name", ["sphere.obj", "textured.obj", "nonmanifold.obj"])
@pytest.mark.parametrize("extension", ["obj", "ply", "off", "stl"])
def test_write_gives_pmdecs_bytes_and_read_gives_them_back(encoded, tmp_path, name, extension):
    pm_path, _ = encoded(name)
    expected = pmdec(pm_path, tmp_path / f"pmdec.{extension}", "--ratio", "0.3")
    level = pmesh.load(pm_path).level(ratio=0.3)
    assert written(level, tmp_path / f"pmesh.{extension}") == expected
    # Reading pmdec's file and writing it again changes nothing: read keeps what the format
    # holds. (STL is read through OpenMesh's reader, which drops faces with a repeated vertex.)
    if extension == "stl" and name == "nonmanifold.obj":
        return
    pmesh.write(tmp_path / f"again.{extension}", pmesh.read(tmp_path / f"pmdec.{extension}"))
    assert (tmp_path / f"again.{extension}").read_bytes() == expected


def test_format_given_by_name_overrides_the_extension(tmp_path):
    path = tmp_path / "mesh.txt"
    path.write_text(TETRAHEDRON_OBJ)
    assert pmesh.read(path, format="obj").faces.shape == (4, 3)
    pmesh.write(tmp_path / "out.bin", pmesh.read(path, format="obj"), format="stl")
    assert pmesh.read(tmp_path / "out.bin", format="stl").faces.shape == (4, 3)


def test_arrays_are_views_of_the_librarys_mesh(tmp_path):
    mesh = pmesh.read(sample("textured.obj"))
    for array in (mesh.positions, mesh.faces, mesh.uvs, mesh.uv_indices, mesh.normals, mesh.colors,
                  mesh.face_materials):
        assert not array.flags.owndata and type(array.base).__name__ == "PyCapsule"
    # Written in place, the library's own mesh changes: write() passes it back as it is.
    mesh.positions *= 2
    pmesh.write(tmp_path / "doubled.obj", mesh)
    np.testing.assert_array_equal(pmesh.read(tmp_path / "doubled.obj").positions, mesh.positions)


def test_a_mesh_made_of_new_arrays_is_written(tmp_path):
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    faces = np.array([[0, 1, 2]], np.uint32)
    pmesh.write(tmp_path / "t.ply", pmesh.Mesh(positions, faces))
    back = pmesh.read(tmp_path / "t.ply")
    np.testing.assert_array_equal(back.positions, positions)
    np.testing.assert_array_equal(back.faces, faces)


def test_strided_arrays_are_read_through_their_strides(tmp_path):
    wide = np.arange(24, dtype=np.float32).reshape(4, 6)
    positions = wide[:, ::2]  # every other column: not contiguous
    faces = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)[::-1]  # negative row stride
    pmesh.write(tmp_path / "s.obj", pmesh.Mesh(positions, faces))
    back = pmesh.read(tmp_path / "s.obj")
    np.testing.assert_array_equal(back.positions, positions)
    np.testing.assert_array_equal(back.faces, faces)


def test_read_errors_carry_the_library_code(tmp_path):
    with pytest.raises(pmesh.Error) as missing:
        pmesh.read(tmp_path / "missing.obj")
    assert missing.value.code == "io-error" and "missing.obj" in missing.value.message
    with pytest.raises(pmesh.Error) as unknown:
        pmesh.read(tmp_path / "mesh.xyz")
    assert unknown.value.code == "unsupported-format"
    (tmp_path / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(pmesh.Error) as bad:
        pmesh.read(tmp_path / "bad.obj")
    assert bad.value.code == "parse-error" and "bad.obj" in str(bad.value)
    (tmp_path / "empty.obj").write_text("# nothing\n")
    with pytest.raises(pmesh.Error) as empty:
        pmesh.read(tmp_path / "empty.obj")
    assert empty.value.code == "empty-mesh"


def test_a_failed_write_leaves_no_file(tmp_path):
    positions = np.zeros((3, 3), np.float32)
    bad = pmesh.Mesh(positions, np.array([[0, 1, 2]], np.uint32))
    bad.faces = np.array([[0, 1, 3]], np.uint32)  # out of range, set after construction
    with pytest.raises(pmesh.Error) as error:
        pmesh.write(tmp_path / "bad.obj", bad)
    assert error.value.code == "invalid-argument" and "faces" in error.value.message
    with pytest.raises(pmesh.Error) as unwritable:
        pmesh.write(tmp_path / "no" / "such" / "dir.obj", pmesh.read(sample("sphere.obj")))
    assert unwritable.value.code == "io-error"
    assert list(tmp_path.iterdir()) == []


def test_a_write_that_fails_midway_leaves_no_file(tmp_path):
    """pmesh.write gives the file its bytes a megabyte at a time (pm::write_mesh_to_sink): a
    write that fails in the middle (here the file size limit, with SIGXFSZ ignored so that
    write() returns EFBIG) raises, and leaves neither the file nor its temporary."""
    import resource
    import signal
    n = 200  # a grid of 80,000 faces: about 2.5 MB of OBJ
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1))
    positions = np.stack([i.ravel(), j.ravel(), np.zeros(i.size)], axis=1).astype(np.float32) / n
    corner = (j[:-1, :-1] * (n + 1) + i[:-1, :-1]).ravel()
    faces = np.concatenate([np.stack([corner, corner + 1, corner + n + 2], axis=1),
                            np.stack([corner, corner + n + 2, corner + n + 1], axis=1)])
    mesh = pmesh.Mesh(positions, faces.astype(np.uint32))
    pmesh.write(tmp_path / "whole.obj", mesh)
    assert (tmp_path / "whole.obj").stat().st_size > 2_000_000
    limits = resource.getrlimit(resource.RLIMIT_FSIZE)
    handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    try:
        resource.setrlimit(resource.RLIMIT_FSIZE, (1_500_000, limits[1]))
        with pytest.raises(pmesh.Error) as error:
            pmesh.write(tmp_path / "cut.obj", mesh)
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, limits)
        signal.signal(signal.SIGXFSZ, handler)
    assert error.value.code == "io-error" and "File too large" in error.value.message
    assert sorted(p.name for p in tmp_path.iterdir()) == ["whole.obj"]


def face_rows(mesh):
    """Each face's corner positions, texture coordinates and colours as one row, rows sorted:
    the same faces in any order (glTF groups them by material)."""
    parts = [mesh.positions[mesh.faces].reshape(len(mesh.faces), -1),
             mesh.uvs[mesh.uv_indices].reshape(len(mesh.faces), -1),
             mesh.colors[mesh.faces].reshape(len(mesh.faces), -1)]
    rows = np.concatenate(parts, axis=1)
    return rows[np.lexsort(rows.T[::-1])]


@pytest.mark.parametrize("extension", ["glb", "gltf"])
def test_gltf_gives_every_face_back(tmp_path, extension):
    pm = pmesh.encode(pmesh.read(sample("textured.obj")))
    level = pm.level(ratio=0.3)
    pmesh.write(tmp_path / f"level.{extension}", level)
    back = pmesh.read(tmp_path / f"level.{extension}")
    np.testing.assert_array_equal(face_rows(back), face_rows(level))
    assert sorted(back.material_names) == sorted(level.material_names)


def test_a_gltf_chain_holds_the_levels_and_reads_as_the_finest(tmp_path):
    pm = pmesh.encode(pmesh.read(sample("textured.obj")))
    indices = [pm.level_for(ratio=r) for r in (0.05, 0.25, 1.0)]
    pmesh.write_gltf(tmp_path / "chain.glb", pm.levels(indices), [pm.error_at(k) for k in indices])
    assert b"MSFT_lod" in (tmp_path / "chain.glb").read_bytes()
    np.testing.assert_array_equal(face_rows(pmesh.read(tmp_path / "chain.glb")), face_rows(pm.level(indices[-1])))
    with pytest.raises(pmesh.Error) as error:
        pmesh.write_gltf(tmp_path / "chain.glb", pm.levels(indices), [0.0])
    assert error.value.code == "invalid-argument"
