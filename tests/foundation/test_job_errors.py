"""Every problem of a job file in one run: one line each at the line of its key, at most
MAX_SHOWN lines and then "... and N more", exit 1 and nothing written."""

from __future__ import annotations

from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.errors import MAX_SHOWN
from millpath.io.tomllines import key_lines, line_of

HEAD = """units = "mm"
[stock]
box = [0, 0, -10, 50, 50, 0]

[[tools]]
number = 1
type = "flat"
diameter = 6
"""

OP = """
[[operations]]
type = "{type}"
tool = 1
polygon = [[5, 5], [45, 5], [45, 45], [5, 45]]
depth = 4
stepdown = 2
feed = 600
"""


def _line(text: str, written: str, nth: int = 0) -> int:
    """The 1-based line of the ``nth`` line reading ``written``."""
    return [k for k, s in enumerate(text.splitlines(), 1) if s == written][nth]


def _run(tmp_path, text: str):
    job = tmp_path / "job.toml"
    job.write_text(text)
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["run", str(job), "-o", str(out), "--quiet"])
    return job, out, r


def test_three_wrong_keys_in_three_operations_are_reported_in_one_run(tmp_path):
    text = (HEAD + OP.format(type="pocket") + "bogus = 3\n"
            + OP.format(type="profile").replace("depth = 4", 'depth = "deep"')
            + OP.format(type="pocket").replace("stepdown = 2", "stepdown = -1"))
    a, b, c = (_line(text, w) for w in ("bogus = 3", 'depth = "deep"', "stepdown = -1"))
    job, out, r = _run(tmp_path, text)
    assert r.exit_code == 1 and not out.exists()
    err = r.stderr.splitlines()
    assert len(err) == 3, r.stderr
    assert err[0].startswith(f"millpath: error: {job}:{a}: operations[0].bogus: unknown key")
    assert err[1] == (f"millpath: error: {job}:{b}: operations[1].depth: expected a number, "
                      f"got str 'deep'")
    assert err[2] == (f"millpath: error: {job}:{c}: operations[2].stepdown: must be "
                      f"positive, got -1")


def test_top_level_tool_and_operation_problems_together(tmp_path):
    text = ('units = "mm"\nspeed = 3\n' + HEAD.split("\n", 1)[1].replace(
        "diameter = 6", "diameter = -6") + OP.format(type="pocket").replace(
        "feed = 600", "feed = true"))
    job, out, r = _run(tmp_path, text)
    err = r.stderr.splitlines()
    assert r.exit_code == 1 and not out.exists()
    want = [_line(text, w) for w in ("speed = 3", "diameter = -6", "feed = true")]
    assert [int(e.split(": ")[2].split(":")[1]) for e in err] == want, err
    assert ".speed: unknown key" in err[0] and "tools[0].diameter" in err[1] \
        and "operations[0].feed: expected a number" in err[2]
    assert not any("is not in the job's [[tools]]" in e for e in err)


def test_errors_are_capped(tmp_path):
    n = MAX_SHOWN + 5
    text = HEAD + OP.format(type="pocket") + "".join(f"bad_{k} = 1\n" for k in range(n))
    job, out, r = _run(tmp_path, text)
    err = r.stderr.splitlines()
    assert r.exit_code == 1 and not out.exists()
    assert len(err) == MAX_SHOWN + 1
    assert err[-1] == "millpath: error: ... and 5 more"
    assert err[0].startswith(f"millpath: error: {job}:{_line(text, 'bad_0 = 1')}: operations[0].bad_0: unknown key")


def test_key_lines_follow_tables_arrays_and_multiline_values():
    text = ('units = "mm"  # a comment = 1\n[stock]\nbox = [0, 0,\n  -10, 50, 50, 0]\n'
            '[[operations]]\ntype = "pocket"\nbottom = {bezier = [[1, 2]]}\n'
            's = """\nx = 3\n"""\n[[operations]]\n"feed" = 3\n[operations.sub]\nc = 1\n')
    lines = key_lines(text)
    assert lines == {"units": 1, "stock": 2, "stock.box": 3, "operations[0]": 5,
                     "operations[0].type": 6, "operations[0].bottom": 7,
                     "operations[0].s": 8, "operations[1]": 11, "operations[1].feed": 12,
                     "operations[1].sub": 13, "operations[1].sub.c": 14}
    assert line_of(".units: bad", lines) == 1
    assert line_of("operations[0].bottom.bezier: bad", lines) == 7   # inline table
    assert line_of("operations[1].sub.c[3]: bad", lines) == 14      # list item
    assert line_of("operations[1].feedx: unknown key", lines) == 11  # its table
    assert line_of("no key named", lines) is None
