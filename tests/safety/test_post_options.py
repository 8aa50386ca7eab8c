"""[post] options written as asked and run the same by LinuxCNC's rs274
and millpath's interpreter; the safe approach after each tool change (item 5)."""

import pytest

from millpath.interpret import interpret
from support.difftest import compare_motions
from millpath.io.schema import validate
from millpath.job.jobfile import POST
from millpath.model import Operation, Tool, Toolpath
from millpath.post.writer import PostOptions, post

TOOLS = {1: Tool(1, "flat", 6.0, stickout=30, flute_length=18),
         2: Tool(2, "flat", 4.0, stickout=30, flute_length=18)}


def _tp():
    tp = Toolpath("mm")
    for n, x in ((1, 10.0), (2, 30.0)):
        tp.begin(Operation("test", f"op {n}", n, 9000, coolant="flood"))
        tp.rapid(x, 10, 5)
        tp.line(x, 10, -1, 100)
        tp.line(x + 10, 10, -1, 200)
        tp.rapid(x + 10, 10, 5)
    return tp


def _words(text):
    return [ln.split("(")[0].split() for ln in text.splitlines()]


OPTIONS = dict(coolant="mist", work_offset="G55", end="M30", line_numbers=True,
               tool_change="G53 G0 Z0", program_number=1234,
               preamble="G64 P0.01\nF50", postamble="G0 Z25")


def test_job_post_table_is_validated_and_fills_the_options(tmp_path):
    v = validate(OPTIONS, POST, "post", tmp_path / "job.toml", tmp_path)
    assert v.pop("machine") is None         # read by the job reader (a machine file)
    assert PostOptions(**v) == PostOptions(**OPTIONS)
    with pytest.raises(Exception, match="post.work_offset"):
        validate({"work_offset": "G60"}, POST, "post", tmp_path / "job.toml", tmp_path)


def test_every_option_is_written():
    text = post(_tp(), TOOLS, options=PostOptions(**OPTIONS))
    lines = text.splitlines()
    assert lines[0] == "(O1234)"
    body = [ln for ln in lines if not ln.startswith("(")]
    assert all(ln.startswith(f"N{10 * (i + 1)} ") for i, ln in enumerate(body))
    words = [w[1:] for w in _words(text) if w]
    flat = [" ".join(w) for w in words]
    assert "G55" in flat and "G64 P0.01" in flat and "F50" in flat
    assert flat.count("G53 G0 Z0") == 2                       # before each M6
    assert [i for i, f in enumerate(flat) if f.endswith("M6")] == \
        [flat.index("G53 G0 Z0") + 1, len(flat) - 1 - flat[::-1].index("G53 G0 Z0") + 1]
    assert flat.count("M7") == 2 and "M8" not in flat
    assert flat[-1] == "M30" and flat[-4] == "G0 Z25"


def test_rs274_runs_the_options_as_millpath_does(rs274):
    from support.rs274 import run_rs274
    text = post(_tp(), TOOLS, options=PostOptions(**OPTIONS))
    ours = interpret(text, TOOLS, machine_units="mm")
    theirs = run_rs274(text, TOOLS, table_units="mm")
    assert theirs.ok, theirs.error
    assert compare_motions(ours, theirs.motions, 1.5e-4) == []


def test_after_each_tool_change_z_rises_first_then_xy_then_down():
    text = post(_tp(), TOOLS)
    motions = interpret(text, TOOLS, machine_units="mm")
    lines = text.splitlines()
    for n in (1, 2):
        m6 = lines.index(f"T{n} M6") + 1
        after = [m for m in motions if m.line > m6][:3]
        up, across, down = after
        assert up.kind == "traverse" and up.end[:2] == up.start[:2] and up.end[2] == 5.0
        assert across.end[2] == across.start[2] == 5.0
        assert down.kind == "feed" and down.end[:2] == across.end[:2]
