"""Misprints of Mohamed (2006), seeds/001, against independent derivations.

- Eq. (5) prints the tangent basis G2'(u) = 41.5 u^2 - 45 u + 9 and G3'(u) =
  -41.5 u^2 + 36 u - 4.5; the derivative of the cubic Lagrange basis on u = 0, 1/3,
  2/3, 1 has 40.5. Eq. (18) repeats it (Q = -13.5 P1 + 41.5 P2 - 41.5 P3 + 13.5 P4)
  and prints R = 18 P1 - 45 P2 + 36 P3 - 36 P4 for ... - 9 P4.
- Table 2's chordal deviations disagree with the paper's own curve (Table 1 points).
"""

from __future__ import annotations

import numpy as np

from millpath.part.curve.fourpoint import DBASIS, FourPointSegment, basis, dbasis
from millpath.part.curve.linearize import chord_deviation

# printed eq. (5) rows: coefficients of (u^2, u, 1) of G1'..G4'
PRINTED_DBASIS = np.array([[-13.5, 18.0, -5.5], [41.5, -45.0, 9.0],
                           [-41.5, 36.0, -4.5], [13.5, -9.0, 1.0]])
PRINTED_R = np.array([18.0, -45.0, 36.0, -36.0])     # eq. (18)'s R (the u coefficients)
SEG1 = np.array([[1.0, 15.0], [3.0, 14.0], [5.0, 12.5], [7.0, 10.0]])      # Table 1
SEG2 = np.array([[7.0, 10.0], [10.33, 4.38], [14.11, 0.44], [15.0, 8.0]])


def _tangent(coeffs, P, u):
    u = np.asarray(u, float)[:, None]
    g = coeffs[:, 0] * u ** 2 + coeffs[:, 1] * u + coeffs[:, 2]     # (n, 4)
    return g @ P


def test_printed_tangent_basis_fails_and_the_derived_one_holds():
    u = np.linspace(0.0, 1.0, 11)
    # independent truth 1: a central difference of the basis functions themselves
    h = 1e-6
    fd = (basis(u[1:-1] + h) - basis(u[1:-1] - h)) / (2 * h)
    assert np.abs(dbasis(u[1:-1]) - fd).max() < 1e-7
    printed = PRINTED_DBASIS[:, 0] * u[1:-1, None] ** 2 + PRINTED_DBASIS[:, 1] * u[1:-1, None] \
        + PRINTED_DBASIS[:, 2]
    assert np.abs(printed - fd).max() > 0.2
    # independent truth 2: points evenly spaced on a line are interpolated by the line
    # itself, P(u) = P1 + u (P4 - P1), whose tangent is P4 - P1 everywhere
    P = np.array([[0.0, 0.0], [1.0, 2.0], [2.0, 4.0], [3.0, 6.0]])
    exact = np.broadcast_to(P[3] - P[0], (len(u), 2))
    assert np.abs(_tangent(DBASIS, P, u) - exact).max() < 1e-12
    assert np.abs(_tangent(PRINTED_DBASIS, P, u) - exact).max() > 0.3


def test_printed_R_of_eq_18_fails_on_a_point_curve():
    # a "curve" whose four points coincide does not move: every tangent coefficient
    # sums to zero over P1..P4
    assert DBASIS[:, 1].tolist() == [18.0, -45.0, 36.0, -9.0]
    assert DBASIS.sum(axis=0).tolist() == [0.0, 0.0, 0.0]
    assert PRINTED_R.sum() == -27.0


def _dense_deviation(P, a, b, n=200_001):
    u = np.linspace(a, b, n)
    C = basis(u) @ P
    d = C[-1] - C[0]
    nrm = np.array([-d[1], d[0]]) / np.hypot(*d)
    return float(np.abs((C - C[0]) @ nrm).max())


def test_table_2_deviations_disagree_with_the_papers_curve():
    """Table 2's first chords (u from, u to, printed delta * 1e5): five of the six
    printed values are not the deviation of those chords on the Table 1 curve (segment
    2's are about 8 times too large; segment 1's off by -20 % and +55 %, only its third
    agrees); millpath's closed form (the tangent-parallel points of the mean value
    theorem) is the deviation, to 1e-12."""
    rows = [(SEG1, 0.0, 0.028, 2.1478), (SEG1, 0.028, 0.05, 1.3047),
            (SEG1, 0.05, 0.066, 2.270), (SEG2, 0.0, 0.00125, 1.578),
            (SEG2, 0.00125, 0.00267, 1.9738), (SEG2, 0.00267, 0.00409, 2.0162)]
    wrong = []
    for k, (P, a, b, printed) in enumerate(rows):
        dense = _dense_deviation(P, a, b)
        ours = float(chord_deviation(FourPointSegment(P), a, b))
        assert abs(ours - dense) <= 1e-12 + 1e-9 * dense
        if abs(printed * 1e-5 - dense) > 0.1 * dense:
            wrong.append(k)
        else:
            assert abs(printed * 1e-5 - dense) < 0.01 * dense
    assert wrong == [0, 1, 3, 4, 5]
    # the printed chord end at u = 0.05 is not on the curve either
    assert np.abs(basis(0.05) @ SEG1 - [1.468, 14.7844]).max() > 0.07
    assert np.abs(basis(0.028) @ SEG1 - [1.168, 14.923]).max() < 1e-3
