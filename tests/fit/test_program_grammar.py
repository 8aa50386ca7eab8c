"""``millpath fit`` reads programs with the interpreter's lexer (one grammar): lines in
any case, spacing and word order are followed and fitted like the post's own shape.

Truth: millpath's interpreter (checked against rs274 elsewhere) on both outputs."""

from __future__ import annotations

import math

from millpath.fit import fit_program
from millpath.interpret import interpret

HEAD = ["%", "G21 G90 G17 G94", "G0 X10 Y0 Z2", "G1 Z-1 F200"]
TAIL = ["G0 Z5", "M2", "%"]


def _circle(n=120, r=10.0):
    pts = [(r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n))
           for k in range(1, n + 1)]
    return pts


def _motion(text):
    return [(m.kind, tuple(round(v, 4) for v in m.end)) for m in interpret(text)]


def test_free_form_lines_are_fitted_like_the_posts_shape():
    pts = _circle()
    plain = [f"G1 X{x:.4f} Y{y:.4f}" if k == 0 else f"X{x:.4f} Y{y:.4f}"
             for k, (x, y) in enumerate(pts)]
    # the same moves: lower case, blanks inside numbers, Y before X, an N word
    free = [f"n{k + 10} g 1 y {y:.4f}  x{x:.4f}" if k == 0 else f"y{y:.4f} X {x:.4f}"
            for k, (x, y) in enumerate(pts)]
    a = fit_program("\n".join(HEAD + plain + TAIL) + "\n", 0.005)
    b = fit_program("\n".join(HEAD + free + TAIL) + "\n", 0.005)
    na = sum(1 for l in a.splitlines() if l.startswith(("G2", "G3")))
    nb = sum(1 for l in b.splitlines() if l.startswith(("G2", "G3")))
    assert na > 0 and na == nb
    assert len(b.splitlines()) == len(a.splitlines()) < len(HEAD) + len(pts) + len(TAIL)
    assert _motion(a) == _motion(b)


def test_lines_with_parameters_are_not_followed():
    """An expression line makes the position unknown; X and Y alone do not give Z back,
    so nothing after it is rewritten (as before the lexer)."""
    pts = _circle()
    body = [f"G1 X[{pts[0][0]:.4f}] Y{pts[0][1]:.4f}"] + [f"X{x:.4f} Y{y:.4f}"
                                                          for x, y in pts[1:]]
    src = "\n".join(HEAD + body + TAIL) + "\n"
    assert fit_program(src, 0.005) == src
