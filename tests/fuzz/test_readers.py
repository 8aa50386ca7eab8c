"""Fuzzed readers: every reader, given a mutated valid input, either reads it
or raises a MillpathError naming the file, never another exception; and it answers
quickly. Seeds are fixed (``derandomize``), so a failure is reproducible."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

from millpath.errors import MillpathError

from tests.fuzz.mutate import mutated

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "millpath" / "examples"

FUZZ = settings(max_examples=150, derandomize=True, deadline=None, database=None,
                suppress_health_check=list(HealthCheck))


def _check(read, text: str, tmp_path: Path, suffix: str, budget: float = 10.0) -> None:
    p = tmp_path / f"input{suffix}"
    p.write_bytes(text.encode("utf-8", "surrogatepass"))
    t0 = time.process_time()
    try:
        read(p)
    except MillpathError as e:
        # a job file's problems come together, one error per line; every other error is one line
        for one in getattr(e, "errors", [e]):
            assert one.file is not None and Path(one.file).name == p.name, str(one)
            assert "\n" not in str(one)
    assert time.process_time() - t0 < budget


JOB = (EXAMPLES / "features-plate" / "job.toml").read_text()
POINTS = "x, y\n0, 0\n10, 0\n10, 5\n0, 5  # a comment\n"
GRID = "x,y,z\n" + "".join(f"{x},{y},{0.1 * x * y}\n" for x in range(4) for y in range(4))
BEZIER = "box = [0, 0, 100, 80]\nheights = [[0, -1, 0], [-1, -5, -1], [0, -1, 0]]\n"
TOOLS = "[[tools]]\nnumber = 1\ntype = \"ball\"\ndiameter = 6\nstickout = 30\n" \
        "holder = [[20, 40]]\n"
TABLE = "T1 P1 D6.0 Z50.0 ;end mill\nT2 P2 D3 Z-10.5\n"
STEP = (ROOT / "tests" / "step" / "fixtures" / "plate_three_holes.stp").read_text()


def _read_job(p: Path) -> None:
    from millpath.job.jobfile import load_job
    # relative paths in the example resolve next to the example
    (p.parent / "part.stp").write_text(STEP) if not (p.parent / "part.stp").exists() else None
    load_job(p)


@FUZZ
@given(text=mutated(JOB))
def test_job_files(tmp_path_factory, text):
    _check(_read_job, text, tmp_path_factory.mktemp("job"), ".toml")


@FUZZ
@given(text=mutated(POINTS))
def test_points_files(tmp_path_factory, text):
    from millpath.io.text import read_number_rows
    _check(lambda p: read_number_rows(p, "x, y"), text, tmp_path_factory.mktemp("pts"), ".csv")


@FUZZ
@given(text=mutated(GRID))
def test_measured_grids(tmp_path_factory, text):
    from millpath.part.surface.load import grid_mesh
    _check(lambda p: grid_mesh(p, "cubic", 8), text, tmp_path_factory.mktemp("grid"), ".csv")


@FUZZ
@given(text=mutated(BEZIER))
def test_bezier_nets(tmp_path_factory, text):
    from millpath.part.surface.load import load_surface
    d = tmp_path_factory.mktemp("bez")
    _check(lambda p: load_surface(p.name, 8, p.parent), text, d, ".toml")


@FUZZ
@given(text=mutated(TOOLS))
def test_tool_libraries(tmp_path_factory, text):
    from millpath.io.toollib import read_tool_library
    _check(read_tool_library, text, tmp_path_factory.mktemp("lib"), ".toml")


@FUZZ
@given(text=mutated(TABLE))
def test_tool_tables(tmp_path_factory, text):
    from millpath.io.tooltable import read_tool_table
    _check(read_tool_table, text, tmp_path_factory.mktemp("tbl"), ".tbl")


@settings(FUZZ, max_examples=60)
@given(text=mutated(STEP))
def test_step_ap224(tmp_path_factory, text):
    from millpath.part.step.ap224 import read_part
    _check(read_part, text, tmp_path_factory.mktemp("stp"), ".stp")


@settings(FUZZ, max_examples=80)
@given(text=mutated(STEP))
def test_step_p21_layer(tmp_path_factory, text):
    """The ISO 10303-21 layer alone (any schema), as ``millpath`` reads every STEP file."""
    from millpath.part.step.p21 import read
    _check(read, text, tmp_path_factory.mktemp("p21"), ".stp")


def _stl_bytes(seed: int) -> list[bytes]:
    """Binary STLs with random headers, counts and values (NaN, inf, huge included)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(60):
        n = int(rng.integers(0, 6))
        rec = np.zeros(n, dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
        v = rng.normal(size=(n, 3, 3)).astype("<f4")
        mask = rng.random(v.shape) < 0.1
        v[mask] = rng.choice(np.array([np.nan, np.inf, -np.inf, 3e38], "<f4"), mask.sum())
        rec["v"] = v
        count = n if rng.random() < 0.7 else int(rng.integers(0, 2**32))
        body = rec.tobytes()
        cut = len(body) if rng.random() < 0.8 else int(rng.integers(0, len(body) + 1))
        out.append(b"binary".ljust(80, b" ") + np.uint32(count).tobytes() + body[:cut])
    out.append(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 nan\nvertex 1 0 0\n"
               b"vertex 0 1 0\nendloop\nendfacet\nendsolid x\n")
    out.append(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 1e999\n")
    out.append(b"")
    return out


@pytest.mark.parametrize("k", range(63))
def test_stl_files(tmp_path, k):
    from millpath.part.surface.mesh import read_stl
    data = _stl_bytes(7)[k]
    p = tmp_path / "input.stl"
    p.write_bytes(data)
    try:
        m = read_stl(p)
    except MillpathError as e:
        assert Path(e.file).name == "input.stl" and "\n" not in str(e)
    else:
        assert np.all(np.isfinite(m.triangles))


def _dxf_text() -> str:
    import io

    import ezdxf
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0, 0, 0, 0), (60, 0, 0, 0, 0.4), (60, 40, 0, 0, 0), (0, 40)],
                       format="xyseb", close=True)
    msp.add_circle((30, 20), 6)
    out = io.StringIO()
    doc.write(out)
    return out.getvalue()


DXF = _dxf_text()


def _read_dxf(p: Path) -> None:
    from millpath.part.drawing.dxf import read_dxf
    from millpath.part.drawing.region import regions_from_loops
    regions_from_loops(read_dxf(p, "mm", 0.01), file=p)


@settings(FUZZ, max_examples=80)
@given(text=mutated(DXF))
def test_dxf_drawings(tmp_path_factory, text):
    _check(_read_dxf, text, tmp_path_factory.mktemp("dxf"), ".dxf")


@pytest.mark.parametrize("cut", ["header", "symbol-table"])
def test_dxf_parser_failures_are_one_line(tmp_path, cut):
    """Found by bench/fuzz.py: a header cut short made ezdxf raise StopIteration, and a
    bad group code gave a message with a newline in it."""
    text = DXF[:DXF.index("$LASTSAVEDBY") + 13] if cut == "header" else \
        DXF.replace("AcDbSymbolTable\n", "AcDbSymbolTable\n\n", 1)
    p = tmp_path / "bad.dxf"
    p.write_text(text)
    with pytest.raises(MillpathError) as e:
        _read_dxf(p)
    assert Path(e.value.file).name == "bad.dxf" and "\n" not in str(e.value)
