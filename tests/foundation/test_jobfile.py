"""Job files: validation errors name the key and the file."""

import pytest

from millpath.errors import JobError
from millpath.job.jobfile import load_job

GOOD = """
units = "mm"
[stock]
box = [0, 0, -20, 150, 100, 0]
[machine]
rapid = 5000
max_feed = 3000
acceleration = 500
[[tools]]
number = 1
type = "flat"
diameter = 6
stickout = 30
holder = [[20, 40], [40, 60]]
"""

OP = """
[[operations]]
type = "test-square"
tool = 1
depth = 2
"""


def write(tmp_path, text):
    p = tmp_path / "job.toml"
    p.write_text(text)
    return p


@pytest.mark.parametrize("text, message", [
    ('units = "cm"\n[[operations]]\ntype = "x"', "units: must be one of"),
    ('units = "mm"\nspeed = 3\n[[operations]]\ntype = "x"', ".speed: unknown key"),
    ('units = "mm"\n[stock]\nbox = [0, 0, 0]\n[[operations]]\ntype = "x"',
     "stock.box: expected 6 numbers"),
    ('units = "mm"\n[stock]\nbox = [0, 0, 0, -1, 1, 1]\n[[operations]]\ntype = "x"',
     "stock.box: each min must be below its max"),
    ('units = "mm"\n[machine]\nrapid = "fast"\n[[operations]]\ntype = "x"',
     "machine.rapid: expected a number"),
    ('units = "mm"\n[machine]\nrapid = nan\n[[operations]]\ntype = "x"',
     "machine.rapid: must be finite"),
    ('units = "mm"\n[[tools]]\nnumber = 1\ndiameter = -6\n[[operations]]\ntype = "x"',
     "tools[0].diameter: must be positive"),
    ('units = "mm"\n[[tools]]\nnumber = 1\ndiameter = 6\ntype = "chamfer"\n'
     '[[operations]]\ntype = "x"', "tools[0].type: must be one of"),
    ('units = "mm"\n[[operations]]\ntype = "laser"', "operations[0].type: unknown operation"),
    ('units = "mm"\noperations = []', "at least one"),
    ('units = "mm"\n[[operations]]\ntool = 1', "operations[0].type: missing required key"),
    ('units = "mm" = 3', "invalid TOML"),
])
def test_bad_job_files_name_key_and_file(tmp_path, text, message):
    p = write(tmp_path, text)
    with pytest.raises(JobError) as e:
        load_job(p)
    assert message in str(e.value)
    assert str(e.value).startswith(str(p))


def test_good_job_loads_stock_machine_and_tools(tmp_path, test_strategy):
    job = load_job(write(tmp_path, GOOD + OP))
    assert job.units == "mm"
    assert job.stock.box == (0, 0, -20, 150, 100, 0)
    assert job.machine.rapid == 5000 and job.machine.acceleration == 500
    t = job.tools[1]
    assert t.holder == [(20.0, 40.0), (40.0, 60.0)] and t.stickout == 30
    assert job.operations[0] == ("test-square", {"tool": 1, "depth": 2.0, "fail": False})


def test_unknown_operation_key_is_rejected(tmp_path, test_strategy):
    p = write(tmp_path, GOOD + OP + "speed = 4\n")
    with pytest.raises(JobError, match=r"operations\[0\]\.speed: unknown key"):
        load_job(p)


def test_operation_with_unknown_tool_is_rejected(tmp_path, test_strategy):
    p = write(tmp_path, GOOD + OP.replace("tool = 1", "tool = 9"))
    with pytest.raises(JobError, match=r"operations\[0\]\.tool: tool 9 is not in"):
        load_job(p)


def test_missing_job_file_is_a_clean_error(tmp_path):
    with pytest.raises(JobError, match="no such job file"):
        load_job(tmp_path / "nope.toml")
