"""Fuzz millpath's readers and commands for a set time: crashes, hangs, memory blow-ups.

    python bench/fuzz.py --minutes 5 [--reader gcode --reader stl ...] [--seed N]

Readers (each the way a command reads its input; most run the command itself, in the
worker process, through its error boundary): gcode (check), simulate, fit, tooltable
(check --tools), job (loading), run (a whole small job), points, grid, bezier, stl
(drop), toollib, p21, ap224 (features), solid (features on a STEP solid, OpenCASCADE),
dxf, options (every command's options: check, simulate, view, fit, drop, features, keys).

Each reader starts with its seeds (one case of each class of bad input found so far),
then draws inputs from hypothesis strategies (fixed seed, no shrinking, no example
database). Each case is written to a file and read in a worker process whose peak
resident memory is measured after each case (over ``--memory-gb``, default 1: "over the
memory limit", and the worker is restarted) and whose address space is capped at three
times that, so a case that needs more fails there instead of taking the machine. A case passes when the command exits 0, or exits 1 with lines
``millpath: error: ...`` (one per problem of a job file) naming the input (its file, or the option); anything else is a
crash: an internal error (exit 2), a message of several lines or naming something else,
another exception, or a worker killed by a signal. A case running over
``--hang-seconds`` (20) is a hang (the worker is killed and restarted), and a
``MemoryError`` or a worker killed by the cap is over the memory limit too. Prints the
counts per reader and one traceback per distinct crash site; exit status 1 if any.

Readers are a small registry: ``register(name, strategy, read, suffix, seeds)``, where
``read(path)`` reads the file the way millpath's command would. Add a reader by calling
``register`` below its siblings. :func:`fuzz` with ``cases=N`` runs the seeds and N
drawn cases (the test suite's fixed sample, tests/fuzz/test_fuzz_sample.py).
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import os
import resource
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from hypothesis import HealthCheck, Phase, given, seed as hyp_seed, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


@dataclass
class Reader:
    name: str
    strategy: st.SearchStrategy       # draws the file's text (str) or bytes
    read: Callable[[Path], object]    # reads it as millpath's command does
    suffix: str = ".txt"
    seeds: tuple = ()                 # one case of each known class of bad input
    slow: bool = False                # seconds a case: fewer cases in the suite's sample
    warm: tuple = ()                  # valid inputs, read once by each new worker


READERS: dict[str, Reader] = {}


def register(name: str, strategy: st.SearchStrategy, read: Callable[[Path], object],
             suffix: str = ".txt", seeds: tuple = (), slow: bool = False,
             warm: tuple = ()) -> None:
    """``warm``: valid inputs each new worker reads before its first case (imports and
    compiled code are not counted in a case's time)."""
    READERS[name] = Reader(name, strategy, read, suffix, tuple(seeds), slow, tuple(warm))


class CommandFailed(Exception):
    """The command ended in something other than its output or one line naming the
    input: an internal error, a traceback, a message of several lines."""


def command(*args, names: tuple[str, ...]) -> str:
    """``millpath ARGS`` in this process as from a shell (click's runner, millpath's own
    error boundary). Exit 0: the output. Exit 1 with lines ``millpath: error: ...``
    (one per problem of a job file), the first naming one of ``names`` (the input's
    file name, an option): MillpathError. Anything else: CommandFailed with what was
    printed."""
    from click.testing import CliRunner

    from millpath.cli.main import cli
    from millpath.errors import MillpathError
    r = CliRunner().invoke(cli, [str(a) for a in args])
    if r.exit_code == 0:
        return r.stdout
    err = [s for s in r.stderr.splitlines() if not s.startswith("millpath: warning:")]
    if r.exit_code == 1 and err and all(s.startswith("millpath: error: ") for s in err):
        if any(n in err[0] for n in names):
            raise MillpathError(err[0])
        raise CommandFailed(f"error names none of {names}: {err[0]}")
    if isinstance(r.exception, MemoryError):
        raise MemoryError
    tb = "".join(traceback.format_exception(*r.exc_info)) if r.exc_info and not isinstance(
        r.exception, SystemExit) else ""
    raise CommandFailed(f"exit {r.exit_code}: {r.stderr.strip()[:2000]}\n{tb}")


# --- numbers that break readers -----------------------------------------------------------
HUGE = st.one_of(
    st.integers(10, 400).map(lambda n: "9" * n),
    st.integers(-400, 400).map(lambda e: f"1e{e}"),
    st.integers(-400, 400).map(lambda e: f"[10**{e}]"),
    st.integers(0, 2000).map(lambda e: f"[EXP[{e}]]"),
    st.sampled_from(["inf", "-inf", "nan", "NaN", "1e308", "-1e308", "1e-320", "[1/0]",
                     "[0/0]", "[1 MOD 0]", "[-2**2001]", "[0**-1]", "[LN[0]]", "[SQRT[-1]]",
                     "[ACOS[2]]", "[TAN[90]]", "[SIN[" + "9" * 300 + "]]", "#[10**300]",
                     "#5401", "[" * 130 + "1" + "]" * 130, "2147483648", "-2147483649",
                     "4294967296", "1e12", "100000000000000000000", "[10**20]"]))
NUMBER = st.one_of(st.integers(-100000, 100000).map(str),
                   st.floats(allow_nan=False, allow_infinity=False).map(lambda v: f"{v:.6f}"),
                   st.floats().map(repr), HUGE)


# --- G-code ---------------------------------------------------------------------------
_G = ["G0", "G1", "G2", "G3", "G4", "G5", "G5.1", "G10 L2 P1", "G10 L1 P1", "G10 L20 P2",
      "G17", "G18", "G19", "G20", "G21", "G28", "G30", "G40", "G41", "G42", "G41.1", "G42.1",
      "G43", "G43.1", "G49", "G52", "G53", "G54", "G55", "G59.3", "G61", "G64", "G73", "G80",
      "G81", "G82", "G83", "G85", "G89", "G90", "G91", "G90.1", "G91.1", "G92", "G92.1",
      "G93", "G94", "G95", "G98", "G99", "M0", "M2", "M3", "M5", "M6", "M30", "T1", "T2",
      "D1", "H1", "o1 while [1]", "o1 endwhile", "o1 repeat", "o1 endrepeat", "o<s> sub",
      "o<s> endsub", "o<s> call", "o1 if", "o1 endif", "o1 do", "o1 continue", "o1 break"]
_WORD = st.tuples(st.sampled_from(list("GMXYZIJKRPQFSTDHLABCE@^$#")), NUMBER).map("".join)
_BLOCK = st.lists(st.one_of(_WORD, st.sampled_from(_G),
                            st.tuples(st.sampled_from(["o1 repeat [", "o1 while [",
                                                       "o<s> call [", "#1=[", "#<a>=["]),
                                      NUMBER).map(lambda t: t[0] + t[1] + "]")),
                  max_size=7).map(" ".join)
GCODE = st.one_of(
    st.lists(_BLOCK, max_size=40).map(lambda b: "G21 F100\n" + "\n".join(b) + "\nM2\n"),
    st.text(alphabet="GMXYZIJKRPFSTDHLNOgxyz0123456789.-+[]#=<>() ;/%*\n\t", max_size=400),
    st.binary(max_size=300).map(lambda b: b.decode("latin-1")),
)
GCODE_TOOLS = "T1 P1 D0.25 Z1\nT2 P2 D0.125 Z0.5\n"
GCODE_SEEDS = (
    "G21\nG1 X100000000000000000000 F100\nM2\n",                      # bounding box 1e20
    "G21 F100\nG0 X0 Y0\nG2 X1 Y0 R100000000000000000000\nM2\n",      # arc radius 1e20
    "G21 F100\no1 repeat [4294967296]\nG1 X1\nG1 X0\no1 endrepeat\nM2\n",
    "G21 F100\no1 while [1]\nG1 X1\nG1 X0\no1 endwhile\nM2\n",
    "G21 F100\n#1=0\no1 while [1]\n#1=[#1+1]\no2 if [[#1 MOD 90000] EQ 0]\nG1 X#1\n"
    "o2 endif\no1 endwhile\nM2\n",                                    # rare motion
    "G21 F100\nG1 X" + "[" * 500 + "1" + "]" * 500 + "\nM2\n",
)


def _beside(path: Path, name: str, text: str) -> Path:
    """A fixed companion input next to the case (written once)."""
    p = path.parent / name
    if not p.exists():
        p.write_text(text)
    return p


def read_gcode(path: Path) -> object:
    """``millpath check PATH --tools T``."""
    tbl = _beside(path, "tools.tbl", GCODE_TOOLS)
    return command("check", path, "--tools", tbl, names=(path.name,))


GOOD_PROGRAM = "G21 F100\nT1 M6 G43\nG0 X0 Y0 Z5\nG1 Z-1\nG1 X10 Y5\nG2 X20 Y5 R5\nM2\n"
register("gcode", GCODE, read_gcode, ".ngc", GCODE_SEEDS, warm=(GOOD_PROGRAM,))


def read_simulate(path: Path) -> object:
    """``millpath simulate PATH --tools T --stock ...`` (interpret, then the Z-map)."""
    tbl = _beside(path, "tools.tbl", GCODE_TOOLS)
    return command("simulate", path, "--tools", tbl, "--stock", "-5,-5,-2,25,25,0",
                   "--machine-units", "mm", names=(path.name,))


register("simulate", GCODE, read_simulate, ".ngc", GCODE_SEEDS[:3], warm=(GOOD_PROGRAM,))


FIT_PROGRAM = ("G21 G90 G17\nG0 X10 Y0 Z2\nG1 Z-1 F200\n"
               + "".join(f"G1 X{10 * math.cos(k / 20):.4f} Y{10 * math.sin(k / 20):.4f}\n"
                         for k in range(1, 80))
               + "G0 Z5\nM2\n")


def _mutated(text: str) -> st.SearchStrategy:
    from tests.fuzz.mutate import mutated
    return mutated(text)


def read_fit(path: Path) -> object:
    """``millpath fit PATH -t 0.01 -o OUT``."""
    return command("fit", path, "-t", "0.01", "-o", path.parent / "fitted.ngc",
                   names=(path.name, "fitted.ngc"))


register("fit", st.one_of(_mutated(FIT_PROGRAM), GCODE), read_fit, ".ngc", GCODE_SEEDS[:3],
         warm=(FIT_PROGRAM,))


# --- tool tables ----------------------------------------------------------------------
_ROW = st.tuples(st.integers(-3, 2**40), st.integers(-3, 100),
                 st.lists(st.tuples(st.sampled_from(list("XYZABCUVWDIJQ")), NUMBER),
                          max_size=5)).map(
    lambda t: f"T{t[0]} P{t[1]} " + " ".join(a + v for a, v in t[2]))
TOOLTABLE = st.one_of(
    st.lists(st.one_of(_ROW, st.text(max_size=40)), max_size=8).map("\n".join),
    st.binary(max_size=200).map(lambda b: b.decode("latin-1")))
PROGRAM_USING_TOOLS = ("G21 F100\nG0 X-10 Y-10 Z5\nT1 M6 G43\nG41 D1\nG1 X0 Y0\nG1 X20\n"
                       "G3 X20 Y20 R10\nG40 G1 X-10 Y-10\nT2 M6 G43 H2\nG1 Z-1\nM2\n")


def read_tooltable(path: Path) -> object:
    """``millpath check P.ngc --tools PATH``: the table, then tools 1 and 2 used."""
    prog = _beside(path, "uses-tools.ngc", PROGRAM_USING_TOOLS)
    return command("check", prog, "--tools", path, "--machine-units", "mm",
                   names=(path.name, prog.name))


register("tooltable", TOOLTABLE, read_tooltable, ".tbl",
         ("T1 P1 Z-1e308 D1\n", "T1 P1 Z1 D1e400\n", "T1e300 P1 D1\n"),
         warm=("T1 P1 D6 Z50\nT2 P2 D3 Z40\n",))


# --- jobs -------------------------------------------------------------------------------
EXAMPLES = ROOT / "millpath" / "examples"
STEP_TEXT = (ROOT / "tests" / "step" / "fixtures" / "plate_three_holes.stp").read_text()
PLATE_JOB = (EXAMPLES / "features-plate" / "job.toml").read_text()


def _job_seeds(text: str, after: str) -> tuple[str, ...]:
    """The job classes: nesting, long integers, work and values checked where written."""
    i = text.index(after) + len(after)
    at = lambda s: text[:i] + s + text[i:]          # noqa: E731 - one-liner
    return (at("\nx = " + "[" * 3000 + "]" * 3000 + "\n"),
            at("\nx = " + "{a = " * 3000 + "1" + "}" * 3000 + "\n"),
            at("\nx" + ".a" * 3000 + " = 1\n"),
            at("\nx = " + "1" * 5000 + "\n"),
            text.replace("resolution = ", "resolution = 0.0001 #", 1),
            text.replace('units = "', 'fit_tolerance = 1e-12\nunits = "', 1),
            text.replace("holder = [[", "holder = [[20, 1e9], [", 1),
            text.replace("diameter = ", "diameter = 1e-12 #", 1))


def read_job(path: Path) -> object:
    """``millpath run PATH``'s loading: the job, its tools and the STEP file it names."""
    from millpath.job.jobfile import load_job
    _beside(path, "part.stp", STEP_TEXT)
    return load_job(path)


register("job", _mutated(PLATE_JOB), read_job, ".toml",
         _job_seeds(PLATE_JOB, "[reference]"), warm=(PLATE_JOB,))

#: a small job a whole run plans, posts, proves and writes in about a second
RUN_JOB = """units = "mm"
name = "fuzz"
[stock]
box = [0, 0, -6, 60, 40, 0]
[simulation]
resolution = 0.5
exact = false
pictures = false
[[tools]]
number = 1
type = "flat"
diameter = 6
flute_length = 15
stickout = 30
holder = [[20, 40]]
[[operations]]
type = "pocket"
tool = 1
polygon = [[10, 10], [50, 10], [50, 30], [10, 30]]
depth = 2
stepdown = 1
feed = 600
spindle = 8000
[reference]
"""


def read_run(path: Path) -> object:
    """``millpath run PATH -o OUT --no-pictures --quiet``: planned, posted, proven."""
    import shutil
    out = path.parent / "out"
    try:
        return command("run", path, "-o", out, "--no-pictures", "--quiet",
                       names=(path.name, out.name))
    finally:
        shutil.rmtree(out, ignore_errors=True)


register("run", _mutated(RUN_JOB), read_run, ".toml",
         _job_seeds(RUN_JOB, "[reference]")
         + (RUN_JOB.replace("resolution = 0.5", "resolution = 1e-300"),),
         slow=True, warm=(RUN_JOB,))


# --- points, grids, nets, meshes (millpath drop) -------------------------------------------
GRID_TEXT = "x,y,z\n" + "".join(f"{x},{y},{0.1 * x * y}\n" for x in range(4) for y in range(4))
POINTS_TEXT = "x, y\n0, 0\n1, 0\n1, 2\n0, 2  # a comment\n"


def _drop(surface: Path, points: Path, *names: str) -> object:
    return command("drop", surface, "--tool", "ball:1", "--xy", points, "--divisions", "16",
                   names=names)


def read_points(path: Path) -> object:
    """A ``millpath drop`` points file."""
    grid = _beside(path, "surface.csv", GRID_TEXT)
    return _drop(grid, path, path.name)


register("points", _mutated(POINTS_TEXT), read_points, ".csv",
         ("x,y\n1e300,0\n", "x,y\n" + "9" * 400 + ",1\n"), warm=(POINTS_TEXT,))


def read_grid(path: Path) -> object:
    """A measured grid under ``millpath drop``."""
    pts = _beside(path, "points.csv", POINTS_TEXT)
    return _drop(path, pts, path.name)


register("grid", _mutated(GRID_TEXT), read_grid, ".csv",
         ("x,y,z\n0,0,0\n1e300,0,0\n0,1,0\n1,1,1\n",), warm=(GRID_TEXT,))

BEZIER_TEXT = "box = [0, 0, 100, 80]\nheights = [[0, -1, 0], [-1, -5, -1], [0, -1, 0]]\n"


def read_bezier(path: Path) -> object:
    """A Bezier net under ``millpath drop``."""
    pts = _beside(path, "points.csv", POINTS_TEXT)
    return _drop(path, pts, path.name)


register("bezier", _mutated(BEZIER_TEXT), read_bezier, ".toml",
         ("box = [0, 0, 1, 1]\nheights = " + "[" * 3000 + "]" * 3000 + "\n",
          "box = [0, 0, 1, 1]\nheights = [[" + "1" * 5000 + "]]\n"), warm=(BEZIER_TEXT,))


def read_toollib(path: Path) -> object:
    from millpath.io.toollib import read_tool_library
    return read_tool_library(path)


TOOLLIB_TEXT = ('[[tools]]\nnumber = 1\ntype = "ball"\ndiameter = 6\nstickout = 30\n'
                'holder = [[20, 40]]\n')
register("toollib", _mutated(TOOLLIB_TEXT), read_toollib, ".toml",
         (TOOLLIB_TEXT.replace("[[20, 40]]", "[[20, 1e9]]"),
          TOOLLIB_TEXT.replace("diameter = 6", "diameter = 1e-12")), warm=(TOOLLIB_TEXT,))


def _stl_case(data: tuple) -> bytes:
    import numpy as np
    n, count, cut, values = data
    rec = np.zeros(n, dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    v = np.resize(np.array(values or [0.0], dtype="<f4"), (n, 3, 3))
    rec["v"] = v
    body = rec.tobytes()
    return (b"binary".ljust(80, b" ") + np.uint32(count if count is not None else n).tobytes()
            + body[:cut if cut is not None else len(body)])


STL_TEXT = ("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\n"
            "vertex 0 10 1\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\n"
            "vertex 10 0 0\nvertex 10 10 1\nvertex 0 10 1\nendloop\nendfacet\nendsolid x\n")
STL = st.one_of(
    st.tuples(st.integers(0, 8), st.one_of(st.none(), st.integers(0, 2**32 - 1)),
              st.one_of(st.none(), st.integers(0, 500)),
              st.lists(st.one_of(st.floats(width=32), st.sampled_from([3e38, -3e38, 0.0])),
                       max_size=40)).map(_stl_case),
    _mutated(STL_TEXT))


def read_stl_file(path: Path) -> object:
    """An STL under ``millpath drop``."""
    pts = _beside(path, "points.csv", POINTS_TEXT)
    return _drop(path, pts, path.name)


register("stl", STL, read_stl_file, ".stl",
         (STL_TEXT.replace("vertex 10 0 0", "vertex 1e300 0 0", 1),
          _stl_case((2, 2**32 - 1, None, [1.0]))), warm=(STL_TEXT,))


# --- STEP -------------------------------------------------------------------------------
def read_p21(path: Path) -> object:
    """The ISO 10303-21 layer alone (any schema), with its reference graph check."""
    from millpath.part.step.p21 import read
    sf = read(path)
    sf.check_tree()
    return sf


def read_ap224(path: Path) -> object:
    """``millpath features PATH --json`` on an AP224 file."""
    return command("features", path, "--json", names=(path.name,))


def _step_seeds(text: str, old: str, ref: str) -> tuple[str, ...]:
    """A reference wrapped in parentheses (a few, thousands), and pointing at itself."""
    assert old in text, old
    return (text.replace(old, old.replace(ref, "((" + ref + "))")),
            text.replace(old, old.replace(ref, "(" * 3000 + ref + ")" * 3000)),
            text.replace(old, old.replace(ref, old.split("=")[0])))


AP224_SEEDS = (_step_seeds(STEP_TEXT, "#22=AXIS2_PLACEMENT_3D('orientation',#19,", "#19")
               + (STEP_TEXT.replace("#1=DIMENSIONAL_EXPONENTS(1.0,",
                                    "#1=DIMENSIONAL_EXPONENTS(1" + "0" * 400 + ","),))
register("p21", _mutated(STEP_TEXT), read_p21, ".stp", AP224_SEEDS, warm=(STEP_TEXT,))
register("ap224", _mutated(STEP_TEXT), read_ap224, ".stp", AP224_SEEDS, warm=(STEP_TEXT,))

SOLID_TEXT = (EXAMPLES / "solid-hole-model" / "part.stp").read_text()


def read_solid(path: Path) -> object:
    """``millpath features PATH --json`` on a STEP solid: read by OpenCASCADE (in a child
    process), features recognised."""
    return command("features", path, "--json", names=(path.name,))


register("solid", _mutated(SOLID_TEXT), read_solid, ".stp",
         _step_seeds(SOLID_TEXT, "#1016=VECTOR('',#1188,", "#1188")
         + _step_seeds(SOLID_TEXT, "#547=ORIENTED_EDGE('',*,*,#858,", "#858")[2:]
         + (SOLID_TEXT.replace("#858=EDGE_CURVE('',#757,", "#858=EDGE_CURVE('',#547,"),),
         slow=True, warm=(SOLID_TEXT,))


# --- DXF --------------------------------------------------------------------------------
def _dxf_text(add=None) -> str:
    """A small valid drawing (a bulged pocket outline, a circle island, an arc, lines and
    a spline), or the entities ``add`` draws."""
    import io
    import ezdxf
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    if add is not None:
        add(msp)
    else:
        msp.add_lwpolyline([(0, 0, 0, 0, 0), (60, 0, 0, 0, 0.4), (60, 40, 0, 0, 0), (0, 40)],
                           format="xyseb", close=True, dxfattribs={"layer": "POCKET"})
        msp.add_circle((30, 20), 6, dxfattribs={"layer": "ISLAND"})
        msp.add_line((80, 0), (100, 0))
        msp.add_arc((100, 10), 10, -90, 90)
        msp.add_line((100, 20), (80, 20))
        msp.add_spline([(80, 20), (75, 10), (80, 0)])
    out = io.StringIO()
    doc.write(out)
    return out.getvalue()


def read_dxf_file(path: Path) -> object:
    """A pocket's drawing: loops, then the regions a pocket operation would build."""
    from millpath.part.drawing.dxf import read_dxf
    from millpath.part.drawing.region import regions_from_loops
    return regions_from_loops(read_dxf(path, "mm", 0.01), file=path)


def _dxf_seeds() -> tuple[str, ...]:
    return (_dxf_text(lambda m: m.add_lwpolyline(
                [(0, 0, 0, 0, 0), (60, 0, 0, 0, 1e9), (60, 40, 0, 0, 0), (0, 40)],
                format="xyseb", close=True)),
            _dxf_text(lambda m: m.add_circle((30, 20), 1e300)),
            _dxf_text(lambda m: m.add_circle((30, 20), 1e6)),
            _dxf_text(lambda m: m.add_ellipse((0, 0), (1e300, 0), 0.5)),
            _dxf_text(lambda m: m.add_spline([(0, 0), (1e300, 1), (0, 2)])),
            # a header value ezdxf reads into an entity without a layer
            _dxf_text().replace("$OBSLTYPE\n280\n0\n", "$OBSLTYPE\n280\n1e-300\n"))


register("dxf", _mutated(_dxf_text()), read_dxf_file, ".dxf", _dxf_seeds(),
         warm=(_dxf_text(),))


# --- command-line options ------------------------------------------------------------------
OPTION_VALUE = st.one_of(NUMBER, st.sampled_from(["", "abc", "-", "--", "1:2:3", "ball:1e308",
                                                  "flat:-1", "bull:6:9", "0,0,0,1,1,1",
                                                  "1e308,0,0,1,1,1", "inch", "mm", "+Q"]))
#: each command with its fixed, valid inputs and the options fuzzed
OPTIONS = {
    "check": (["prog.ngc", "--tools", "tools.tbl"],
              ["--machine-units", "--tool", "--max-feed"]),
    "simulate": (["prog.ngc", "--tools", "tools.tbl", "--stock", "-5,-5,-2,25,25,0"],
                 ["--machine-units", "--tool", "--max-feed", "--resolution", "--stock"]),
    "view": (["prog.ngc", "--tools", "tools.tbl", "--stock", "-5,-5,-2,25,25,0", "-o",
              "view.html"], ["--tool", "--tolerance", "--stock", "--machine-units"]),
    "fit": (["fit.ngc", "-t", "0.01", "-o", "fitted.ngc"],
            ["--tolerance", "--min-radius", "--mode"]),
    "drop": (["surface.csv", "--xy", "points.csv", "--tool", "ball:1"],
             ["--tool", "--tool-length", "--holder", "--holder-clearance", "--floor",
              "--divisions", "--chord-tolerance"]),
    "features": (["part.stp"], ["--body", "--setup"]),
    "keys": ([], []),
}
OPTION_ARGS = st.sampled_from(sorted(OPTIONS)).flatmap(
    lambda c: st.lists(st.tuples(st.sampled_from(OPTIONS[c][1] or ["--x"]), OPTION_VALUE),
                       max_size=3).map(lambda kv: [c, *OPTIONS[c][0]]
                                       + [x for k, v in kv for x in (k, v)]))
OPTION_SEEDS = tuple(json.dumps(a) for a in (
    ["fit", "fit.ngc", "-t", "1e308"], ["fit", "fit.ngc", "-t", "0.01", "--min-radius", "1e308"],
    ["drop", "surface.csv", "--xy", "points.csv", "--tool", "ball:1e308"],
    ["drop", "surface.csv", "--xy", "points.csv", "--tool", "ball:6", "--tool-length",
     "1e308", "--holder", "20:40"],
    ["simulate", "prog.ngc", "--tools", "tools.tbl", "--stock", "-5,-5,-2,25,25,0",
     "--resolution", "0.0001"],
    ["simulate", "prog.ngc", "--tools", "tools.tbl", "--stock", "-5,-5,-2,25,25,0",
     "--resolution", "1e-320"],
    ["view", "prog.ngc", "--tools", "tools.tbl", "--stock", "-5,-5,-2,25,25,0", "-o",
     "view.html", "--tolerance", "1e399"]))


def read_options(path: Path) -> object:
    """``millpath COMMAND [inputs] OPTIONS`` for the arguments in the case (JSON)."""
    d = path.parent
    _beside(path, "prog.ngc", "G21 F100\nT1 M6 G43\nG0 X0 Y0 Z5\nG1 Z-1\nG1 X20 Y20\nM2\n")
    _beside(path, "tools.tbl", GCODE_TOOLS)
    _beside(path, "fit.ngc", FIT_PROGRAM)
    _beside(path, "surface.csv", GRID_TEXT)
    _beside(path, "points.csv", POINTS_TEXT)
    _beside(path, "part.stp", STEP_TEXT)
    args = json.loads(path.read_text())
    os.chdir(d)                             # the inputs are named as a user in d would
    opts = tuple(a for a in args if a.startswith("-"))
    out = command(*args, names=opts + ("prog.ngc", "tools.tbl", "fit.ngc", "surface.csv",
                                       "points.csv", "part.stp", "view.html", "fitted.ngc",
                                       "Missing", "No such", "Got unexpected", "requires"))
    for name in ("view.html", "fitted.ngc"):
        (d / name).unlink(missing_ok=True)
    return out


register("options", OPTION_ARGS.map(json.dumps), read_options, ".json", OPTION_SEEDS,
         warm=tuple(json.dumps([c, *OPTIONS[c][0]]) for c in sorted(OPTIONS)))


# --- worker process -----------------------------------------------------------------------
def _write(path: Path, data: str | bytes) -> None:
    if isinstance(data, bytes):
        path.write_bytes(data)
    else:
        path.write_text(data, encoding="utf-8", errors="surrogatepass")


def _peak() -> int:
    """Peak resident memory of this process (bytes)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _worker(conn, name: str, memory: int, folder: str, warm: bool) -> None:
    import logging
    cap = max(3 * memory, 3 << 30)
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    logging.disable(logging.CRITICAL)           # ezdxf's notes on odd files
    from millpath.errors import MillpathError
    reader = READERS[name]
    path = Path(folder) / f"case{reader.suffix}"
    for data in reader.warm if warm else ():
        _write(path, data)
        try:
            reader.read(path)
        except Exception:                                     # noqa: BLE001 - warming
            pass
    conn.send("ready")
    while True:
        data = conn.recv()
        if data is None:
            return
        _write(path, data)
        try:
            reader.read(path)
            result = ("ok", "")
        except MillpathError as e:
            # a job file's problems are several errors, each of one line
            msgs = [str(x) for x in getattr(e, "errors", [e])]
            result = ("error" if not any("\n" in m.strip() for m in msgs) else "crash",
                      "multi-line message: " + "\n".join(msgs))
        except MemoryError:
            result = ("memory", "MemoryError")
        except CommandFailed as e:
            result = ("crash", str(e))
        except Exception:                                     # noqa: BLE001 - the point
            result = ("crash", traceback.format_exc(limit=-8))
        if _peak() > memory:
            result = ("memory", f"peak {_peak() / 2**20:.0f} MB")
        conn.send(result)


@dataclass
class Tally:
    cases: int = 0
    ok: int = 0
    errors: int = 0
    crashes: dict[str, tuple[str, str]] = field(default_factory=dict)  # site -> (tb, input)
    crash_cases: int = 0
    hangs: list[str] = field(default_factory=list)
    memory: list[str] = field(default_factory=list)
    slowest: float = 0.0

    @property
    def bad(self) -> int:
        return self.crash_cases + len(self.hangs) + len(self.memory)


class _Done(BaseException):
    """Time is up (a BaseException, so hypothesis lets it through at once)."""


class Pool:
    """One worker process at a time, restarted after a hang or a death."""

    def __init__(self, name: str, memory: int, folder: str, warm: bool = True):
        self.name, self.memory, self.folder, self.warm = name, memory, folder, warm
        self.ctx = mp.get_context("fork")
        self.start()

    def start(self) -> None:
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=_worker,
                                     args=(child, self.name, self.memory, self.folder,
                                           self.warm),
                                     daemon=True)
        self.proc.start()
        if not self.conn.poll(600) or self.conn.recv() != "ready":
            raise RuntimeError(f"the {self.name} worker did not start")

    def restart(self) -> None:
        self.proc.kill()
        self.proc.join()
        self.start()

    def run(self, data, timeout: float) -> tuple[str, str, float]:
        t0 = time.perf_counter()
        self.conn.send(data)
        if not self.conn.poll(timeout):
            self.restart()
            return "hang", "", time.perf_counter() - t0
        try:
            kind, info = self.conn.recv()
        except EOFError:                 # died: the memory limit, or a signal
            code = self.proc.exitcode
            self.restart()
            return ("memory" if code in (-9, None) else "crash",
                    f"worker died (exit {code})", time.perf_counter() - t0)
        if kind == "memory":             # a fresh worker measures the next case's peak
            self.restart()
        return kind, info, time.perf_counter() - t0

    def close(self) -> None:
        try:
            self.conn.send(None)
        except OSError:
            pass
        self.proc.join(5)
        if self.proc.is_alive():
            self.proc.kill()


def _site(tb: str) -> str:
    lines = [s.strip() for s in tb.strip().splitlines()]
    frames = [s for s in lines if s.startswith("File ")]
    return (frames[-1] if frames else "") + " | " + (lines[-1] if lines else "")[:200]


def fuzz(name: str, seconds: float | None = None, seed: int = 0, memory: int = 1 << 30,
         hang: float = 20.0, cases: int | None = None, warm: bool = True) -> Tally:
    """The reader's seeds, then drawn cases for ``seconds`` or until ``cases`` were run;
    ``warm``: each new worker first reads the reader's valid inputs, uncounted."""
    reader = READERS[name]
    tally = Tally()
    deadline = time.monotonic() + seconds if seconds is not None else None
    with tempfile.TemporaryDirectory(prefix=f"fuzz-{name}-") as folder:
        pool = Pool(name, memory, folder, warm)

        def record(data) -> None:
            kind, info, took = pool.run(data, hang)
            tally.cases += 1
            tally.slowest = max(tally.slowest, took)
            if kind == "ok":
                tally.ok += 1
            elif kind == "error":
                tally.errors += 1
            elif kind == "hang":
                tally.hangs.append(repr(data)[:300])
            elif kind == "memory":
                tally.memory.append(f"{info}: {repr(data)[:300]}")
            else:
                tally.crash_cases += 1
                tally.crashes.setdefault(_site(info), (info, repr(data)[:1500]))

        @hyp_seed(seed)
        @settings(max_examples=10**9, deadline=None, database=None, phases=[Phase.generate],
                  suppress_health_check=list(HealthCheck))
        @given(reader.strategy)
        def one(data):
            if (deadline is not None and time.monotonic() > deadline) or (
                    cases is not None and tally.cases >= cases + len(reader.seeds)):
                raise _Done
            record(data)

        try:
            for data in reader.seeds:
                record(data)
            while deadline is None or time.monotonic() < deadline:
                one()
        except _Done:
            pass
        finally:
            pool.close()
    return tally


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=5.0, help="per reader")
    ap.add_argument("--reader", action="append", choices=sorted(READERS),
                    help="reader(s) to fuzz (default: all)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--memory-gb", type=float, default=1.0)
    ap.add_argument("--hang-seconds", type=float, default=20.0)
    ns = ap.parse_args()
    bad = 0
    names = ns.reader or sorted(READERS)
    print(f"{'reader':10s} {'cases':>6s} {'read':>6s} {'errors':>6s} {'crashes':>7s} "
          f"{'hangs':>5s} {'memory':>6s} {'slowest':>8s}", flush=True)
    for name in names:
        t = fuzz(name, ns.minutes * 60, ns.seed, int(ns.memory_gb * (1 << 30)),
                 ns.hang_seconds)
        print(f"{name:10s} {t.cases:6d} {t.ok:6d} {t.errors:6d} {t.crash_cases:7d} "
              f"{len(t.hangs):5d} {len(t.memory):6d} {t.slowest:7.2f}s", flush=True)
        for site, (tb, data) in t.crashes.items():
            print(f"--- crash at {site}\ninput: {data}\n{tb}")
        for data in t.hangs[:5]:
            print(f"--- hang over {ns.hang_seconds:g} s: {data}")
        for data in t.memory[:5]:
            print(f"--- over {ns.memory_gb:g} GB: {data}")
        bad += t.bad
    print(f"in {ns.minutes:g} min per reader (seed {ns.seed}): crashes are internal errors, "
          f"messages not naming the input and signal deaths")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
