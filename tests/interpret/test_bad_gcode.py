"""Bad G-code and tool tables never crash or hang ``millpath check``.

Each case is a reproducer of one failure found by fuzzing: the command must exit 1 with
one line ``millpath: error: FILE:LINE: message`` naming the file, within a time and
memory bound (the child runs under a 2 GB address-space limit). Where rs274 reports
the same error, its wording is expected (checked against rs274 in
``test_messages_match_rs274``).
"""

from __future__ import annotations

import resource
import subprocess
import sys
import time

import pytest

BIG = "9" * 29
CASES = {
    # name: (program, line, message)
    "exp-overflow": ("G21\nG1 X[EXP[1000]] F100\nM2\n", 2, "Calculation resulted in 'infinity'"),
    "power-overflow": ("G21\nG1 X[10**400] F100\nM2\n", 2, "Calculation resulted in 'infinity'"),
    "negative-power-overflow": ("G21\nG1 X[-2**2001] F100\nM2\n", 2,
                                "Calculation resulted in 'infinity'"),
    "product-overflow": ("G21\n#1=" + "9" * 100 + "\n#2=[#1*#1*#1*#1]\nM2\n", 3,
                         "Calculation resulted in 'infinity'"),
    "mod-zero": ("G21\nG1 X[1 MOD 0] F100\nM2\n", 2, "Calculation resulted in 'not a number'"),
    "huge-g": ("G21\nG" + BIG + "\nM2\n", 2, "Negative g code used"),
    "fraction-g": ("G21\nG1.23\nM2\n", 2, "G-code out of range"),
    "huge-m": ("G21\nM" + BIG + "\nM2\n", 2, "Negative m code used"),
    "huge-t": ("G21\nT" + BIG + "\nM2\n", 2, "Negative tool id (tool not found)"),
    "huge-l": ("G21 F100\nG0 X0 Y0 Z1\nG81 X1 Z-1 R1 L" + BIG + "\nM2\n", 3,
               "Negative l word used"),
    "arc-turns": ("G21 F100\nG2 X1 Y0 I0.5 J0 P1000000000000\nM2\n", 2,
                  "P value not an integer with M19 G2 or G3"),
    "nested-brackets": ("G21\nG1 X" + "[" * 500 + "1" + "]" * 500 + " F100\nM2\n", 2,
                        "Command too long"),
    "long-number": ("G21\nG" + "9" * 340 + "\nM2\n", 2, "Command too long"),
    "recursion": ("G21\no<r> sub\no<r> call\no<r> endsub\no<r> call\nM2\n", 3,
                  "Too many subroutine levels"),
    "endless-while": ("G21\no100 while [1]\no100 endwhile\nM2\n", 3,
                      "loop ran 100000 times without motion: endless loop?"),
    "endless-repeat": ("G21\no100 repeat [1e300]\no100 endrepeat\nM2\n", 2,
                       "Unknown operation name starting with e"),
    "huge-repeat": ("G21\no100 repeat [" + "9" * 200 + "]\no100 endrepeat\nM2\n", 2,
                    "repeat 1e+200 times: more than the 1000000 loop iterations a program "
                    "may run"),
    "moving-repeat": ("G21 F100\no1 repeat [4294967296]\nG1 X1\nG1 X0\no1 endrepeat\nM2\n", 2,
                      "repeat 4294967296 times: more than the 1000000 loop iterations a "
                      "program may run"),
    "moving-while": ("G21 F100\no1 while [1]\nG1 X1\nG1 X0\no1 endwhile\nM2\n", 4,
                     "the program read more than 5000000 characters through its loops and calls: "
                     "endless loop?"),
    "huge-coordinate": ("G21\nG1 X100000000000000000000 F100\nM2\n", 2,
                        "X word 1e+20 is larger than the 1e+09 limit"),
    "huge-parameter-coordinate": ("G21\n#1=[10**20]\nG1 Y#1 F100\nM2\n", 3,
                                  "Y word 1e+20 is larger than the 1e+09 limit"),
    "huge-arc-radius": ("G21 F100\nG0 X0 Y0\nG2 X1 Y0 R100000000000000000000\nM2\n", 3,
                        "R word 1e+20 is larger than the 1e+09 limit"),
    "tiny-peck": ("G21 F100\nG0 X0 Y0 Z1\nG83 X1 Z-1000 R1 Q0.0000000001\nM2\n", 3,
                  "canned cycle would make more than 1000000 moves "
                  "(1 repeats, 1e+13 pecks each)"),
    "many-repeats": ("G21 F100\nG0 X0 Y0 Z1\nG81 X1 Z-1 R1 L2000000000\nM2\n", 3,
                     "canned cycle would make more than 1000000 moves "
                     "(2000000000 repeats, 1 pecks each)"),
}
#: wall-clock bound per case: the child's start-up (imports) plus the work, on a loaded
#: 2-core machine; the endless loops trip in well under this
SECONDS = 20.0
MEMORY = 2 << 30


def _limit() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def _check(args, cwd) -> tuple[subprocess.CompletedProcess, float]:
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "millpath.cli.main", *args], cwd=cwd,
                       capture_output=True, text=True, timeout=SECONDS * 3,
                       preexec_fn=_limit)
    return p, time.perf_counter() - t0


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_program_is_one_line_error(name, tmp_path):
    text, line, message = CASES[name]
    (tmp_path / f"{name}.ngc").write_text(text)
    p, seconds = _check(["check", f"{name}.ngc"], tmp_path)
    assert p.returncode == 1, p.stderr
    assert p.stdout == ""
    assert p.stderr == f"millpath: error: {name}.ngc:{line}: {message}\n"
    assert seconds < SECONDS


@pytest.mark.parametrize("row,message", [
    ("T1 P1 Z-1e308 D1", "number out of range in word 'Z-1e308' (limit 1e+09)"),
    ("T1 P1 Z1 D1e400", "non-finite number in word 'D1e400'"),
    ("T1 P1 Znan D1", "non-finite number in word 'Znan'"),
    ("T1 P1 X-inf D1", "non-finite number in word 'X-inf'"),
    ("T1e300 P1 D1", "number out of range in word 'T1e300' (limit 1e+09)"),
])
def test_bad_tool_table_is_one_line_error(row, message, tmp_path):
    (tmp_path / "p.ngc").write_text("G21 F100\nT1 M6 G43\nG1 X1\nM2\n")
    (tmp_path / "t.tbl").write_text("T2 P2 Z1 D0.5\n" + row + "\n")
    p, seconds = _check(["check", "p.ngc", "--tools", "t.tbl"], tmp_path)
    assert p.returncode == 1
    assert p.stderr == f"millpath: error: t.tbl:2: {message}\n"
    assert seconds < SECONDS


def test_coordinates_up_to_the_limit_give_a_summary(tmp_path):
    """Coordinates up to the limit (1e9, rs274 takes any finite number) give a summary
    whose lengths and cycle time do not overflow."""
    (tmp_path / "p.ngc").write_text("G21 F100\n#1=[999999999]\nG1 X#1 Y#1\n"
                                    "G0 X-#1\nM2\n")
    p, _ = _check(["check", "p.ngc"], tmp_path)
    assert p.returncode == 0, p.stderr
    assert "feed length 1414213560.959 mm" in p.stdout


@pytest.mark.parametrize("name", sorted(n for n in CASES if n not in (
    "endless-while", "huge-repeat", "tiny-peck", "many-repeats", "long-number",
    "moving-repeat", "moving-while", "huge-coordinate", "huge-parameter-coordinate",
    "huge-arc-radius")))
def test_messages_match_rs274(name, rs274, tmp_path):
    """The same reproducers through LinuxCNC's rs274: same message, same line text
    (the cases millpath bounds where rs274 runs on for minutes are left out)."""
    text, line, message = CASES[name]
    f = tmp_path / f"{name}.ngc"
    f.write_text(text)
    with open(f) as stdin_null:
        q = subprocess.run([str(rs274), "-g", str(f)], capture_output=True, text=True,
                           stdin=stdin_null, timeout=60)
    out = [s for s in (q.stdout + q.stderr).splitlines()
           if s.strip() and not s.lstrip()[:1].isdigit() and s.strip() != "executing"]
    assert message in out, out
    # rs274 prints the failing line (truncated to its buffer)
    assert out[out.index(message) + 1].strip()[:200] == text.splitlines()[line - 1][:200]


def _peak_mb(args, cwd) -> tuple[int, float, str]:
    """Exit status, peak resident MB and stdout of one ``millpath`` child."""
    import os
    with open(cwd / "out.txt", "w") as out:
        p = subprocess.Popen([sys.executable, "-m", "millpath.cli.main", *args], cwd=cwd,
                             stdout=out, stderr=subprocess.DEVNULL)
        _, status, ru = os.wait4(p.pid, 0)
    return os.waitstatus_to_exitcode(status), ru.ru_maxrss / 1024, (cwd / "out.txt").read_text()


@pytest.mark.slow
def test_check_memory_does_not_grow_with_motion(tmp_path):
    """``check`` streams motion into its summary: on a 1,000,000-move program it peaks
    at its 10-line peak plus a small multiple of the program text, not plus the 100 MB
    its motion records would take (the issue's bound: 10,000,000 lines under 1 GB)."""
    lines = ["G21 F1000", "G0 X0 Y0 Z1"]
    lines += [f"G1 X{i % 1000}.5 Y{i % 7}" for i in range(1_000_000)]
    lines.append("M2")
    text = "\n".join(lines) + "\n"
    (tmp_path / "long.ngc").write_text(text)
    (tmp_path / "short.ngc").write_text("\n".join(lines[:10] + ["M2"]) + "\n")
    status, base, _ = _peak_mb(["check", "short.ngc"], tmp_path)
    assert status == 0
    status, peak, out = _peak_mb(["check", "long.ngc"], tmp_path)
    assert status == 0
    assert "feed 1000000" in out
    text_mb = len(text) / (1 << 20)
    assert peak - base < 3 * text_mb + 20, (base, peak, text_mb)
