"""``millpath drop``: cutter-location Z on exact meshes (planes, a wall) for ball, flat and
bull cutters, holder lift, contact points, and one-line errors."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.part.surface.mesh import Mesh, function_mesh, grid_triangles, write_stl

SLOPE = 0.5


def _tilted(x, y):
    return 1.0 + SLOPE * x + 0.0 * y


@pytest.fixture
def surfaces(tmp_path):
    """flat.stl: z = 2; tilted.stl: z = 1 + x / 2 (both over [-20, 20]^2, vertices exact
    in float32); wall.stl: floor z = 0 with a block 20 high for x >= 10."""
    write_stl(function_mesh(lambda x, y: 2.0 + 0.0 * x, (-20, 20), (-20, 20), 11, 11),
              tmp_path / "flat.stl")
    write_stl(function_mesh(_tilted, (-20, 20), (-20, 20), 11, 11), tmp_path / "tilted.stl",
              ascii=True)
    x = np.array([-30.0, -10.0, 10.0, 10.0, 30.0])
    y = np.array([-30.0, 0.0, 30.0])
    z = np.where(np.arange(5)[None, :] >= 3, 20.0, 0.0) * np.ones((3, 1))
    write_stl(Mesh(grid_triangles(x, y, z)), tmp_path / "wall.stl")
    pts = tmp_path / "points.csv"
    pts.write_text("x,y\n0,0\n-4.5 3.25\n7;-6\n# a comment\n\n10.5, 9\n")
    return tmp_path


PTS = np.array([[0.0, 0.0], [-4.5, 3.25], [7.0, -6.0], [10.5, 9.0]])


def run(*args):
    return CliRunner().invoke(cli, ["drop", *map(str, args)])


def _rows(text: str) -> tuple[list[str], np.ndarray]:
    lines = text.strip().splitlines()
    cols = lines[0].split(",")
    vals = np.array([[float(v) if v else np.nan for v in ln.split(",")] for ln in lines[1:]])
    return cols, vals


@pytest.mark.parametrize("tool, radius, corner", [
    ("ball:6", 3.0, 3.0), ("flat:6", 3.0, 0.0), ("bull:6:1", 3.0, 1.0), ("bull:8:0.5", 4.0, 0.5),
])
def test_cl_z_on_planes_is_exact(surfaces, tool, radius, corner):
    r = run(surfaces / "flat.stl", "--tool", tool, "--xy", surfaces / "points.csv")
    assert r.exit_code == 0, r.output
    cols, v = _rows(r.stdout)
    assert cols == ["x", "y", "z"]
    np.testing.assert_array_equal(v[:, :2], PTS)
    np.testing.assert_allclose(v[:, 2], 2.0, atol=1e-6)

    r = run(surfaces / "tilted.stl", "--tool", tool, "--xy", surfaces / "points.csv")
    assert r.exit_code == 0, r.output
    _, v = _rows(r.stdout)
    # the torus touches the plane (upward normal n) where its tube circle, a = R - rc
    # from the axis on the uphill side, is rc from the plane: tip = plane + a m + rc (s - 1)
    s = math.sqrt(1.0 + SLOPE ** 2)
    expect = _tilted(PTS[:, 0], PTS[:, 1]) + (radius - corner) * SLOPE + corner * (s - 1.0)
    np.testing.assert_allclose(v[:, 2], expect, atol=1e-6)


def test_contact_points_and_output_file(surfaces):
    out = surfaces / "cl.csv"
    r = run(surfaces / "tilted.stl", "--tool", "ball:6", "--xy", surfaces / "points.csv",
            "--contact", "-o", out)
    assert r.exit_code == 0 and r.output == ""
    cols, v = _rows(out.read_text())
    assert cols == ["x", "y", "z", "cx", "cy", "cz"]
    s = math.sqrt(1.0 + SLOPE ** 2)
    n = np.array([-SLOPE, 0.0, 1.0]) / s
    centre = np.column_stack([v[:, :2], v[:, 2] + 3.0])
    np.testing.assert_allclose(v[:, 3:], centre - 3.0 * n, atol=1e-6)
    # outside the surface nothing is touched: the tip rests on the floor (lowest Z)
    far = surfaces / "far.csv"
    far.write_text("100 100\n")
    r = run(surfaces / "tilted.stl", "--tool", "ball:6", "--xy", far, "--contact")
    assert r.stdout.splitlines()[1] == "100,100,-9,,,"
    r = run(surfaces / "tilted.stl", "--tool", "ball:6", "--xy", far, "--floor", "-50")
    assert r.stdout.splitlines()[1] == "100,100,-50"


def test_holder_lifts_the_tool_off_a_wall(surfaces):
    pts = surfaces / "wall_points.csv"
    pts.write_text("-5 0\n5 0\n8.5 0\n12 0\n")
    args = [surfaces / "wall.stl", "--tool", "ball:6", "--xy", pts]
    r = run(*args)
    _, v = _rows(r.stdout)
    # ball R3 alone: floor, floor, the wall's top edge at x = 10 (d = 1.5), the top
    np.testing.assert_allclose(v[:, 2], [0.0, 0.0, 20.0 - 3.0 + math.sqrt(9 - 1.5 ** 2), 20.0],
                               atol=1e-9)
    r = run(*args, "--tool-length", 15, "--holder", "20:30,40:10", "--contact")
    assert r.exit_code == 0, r.output
    cols, v = _rows(r.stdout)
    assert cols == ["x", "y", "z", "lifted", "cx", "cy", "cz"]
    # holder D20 from 15 above the tip: at x = 5 its rim reaches the block top (z 20);
    # the D40 cylinder above it (from 45) never reaches down to it here
    # (at x = 8.5 the ball on the wall's edge is higher than the holder needs)
    edge = 20.0 - 3.0 + math.sqrt(9 - 1.5 ** 2)
    np.testing.assert_allclose(v[:, 2], [0.0, 5.0, edge, 20.0], atol=1e-9)
    np.testing.assert_array_equal(v[:, 3], [0, 1, 0, 0])
    assert np.isnan(v[1, 4:]).all() and np.isfinite(v[[0, 2, 3], 4:]).all()
    np.testing.assert_allclose(v[2, 4:], [10.0, 0.0, 20.0], atol=1e-9)
    r = run(*args, "--tool-length", 15, "--holder", "20:30", "--holder-clearance", 1)
    np.testing.assert_allclose(_rows(r.stdout)[1][:, 2], [0.0, 6.0, edge, 20.0], atol=1e-9)


def _error_line(r) -> str:
    assert r.exit_code == 1, r.output
    assert "Traceback" not in r.output and r.output.count("\n") == 1, r.output
    assert r.output.startswith("millpath: error: ")
    return r.output.strip()


@pytest.mark.parametrize("points, args, message", [
    ("x,y\n1,2\n3,4,5\n", [], "points.csv:3: expected two numbers x, y, got 3 fields"),
    ("1 2\n3 nan\n", [], "points.csv:2: NaN or infinite coordinate"),
    ("1 2\n3 abc\n", [], "points.csv:2: expected two numbers x, y, got '3 abc'"),
    ("x,y\n", [], "points.csv: points file has no x, y rows"),
    ("1 2\n", ["--tool", "cone:6"], "--tool: bad tool 'cone:6'"),
    ("1 2\n", ["--tool", "bull:6:4"], "--tool: corner radius must be in [0, 3.0]"),
    ("1 2\n", ["--holder", "20:30"], "--holder: give --tool-length"),
    ("1 2\n", ["--tool-length", "20"], "--tool-length: places the holder face; give --holder too"),
    ("1 2\n", ["--tool-length", "20", "--holder", "20x30"], "--holder: bad holder cylinder"),
])
def test_bad_input_is_one_line_and_writes_nothing(surfaces, points, args, message):
    p = surfaces / "points.csv"
    p.write_text(points)
    out = surfaces / "out.csv"
    tool = [] if "--tool" in args else ["--tool", "ball:6"]
    r = run(surfaces / "flat.stl", *tool, "--xy", p, *args, "-o", out)
    assert message in _error_line(r)
    assert not out.exists()


def test_bad_surface_is_one_line(surfaces):
    pts = surfaces / "points.csv"
    assert "no such file" in _error_line(run(surfaces / "nope.stl", "--tool", "ball:6",
                                             "--xy", pts))
    (surfaces / "part.obj").write_text("v 0 0 0\n")
    assert "unknown surface file type '.obj'" in _error_line(
        run(surfaces / "part.obj", "--tool", "ball:6", "--xy", pts))
    (surfaces / "broken.stl").write_bytes(b"solid x\nfacet normal 0 0 1\nouter loop\n")
    line = _error_line(run(surfaces / "broken.stl", "--tool", "ball:6", "--xy", pts))
    assert "broken.stl" in line


def test_other_surface_kinds(surfaces):
    """A CSV grid and a TOML Bezier net of the plane z = 2 give z = 2 for any cutter."""
    grid = surfaces / "grid.csv"
    grid.write_text("".join(f"{x},{y},2\n" for y in range(-20, 21, 5) for x in range(-20, 21, 5)))
    net = surfaces / "net.toml"
    net.write_text("heights = [[2, 2, 2], [2, 2, 2]]\nbox = [-20, -20, 20, 20]\n")
    for surface in (grid, net):
        r = run(surface, "--tool", "bull:6:1", "--xy", surfaces / "points.csv",
                "--divisions", 8)
        assert r.exit_code == 0, r.output
        np.testing.assert_allclose(_rows(r.stdout)[1][:, 2], 2.0, atol=1e-9)


def test_step_surface_output_is_clean_csv(tmp_path):
    pytest.importorskip("OCP", reason="STEP surfaces need the optional extra "
                                      "millpath[step-brep] (cadquery-ocp, 67 MB)")
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    from OCP.gp import gp_Pnt
    w = STEPControl_Writer()
    w.Transfer(BRepPrimAPI_MakeBox(gp_Pnt(-20, -20, 0), 40, 40, 5).Shape(), STEPControl_AsIs)
    w.Write(str(tmp_path / "box.step"))
    (tmp_path / "p.csv").write_text("0 0\n5 -3\n")
    # a separate process: OpenCASCADE prints on file descriptor 1, which must not reach
    # the CSV on standard output
    p = subprocess.run([sys.executable, "-m", "millpath.cli.main", "drop", "box.step",
                        "--tool", "bull:6:1", "--xy", "p.csv"], cwd=tmp_path,
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert p.stdout == "x,y,z\n0,0,5\n5,-3,5\n"


def test_console_script_error_has_no_traceback(tmp_path):
    p = subprocess.run([sys.executable, "-m", "millpath.cli.main", "drop", "x.stl",
                        "--tool", "ball:6", "--xy", str(tmp_path / "none.csv")],
                       capture_output=True, text=True)
    assert p.returncode == 1 and p.stdout == ""
    assert p.stderr == f"millpath: error: {tmp_path / 'none.csv'}: no such points file\n"
