"""pmesh.encode, to_bytes, decode and load: the same stream as pmenc, byte for byte, with the
same options; decoded streams give back the encoder's levels."""

import json

import numpy as np
import pytest

import pmesh
from conftest import PMENC, SAMPLE_NAMES, SHARED_NAMES, mesh_path, pmenc, run, sample


@pytest.mark.parametrize("name", SAMPLE_NAMES + SHARED_NAMES)
def test_encode_writes_pmencs_stream(tmp_path, name):
    source = mesh_path(name)
    expected = pmenc(source, tmp_path / "pmenc.pm").read_bytes()
    pm = pmesh.encode(pmesh.read(source))
    assert pm.to_bytes() == expected
    pm.save(tmp_path / "pmesh.pm")
    assert (tmp_path / "pmesh.pm").read_bytes() == expected


@pytest.mark.parametrize(
    "name, options, pmenc_options",
    [
        ("textured.obj", dict(quantize=14), ["--quantize", "14"]),
        ("textured.obj", dict(quantize=12, quantize_uv=10, quantize_normal=8, error_bits=0),
         ["--quantize", "12", "--quantize-uv", "10", "--quantize-normal", "8", "--error-bits", "0"]),
        ("textured.obj", dict(keep_order=True, drop_attributes=True), ["--keep-order", "--drop-attributes"]),
        ("block_features.obj", dict(metric="schroeder", feature_angle=40, keep_corners=True),
         ["--metric", "schroeder", "--feature-angle", "40", "--keep-corners"]),
        ("terrain_holes.obj", dict(layered=True, chunk_splits=512, zstd_level=3),
         ["--layered", "--chunk-splits", "512", "--zstd-level", "3"]),
        ("sphere.obj", dict(fast=True, min_faces=300), ["--fast", "--min-faces", "300"]),
        ("sphere.obj", dict(fast_from=5000, layer_window=0), ["--fast-from", "5000", "--layer-window", "0"]),
        ("nonmanifold.obj", dict(max_normal_flip=45, min_vertices=40), ["--max-normal-flip", "45", "--min-vertices", "40"]),
    ],
)
def test_options_give_pmencs_stream_for_the_same_options(tmp_path, name, options, pmenc_options):
    expected = pmenc(sample(name), tmp_path / "pmenc.pm", *pmenc_options).read_bytes()
    assert pmesh.encode(pmesh.read(sample(name)), **options).to_bytes() == expected


def test_a_lossy_encoding_holds_what_its_stream_decodes_to(tmp_path):
    pm = pmesh.encode(pmesh.read(sample("sphere.obj")), quantize=8)
    decoded = pmesh.decode(pm.to_bytes())
    np.testing.assert_array_equal(pm.positions, decoded.positions)
    np.testing.assert_array_equal(pm.splits()["error"], decoded.splits()["error"])
    lossless = pmesh.encode(pmesh.read(sample("sphere.obj")))
    assert not np.array_equal(pm.positions, lossless.positions)  # 8 bits moved them


def test_arrays_and_mesh_give_the_same_encoding():
    mesh = pmesh.read(sample("textured.obj"))
    from_mesh = pmesh.encode(mesh).to_bytes()
    from_arrays = pmesh.encode(
        mesh.positions.copy(), mesh.faces.copy(), uvs=mesh.uvs.copy(), uv_indices=mesh.uv_indices.copy(),
        normals=mesh.normals.copy(), normal_indices=mesh.normal_indices.copy(), colors=mesh.colors.copy(),
        face_materials=mesh.face_materials.copy(), material_names=list(mesh.material_names),
        material_libraries=list(mesh.material_libraries)).to_bytes()
    assert from_arrays == from_mesh
    # Geometry alone: the arrays of positions and faces, as a numpy user has them.
    assert pmesh.encode(mesh.positions, mesh.faces).to_bytes() == \
        pmesh.encode(mesh, drop_attributes=True).to_bytes()


@pytest.mark.parametrize("name", ["nonmanifold.obj", "textured.obj"])
def test_stats_are_pmencs_json(tmp_path, name):
    report = json.loads(run(PMENC, sample(name), "-o", tmp_path / "x.pm", "--json", "-q"))
    stats = pmesh.encode(pmesh.read(sample(name))).stats
    assert (stats["input_faces"], stats["base_faces"], stats["base_vertices"], stats["splits"], stats["loop"]) == (
        report["input_faces"], report["base_faces"], report["base_vertices"], report["splits"], report["loop"])
    if name == "nonmanifold.obj":  # its repairs: README, samples/README.md
        assert stats["repair"]["complex_edges"] > 0 and stats["repair"]["loose_vertices"] == 2


def test_fast_from_takes_the_fast_loop_by_size(tmp_path):
    # pm::EncodeOptions::fast_from decides, for pmenc and pmesh alike: "loop" says which ran.
    mesh = pmesh.read(sample("sphere.obj"))
    faces = len(mesh.faces)
    assert pmesh.encode(mesh, fast_from=faces).stats["loop"] == "fast"
    assert pmesh.encode(mesh, fast_from=faces + 1).stats["loop"] == "default"
    assert pmesh.encode(mesh, fast_from=0).stats["loop"] == "default"
    report = json.loads(run(PMENC, sample("sphere.obj"), "-o", tmp_path / "x.pm", "--fast-from", str(faces),
                            "--json", "-q"))
    assert report["loop"] == "fast"
    assert (tmp_path / "x.pm").read_bytes() == pmesh.encode(mesh, fast_from=faces).to_bytes()


def moves_by_split(pm):
    """Each split's moved faces, sorted within the split."""
    splits = pm.splits()
    owner = np.repeat(np.arange(len(splits)), splits["moved_count"])
    moved = pm.moved_faces
    return moved[np.lexsort((moved, owner))]


def test_decode_and_load_give_the_encoders_record(encoded):
    pm_path, mesh = encoded("textured.obj")
    pm = pmesh.encode(mesh)
    for decoded in (pmesh.decode(pm_path.read_bytes()), pmesh.decode(bytearray(pm_path.read_bytes())),
                    pmesh.decode(memoryview(pm_path.read_bytes())), pmesh.load(pm_path), pmesh.load(str(pm_path))):
        assert len(decoded) == len(pm) == pm.split_count + 1
        assert decoded.stats is None
        np.testing.assert_array_equal(decoded.positions, pm.positions)
        np.testing.assert_array_equal(decoded.base_faces, pm.base_faces)
        np.testing.assert_array_equal(decoded.splits(), pm.splits())
        # A reader lists each split's moved faces in the order of u's fan (Hoppe 1998, §4),
        # not necessarily the encoder's: the same faces per split.
        np.testing.assert_array_equal(moves_by_split(decoded), moves_by_split(pm))
        assert decoded.to_bytes() == pm_path.read_bytes()  # lossless: written back the same


def test_decode_with_a_memory_bound_refuses_a_larger_stream(encoded):
    pm_path, _ = encoded("sphere.obj")
    with pytest.raises(pmesh.Error) as error:
        pmesh.decode(pm_path.read_bytes(), max_memory=1000)
    assert error.value.code == "resource-limit"


def test_a_cut_stream_decodes_to_the_finest_level_it_holds_when_allowed(encoded):
    pm_path, _ = encoded("terrain_holes.obj")
    data = pm_path.read_bytes()
    whole = pmesh.decode(data)
    cut = pmesh.decode(data[: len(data) * 2 // 3], allow_truncated=True)
    assert 1 < len(cut) < len(whole)
    np.testing.assert_array_equal(cut.splits(), whole.splits()[: cut.split_count])
    with pytest.raises(pmesh.Error) as error:
        pmesh.decode(data[: len(data) * 2 // 3])
    assert error.value.code == "truncated-stream"


def test_arrays_go_in_without_a_copy_and_any_layout_gives_the_same_stream():
    """A column slice of a wider array (rows a stride apart, padding that is not finite) is read
    in place, as a C-contiguous array is; Fortran order and rows backwards are copied first.
    Every layout gives the contiguous arrays' stream byte for byte."""
    mesh = pmesh.read(sample("textured.obj"))
    positions, faces, uvs = mesh.positions.copy(), mesh.faces.copy(), mesh.uvs.copy()
    extra = dict(uv_indices=mesh.uv_indices.copy(), normals=mesh.normals.copy(),
                 normal_indices=mesh.normal_indices.copy(), colors=mesh.colors.copy(),
                 face_materials=mesh.face_materials.copy(), material_names=list(mesh.material_names),
                 material_libraries=list(mesh.material_libraries))
    contiguous = pmesh.encode(positions, faces, uvs=uvs, **extra)
    assert contiguous.stats["input_copies"] == 0

    wide = np.full((len(positions), 5), np.nan, dtype=np.float32)  # the library must skip the NaNs
    wide[:, 1:4] = positions
    wide_faces = np.zeros((len(faces), 4), dtype=np.uint32)
    wide_faces[:, :3] = faces
    wide_faces[:, 3] = 0xFFFFFFFF
    sliced = pmesh.encode(wide[:, 1:4], wide_faces[:, :3], uvs=uvs, **extra)
    assert not wide[:, 1:4].flags.c_contiguous
    assert sliced.stats["input_copies"] == 0
    assert sliced.to_bytes() == contiguous.to_bytes()

    fortran = pmesh.encode(np.asfortranarray(positions), faces, uvs=np.asfortranarray(uvs), **extra)
    assert fortran.stats["input_copies"] == 2
    assert fortran.to_bytes() == contiguous.to_bytes()
    backwards_faces = faces[::-1].copy()[::-1]  # the same rows, read from the end of memory
    assert backwards_faces.strides[0] < 0
    backwards = pmesh.encode(positions, backwards_faces, uvs=uvs, **extra)
    assert backwards.stats["input_copies"] == 1
    assert backwards.to_bytes() == contiguous.to_bytes()
    # The library's own mesh goes in as it is, with no view to make.
    assert pmesh.encode(mesh).stats["input_copies"] == 0
    assert pmesh.encode(mesh).to_bytes() == contiguous.to_bytes()
