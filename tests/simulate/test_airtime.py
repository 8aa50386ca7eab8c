"""Where an operation's time goes: cutting, air, traverses, retracts and entries.

Truth: a program whose every move is known to cut or not (a slot through a box, moves
above it and back through the slot), timed as length over feed on a machine with an
acceleration so high that speed changes take no measurable time; and a job fed so
slowly that it runs for hours."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.interpret import interpret
from millpath.io.tooltable import ToolEntry
from millpath.model import Stock, Tool
from millpath.model.stock import Machine
from millpath.simulate import simulate_motions
from millpath.simulate.airtime import time_note, time_use

PROGRAM = """G21 G90 G17
T1 M6
G0 X-10 Y10 Z5
G0 Z-2
G1 X50 F600
G1 Z5
G1 X-10
G0 Z20
G0 X20
G1 Z-1 F300
G1 Y30
G0 Z20
M2
"""


def test_time_splits_into_cutting_air_and_traverses():
    motions = interpret(PROGRAM, [ToolEntry(1, 1, 6.0)], machine_units="mm")
    stock = Stock(0, 0, -10, 40, 20, 0)
    machine = Machine(rapid=5000.0, max_feed=3000.0, acceleration=1e7)
    sim = simulate_motions(motions, {1: Tool(1, "flat", 6.0)}, stock, resolution=0.25,
                           machine=machine, accuracy=None)
    from millpath.simulate import motion_times
    from millpath.simulate.approach import approach_from_above
    moved = approach_from_above(list(motions), stock.zmax)
    times = motion_times(moved, machine)
    (use,) = time_use(moved, times, sim.removes, [0] * len(moved), 1)
    # cutting: the slot along X at Z-2 (60 mm at 600) and the cut out of it along Y at
    # Z-1 (20 mm at 300, into material from Y13 on)
    assert use["cutting_s"] == pytest.approx(60 / 600 * 60 + 20 / 300 * 60, abs=1e-3)
    # air: up beside the stock (7 mm at 600), back above it (60 mm at 600), down into
    # the cut slot (21 mm at 300)
    assert use["air_s"] == pytest.approx((7 + 60) / 600 * 60 + 21 / 300 * 60, abs=1e-3)
    assert use["retracts"] == 2 and use["entries"] == 2
    total = use["cutting_s"] + use["air_s"] + use["traverse_s"]
    assert total == pytest.approx(float(times.sum()), abs=1e-3)
    assert use["air_share"] == pytest.approx(use["air_s"] / total, abs=1e-4)


def test_a_note_only_for_air_over_a_third_or_over_two_hours():
    assert time_note({"cycle_time_s": 600, "time": {"air_share": 0.30}}) is None
    text, air, long = time_note({"cycle_time_s": 600, "time": {"air_share": 0.5,
                                                               "entries": 3, "retracts": 4}})
    assert (air, long) == (True, False)
    assert text == "50 % of its 10 min 00 s feeds through air (3 entries, 4 retracts)"
    text, air, long = time_note({"cycle_time_s": 3 * 3600 + 60, "time": {"air_share": 0.1}})
    assert (air, long) == (False, True) and text == "it runs 3 h 01 min"


JOB = """units = "mm"
[stock]
box = [-5, -5, -6, 25, 25, 0]
[[tools]]
number = 1
type = "flat"
diameter = 6.0
[[operations]]
type = "pocket"
tool = 1
polygon = [[0, 0], [20, 0], [20, 20], [0, 20]]
depth = 3.0
stepdown = 3.0
feed = 1.0
"""


def test_an_operation_over_two_hours_is_reported_and_warned_at_its_line(tmp_path):
    (tmp_path / "job.toml").write_text(JOB)
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["run", str(tmp_path / "job.toml"), "-o", str(out),
                                 "--quiet", "--no-pictures"])
    assert r.exit_code == 0, r.output
    rep = json.loads((out / "report.json").read_text())
    (op,) = rep["operations"]
    t = op["time"]
    assert op["lines"] == rep["lines"]
    assert t["cutting_s"] + t["air_s"] + t["traverse_s"] + t["dwell_s"] == \
        pytest.approx(op["cycle_time_s"], abs=2e-3)
    assert t["cutting_s"] > 2 * 3600 and t["entries"] >= 1 and t["retracts"] >= 1
    warned = [line for line in r.output.splitlines() if "warning" in line]
    assert len(warned) == 1, r.output
    assert warned[0].startswith(f"millpath: warning: {tmp_path / 'job.toml'}:8: "
                                "operations[0] (pocket, ")
    assert ": it runs " in warned[0] and warned[0].endswith(
        "stepover, stepdown, feed change it")
