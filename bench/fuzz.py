"""Fuzz millpath's readers for a set time: crashes, hangs and memory blow-ups.

    python bench/fuzz.py --minutes 5 [--reader gcode --reader stl ...] [--seed N]

Readers: gcode, tooltable, job, points, grid, bezier, toollib, p21, ap224, stl, dxf.

Inputs come from hypothesis strategies (fixed seed, no shrinking, no example database);
each case is written to a file and read in a worker process limited to ``--memory-gb``
(2) of address space, so a case that needs more fails there instead of taking the
machine. A case passes when the reader returns or raises ``MillpathError`` (the one-line
error the CLI prints); any other exception is a crash (its traceback is kept), a case
running over ``--hang-seconds`` (20) is a hang (the worker is killed and restarted), and
a ``MemoryError`` or a worker killed by the limit is "over the memory limit". Prints the
counts per reader and one traceback per distinct crash site; exit status 1 if any.

Readers are a small registry: ``register(name, strategy, read)``, where ``read(path)``
reads the file the way millpath's command would (and may use what it read, as the
command does). Add a reader by calling ``register`` below its siblings.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
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


READERS: dict[str, Reader] = {}


def register(name: str, strategy: st.SearchStrategy, read: Callable[[Path], object],
             suffix: str = ".txt") -> None:
    READERS[name] = Reader(name, strategy, read, suffix)


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
                     "4294967296", "1e12"]))
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


def read_gcode(path: Path) -> object:
    """``millpath check PATH --tools T``: interpret, then the summary it prints."""
    from millpath.cli.check import summary
    from millpath.errors import MillpathError
    from millpath.interpret import run
    tbl = path.with_suffix(".tbl")
    if not tbl.exists():
        tbl.write_text(GCODE_TOOLS)
    r = run(path, tbl)
    if r.error is not None:
        raise MillpathError(r.error.message, path, r.error.line)
    return summary(r.motions, r.units)


register("gcode", GCODE, read_gcode, ".ngc")


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
    """``millpath check P.ngc --tools PATH``: read the table, then use tools 1 and 2."""
    from millpath.cli.check import summary
    from millpath.interpret import run
    from millpath.io.tooltable import read_tool_table
    entries = read_tool_table(path)
    r = run(PROGRAM_USING_TOOLS, entries, machine_units="mm")
    return summary(r.motions, r.units)


register("tooltable", TOOLTABLE, read_tooltable, ".tbl")


# --- the file readers (mutations of valid inputs, tests/fuzz/mutate.py) ------------------
def _mutated(text: str) -> st.SearchStrategy:
    from tests.fuzz.mutate import mutated
    return mutated(text)


EXAMPLES = ROOT / "millpath" / "examples"
STEP_TEXT = (ROOT / "tests" / "step" / "fixtures" / "plate_three_holes.stp").read_text()


def read_job(path: Path) -> object:
    """``millpath run PATH``'s loading: the job, its tools and the STEP file it names."""
    from millpath.job.jobfile import load_job
    part = path.parent / "part.stp"
    if not part.exists():
        part.write_text(STEP_TEXT)
    return load_job(path)


register("job", _mutated((EXAMPLES / "features-plate" / "job.toml").read_text()), read_job,
         ".toml")


def read_points(path: Path) -> object:
    """A die-cavity / ``millpath drop`` points file."""
    from millpath.io.text import read_number_rows
    return read_number_rows(path, "x, y")


register("points", _mutated("x, y\n0, 0\n10, 0\n10, 5\n0, 5  # a comment\n"), read_points,
         ".csv")


def read_grid(path: Path) -> object:
    """A measured grid, meshed as a surface operation meshes it."""
    from millpath.part.surface.load import grid_mesh
    return grid_mesh(path, "cubic", 8)


register("grid", _mutated("x,y,z\n" + "".join(f"{x},{y},{0.1 * x * y}\n"
                                                for x in range(4) for y in range(4))),
         read_grid, ".csv")


def read_bezier(path: Path) -> object:
    """A Bezier net file, meshed as a surface operation meshes it."""
    from millpath.part.surface.load import load_surface
    return load_surface(path.name, 8, path.parent)


register("bezier", _mutated("box = [0, 0, 100, 80]\nheights = [[0, -1, 0], [-1, -5, -1], "
                            "[0, -1, 0]]\n"), read_bezier, ".toml")


def read_toollib(path: Path) -> object:
    from millpath.io.toollib import read_tool_library
    return read_tool_library(path)


register("toollib", _mutated('[[tools]]\nnumber = 1\ntype = "ball"\ndiameter = 6\n'
                             'stickout = 30\nholder = [[20, 40]]\n'), read_toollib, ".toml")


def read_p21(path: Path) -> object:
    """The ISO 10303-21 layer alone (any schema)."""
    from millpath.part.step.p21 import read
    return read(path)


def read_ap224(path: Path) -> object:
    """The AP224 feature layer (``millpath features``)."""
    from millpath.part.step.ap224 import read_part
    return read_part(path)


register("p21", _mutated(STEP_TEXT), read_p21, ".stp")
register("ap224", _mutated(STEP_TEXT), read_ap224, ".stp")


def _stl_case(data: tuple) -> bytes:
    import numpy as np
    n, count, cut, values = data
    rec = np.zeros(n, dtype=[("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    v = np.resize(np.array(values or [0.0], dtype="<f4"), (n, 3, 3))
    rec["v"] = v
    body = rec.tobytes()
    return (b"binary".ljust(80, b" ") + np.uint32(count if count is not None else n).tobytes()
            + body[:cut if cut is not None else len(body)])


STL = st.one_of(
    st.tuples(st.integers(0, 8), st.one_of(st.none(), st.integers(0, 2**32 - 1)),
              st.one_of(st.none(), st.integers(0, 500)),
              st.lists(st.one_of(st.floats(width=32), st.sampled_from([3e38, -3e38, 0.0])),
                       max_size=40)).map(_stl_case),
    _mutated("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\n"
             "vertex 0 10 1\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\n"
             "vertex 10 0 0\nvertex 10 10 1\nvertex 0 10 1\nendloop\nendfacet\n"
             "endsolid x\n"))


def read_stl_file(path: Path) -> object:
    from millpath.part.surface.mesh import read_stl
    return read_stl(path)


register("stl", STL, read_stl_file, ".stl")


def _dxf_text() -> str:
    """A small valid drawing: a bulged pocket outline, a circle island, an arc and lines."""
    import io
    import ezdxf
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
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


register("dxf", _mutated(_dxf_text()), read_dxf_file, ".dxf")


# --- worker process -----------------------------------------------------------------------
def _worker(conn, name: str, memory: int, folder: str) -> None:
    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    from millpath.errors import MillpathError
    reader = READERS[name]
    path = Path(folder) / f"case{reader.suffix}"
    while True:
        data = conn.recv()
        if data is None:
            return
        if isinstance(data, bytes):
            path.write_bytes(data)
        else:
            path.write_text(data, encoding="utf-8", errors="surrogatepass")
        try:
            reader.read(path)
            conn.send(("ok", ""))
        except MillpathError as e:
            msg = str(e)
            conn.send(("error" if "\n" not in msg.strip() else "crash",
                       "multi-line message: " + msg))
        except MemoryError:
            conn.send(("memory", ""))
        except RecursionError:
            conn.send(("crash", traceback.format_exc(limit=-8)))
        except Exception:                                     # noqa: BLE001 - the point
            conn.send(("crash", traceback.format_exc()))


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


class _Done(BaseException):
    """Time is up (a BaseException, so hypothesis lets it through at once)."""


class Pool:
    """One worker process at a time, restarted after a hang or a death."""

    def __init__(self, name: str, memory: int, folder: str):
        self.name, self.memory, self.folder = name, memory, folder
        self.ctx = mp.get_context("fork")
        self.start()

    def start(self) -> None:
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=_worker,
                                     args=(child, self.name, self.memory, self.folder),
                                     daemon=True)
        self.proc.start()

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
        except EOFError:                 # died: the memory limit, or a hard crash
            code = self.proc.exitcode
            self.restart()
            return ("memory" if code in (-9, None) else "crash",
                    f"worker died (exit {code})", time.perf_counter() - t0)
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
    return (frames[-1] if frames else "") + " | " + (lines[-1] if lines else "")


def fuzz(name: str, seconds: float, seed: int, memory: int, hang: float) -> Tally:
    reader = READERS[name]
    tally = Tally()
    deadline = time.monotonic() + seconds
    with tempfile.TemporaryDirectory(prefix=f"fuzz-{name}-") as folder:
        pool = Pool(name, memory, folder)

        @hyp_seed(seed)
        @settings(max_examples=10**9, deadline=None, database=None, phases=[Phase.generate],
                  suppress_health_check=list(HealthCheck))
        @given(reader.strategy)
        def one(data):
            if time.monotonic() > deadline:
                raise _Done
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
                tally.memory.append(repr(data)[:300])
            else:
                tally.crash_cases += 1
                tally.crashes.setdefault(_site(info), (info, repr(data)[:500]))

        try:
            while time.monotonic() < deadline:
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
    ap.add_argument("--memory-gb", type=float, default=2.0)
    ap.add_argument("--hang-seconds", type=float, default=20.0)
    ns = ap.parse_args()
    bad = 0
    for name in ns.reader or sorted(READERS):
        t = fuzz(name, ns.minutes * 60, ns.seed, int(ns.memory_gb * (1 << 30)),
                 ns.hang_seconds)
        print(f"{name}: {t.cases} cases in {ns.minutes:g} min: {t.ok} read, {t.errors} "
              f"one-line errors, {t.crash_cases} crashes ({len(t.crashes)} distinct), "
              f"{len(t.hangs)} hangs over {ns.hang_seconds:g} s, {len(t.memory)} over "
              f"{ns.memory_gb:g} GB; slowest case {t.slowest:.2f} s", flush=True)
        for site, (tb, data) in t.crashes.items():
            print(f"--- crash at {site}\ninput: {data}\n{tb}")
        for data in t.hangs[:5]:
            print(f"--- hang: {data}")
        for data in t.memory[:5]:
            print(f"--- memory: {data}")
        bad += t.crash_cases + len(t.hangs) + len(t.memory)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
