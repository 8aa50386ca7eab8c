"""Surface inputs: STL (binary and ASCII), Bezier nets (TOML), measured grids (CSV) and
STEP (OpenCASCADE, optional) all arrive as meshes that the drop-cutter reads."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from millpath.errors import GeometryError, JobError, MillpathError
from millpath.part.surface.bezier import BezierPatch
from millpath.part.surface.load import load_surface
from millpath.part.surface.mesh import function_mesh, write_stl
from millpath.geometry.cutter import Cutter
from millpath.plan.surface.dropcutter import MeshHeight, build_index, drop

BALL = Cutter(3.0, 3.0)


def _bump(x, y):
    return 5.0 + 3.0 * np.sin(x / 7.0) * np.cos(y / 9.0)


def _drop_z(mesh, xy, cutter=BALL):
    return drop(build_index(mesh), cutter, xy).z


def test_ascii_and_binary_stl_give_the_same_mesh_and_drops(tmp_path):
    mesh = function_mesh(_bump, (0, 40), (0, 30), 21, 16)
    write_stl(mesh, tmp_path / "bin.stl")
    write_stl(mesh, tmp_path / "asc.stl", ascii=True)
    assert (tmp_path / "asc.stl").read_bytes().startswith(b"solid")
    a = load_surface("bin.stl", 160, tmp_path)
    b = load_surface(str(tmp_path / "asc.stl"), 160, Path("/nonexistent"))  # absolute path
    assert len(a) == len(b) == len(mesh)
    # binary STL stores float32; ASCII keeps about as many digits
    np.testing.assert_allclose(a.triangles, mesh.triangles, atol=1e-5)
    np.testing.assert_allclose(b.triangles, a.triangles, atol=1e-5)
    xy = np.random.default_rng(1).uniform([0, 0], [40, 30], (200, 2))
    for cutter in (BALL, Cutter(3.0, 0.0), Cutter(3.0, 1.0)):
        np.testing.assert_allclose(_drop_z(a, xy, cutter), _drop_z(b, xy, cutter), atol=1e-5)


def _write_grid(path, xs, ys, f, sep=",", header="x,y,z"):
    lines = [header] if header else []
    for y in ys:
        for x in xs:
            lines.append(sep.join(f"{v:.12g}" for v in (x, y, f(x, y))))
    path.write_text("\n".join(lines) + "\n")


def test_csv_grid_mesh_passes_through_the_samples(tmp_path):
    xs, ys = np.linspace(0, 40, 9), np.linspace(0, 30, 7)
    _write_grid(tmp_path / "g.csv", xs, ys, _bump)
    mesh = load_surface("g.csv", 32, tmp_path)
    # k = ceil(32 / 8) = 4 sub-cells per grid cell: 32 x 24 cells, two triangles each
    assert len(mesh) == 2 * 32 * 24
    lo, hi = mesh.bounds
    np.testing.assert_allclose([lo[0], lo[1], hi[0], hi[1]], [0, 0, 40, 30])
    # every sample is a vertex and the surface height there is the sample's Z
    verts = np.unique(mesh.triangles.reshape(-1, 3), axis=0)
    X, Y = np.meshgrid(xs, ys)
    samples = np.stack([X.ravel(), Y.ravel(), _bump(X, Y).ravel()], axis=1)
    gap = np.linalg.norm(samples[:, None, :] - verts[None, :, :], axis=2).min(axis=1)
    assert gap.max() < 1e-9


def test_csv_grid_round_trip_linear_and_cubic(tmp_path):
    """A plane is reproduced exactly by both methods; the cubic grid follows a smooth
    surface between the samples much closer than the linear one."""
    xs, ys = np.linspace(0, 40, 11), np.linspace(0, 30, 9)
    plane = lambda x, y: 2.0 + 0.1 * x - 0.05 * y          # noqa: E731
    _write_grid(tmp_path / "plane.xyz", xs, ys, plane, sep=" ", header="")
    xy = np.random.default_rng(2).uniform([5, 5], [35, 25], (100, 2))
    z = _drop_z(load_surface("plane.xyz", 40, tmp_path), xy, Cutter(3.0, 0.0))
    # flat end mill on a plane of slope (0.1, -0.05): the rim touches at R |grad| above
    assert np.allclose(z, plane(xy[:, 0], xy[:, 1]) + 3.0 * math.hypot(0.1, 0.05), atol=1e-9)

    _write_grid(tmp_path / "bump.txt", xs, ys, _bump, sep=";", header="# x y z")
    lin = load_surface("bump.txt", 80, tmp_path)
    cub = load_surface({"grid": "bump.txt", "method": "cubic"}, 80, tmp_path)
    pts = np.random.default_rng(3).uniform([2, 2], [38, 28], (400, 2))
    true = _bump(pts[:, 0], pts[:, 1])
    e_lin = np.abs(MeshHeight(build_index(lin)).height(pts[:, 0], pts[:, 1]) - true).max()
    e_cub = np.abs(MeshHeight(build_index(cub)).height(pts[:, 0], pts[:, 1]) - true).max()
    assert e_cub < 0.2 * e_lin and e_cub < 0.01


def test_grid_errors_name_file_and_line(tmp_path):
    p = tmp_path / "g.csv"
    p.write_text("x,y,z\n0,0,1\n1,0,1\n0,1,oops\n1,1,1\n")
    with pytest.raises(GeometryError) as e:
        load_surface("g.csv", 10, tmp_path)
    assert str(e.value).startswith(f"{p}:4: ")
    with pytest.raises(JobError, match="surface.method"):
        load_surface({"grid": "g.csv", "method": "quintic"}, 10, tmp_path)
    with pytest.raises(JobError, match="surface.grid: no such file"):
        load_surface({"grid": "missing.csv"}, 10, tmp_path)
    with pytest.raises(JobError, match="surface.spacing: unknown key"):
        load_surface({"grid": "g.csv", "spacing": 1}, 10, tmp_path)


def test_bezier_toml_file_and_table_give_the_same_mesh(tmp_path):
    heights = [[0.0, 2.0, 0.0], [1.0, 6.0, 1.0], [0.0, 2.0, 0.0]]
    box = [0.0, 0.0, 30.0, 20.0]
    (tmp_path / "net.toml").write_text(f"heights = {heights}\nbox = {box}\n")
    a = load_surface("net.toml", 12, tmp_path)
    b = load_surface({"heights": heights, "box": box}, 12, tmp_path)
    assert len(a) == 2 * 12 * 12
    np.testing.assert_array_equal(a.triangles, b.triangles)
    patch = BezierPatch.from_heights(np.array(heights), tuple(box))
    v = a.triangles.reshape(-1, 3)
    np.testing.assert_allclose(v[:, 2], patch.height(v[:, 0], v[:, 1]), atol=1e-9)
    (tmp_path / "bad.toml").write_text("heights = [[1, 2], [3, 4]]\n")
    with pytest.raises(JobError, match="box"):
        load_surface("bad.toml", 12, tmp_path)


@pytest.mark.parametrize("name, message", [
    ("part.obj", "unknown surface file type '.obj'"),
    ("noext", "unknown surface file type 'noext'"),
    ("missing.stl", "no such file 'missing.stl'"),
    ("missing.step", "no such file 'missing.step'"),
])
def test_bad_surface_files_are_one_line_errors(tmp_path, name, message):
    with pytest.raises(MillpathError) as e:
        load_surface(name, 10, tmp_path, file="job.toml")
    assert message in str(e.value) and str(e.value).startswith("job.toml: surface: ")
    assert "\n" not in str(e.value)


def test_step_without_opencascade_names_the_extra(tmp_path, monkeypatch):
    import builtins
    real_import = builtins.__import__

    def no_ocp(name, *args, **kwargs):
        if name == "OCP" or name.startswith("OCP."):
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    (tmp_path / "part.step").write_text("ISO-10303-21;\nEND-ISO-10303-21;\n")
    monkeypatch.setattr(builtins, "__import__", no_ocp)
    with pytest.raises(JobError, match=r"pip install 'millpath\[step-brep\]'"):
        load_surface("part.step", 10, tmp_path)


# --- STEP through OpenCASCADE -------------------------------------------------------
BOX = (40.0, 30.0, 10.0)     # x, y, z size of the block, corner at the origin
FILLET = 4.0                 # radius of the fillets along the four top edges


def _filleted_block_step(path: Path) -> None:
    """A 40 x 30 x 10 block whose top edges are rounded with radius 4, as STEP."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_VERTEX
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS
    from OCP.BRep import BRep_Tool

    cast_edge = getattr(TopoDS, "Edge_s", None) or TopoDS.Edge
    cast_vertex = getattr(TopoDS, "Vertex_s", None) or TopoDS.Vertex
    block = BRepPrimAPI_MakeBox(*BOX).Shape()
    fillet = BRepFilletAPI_MakeFillet(block)
    edges = TopExp_Explorer(block, TopAbs_EDGE)
    while edges.More():
        edge = cast_edge(edges.Current())
        edges.Next()
        zs = []
        vertices = TopExp_Explorer(edge, TopAbs_VERTEX)
        while vertices.More():
            zs.append(BRep_Tool.Pnt_s(cast_vertex(vertices.Current())).Z())
            vertices.Next()
        if all(abs(z - BOX[2]) < 1e-9 for z in zs):
            fillet.Add(FILLET, edge)
    writer = STEPControl_Writer()
    writer.Transfer(fillet.Shape(), STEPControl_AsIs)
    writer.Write(str(path))


def test_step_surface_meshed_within_the_chord_tolerance(tmp_path):
    pytest.importorskip("OCP", reason="STEP surfaces need the optional extra "
                                      "millpath[step-brep] (cadquery-ocp, 67 MB)")
    _filleted_block_step(tmp_path / "block.step")
    tol = 0.01
    mesh = load_surface("block.step", 10, tmp_path, chord_tolerance=tol)
    lo, hi = mesh.bounds
    np.testing.assert_allclose(lo, [0, 0, 0], atol=1e-6)
    np.testing.assert_allclose(hi, BOX, atol=1e-6)
    # ball R3 over the top and rolling over the fillet along x = 40 (axis at x 36, z 6)
    y = BOX[1] / 2.0
    x = np.array([10.0, 20.0, 36.0, 37.5, 39.0, 41.0, 42.9])
    c = x - (BOX[0] - FILLET)
    expect = np.where(c <= 0, BOX[2],
                      BOX[2] - FILLET + np.sqrt((FILLET + 3.0) ** 2 - np.maximum(c, 0) ** 2)
                      - 3.0)
    # The triangles lie inside the convex fillet, at most tol from it along the normal;
    # the ball then sits at most tol lower along the normal, tol / cos(slope) in Z.
    cos_slope = np.sqrt((FILLET + 3.0) ** 2 - np.maximum(c, 0) ** 2) / (FILLET + 3.0)
    xy = np.stack([x, np.full_like(x, y)], axis=1)
    for t in (tol, tol / 10):
        mesh = load_surface("block.step", 10, tmp_path, chord_tolerance=t)
        z = _drop_z(mesh, xy)
        assert np.all(z <= expect + 1e-6), z - expect
        assert np.all(z >= expect - t / cos_slope - 1e-6), (z - expect) * cos_slope
        assert np.all(np.abs(z - expect)[x <= 39.0] <= t + 1e-6)   # slope < 45 degrees


def test_broken_step_file_is_a_one_line_error(tmp_path):
    pytest.importorskip("OCP", reason="STEP surfaces need the optional extra "
                                      "millpath[step-brep] (cadquery-ocp, 67 MB)")
    p = tmp_path / "junk.stp"
    p.write_text("this is not STEP\n")
    with pytest.raises(GeometryError) as e:
        load_surface("junk.stp", 10, tmp_path)
    assert str(e.value).startswith(f"{p}:1: cannot read STEP: not an ISO 10303-21 file")
    assert "\n" not in str(e.value)


def test_step_surface_in_an_inch_job_is_planned_in_inches(tmp_path):
    pytest.importorskip("OCP", reason="STEP surfaces need the optional extra "
                                      "millpath[step-brep] (cadquery-ocp, 67 MB)")
    from millpath.job.jobfile import load_job
    from millpath.pipeline import plan_job
    _filleted_block_step(tmp_path / "block.step")
    (tmp_path / "job.toml").write_text("""units = "inch"
[stock]
box = [0.0, 0.0, 0.0, 1.575, 1.182, 0.45]
[[tools]]
number = 1
type = "ball"
diameter = 0.25
flute_length = 0.75
stickout = 1.2
[[operations]]
type = "surface-finish"
surface = "block.step"
tool = 1
scallop = 0.002
tolerance = 0.001
compare = false
""")
    job = load_job(tmp_path / "job.toml")
    tp, results, stock = plan_job(job)
    # the block's top (10 mm) is 0.3937 in: the passes over the flat top run at that
    # height (beyond the block the tool drops to its foot, z 0), and nothing is planned
    # at millimetre size
    z = np.round([m.end[2] for m in tp.moves if m.kind == "line" and m.end[2] > 0.2], 4)
    top = BOX[2] / 25.4
    assert np.sum(np.abs(z - top) < 1e-4) > 20
    # nothing above the top but entries (ramps down at the plunge feed beside the block)
    feed = max(m.feed for m in tp.moves if m.kind == "line")
    zc = np.round([m.end[2] for m in tp.moves if m.kind == "line" and m.feed == feed], 4)
    assert not np.any((zc > top + 1e-4) & (zc < stock.zmax))
    # the passes run over the block's edge until the ball leaves it, a radius beyond
    # (the default region is the silhouette grown by the radius; the last point where
    # the ball still touches is bracketed by the chord refinement)
    xmax = max(m.end[0] for m in tp.moves)
    assert BOX[0] / 25.4 + 0.125 - 0.002 <= xmax <= BOX[0] / 25.4 + 0.125 + 1e-6
