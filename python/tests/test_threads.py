"""Long calls release the GIL: two encodes on two threads are inside the encoder at the same
time. Shown by the encoder's own progress calls (every 4096 collapses, on the calling
thread), not by a speedup, which a loaded machine would blur: had encode() held the GIL, the
second thread could not enter it before the first returned, and the two threads' progress
calls could not interleave."""

import threading
import time

import numpy as np

import pmesh


def wavy_grid(n):
    """An n x n height field with waves: ~2 n^2 faces with shape to keep."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    z = 0.05 * np.sin(9 * x) * np.cos(7 * y)
    positions = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    i = np.arange(n - 1)
    corner = (i[:, None] * n + i[None, :]).reshape(-1)
    faces = np.concatenate([np.stack([corner, corner + 1, corner + n + 1], 1),
                            np.stack([corner, corner + n + 1, corner + n], 1)])
    return positions, faces.astype(np.uint32)


def test_two_encodes_run_at_the_same_time():
    positions, faces = wavy_grid(110)  # 12,100 vertices: progress at 4096 and 8192 collapses, and the end
    start = threading.Barrier(2)
    calls = {0: [], 1: []}
    results = {}

    def work(k):
        start.wait()
        results[k] = pmesh.encode(positions, faces, progress=lambda f: calls[k].append((time.monotonic(), f)))

    threads = [threading.Thread(target=work, args=(k,)) for k in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results[0].to_bytes() == results[1].to_bytes()
    first = [t for t, _ in calls[0]]
    second = [t for t, _ in calls[1]]
    assert len(first) >= 3 and len(second) >= 3, calls
    # Each thread's calls span its time inside the encoder: the spans overlap.
    assert max(first[0], second[0]) < min(first[-1], second[-1]), calls


def test_levels_are_extracted_from_one_mesh_on_several_threads():
    positions, faces = wavy_grid(40)
    pm = pmesh.encode(positions, faces)
    expected = [pm.level(ratio=r).faces.copy() for r in (0.1, 0.3, 0.6, 1.0)]
    out = {}

    def work(k, ratio):
        out[k] = pm.level(ratio=ratio).faces

    threads = [threading.Thread(target=work, args=(k, r)) for k, r in enumerate((0.1, 0.3, 0.6, 1.0))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in range(4):
        np.testing.assert_array_equal(out[k], expected[k])
