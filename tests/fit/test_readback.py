"""``millpath fit`` on programs with N words (as Fusion's LinuxCNC post writes them), and
the read-back of every fitted program before it is written.

Truth: LinuxCNC's rs274 reads the fitted program (``number=False``: the program's own N
words); millpath's interpreter and the program's points as written."""

from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.errors import MillpathError
from millpath.fit import fit_program
from millpath.fit.program import with_code
from millpath.verify.readback import read_back, stand_in_tools
from millpath.interpret import run


def fusion_program() -> str:
    """A Fusion-like program: every block numbered, a tool change with G43, a quarter
    circle of G1 moves (fitted into an arc), then numbered blocks that rely on the
    motion mode (a lone move at another feed) and a block-deleted one."""
    lines = ["%", "(fusion style)", "N10 G90 G94 G17", "N15 G21", "N20 T1 M6",
             "N25 S10000 M3", "N30 G0 G43 Z15. H1", "N35 G0 X20. Y0.", "N40 Z2.",
             "N45 G1 Z-1. F300."]
    n = 50
    for k in range(1, 91):
        a = math.radians(k)
        lines.append(f"N{n} X{20 * math.cos(a):.4f} Y{20 * math.sin(a):.4f} F1000.")
        n += 5
    lines += [f"N{n} X-5. Y25. F500.", f"/N{n + 5} X-10.", f"N{n + 10} X-12.",
              f"N{n + 15} G0 Z15.", f"N{n + 20} M5", f"N{n + 25} M30", "%"]
    return "\n".join(lines) + "\n"


def test_with_code_keeps_block_delete_and_line_number_first():
    assert with_code("G1", "N150 X1.") == "N150 G1 X1."
    assert with_code("G1", "  /N150X1.") == "/N150 G1 X1."
    assert with_code("G1", "n 1 5 0 x1") == "n 1 5 0 G1 x1"
    assert with_code("G1", "X1 Y2") == "G1 X1 Y2"


def test_fit_keeps_n_words_first_and_the_output_interprets(tmp_path):
    src = fusion_program()
    out = fit_program(src, 0.005)
    assert "G2" in out or "G3" in out
    for line in out.splitlines():
        s = line.strip().lstrip("/").strip()
        # a line number, when there is one, is the first word
        assert not (("N" in s) and s[:1] in "GXYZF" and s.find("N") > 0), line
    r = run(out, stand_in_tools(out), machine_units="mm")
    assert r.error is None, r.error
    back = read_back(src, out, 0.005)
    assert back.compared > 0 and back.deviation <= 0.005 * 1.031
    # the command reads it back and says so
    p = tmp_path / "fusion.ngc"
    p.write_text(src)
    res = CliRunner().invoke(cli, ["fit", str(p), "-t", "0.005", "-o", str(tmp_path / "o.ngc")])
    assert res.exit_code == 0, res.output
    assert "read back:" in res.output
    assert (tmp_path / "o.ngc").read_text() == out


@pytest.mark.rs274
def test_linuxcnc_reads_the_fitted_fusion_program(rs274):
    from support.rs274 import run_rs274
    src = fusion_program()
    out = fit_program(src, 0.005)
    tools = stand_in_tools(src)
    r0 = run_rs274(src, tools, number=False)
    r1 = run_rs274(out, tools, number=False)
    assert r0.ok, r0.error
    assert r1.ok, (r1.error, r1.error_block)
    # the same rapids, and the fitted feed ends on the program's last point
    e0 = [m.end for m in r0.motions if m.kind == "traverse"]
    e1 = [m.end for m in r1.motions if m.kind == "traverse"]
    assert np.allclose(e0, e1, atol=1e-6)


def test_read_back_refuses_what_does_not_interpret_or_leaves_the_path(tmp_path):
    src = fusion_program()
    out = fit_program(src, 0.005)
    # the old way of prefixing the motion mode: LinuxCNC's "Bad character 'n' used"
    bad = out.replace("N500 G1 X-5.", "G1 N500 X-5.")
    assert bad != out
    with pytest.raises(MillpathError, match=r"the fitted program does not interpret: "
                                            r"line \d+: Bad character 'n' used"):
        read_back(src, bad, 0.005)
    # an arc whose end is moved 0.05 off (its centre kept): out of the tolerance
    lines = out.splitlines()
    k = next(i for i, l in enumerate(lines) if l.startswith(("G2", "G3")) or " G3 " in l
             or " G2 " in l)
    words = lines[k].split()
    j = next(i for i, w in enumerate(words) if w.startswith("Y"))
    words[j] = f"Y{float(words[j][1:]) + 0.05:.4f}"
    lines[k] = " ".join(words)
    with pytest.raises(MillpathError, match="does not interpret|leaves the program's path"):
        read_back(src, "\n".join(lines) + "\n", 0.005)
    # a program that does not interpret is not fitted
    p = tmp_path / "bad.ngc"
    p.write_text("G21\nG0 X0 Y0 Z1\nG1 X1 F100 Q\nG1 X2\nG1 X3\nM2\n")
    res = CliRunner().invoke(cli, ["fit", str(p), "-t", "0.005"])
    assert res.exit_code == 1
    assert "the program does not interpret: line 3" in res.output
    assert not (tmp_path / "bad-fit.ngc").exists()


def test_read_back_finds_a_path_moved_within_a_run():
    src = "G21\nG0 X0 Y0 Z1\nG1 Z-1 F100\n" + "".join(
        f"X{k:.1f} Y0\n" for k in range(1, 11)) + "G0 Z5\nM2\n"
    moved = src.replace("X5.0 Y0", "X5.0 Y0.02")
    with pytest.raises(MillpathError, match=r"leaves the program's path by 0\.02"):
        read_back(src, moved, 0.01)
    read_back(src, moved, 0.03)
