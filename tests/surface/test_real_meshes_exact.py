"""Issue 25's real meshes, reduced (coarser scallop), proven by the exact verification
(``[simulation] exact = true``, issue 15): each operation's gouge measured normal to the
mesh within its tolerance, no holder contact, no rapid through material, the program
written (the safety gate passed). The textbox's letters are where the exact check once
took a cutter outside a letter, behind the plane of its end wall, for a 2 mm gouge.
Lengths in mm unless the job says inch."""

from __future__ import annotations

import json

import pytest

from millpath.pipeline import run_job

TOOLS = """[[tools]]
number = 1
type = "flat"
diameter = {d1}
flute_length = {fl}
stickout = {so}
holder = [[{h1}, {h2}]]
[[tools]]
number = 2
type = "ball"
diameter = {d2}
flute_length = {fl}
stickout = {so}
holder = [[{h1}, {h2}]]
"""

JOB = """units = "{units}"
[stock]
box = {stock}
{tools}
[[operations]]
type = "surface-rough"
surface = {surface}
tool = 1
stepdown = {stepdown}
allowance = {allowance}
[[operations]]
type = "surface-finish"
surface = {surface}
tool = 2
strategy = "{strategy}"
scallop = {scallop}
tolerance = {tol}
[simulation]
exact = true
"""


def _proven(tmp_path, text: str, tolerances: list[float]) -> dict:
    (tmp_path / "job.toml").write_text(text)
    run_job(tmp_path / "job.toml", tmp_path / "out")       # refused: UnsafeProgramError
    assert (tmp_path / "out" / "program.ngc").is_file()
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    v = rep["verification"]
    assert "operations[0] design" in v["reference"] and v["accuracy"] <= 0.001
    assert v["holder_contacts"] == 0 and v["rapids_through_material"] == 0
    rows = v["by_operation"]
    assert len(rows) == len(tolerances)
    for row, tol in zip(rows, tolerances):
        assert row["max_gouge"] <= tol + v["accuracy"], row
    assert rep["safety"]["status"] == "ok"
    return v


@pytest.mark.slow
def test_textbox_reduced_exact(tmp_path, shared_dir):
    """pycam-textbox.stl: rough 6 mm flat (stepdown 2, allowance 0.2), waterline 2 mm
    ball at scallop 0.1 (the issue: 0.02), tolerance 0.01."""
    stl = shared_dir / "meshes" / "pycam-textbox.stl"
    text = JOB.format(units="mm", stock="[0.0, 0.0, -10.0, 130.0, 50.0, 3.5]",
                      tools=TOOLS.format(d1=6.0, d2=2.0, fl=60.0, so=70.0, h1=30.0, h2=40.0),
                      surface=f'"{stl}"', stepdown=2.0, allowance=0.2,
                      strategy="waterline", scallop=0.1, tol=0.01)
    # surface-rough promises a quarter of its allowance (0.05 mm); the finish 0.01
    _proven(tmp_path, text, [0.05, 0.01])
