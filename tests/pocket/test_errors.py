"""Bad pocket and profile input: one line ``millpath: error: FILE: message``, exit 1,
nothing written."""

from __future__ import annotations

import ezdxf
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli

HEAD = """units = "mm"
[stock]
box = [-10, -10, -10, 110, 110, 0]
[[tools]]
number = 1
type = "flat"
diameter = 6.0
[[operations]]
type = "pocket"
tool = 1
depth = 3.0
stepdown = 3.0
feed = 1000.0
"""


def _run(tmp_path, extra: str):
    job = tmp_path / "job.toml"
    job.write_text(HEAD + extra)
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["run", str(job), "-o", str(out)])
    assert r.exit_code == 1, r.output
    assert r.output.count("\n") == 1 and "Traceback" not in r.output
    assert not out.exists()
    return r.output.strip()


def _dxf(tmp_path, draw) -> str:
    doc = ezdxf.new()
    doc.header["$INSUNITS"] = 4
    draw(doc.modelspace())
    p = tmp_path / "part.dxf"
    doc.saveas(p)
    return p


def test_engagement_outside_0_1(tmp_path):
    msg = _run(tmp_path, 'polygon = [[0, 0], [50, 0], [50, 50], [0, 50]]\n'
                         'strategy = "adaptive"\nengagement = 1.2\n')
    assert msg.startswith(f"millpath: error: {tmp_path / 'job.toml'}:16: operations[0].engagement: "
                          "must be a fraction of the tool diameter in (0, 1), got 1.2")


def test_island_outside_the_pocket(tmp_path):
    msg = _run(tmp_path, 'polygon = [[0, 0], [50, 0], [50, 50], [0, 50]]\n'
                         'islands = [[[60, 10], [70, 10], [70, 20]]]\n')
    assert "islands[0]: the island at" in msg and "is not inside the pocket polygon" in msg


def test_tool_too_big_and_neck(tmp_path):
    msg = _run(tmp_path, 'polygon = [[0, 0], [5, 0], [5, 50], [0, 50]]\n')
    assert "does not fit in the pocket polygon" in msg and "is 5 wide" in msg
    msg = _run(tmp_path, 'polygon = [[0, 0], [20, 0], [20, 9], [30, 9], [30, 0], [50, 0], '
                         '[50, 20], [30, 20], [30, 11], [20, 11], [20, 20], [0, 20]]\n')
    assert "does not fit through the neck of the pocket polygon at (25.000, 10.000)" in msg


def test_dxf_without_closed_contour(tmp_path):
    p = _dxf(tmp_path, lambda m: (m.add_line((0, 0), (10, 0)), m.add_line((10, 0), (10, 10))))
    msg = _run(tmp_path, f'dxf = "{p}"\n')
    assert msg.startswith(f"millpath: error: {p}: entity ") and "open contour" in msg


def test_dxf_self_intersecting_contour(tmp_path):
    holder = {}

    def draw(m):
        holder["e"] = m.add_lwpolyline([(0, 0), (40, 40), (40, 0), (0, 40)], close=True)

    p = _dxf(tmp_path, draw)
    msg = _run(tmp_path, f'dxf = "{p}"\n')
    assert msg == (f"millpath: error: {p}: entity {holder['e'].dxf.handle}: the contour "
                   "crosses itself at (20.0000, 20.0000)")
