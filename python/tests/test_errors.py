"""Bad inputs raise pmesh.Error with the library's stable code name, before any work runs:
wrong dtype or shape, indices out of range, NaN, bad options, corrupt or cut streams."""

import numpy as np
import pytest

import pmesh
from conftest import sample

POSITIONS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], np.uint32)


def refused(code, call, *words):
    with pytest.raises(pmesh.Error) as error:
        call()
    assert error.value.code == code, error.value
    for word in words:
        assert word in error.value.message, (word, error.value.message)
    return error.value


def encode_refuses(*words, **arrays):
    """encode() with these arrays replaced refuses them, without calling progress once."""
    calls = []
    arguments = dict(positions=POSITIONS, faces=FACES)
    arguments.update(arrays)
    refused("invalid-argument",
            lambda: pmesh.encode(arguments.pop("positions"), arguments.pop("faces"), progress=calls.append,
                                 **arguments),
            *words)
    assert calls == []  # checked before the encoder started


def test_wrong_dtypes_are_refused():
    encode_refuses("positions", "float64", positions=POSITIONS.astype(np.float64))
    encode_refuses("faces", "int64", faces=FACES.astype(np.int64))
    encode_refuses("faces", "int32", faces=FACES.astype(np.int32))
    encode_refuses("positions", "list", positions=POSITIONS.tolist())
    encode_refuses("positions", ">f4", positions=POSITIONS.astype(">f4"))  # not native order
    encode_refuses("colors", "float64", colors=np.ones((4, 3)))


def test_wrong_shapes_are_refused():
    encode_refuses("positions", "(count, 3)", "(4, 2)", positions=POSITIONS[:, :2].copy())
    encode_refuses("faces", "(12,)", faces=FACES.reshape(-1))
    encode_refuses("colors", "3 or 4", colors=np.ones((4, 5), np.float32))
    encode_refuses("colors", "3 rows for 4 vertices", colors=np.ones((3, 3), np.float32))
    encode_refuses("uv_indices", "2 rows for 4 faces", uvs=np.zeros((1, 2), np.float32),
                   uv_indices=np.zeros((2, 3), np.uint32))
    encode_refuses("uvs and uv_indices go together", uvs=np.zeros((1, 2), np.float32))


def test_indices_out_of_range_are_refused():
    encode_refuses("faces", "row 3", "vertex 4 of 4", faces=np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 4]], np.uint32))
    encode_refuses("uv_indices", "row 0", "texture coordinate 1 of 1", uvs=np.zeros((1, 2), np.float32),
                   uv_indices=np.array([[0, 1, 0]] + [[0, 0, 0]] * 3, np.uint32))
    encode_refuses("face_materials", "material 1 of 1", face_materials=np.array([0, 0, 1, 0], np.uint32),
                   material_names=["only"])
    # NO_ATTRIBUTE is not out of range: a corner or face without the attribute.
    pmesh.encode(POSITIONS, FACES, face_materials=np.array([0, pmesh.NO_ATTRIBUTE, 0, 0], np.uint32),
                 material_names=["only"])


def test_nan_and_infinity_are_refused():
    for bad in (np.nan, np.inf, -np.inf):
        positions = POSITIONS.copy()
        positions[2, 1] = bad
        encode_refuses("positions", "row 2", "not finite", positions=positions)
    normals = np.array([[0, 0, np.nan]], np.float32)
    encode_refuses("normals", "row 0", normals=normals, normal_indices=np.zeros((4, 3), np.uint32))


def test_the_mesh_constructor_and_every_mesh_argument_check_too():
    refused("invalid-argument", lambda: pmesh.Mesh(POSITIONS, FACES.astype(np.int64)), "faces")
    bad = pmesh.Mesh(POSITIONS, FACES)
    bad.positions = np.full((4, 3), np.nan, np.float32)
    refused("invalid-argument", bad.check, "positions")
    refused("invalid-argument", lambda: pmesh.surface_distance(bad, pmesh.Mesh(POSITIONS, FACES)), "reference", "positions")
    refused("invalid-argument", lambda: pmesh.group_faces_by_material(bad), "positions")
    refused("invalid-argument", lambda: pmesh.encode(bad), "input", "positions")
    refused("invalid-argument", lambda: pmesh.encode(pmesh.Mesh(POSITIONS, FACES), FACES), "not both")


@pytest.mark.parametrize("options, word", [
    (dict(quantize=3), "quantize"), (dict(quantize_uv=25), "quantize_uv"), (dict(error_bits=25), "error_bits"),
    (dict(metric="area"), "metric"), (dict(zstd_level=0), "zstd_level"), (dict(chunk_splits=0), "chunk_splits"),
    (dict(layer_window=2.0), "layer_window"), (dict(feature_angle=200.0), "feature_angle"),
    (dict(max_normal_flip=-1.0), "max_normal_flip"), (dict(progress=42), "progress"),
])
def test_bad_options_are_refused(options, word):
    refused("invalid-argument", lambda: pmesh.encode(POSITIONS, FACES, **options), word)


def test_an_empty_mesh_is_the_librarys_error():
    refused("empty-mesh", lambda: pmesh.encode(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32)))


def test_corrupt_and_cut_streams_raise_their_codes(encoded):
    data = encoded("sphere.obj")[0].read_bytes()
    flipped = bytearray(data)
    flipped[len(data) // 2] ^= 0x40
    refused("checksum-mismatch", lambda: pmesh.decode(bytes(flipped)))
    header = bytearray(data)
    header[0] ^= 0xFF  # the magic
    assert refused("corrupt-stream", lambda: pmesh.decode(bytes(header))).message.startswith("decode: ")
    for length in (0, 10, 96, len(data) - 1):
        refused("truncated-stream", lambda: pmesh.decode(data[:length]))
    refused("corrupt-stream", lambda: pmesh.decode(data + b"\0"))
    refused("invalid-argument", lambda: pmesh.decode(np.zeros(8, np.float32)), "bytes")
    refused("invalid-argument", lambda: pmesh.decode(memoryview(data)[::2]), "bytes")
    refused("io-error", lambda: pmesh.load(sample("no-such.pm")), "no-such.pm")


def test_an_exception_in_progress_is_raised_after_encoding():
    def progress(fraction):
        raise KeyError("stop")
    with pytest.raises(KeyError):
        pmesh.encode(pmesh.read(sample("sphere.obj")), progress=progress)


def test_error_is_an_exception_with_code_and_message():
    error = refused("invalid-argument", lambda: pmesh.encode(POSITIONS, FACES, metric="x"))
    assert isinstance(error, Exception) and error.code == "invalid-argument"
    assert str(error) == f"{error.message} [invalid-argument]"
