"""Regression tests for the bad inputs of issue 16 that escaped as tracebacks, ran for
minutes or were accepted silently: each runs the command as a user does and checks the
exit status, the single line naming the file, and that it answers at once."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli

JOB = """units = "mm"
[stock]
box = {box}
[[tools]]
number = 1
type = "flat"
diameter = 6
[[operations]]
type = "die-cavity"
tool = 1
points = [[0, 0], [40, 0], [40, 30], [0, 30]]
depth = 5
stepdown = {step}
tolerance = 0.01
feed = 600
spindle = 7000
"""


def _millpath(*args: str, cwd: Path) -> tuple[subprocess.CompletedProcess, float]:
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "millpath.cli.main", *args], cwd=cwd,
                       capture_output=True, text=True, timeout=120)
    return p, time.perf_counter() - t0


def _one_line_error(p: subprocess.CompletedProcess, name: str) -> str:
    assert p.returncode == 1, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith(f"millpath: error: {name}"), lines[0]
    assert "Traceback" not in p.stderr
    return lines[0]


@pytest.mark.parametrize("box, step, words", [
    ("[0, 0, -20, 100, 100, " + "1" * 400 + "]", "1.0", "too large"),
    ("[0, 0, -20, 100, 100, 1e23]", "1.0", "1e+23 is larger than the 1e+09 limit"),
    ("[0, 0, -20, 100, 100, 1e8]", "1.0", "larger than the 10000 mm limit"),
    ("[0, 0, -20, 100, 100, 0]", "1e-9", "layers, more than the limit"),
])
def test_absurd_numbers_in_a_job_are_refused_at_once(tmp_path, box, step, words):
    (tmp_path / "job.toml").write_text(JOB.format(box=box, step=step))
    p, secs = _millpath("run", "job.toml", "-o", "out", cwd=tmp_path)
    line = _one_line_error(p, "job.toml")
    assert words in line
    assert secs < 20 and not (tmp_path / "out").exists()


def test_limits_can_be_raised_in_the_job(tmp_path):
    from millpath.job.jobfile import load_job
    (tmp_path / "job.toml").write_text(JOB.format(box="[0, 0, -20, 100, 100, 0]", step="0.001")
                                       + "[limits]\nmax_layers = 30000\n")
    assert load_job(tmp_path / "job.toml").limits.max_layers == 30000


def test_bezier_net_errors_name_the_file(tmp_path):
    from millpath.errors import MillpathError
    from millpath.part.surface.load import load_surface
    (tmp_path / "net.toml").write_text("box = [1e999, 0, 100, 80]\nheights = [[0, 1], [1, 0]]\n")
    with pytest.raises(MillpathError) as e:
        load_surface("net.toml", 8, tmp_path)
    assert e.value.file == str(tmp_path / "net.toml") and "surface.box" in str(e.value)


def test_mesh_of_only_degenerate_triangles_is_refused(tmp_path):
    from millpath.errors import GeometryError
    from millpath.part.surface.mesh import Mesh, read_stl, write_stl
    tris = np.zeros((50, 3, 3))
    tris[:, 1, 0] = 1.0
    tris[:, 2, 0] = 2.0                      # collinear corners: no area
    write_stl(Mesh(tris, "flat"), tmp_path / "d.stl")
    with pytest.raises(GeometryError, match="all degenerate") as e:
        read_stl(tmp_path / "d.stl")
    assert e.value.file == str(tmp_path / "d.stl")


def test_a_bug_is_one_line_with_exit_2_and_debug_shows_it(monkeypatch, tmp_path):
    import millpath.cli.check as check

    def boom(*a, **k):
        raise KeyError("not an input problem")
    monkeypatch.setattr(check, "run", boom)
    prog = tmp_path / "p.ngc"
    prog.write_text("G0 X1\nM2\n")
    r = CliRunner().invoke(cli, ["check", str(prog)])
    assert r.exit_code == 2
    assert r.output.strip().splitlines() == [
        "millpath: internal error: KeyError: 'not an input problem' (this is a bug in "
        "millpath; run with --debug for the traceback)"]
    r = CliRunner().invoke(cli, ["--debug", "check", str(prog)])
    assert isinstance(r.exception, KeyError)


def test_library_warnings_are_silenced_and_ours_are_one_line(monkeypatch, tmp_path):
    import warnings

    import millpath.cli.check as check
    from millpath.errors import MillpathError, warn

    def noisy(*a, **k):
        np.array([1.0]) / np.array([0.0])                   # numpy RuntimeWarning
        warnings.warn("a library's deprecation", DeprecationWarning)
        warn("something to know", "p.ngc", 3)
        raise MillpathError("the real problem", "p.ngc", 4)
    monkeypatch.setattr(check, "run", noisy)
    prog = tmp_path / "p.ngc"
    prog.write_text("G0 X1\nM2\n")
    r = CliRunner().invoke(cli, ["check", str(prog)])
    assert r.exit_code == 1
    assert r.output.strip().splitlines() == ["millpath: warning: p.ngc:3: something to know",
                                             "millpath: error: p.ngc:4: the real problem"]


@pytest.mark.parametrize("value", ["1" + "0" * 400, "1e999", "0", "-2"])
def test_holder_numbers_too_large_or_not_positive_name_the_key(tmp_path, value):
    """Found by ``bench/fuzz.py --reader toollib``: a holder length of 10**400 raised
    OverflowError (a traceback through the CLI)."""
    from millpath.errors import MillpathError
    from millpath.io.toollib import read_tool_library
    p = tmp_path / "tools.toml"
    p.write_text(f'[[tools]]\nnumber = 1\ntype = "ball"\ndiameter = 6\nstickout = 30\n'
                 f'holder = [[20, {value}]]\n')
    with pytest.raises(MillpathError) as e:
        read_tool_library(p)
    assert Path(e.value.file) == p and "tools[0].holder[0]" in str(e.value)
    assert "\n" not in str(e.value)
