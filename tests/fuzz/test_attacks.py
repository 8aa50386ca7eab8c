"""The classes of bad input an attacker's fuzzing found (about 6,300 cases through the
real ``millpath`` command): each case runs the command and must end in one line
``millpath: error: FILE[:LINE]: message`` naming the user's input, exit status 1, with
nothing written, quickly. Cases that could kill the process run in a child."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "millpath" / "examples"

JOB = """units = "mm"
{top}
[stock]
box = [0, 0, -10, 160, 100, 0]
[simulation]
resolution = {resolution}
[[tools]]
number = 1
type = "flat"
diameter = 6
stickout = 30
holder = [[20, {holder}]]
[[operations]]
type = "pocket"
tool = 1
polygon = [[10, 10], [60, 10], [60, 50], [10, 50]]
depth = 2
stepdown = 1
feed = 600
spindle = 8000
{reference}
"""


def job(top: str = "", resolution: str = "0.5", holder: str = "40",
        reference: str = "") -> str:
    return JOB.format(top=top, resolution=resolution, holder=holder, reference=reference)


def one_line(output: str, name: str) -> str:
    """The single error line of a command's output, checked to name ``name``."""
    lines = output.strip().splitlines()
    assert len(lines) == 1, output
    assert lines[0].startswith(f"millpath: error: {name}"), lines[0]
    return lines[0]


def run_cli(tmp_path: Path, monkeypatch, *args: str):
    monkeypatch.chdir(tmp_path)
    t0 = time.process_time()
    r = CliRunner().invoke(cli, list(args))
    assert time.process_time() - t0 < 10.0
    return r


@pytest.mark.parametrize("text, where, words", [
    (job(reference="[reference]\nx = " + "[" * 3000 + "]" * 3000), "job.toml:22:",
     "arrays and tables nested more than 64 deep"),
    (job(reference="[reference]\nx = " + "{a = " * 3000 + "1" + "}" * 3000), "job.toml:22:",
     "arrays and tables nested more than 64 deep"),
    (job(reference="[reference]\nx" + ".a" * 3000 + " = 1"), "job.toml:",
     "keys nested more than 64 deep (reference.x.a.a...)"),
    (job(reference="[reference]\nx = " + "1" * 5000), "job.toml:22:",
     "a number of 5000 digits (at most 1000)"),
    (job(resolution="1" * 5000), "job.toml:6:", "a number of 5000 digits (at most 1000)"),
    (job(resolution="0.0001"), "job.toml:6: simulation.resolution:",
     "0.0001 makes 1.6e+12 cells over the stock, more than the limit of 16000000 (use "
     "0.032 or more, or raise [limits] max_cells)"),
    (job(top="fit_tolerance = 1e-12"), "job.toml:2: fit_tolerance:",
     "1e-12 mm is finer than the program's 4 decimals can hold (at least 0.0002 mm)"),
    (job(holder="1e9"), "job.toml:12: tools[0].holder:",
     "a tool and holder length of 1e+09 mm is larger than the 10000 mm limit"),
    (job().replace("diameter = 6", "diameter = 1e-12"), "job.toml:10: tools[0].diameter:",
     "a diameter of 1e-12 mm is outside 0.01 .. 1000 mm (wrong units?)"),
    (job(resolution="8"), "job.toml:6: simulation.resolution:",
     "cells of 8 mm are wider than the 6 mm tool 1 of operations[0]"),
    (job(resolution="1e-300"), "job.toml:6: simulation.resolution:",
     "1e-300 makes inf cells over the stock"),
    (job(reference='[post]\npreamble = "G92 X0\\nG0 X100000000000000000000"'),
     "job.toml:22: post.preamble:", "line 2: X word 1e+20 is larger than the 1e+09 limit"),
])
def test_job_values_are_refused_where_written(tmp_path, monkeypatch, text, where, words):
    (tmp_path / "job.toml").write_text(text)
    r = run_cli(tmp_path, monkeypatch, "run", "job.toml", "-o", "out")
    assert r.exit_code == 1, r.output
    line = one_line(r.output, where)
    assert words in line
    assert not (tmp_path / "out").exists()


def test_toml_surface_nets_are_bounded_too(tmp_path):
    from millpath.errors import MillpathError
    from millpath.part.surface.load import load_surface
    (tmp_path / "net.toml").write_text("box = [0, 0, 10, 10]\nheights = "
                                       + "[" * 500 + "]" * 500 + "\n")
    with pytest.raises(MillpathError, match="nested more than 64 deep") as e:
        load_surface("net.toml", 8, tmp_path)
    assert e.value.file == str(tmp_path / "net.toml") and e.value.line == 2


# --- STEP: what OpenCASCADE would crash on ----------------------------------------------
SOLID = (EXAMPLES / "solid-hole-model" / "part.stp").read_text()


def millpath_child(args: list[str], cwd: Path, code: str = "") -> subprocess.CompletedProcess:
    """The command in a child process (``code`` runs first: a test's patch)."""
    prog = f"import sys\n{code}\nfrom millpath.cli.main import main\nsys.argv = " \
           f"['millpath'] + {args!r}\nmain()\n"
    return subprocess.run([sys.executable, "-c", prog], cwd=cwd, capture_output=True,
                          text=True, timeout=120)


@pytest.mark.parametrize("old, new, words", [
    ("#1016=VECTOR('',#1188,", "#1016=VECTOR('',#1016,", "step.stp:1043: #1016: VECTOR refers to itself"),
    ("#547=ORIENTED_EDGE('',*,*,#858,", "#547=ORIENTED_EDGE('',*,*,#547,",
     "step.stp:574: #547: ORIENTED_EDGE refers to itself"),
    ("#858=EDGE_CURVE('',#757,", "#858=EDGE_CURVE('',#547,",
     "step.stp:574: #547: ORIENTED_EDGE is part of a reference cycle (#547 -> #858 -> #547)"),
    ("#1016=VECTOR('',#1188,", "#1016=VECTOR('',"  + "(" * 3000 + "#1188" + ")" * 3000 + ",",
     "step.stp:1043: #1016: parameters nested more than 64 deep"),
])
def test_step_graphs_opencascade_would_crash_on_are_refused(tmp_path, old, new, words):
    pytest.importorskip("OCP", reason="STEP solids need millpath[step-brep]")
    assert old in SOLID
    (tmp_path / "step.stp").write_text(SOLID.replace(old, new))
    p = millpath_child(["features", "step.stp"], tmp_path)
    assert p.returncode == 1, p.stderr
    assert p.stdout == ""
    assert one_line(p.stderr, "step.stp").startswith(f"millpath: error: {words}")


@pytest.mark.parametrize("parens", [2, 3000])
def test_step_references_wrapped_in_parentheses(tmp_path, monkeypatch, parens):
    """An AP224 file read by millpath's own reader: a reference in a list where the
    entity needs a reference, or nested beyond the bound."""
    text = (ROOT / "tests" / "step" / "fixtures" / "plate_three_holes.stp").read_text()
    old = "#22=AXIS2_PLACEMENT_3D('orientation',#19,"
    assert old in text
    (tmp_path / "p.stp").write_text(text.replace(
        old, "#22=AXIS2_PLACEMENT_3D('orientation'," + "(" * parens + "#19" + ")" * parens
        + ","))
    r = run_cli(tmp_path, monkeypatch, "features", "p.stp")
    assert r.exit_code == 1, r.output
    assert one_line(r.output, "p.stp:29: #22: ").endswith(
        "a list (...) where a reference #n is expected" if parens == 2
        else "parameters nested more than 64 deep")


def test_a_native_crash_in_opencascade_is_one_line(tmp_path):
    """The wall behind the graph check: with the check switched off, OpenCASCADE's
    SIGSEGV on a self-referencing VECTOR happens in a child process."""
    pytest.importorskip("OCP", reason="STEP solids need millpath[step-brep]")
    (tmp_path / "step.stp").write_text(SOLID.replace("#1016=VECTOR('',#1188,",
                                                     "#1016=VECTOR('',#1016,"))
    off = "import millpath.part.step.p21 as p21; p21.StepFile.check_tree = lambda self: None"
    for args in (["features", "step.stp"],
                 ["drop", "step.stp", "--tool", "ball:6", "--xy", "xy.csv"]):
        (tmp_path / "xy.csv").write_text("x,y\n1,1\n")
        p = millpath_child(args, tmp_path, off)
        assert p.returncode == 1, p.stderr
        assert one_line(p.stderr, "step.stp") == (
            "millpath: error: step.stp: OpenCASCADE crashed reading this file (signal 11)")


# --- DXF: curves that would be cut into billions of points -------------------------------
def _dxf(path: Path, add) -> None:
    import ezdxf
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    add(doc.modelspace())
    doc.saveas(path)


DXF_JOB = job().replace('polygon = [[10, 10], [60, 10], [60, 50], [10, 50]]',
                        'dxf = "part.dxf"')


def test_a_damaged_dxf_entity_without_a_layer_is_read(tmp_path):
    """A header value ezdxf reads into a model-space entity that has no layer."""
    import io

    import ezdxf
    from millpath.part.drawing.dxf import read_dxf
    doc = ezdxf.new("R2010")
    doc.modelspace().add_circle((30, 20), 6)
    out = io.StringIO()
    doc.write(out)
    text = out.getvalue()
    assert "$OBSLTYPE\n280\n0\n" in text
    (tmp_path / "d.dxf").write_text(text.replace("$OBSLTYPE\n280\n0\n",
                                                 "$OBSLTYPE\n280\n1e-300\n"))
    loops = read_dxf(tmp_path / "d.dxf", "mm", 0.01)
    assert len(loops) == 1


@pytest.mark.parametrize("add, tolerance, words", [
    (lambda m: m.add_lwpolyline([(0, 0, 0, 0, 0), (60, 0, 0, 0, 1e9), (60, 40, 0, 0, 0),
                                 (0, 40)], format="xyseb", close=True),
     None, "LWPOLYLINE: vertex 2 (bulge 1e+09): a radius of 1e+10 mm is larger than the "
           "10000 mm limit"),
    (lambda m: m.add_circle((30, 20), 1e300), None,
     "CIRCLE: a radius of 1e+300 mm is larger than the 10000 mm limit"),
    (lambda m: m.add_circle((30, 20), 1e6), None,
     "CIRCLE: a radius of 1e+06 mm is larger than the 10000 mm limit"),
    (lambda m: [m.add_circle((0, 0), 4000 + k) for k in range(3)], "0.000001",
     "CIRCLE: needs 8.89e+05 points within 2.5e-08 mm: more than the 2000000 a drawing may "
     "be cut into"),
])
def test_dxf_curves_are_measured_before_they_are_cut(tmp_path, monkeypatch, add, tolerance,
                                                     words):
    _dxf(tmp_path / "part.dxf", add)
    text = DXF_JOB if tolerance is None else DXF_JOB.replace(
        "stepdown = 1", f"stepdown = 1\ntolerance = {tolerance}")
    (tmp_path / "job.toml").write_text(text)
    r = run_cli(tmp_path, monkeypatch, "run", "job.toml", "-o", "out")
    assert r.exit_code == 1, r.output
    line = one_line(r.output, "part.dxf: entity ")
    assert words in line
    assert not (tmp_path / "out").exists()


# --- command-line options ----------------------------------------------------------------
PROGRAM = "G21 F100\nG1 X0 Y0\nG1 X1 Y0.1\nG1 X2 Y0.3\nG1 X3 Y0.6\nG1 X4 Y1\nM2\n"


@pytest.mark.parametrize("args, words", [
    (["-t", "1e308"], "p.ngc: --tolerance 1e+308: the fit tolerance must be above 0 and at "
                      "most 1 (program units)"),
    (["-t", "0.01", "--min-radius", "1e308"],
     "p.ngc: --min-radius 1e+308: the min radius must be 0 .. 1000 (program units"),
])
def test_fit_options_are_bounded(tmp_path, monkeypatch, args, words):
    (tmp_path / "p.ngc").write_text(PROGRAM)
    r = run_cli(tmp_path, monkeypatch, "fit", "p.ngc", *args, "-o", "out.ngc")
    assert r.exit_code == 1, r.output
    assert one_line(r.output, words)
    assert not (tmp_path / "out.ngc").exists()


@pytest.mark.parametrize("args, words", [
    (["--tool", "ball:1e308"], "--tool: a diameter of 1e+308 is outside 0.0004 .. 1000"),
    (["--tool", "ball:6", "--tool-length", "1e308", "--holder", "20:40"],
     "--tool-length: must be above 0 and at most 10000 (surface units), got 1e+308"),
    (["--tool", "ball:6", "--tool-length", "50", "--holder", "20:1e308"],
     "--holder: bad holder cylinder '20:1e308'"),
    (["--tool", "ball:6", "--divisions", "100000"], "--divisions: must be 1 .. 1000"),
    (["--tool", "ball:6", "--floor", "1e300"], "--floor: 1e+300 is larger than the 1e+09"),
])
def test_drop_options_are_bounded(tmp_path, monkeypatch, args, words):
    (tmp_path / "g.csv").write_text("x,y,z\n0,0,0\n10,0,0\n0,10,0\n10,10,1\n")
    (tmp_path / "p.csv").write_text("x,y\n1,1\n5,5\n")
    r = run_cli(tmp_path, monkeypatch, "drop", "g.csv", "--xy", "p.csv", *args, "-o", "o.csv")
    assert r.exit_code == 1, r.output
    assert one_line(r.output, words)
    assert not (tmp_path / "o.csv").exists()


# --- a full disk -------------------------------------------------------------------------
@pytest.fixture
def full_disk(monkeypatch):
    """Every file written through millpath.io.atomic fails as on a full disk."""
    import errno
    import os

    import millpath.io.atomic as atomic
    real = os.fdopen

    class Full:
        def __init__(self, fh):
            self.fh = fh

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.fh.close()

        def write(self, data):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(atomic.os, "fdopen", lambda fd, mode: Full(real(fd, mode)))


def test_a_full_disk_names_the_file(tmp_path, monkeypatch, full_disk):
    (tmp_path / "p.ngc").write_text(PROGRAM)
    r = run_cli(tmp_path, monkeypatch, "fit", "p.ngc", "-t", "0.01", "-o", "out.ngc")
    assert r.exit_code == 1, r.output
    assert one_line(r.output, "out.ngc: No space left on device")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.ngc"]


def test_a_full_disk_names_the_output_folder_not_the_staging(tmp_path, full_disk):
    from millpath.io.atomic import staged_dir, write_text
    out = tmp_path / "out"
    with pytest.raises(OSError) as e:
        with staged_dir(out) as tmp:
            write_text(tmp / "program.ngc", "M2\n")
    assert e.value.filename == str(out / "program.ngc")
    assert e.value.strerror == "No space left on device"
    assert not out.exists() and [p.name for p in tmp_path.iterdir()] == [".out.lock"]


def test_step_integers_beyond_64_bits_are_refused(tmp_path, monkeypatch):
    """Found by bench/fuzz.py: a 401-digit integer passed the reader and overflowed a
    float in the AP224 layer (an internal error)."""
    text = (ROOT / "tests" / "step" / "fixtures" / "plate_three_holes.stp").read_text()
    old = "#1=DIMENSIONAL_EXPONENTS(1.0,"
    assert old in text
    (tmp_path / "p.stp").write_text(text.replace(old, "#1=DIMENSIONAL_EXPONENTS(1"
                                                 + "0" * 400 + ","))
    r = run_cli(tmp_path, monkeypatch, "features", "p.stp")
    assert r.exit_code == 1, r.output
    assert one_line(r.output, "p.stp:8: #1: integer " + "1" + "0" * 29 + "... "
                              "out of range (a 64-bit integer)")


def test_view_tolerance_is_bounded(tmp_path, monkeypatch):
    """Found by bench/fuzz.py: --tolerance 1e399 (infinite) reached the page's JSON."""
    (tmp_path / "p.ngc").write_text("G21 F100\nT1 M6 G43\nG0 X0 Y0 Z5\nG1 Z-1\nG1 X20\nM2\n")
    (tmp_path / "t.tbl").write_text("T1 P1 D6 Z50\n")
    r = run_cli(tmp_path, monkeypatch, "view", "p.ngc", "--tools", "t.tbl", "--stock",
                "-5,-5,-2,25,25,0", "--tolerance", "1e399", "-o", "v.html")
    assert r.exit_code == 1, r.output
    assert one_line(r.output, "--tolerance must be a length of 0 .. 1 (program units), "
                              "not inf")
    assert not (tmp_path / "v.html").exists()


def test_simulate_resolution_too_fine_for_a_float(tmp_path, monkeypatch):
    """Found by bench/fuzz.py: --resolution 1e-320 made the cell count infinite (an
    OverflowError) before the Z-map's bound was checked."""
    (tmp_path / "p.ngc").write_text("G21 F100\nT1 M6 G43\nG0 X0 Y0 Z5\nG1 Z-1\nG1 X20\nM2\n")
    (tmp_path / "t.tbl").write_text("T1 P1 D6 Z50\n")
    r = run_cli(tmp_path, monkeypatch, "simulate", "p.ngc", "--tools", "t.tbl", "--stock",
                "-5,-5,-2,25,25,0", "--resolution", "1e-320")
    assert r.exit_code == 1, r.output
    assert one_line(r.output, "p.ngc: resolution 1e-320 gives inf x inf cells: too many")
