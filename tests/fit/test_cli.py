"""The ``millpath fit`` command."""

from __future__ import annotations

import math
import re

from click.testing import CliRunner

from millpath.cli.main import cli


def write_program(path, n=360):
    lines = ["G21 G90 G17", "G0 X10 Y0 Z2", "G1 Z-1 F200"]
    lines += [f"X{10 * math.cos(2 * math.pi * k / n):.4f} Y{10 * math.sin(2 * math.pi * k / n):.4f}"
              for k in range(1, n + 1)]
    lines += ["G0 Z5", "M2"]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_fit_writes_the_output_atomically_and_reports_counts(tmp_path):
    src = write_program(tmp_path / "part.ngc")
    out = tmp_path / "out" / "fitted.ngc"
    r = CliRunner().invoke(cli, ["fit", str(src), "--tolerance", "0.005", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "365 -> " in r.output and out.is_file()
    text = out.read_text()
    assert "G3" in text and len(text.splitlines()) < 20
    assert not list(out.parent.glob(".*.tmp"))


def test_fit_default_output_name_and_cubic_mode(tmp_path):
    src = write_program(tmp_path / "part.ngc")
    r = CliRunner().invoke(cli, ["fit", str(src), "-t", "0.005", "--mode", "arcs+cubics"])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "part-fit.ngc").is_file()


def test_fit_errors_are_one_line_with_the_file(tmp_path):
    src = write_program(tmp_path / "part.ngc")
    r = CliRunner().invoke(cli, ["fit", str(src), "-t", "-1"])
    assert r.exit_code == 1
    assert r.output.startswith(f"millpath: error: {src}: ") and r.output.count("\n") == 1
    r = CliRunner().invoke(cli, ["fit", str(tmp_path / "missing.ngc"), "-t", "0.01"])
    assert r.exit_code == 1 and "missing.ngc" in r.output
    r = CliRunner().invoke(cli, ["fit", str(src), "-t", "0.01", "-o", str(src)])
    assert r.exit_code == 1 and "overwrite" in r.output


def test_fit_min_radius_keeps_arcs_larger_than_it(tmp_path):
    src = write_program(tmp_path / "part.ngc")          # a 10 mm circle
    out = tmp_path / "fitted.ngc"
    r = CliRunner().invoke(cli, ["fit", str(src), "-t", "0.005", "--min-radius", "10.5",
                                 "-o", str(out)])
    assert r.exit_code == 0, r.output
    text = out.read_text()
    for line in text.splitlines():
        if re.match(r"G[23]\b", line):
            w = dict(re.findall(r"([IJ])(-?[\d.]+)", line))
            assert math.hypot(float(w["I"]), float(w["J"])) > 10.5
    assert len(text.splitlines()) > 100            # a 10 mm circle stays mostly lines
    r = CliRunner().invoke(cli, ["fit", str(src), "-t", "0.005", "--min-radius", "nan"])
    assert r.exit_code == 1 and "min radius" in r.output


def test_fit_says_why_it_changed_nothing(tmp_path):
    """Truth: a zigzag whose inner corners stand 0.5 mm off the segments joining their
    neighbours (computed by hand), and two moves in G91 that the fitter must not touch."""
    src = tmp_path / "zig.ngc"
    src.write_text("G21 G90 G17\nG0 X0 Y0 Z2\nG1 Z-1 F200\nX1 Y0.5\nX2 Y0\nX3 Y0.5\nX4 Y0\n"
                   "G91\nG1 X1\nX1\nG90\nG0 Z5\nM2\n")
    out = tmp_path / "fitted.ngc"
    r = CliRunner().invoke(cli, ["fit", str(src), "-t", "0.01", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert out.read_text() == src.read_text()
    why = r.output.splitlines()[-1]
    assert why.startswith("nothing fitted: of 7 G1 moves, 5 could not be fitted within "
                          "--tolerance 0.01")
    assert "one line needs a deviation of 0.5;" in why
    assert "2 in incremental distance mode (G91)" in why
    r = CliRunner().invoke(cli, ["fit", str(src), "-t", "0.6", "-o", str(out)])
    assert r.exit_code == 0 and "nothing fitted" not in r.output
    assert out.read_text() != src.read_text()
