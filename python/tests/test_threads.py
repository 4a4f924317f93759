"""Long calls release the GIL: while one thread is inside the encoder, another thread runs
Python. Shown without timing thresholds, which a loaded machine would break: the encoder's
progress callback is `list.append`, a builtin that runs no bytecode, so had encode() held the
GIL from entry to return, no other thread could run between its first and last progress
calls, and could never see the list partly filled."""

import threading

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


def encode_watched(positions, faces):
    """Encodes on this thread while a second thread busily records how many progress calls it
    sees; returns (the .pm, the final progress list, the lengths the watcher saw)."""
    progress = []
    seen = set()
    done = threading.Event()
    ready = threading.Barrier(2)

    def watch():
        ready.wait()
        while not done.is_set():
            seen.add(len(progress))

    watcher = threading.Thread(target=watch)
    watcher.start()
    ready.wait()
    try:
        pm = pmesh.encode(positions, faces, progress=progress.append)
    finally:
        done.set()
        watcher.join()
    return pm, progress, seen


def test_another_thread_runs_python_while_encoding():
    positions, faces = wavy_grid(110)  # 12,100 vertices: progress at 4096 and 8192 collapses, and the end
    reference = pmesh.encode(positions, faces).to_bytes()
    # A loaded machine may not schedule the watcher inside one encode's window; a few tries make
    # that vanishingly unlikely, while a held GIL fails every one.
    for attempt in range(8):
        pm, progress, seen = encode_watched(positions, faces)
        assert pm.to_bytes() == reference
        assert len(progress) >= 3 and progress[-1] == 1.0, progress
        inside = {n for n in seen if 0 < n < len(progress)}
        if inside:
            return
    raise AssertionError(f"in 8 encodes no other thread ran between the first and last progress calls: saw {sorted(seen)} of {len(progress)}")


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
