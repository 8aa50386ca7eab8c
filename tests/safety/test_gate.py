"""The proof stops the run: each gate condition is made to happen by a
small test strategy whose tool path is wrong on purpose, in a way an analytic check
states (a holder face below the stock top, a rapid into the solid block, a floor cut
below the designed floor); the run must exit 1 with one line, write no program.ngc
but the report and pictures; --force writes program.unsafe.ngc."""

import json
import sys
import types

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.io.schema import Param
from millpath.model import Operation, Toolpath
from millpath.plan import registry
from millpath.plan.base import PlanResult


class Floor:
    """Design: stock top z 0, a 20 x 20 pocket floor at ``z`` (mm)."""

    def __init__(self, z):
        self.z = z

    def height(self, x, y):
        inside = (x >= 14) & (x <= 46) & (y >= 14) & (y <= 46)
        return np.where(inside, self.z, 0.0)


def _plan(ctx, params):
    tp = Toolpath(ctx.units)
    case = params["case"]
    tp.begin(Operation("test-gate", f"case {case}", 1, 10000, tolerance=0.01))
    floor = -4.0
    cut = floor - (0.5 if case == "gouge" else 0.0)
    tp.rapid(20, 20, 5)
    tp.line(20, 20, 1, 300)
    tp.line(20, 20, cut, 100)       # drilling-like entry into a cleared-by-design spot
    tp.line(40, 20, cut, 300)
    tp.line(40, 40, cut, 300)
    tp.line(20, 40, cut, 300)
    tp.line(20, 20, cut, 300)
    tp.rapid(20, 20, 5)
    if case == "rapid":
        tp.rapid(50, 50, 5)
        tp.rapid(50, 50, -3)        # rapid down into the solid corner of the block
        tp.rapid(50, 50, 5)
    report = {}
    if case in ("feature", "feature-listed"):
        report = {"features": {"unmachinable": [
            {"id": 77, "type": "HOLE", "reason": "needs 85 mm of reach, the longest tool "
                                                 "reaches 45", "kind": "reach"}]}}
    if case == "feature-listed":
        report["features"]["unmachinable_policy"] = "list"
    return PlanResult(tp, design=Floor(floor), report=report)


@pytest.fixture
def gate_strategy(monkeypatch):
    mod = types.ModuleType("millpath_test_gate")
    mod.PARAMS = {"case": Param("str", "ok")}
    mod.plan = _plan
    monkeypatch.setitem(sys.modules, "millpath_test_gate", mod)
    monkeypatch.setitem(registry.STRATEGIES, "test-gate", "millpath_test_gate")
    return mod


def _job(tmp_path, case, stickout=30.0, flutes=20.0):
    p = tmp_path / f"{case}.toml"
    p.write_text(f"""
units = "mm"
[stock]
box = [0, 0, -10, 60, 60, 0]
[simulation]
resolution = 0.25
[[tools]]
number = 1
type = "flat"
diameter = 6
flute_length = {flutes}
shank_diameter = 5.5
stickout = {stickout}
holder = [[30, 40]]
[[operations]]
type = "test-gate"
case = "{case}"
""")
    return p


def test_the_exact_check_refuses_the_gouge_too(tmp_path, gate_strategy):
    """``[simulation] exact = true``: the grid-free figure (0.5 mm, normal to the floor)
    goes through the per-operation rows of the report to the gate."""
    job = _job(tmp_path, "gouge")
    job.write_text(job.read_text().replace("[simulation]\n", "[simulation]\nexact = true\n"))
    out = tmp_path / "out"
    r = _run(job, out)
    assert r.exit_code == 1, r.output
    rep = json.loads((out / "report.json").read_text())
    ver = rep["verification"]
    assert abs(ver["max_gouge"] - 0.5) <= 0.002      # accuracy 0.001 + 0.001 slack
    assert ver["by_operation"][0]["max_gouge"] == ver["max_gouge"]
    assert rep["safety"]["problems"][0]["kind"] == "gouge"
    assert not (out / "program.ngc").exists()


def _run(job, out, *extra, quiet=True):
    return CliRunner().invoke(cli, ["run", str(job), "-o", str(out)]
                              + (["--quiet"] if quiet else []) + list(extra))


CASES = [
    # case, tool stick-out / flute length, what the one line must name
    ("holder", 30.0, 2.0, "holder contact"),    # 2 mm flutes 4 deep: the shank rubs
    ("rapid", 30.0, 20.0, "rapid through material"),
    ("gouge", 30.0, 20.0, "gouge"),
    ("feature", 30.0, 20.0, "feature not machined"),
]


@pytest.mark.parametrize("case,stickout,flutes,what", CASES)
def test_each_condition_refuses_the_program(tmp_path, gate_strategy, case, stickout,
                                            flutes, what):
    job = _job(tmp_path, case, stickout, flutes)
    out = tmp_path / "out"
    r = _run(job, out)
    assert r.exit_code == 1
    err = r.stderr.strip().splitlines()
    assert len(err) == 1, r.stderr
    assert err[0].startswith(f"millpath: error: {job}: program refused: ")
    assert what in err[0].split("program refused: ")[1].split(";")[0]
    names = {f.name for f in out.iterdir()}
    assert "program.ngc" not in names and "program.unsafe.ngc" not in names
    assert {"report.json", "preview.png", "stock.png", "deviation.png", "view.html"} <= names
    rep = json.loads((out / "report.json").read_text())
    assert rep["safety"]["status"] == "refused" and rep["program"] is None
    assert rep["safety"]["problems"][0]["kind"] == what
    if case in ("holder", "rapid"):
        p = rep["safety"]["problems"][0]
        assert p["line"] is not None and p["operation"] == 0 and p["at"] is not None

    forced = tmp_path / "forced"
    r = _run(job, forced, "--force")
    assert r.exit_code == 0, r.output
    names = {f.name for f in forced.iterdir()}
    assert "program.unsafe.ngc" in names and "program.ngc" not in names
    text = (forced / "program.unsafe.ngc").read_text()
    assert text.startswith("(UNSAFE PROGRAM")
    assert what.upper() in text.upper().split("(DO NOT RUN")[0]
    assert "warning" in r.stderr and "program.unsafe.ngc" in r.stderr


def test_holder_contact_names_a_move_at_the_cutting_depth(tmp_path, gate_strategy):
    """With 2 mm of flutes 4 mm deep the shank meets the material left above the flutes
    (the first side move at the latest): the problem names a program line whose motion
    ends at the cutting depth z -4 inside the pocket outline, and the operation."""
    out = tmp_path / "out"
    _run(_job(tmp_path, "holder", 30.0, 2.0), out)
    rep = json.loads((out / "report.json").read_text())
    p = rep["safety"]["problems"][0]
    assert p["at"][2] == -4.0 and 20.0 <= p["at"][0] <= 40.0 and p["at"][1] == 20.0
    assert p["operation"] == 0 and p["operation_name"] == "case holder"
    forced = tmp_path / "forced"
    _run(_job(tmp_path, "holder", 30.0, 2.0), forced, "--force")
    lines = (forced / "program.unsafe.ngc").read_text().splitlines()
    p = json.loads((forced / "report.json").read_text())["safety"]["problems"][0]
    assert "Z-4" in lines[p["line"] - 1]          # the named line of the written file


def test_depth_beyond_the_tool_reach_is_refused_before_planning_output(tmp_path,
                                                                     gate_strategy):
    """Stick-out 3 for a cut 4 deep: refused up front, naming the key."""
    r = _run(_job(tmp_path, "ok", 3.0, 3.0), tmp_path / "out")
    assert r.exit_code == 1
    (line,) = r.stderr.strip().splitlines()
    assert "operations[0]: T1 cuts 4 below the stock top but reaches only 3" in line
    assert not (tmp_path / "out").exists()


def test_the_same_job_with_a_long_tool_is_clean(tmp_path, gate_strategy):
    out = tmp_path / "out"
    r = _run(_job(tmp_path, "ok"), out, quiet=False)
    assert r.exit_code == 0, r.stderr
    assert (out / "program.ngc").exists()
    rep = json.loads((out / "report.json").read_text())
    assert rep["safety"] == {"status": "ok", "problems": []}
    assert "holder contacts 0" in r.stdout and "rapids through material 0" in r.stdout
    assert "features not machined 0" in r.stdout and "max gouge" in r.stdout


def test_features_left_on_purpose_are_listed_not_refused(tmp_path, gate_strategy):
    """``unmachinable = "list"`` (features operation): the user leaves the features it
    cannot machine for another setup; the program is written, the report keeps the list
    and the console says how many were left on purpose."""
    job = _job(tmp_path, "feature-listed")
    out = tmp_path / "out"
    r = _run(job, out, quiet=False)
    assert r.exit_code == 0, r.output
    assert (out / "program.ngc").exists()
    rep = json.loads((out / "report.json").read_text())
    assert rep["safety"]["status"] == "ok"
    assert rep["plans"][0]["features"]["unmachinable"][0]["id"] == 77
    text = " ".join(r.output.split())             # rich wraps at the terminal width
    assert "features not machined 0" in text and "1 left on purpose" in text
