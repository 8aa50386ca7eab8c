"""The machine as a program finds it: the units the control starts in (``--units``),
its stored work offsets (``--work-offset``, a LinuxCNC ``.var`` file with ``--var``).

Truths: LinuxCNC's rs274 (``-v FILE`` reads a parameter file; a program without
G20 read in inch moves as the same program with ``G20`` written first), and the
part's frame set by G54's stored offset (a ``G53 G0 Z0`` goes to the top of the
machine's travel, far above the part).
"""

from __future__ import annotations

import json
import subprocess

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli

FUSION_END = """G21 G90 G17
T1 M6 G43 H1
G0 X5 Y5 Z5
G1 Z-1 F100
G1 X20 F300
G53 G0 Z0
M30
"""
VAR = "5220 1\n5221 -200\n5222 -100\n5223 -150\n"


def _invoke(args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def _canon_ends(rs274, ngc, tbl, var=None):
    cmd = [rs274, "-t", str(tbl)] + (["-v", str(var)] if var else []) + ["-g", str(ngc)]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=60,
                         env={"HOME": str(ngc.parent), "PATH": "/usr/bin:/bin"}).stdout
    ends = []
    for line in out.splitlines():
        if "STRAIGHT_TRAVERSE(" in line or "STRAIGHT_FEED(" in line:
            nums = line.split("(", 1)[1].rstrip(")").split(",")
            ends.append([float(v) for v in nums[:3]])
    return ends


def test_var_file_places_g53_as_rs274(rs274, tmp_path):
    (tmp_path / "p.ngc").write_text(FUSION_END)
    (tmp_path / "t.tbl").write_text("T1 P1 D0.25 Z2\n")          # inches, as rs274 reads
    (tmp_path / "m.var").write_text(VAR)                           # inches too
    want = _canon_ends(rs274, tmp_path / "p.ngc", tmp_path / "t.tbl", tmp_path / "m.var")
    r = _invoke(["check", tmp_path / "p.ngc", "--tools", tmp_path / "t.tbl",
                 "--var", tmp_path / "m.var", "--json"])
    assert r.exit_code == 0, r.output
    got = [m["end"] for m in json.loads(r.stdout)["moves"] if m["kind"] != "dwell"]
    assert len(got) == len(want) == 4
    assert max(abs(a - b) for g, w in zip(got, want) for a, b in zip(g, w)) <= 5e-5
    assert got[-1][2] == pytest.approx(150 * 25.4 - 2 * 25.4)    # G53 Z0, in program mm


def test_fusion_closing_g53_is_no_rapid_through_material_with_the_work_offset(tmp_path):
    (tmp_path / "p.ngc").write_text(FUSION_END)
    (tmp_path / "t.tbl").write_text("; values in mm\nT1 P1 D6 Z50\n")
    (tmp_path / "m.var").write_text(VAR)                           # mm, as the table
    base = ["simulate", tmp_path / "p.ngc", "--tools", tmp_path / "t.tbl", "--stock",
            "0,0,-10,30,20,0", "--json"]
    bare = _invoke(base)
    assert bare.exit_code == 0, bare.output
    # without the machine's offsets machine Z0 is the part's zero: the tip goes 50 mm
    # below it, through the stock
    assert json.loads(bare.stdout)["rapids_through_material"] >= 1
    for extra in (["--var", tmp_path / "m.var"], ["--work-offset", "-200,-100,-150"]):
        r = _invoke(base + extra)
        assert r.exit_code == 0, r.output
        j = json.loads(r.stdout)
        assert j["rapids_through_material"] == 0
        assert j["removed_volume"] == pytest.approx(15 * 6 + 3.14159 * 9, rel=0.02)


def test_units_option_reads_a_program_without_g20_in_inch(rs274, tmp_path):
    body = "G0 X1 Y0.5 Z0.2\nG1 Z-0.05 F10\nG2 X2 Y0.5 I0.5 J0\nG0 Z0.2\nM2\n"
    (tmp_path / "p.ngc").write_text(body)
    (tmp_path / "g20.ngc").write_text("G20\n" + body)
    (tmp_path / "t.tbl").write_text("T1 P1 D0.25 Z0\n")
    want = _canon_ends(rs274, tmp_path / "g20.ngc", tmp_path / "t.tbl")
    r = _invoke(["check", tmp_path / "p.ngc", "--tools", tmp_path / "t.tbl", "--units",
                 "inch", "--json"])
    assert r.exit_code == 0, r.output
    j = json.loads(r.stdout)
    assert j["units"] == "inch"
    got = [m["end"] for m in j["moves"] if m["kind"] in ("traverse", "feed")]
    assert len(want) == len(got) == 3
    assert max(abs(a - b) for g, w in zip(got, want) for a, b in zip(g, w)) <= 5e-5
    # the same program read in mm by default
    plain = json.loads(_invoke(["check", tmp_path / "p.ngc", "--tools", tmp_path / "t.tbl",
                                "--json"]).stdout)
    assert plain["units"] == "mm"


def test_bad_var_file_names_its_line(tmp_path):
    (tmp_path / "p.ngc").write_text(FUSION_END)
    (tmp_path / "m.var").write_text("5221 -200\n5222 abc\n")
    r = _invoke(["check", tmp_path / "p.ngc", "--var", tmp_path / "m.var"])
    assert r.exit_code == 1
    assert r.output.strip().startswith(f"millpath: error: {tmp_path / 'm.var'}:2: ")
    r = _invoke(["check", tmp_path / "p.ngc", "--work-offset", "1,2"])
    assert r.exit_code == 1 and "--work-offset" in r.output
