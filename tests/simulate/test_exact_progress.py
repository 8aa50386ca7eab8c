"""The exact verification shows its progress as it goes: the motions-checked bar moves
within a block of motions (its chords and material-left rays are checked in slices),
never backwards, and ends at count/count; the material-left peak search has a bar of
its own, one step per grid. Slicing the work changes no figure: ball passes over a
plate leave scallop cusps of R - sqrt(R^2 - (w/2)^2), w the stepover (accuracy
0.001 mm), however the work is sliced."""

from __future__ import annotations

import math
from contextlib import contextmanager

import numpy as np
import pytest

from millpath.model import Stock, Tool
from millpath.model.motion import Motion
from millpath.simulate import exact
from millpath.simulate.exact import Reference, orient_outward, verify_exact
from millpath.simulate.leftpeak import peak_rounds

ACC = 0.001
BALL = Tool(1, "ball", 6.0, flute_length=20, stickout=30)
W = 1.3


class _Bar:
    def __init__(self, total):
        self.total = total
        self.completed = 0.0
        self.seen: list[tuple[float, float]] = []

    def update(self, *, completed=None, total=None, info=None):
        if completed is not None:
            self.completed = completed
        if total is not None:
            self.total = total
        self.seen.append((self.completed, self.total))

    def advance(self, n=1.0):
        self.update(completed=self.completed + n)


class _Bars:
    """Records every bar's updates (the calls :class:`millpath.progress.Progress` takes)."""

    def __init__(self):
        self.bars: dict[str, _Bar] = {}

    @contextmanager
    def task(self, label, total=None):
        self.bars[label] = _Bar(total)
        yield self.bars[label]


def _plate() -> np.ndarray:
    lo, hi = (-10, -10, -5), (10, 10, 0)
    v = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                  for z in (lo[2], hi[2])], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tri = [[v[a], v[b], v[c]] for a, b, c, d in quads] + [[v[a], v[c], v[d]]
                                                          for a, b, c, d in quads]
    return orient_outward(np.array(tri))


def _passes(dip: float = 0.0) -> list[Motion]:
    """Ball passes along X at tip z = 0, W apart, each in 16 moves; the 10th pass runs
    ``dip`` below z = 0 from x = 0 to 2."""
    out, y = [], -13.0
    xs = np.linspace(-16.0, 16.0, 17)
    for k in range(int((25.0 + W) // W) + 1):
        out += [Motion("feed", 1, (a, y, -dip if (k == 9 and a == 0.0) else 0.0),
                       (b, y, -dip if (k == 9 and a == 0.0) else 0.0), 500, tool=1)
                for a, b in zip(xs[:-1], xs[1:])]
        y += W
    return out


def _run(bars=None, dip: float = 0.0):
    return verify_exact(_passes(dip), {1: BALL}, Stock(-10, -10, -5, 10, 10, 1),
                        [Reference(_plate(), "plate")], accuracy=ACC,
                        **({"progress": bars} if bars is not None else {}))


def test_bars_move_within_a_block_and_end_full(monkeypatch):
    monkeypatch.setattr(exact, "LEAST_CHORDS", 1)
    monkeypatch.setattr(exact, "LEAST_RAYS", 1)
    bars = _Bars()
    res = _run(bars)
    n = len(_passes())
    motions = bars.bars["verifying exactly: motions checked"]
    done = [c for c, _ in motions.seen]
    assert all(b >= a for a, b in zip(done, done[1:])), "the bar never goes back"
    inside = {round(c, 6) for c, t in motions.seen if 0 < c < t}
    assert len(inside) >= exact.TICKS, f"{len(inside)} steps inside one block of {n} motions"
    assert motions.seen[-1][0] == motions.seen[-1][1] in (n, 2 * n)
    peaks = bars.bars["verifying exactly: material-left peaks"]
    rounds = peak_rounds(res.spacing, ACC) + 1
    assert peaks.total == rounds
    assert peaks.completed == rounds
    assert len(peaks.seen) >= rounds      # one step per grid
    cusp = BALL.radius - math.sqrt(BALL.radius ** 2 - (W / 2) ** 2)
    assert res.max_left == pytest.approx(cusp, abs=ACC)


@pytest.mark.parametrize("dip", [0.0, 0.05])
def test_slicing_changes_no_figure(monkeypatch, dip):
    whole = _run(dip=dip)
    monkeypatch.setattr(exact, "LEAST_CHORDS", 1)
    monkeypatch.setattr(exact, "LEAST_RAYS", 1)
    sliced = _run(_Bars(), dip=dip)
    assert whole.max_gouge == pytest.approx(dip, abs=ACC)
    assert sliced.max_gouge == whole.max_gouge
    assert sliced.gouge_at == whole.gouge_at
    assert sliced.max_left == whole.max_left
    assert sliced.left_at == whole.left_at
    assert np.array_equal(sliced.motion_gouge, whole.motion_gouge)
