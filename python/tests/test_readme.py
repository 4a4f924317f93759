"""The README's Python example is python/examples/levels.py, word for word, and it runs: a
user can paste it."""

import os
import re
import subprocess
import sys
import textwrap

import pmesh
from conftest import HERE, README, sample

EXAMPLE = HERE.parent / "examples" / "levels.py"


def readme_example():
    """The indented code block of the README's Python section that starts as the example does."""
    section = README.read_text().split("\n## Python\n", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"((?:\n    .*|\n)+)", section)
    first_line = EXAMPLE.read_text().splitlines()[0]
    for block in blocks:
        code = textwrap.dedent(block).strip("\n") + "\n"
        if code.startswith(first_line):
            return code
    raise AssertionError(f"no code block starting with {first_line!r} in README.md's Python section")


def test_the_readme_shows_the_example_file():
    assert readme_example() == EXAMPLE.read_text()


def test_the_example_writes_four_levels_and_prints_their_measured_errors(tmp_path):
    script = tmp_path / "levels.py"
    script.write_text(readme_example())
    result = subprocess.run([sys.executable, script, sample("textured.obj")], cwd=tmp_path,
                            capture_output=True, text=True, env=dict(os.environ))
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == 4
    mesh = pmesh.read(sample("textured.obj"))
    for line, ratio in zip(lines, ["1", "0.25", "0.05", "0.01"]):
        found = re.fullmatch(r"(\S+): (\d+) faces, Hausdorff ([\d.]+)% and RMS ([\d.]+)% of the bounding-box diagonal", line)
        assert found, line
        assert found[1] == f"textured_{ratio}.obj"
        level = pmesh.read(tmp_path / found[1])
        assert len(level.faces) == int(found[2])
        d = pmesh.surface_distance(mesh, level)
        assert (found[3], found[4]) == (f"{d.hausdorff_percent:.3f}", f"{d.rms_percent:.4f}")
    assert lines[0].endswith("faces, Hausdorff 0.000% and RMS 0.0000% of the bounding-box diagonal")
