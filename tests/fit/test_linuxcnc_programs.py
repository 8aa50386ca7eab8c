"""fit_program on LinuxCNC's own trajectory-planner test programs (../shared).

Each program is fitted at 0.005 program units; millpath's interpreter (full precision)
must give motion within that distance of the original's, and LinuxCNC's rs274 must
accept the fitted program. rs274 prints positions with 4 decimals, too coarse to
measure a 0.005 in tolerance in inch programs, so the distance is measured on
millpath's interpretation, sampling every half tolerance (the measurement never
overestimates; these paths are up to 850 units long).
"""

from __future__ import annotations

import pytest

from millpath.fit import fit_program

TP = "linuxcnc/tests/trajectory-planner/circular-arcs/nc_files"
PROGRAMS = [
    "diagnostic/tangent_check.ngc",
    "performance/spiral_lines.ngc",
    "quick-tests/dodecagon_0.1in.ngc",
    "performance/line-contouring-xz.ngc",
    "violation_checks/stellabee-violation-spirals.ngc",
    "performance/random_lines_0.001in.ngc",
    "performance/zigzag_0.002_0.001.ngc",
    "quick-tests/linearc-stellabee.ngc",
    "quick-tests/sam-tolerance-issue.ngc",
    "performance/blur_torus.ngc",
]


def _moves(motions):
    from millpath.model.toolpath import Move
    out = []
    for m in motions:
        if m.kind in ("feed", "traverse"):
            out.append(Move("line", m.end))
        elif m.kind == "arc":
            out.append(Move("arc", m.end, center=m.center, plane=m.plane,
                            clockwise=m.rotation < 0, turns=abs(m.rotation)))
    return out


@pytest.mark.parametrize("name", PROGRAMS)
def test_linuxcnc_test_programs_fit_within_tolerance(shared_dir, rs274, fitkit, name):
    from millpath.interpret import interpret
    from support.rs274 import run_rs274
    path = shared_dir / TP / name
    if not path.is_file():
        pytest.skip(f"{name} is not in ../shared")
    text = path.read_text()
    out = fit_program(text, 0.005, "arcs", file=str(path))
    assert len(out.splitlines()) < len(text.splitlines())
    a = [m for m in interpret(text) if m.kind in ("feed", "traverse", "arc")]
    b = [m for m in interpret(out) if m.kind in ("feed", "traverse", "arc")]
    assert fitkit.hausdorff(a[0].start, _moves(a), _moves(b), 0.005 / 2) <= 0.005 * 1.002
    r = run_rs274(out)
    assert r.ok, (r.error, r.error_block)
