"""``millpath simulate`` / ``check`` on programs as LinuxCNC's samples are written: the
tool already in the spindle (``--tool N``), the default resolution from the tools the
program cuts with, and the cycle time capped by the machine's feed limit.

References are built by the tests: the same program with ``T1 M6`` written in, the
same program with its absurd feed replaced by the limit, and an analytic slot volume.
"""

from __future__ import annotations

import json
import math

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.cli.programs import simulate_program
from millpath.interpret import interpret
from millpath.io.tooltable import ToolEntry

# no tool change: LinuxCNC's sample programs assume the tool is in the spindle
BODY = """G21 G17 G90
G0 X10 Y0 Z5
G1 Z-1 F200
G1 X40 F{feed}
G0 Z5
M2
"""
STOCK = "0,-10,-5,50,10,0"
SLOT = 30 * 6 * 1 + math.pi * 9 * 1       # flat D6 one deep from X10 to X40 (mm^3)


@pytest.fixture
def files(tmp_path):
    (tmp_path / "nochange.ngc").write_text(BODY.format(feed=600))
    (tmp_path / "withchange.ngc").write_text("T1 M6\n" + BODY.format(feed=600))
    (tmp_path / "fast.ngc").write_text(BODY.format(feed=4500000))
    (tmp_path / "capped.ngc").write_text(BODY.format(feed=3000))
    # T2 is tiny and never used: it must not set the resolution. Lengths are 0, as on a
    # machine whose tools are touched off into the work offset (the samples' G49 runs
    # the tool's tip at the programmed point only then)
    (tmp_path / "tools.tbl").write_text("; values in mm\nT1 P1 D6 Z0\nT2 P2 D0.1 Z0\n")
    return tmp_path


def _invoke(args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def test_tool_in_spindle_is_the_tool_changed_in(files):
    """--tool 1 interprets and cuts exactly as the program with T1 M6 in front."""
    tools = [ToolEntry(1, 1, 6.0, {"Z": 0.0})]
    a = list(interpret(files / "nochange.ngc", tools, machine_units="mm", spindle_tool=1))
    b = list(interpret(files / "withchange.ngc", tools, machine_units="mm"))
    assert len(a) == len(b) and all(m.tool == 1 for m in a)
    for x, y in zip(a, b):
        assert (x.kind, x.start, x.end, x.feed, x.tool, x.tool_offset) == \
               (y.kind, y.start, y.end, y.feed, y.tool, y.tool_offset)
        assert x.line + 1 == y.line
    out = {}
    for name, extra in (("nochange.ngc", ["--tool", 1]), ("withchange.ngc", [])):
        r = _invoke(["simulate", files / name, "--tools", files / "tools.tbl", "--stock", STOCK,
                     "--json", *extra])
        assert r.exit_code == 0, r.output
        out[name] = json.loads(r.stdout)
    assert out["nochange.ngc"] == out["withchange.ngc"]
    assert out["nochange.ngc"]["removed_volume"] == pytest.approx(SLOT, rel=0.01)


def test_without_tool_nothing_is_cut_and_the_warning_names_tool(files):
    r = _invoke(["simulate", files / "nochange.ngc", "--tools", files / "tools.tbl",
                 "--stock", STOCK, "--json"])
    assert r.exit_code == 0
    assert json.loads(r.stdout)["removed_volume"] == 0
    assert "--tool N" in r.stderr


def test_unknown_spindle_tool_is_a_one_line_error(files):
    r = _invoke(["simulate", files / "nochange.ngc", "--tools", files / "tools.tbl",
                 "--stock", STOCK, "--tool", 7])
    assert r.exit_code == 1
    assert r.output.strip().count("\n") == 0 and "--tool 7" in r.output
    assert "Traceback" not in r.output


def test_default_resolution_from_the_tools_the_program_cuts_with(files):
    """A 1000 mm stock: 1000/1000 = 1 mm, capped at D/10 of T1 (0.6 mm), not T2's 0.01."""
    sp = simulate_program(files / "withchange.ngc", files / "tools.tbl",
                          "0,-10,-5,1000,10,0", None, None)
    assert sp.resolution == pytest.approx(0.6)
    sp = simulate_program(files / "nochange.ngc", files / "tools.tbl", STOCK, None, None,
                          spindle_tool=1)
    assert sp.resolution == pytest.approx(50 / 1000)


def test_simulate_cycle_time_capped_by_max_feed_with_a_warning(files):
    base = ["--tools", files / "tools.tbl", "--stock", STOCK, "--tool", 1, "--json"]
    fast = _invoke(["simulate", files / "fast.ngc", *base])
    capped = _invoke(["simulate", files / "capped.ngc", *base])
    assert fast.exit_code == 0 and capped.exit_code == 0
    tf = json.loads(fast.stdout)["cycle_time_s"]
    tc = json.loads(capped.stdout)["cycle_time_s"]
    assert tf == pytest.approx(tc, rel=1e-12)
    warn = [ln for ln in fast.stderr.splitlines() if "max_feed" in ln]
    assert len(warn) == 1 and f"{files / 'fast.ngc'}:4:" in warn[0] and "F4500000" in warn[0]
    assert "max_feed" not in capped.stderr
    # a faster machine: the limit given on the command line, no warning
    quick = _invoke(["simulate", files / "fast.ngc", *base, "--max-feed", 5e6])
    assert quick.exit_code == 0 and "max_feed" not in quick.stderr
    assert json.loads(quick.stdout)["cycle_time_s"] < tc


def test_check_cycle_time_capped_by_max_feed_with_a_warning(files):
    fast = _invoke(["check", files / "fast.ngc"])
    capped = _invoke(["check", files / "capped.ngc"])
    assert fast.exit_code == 0 and capped.exit_code == 0

    def clock(r):
        line = next(ln for ln in r.stdout.splitlines() if "cycle time" in ln)
        m, s = line.split()[2].split(":")
        return 60 * int(m) + float(s)

    assert clock(fast) == clock(capped)
    # 30 mm at 3000 mm/min, the plunge from Z5 (6 mm at 200), rapids at 5000 mm/min
    rapids = math.hypot(10, 5) + 6
    assert clock(capped) == pytest.approx(round(30 / 50 + 6 / 200 * 60 + rapids / 5000 * 60, 1))
    assert f"{files / 'fast.ngc'}:4:" in fast.stderr and "F4500000" in fast.stderr
    assert "max_feed" not in capped.stderr
    r = _invoke(["check", files / "fast.ngc", "--max-feed", 0])
    assert r.exit_code == 1 and "--max-feed" in r.output


def test_view_takes_the_tool_in_the_spindle(files):
    out = files / "v.html"
    r = _invoke(["view", files / "nochange.ngc", "--tools", files / "tools.tbl", "--stock",
                 STOCK, "--tool", 1, "-o", out])
    assert r.exit_code == 0, r.output
    assert out.is_file() and "nothing is cut" not in r.stderr
