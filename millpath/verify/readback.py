"""Read a fitted program back before it is written: both programs interpreted by
millpath's interpreter, their motion compared.

:func:`read_back` refuses (MillpathError) a fitted program that

- does not interpret (its first error, line and message), or whose original does not
  (fit writes only what its interpreter reads back);
- moves differently at rapid: the rapids (which fit never touches) must end at the same
  points, in the same order, within 1e-6 program units;
- leaves the original's cutting path: every point of a cutting motion (line, arc,
  cubic) that is not one of the original's, sampled every ``tolerance / 2``, must lie
  within ``tolerance`` of the original's cutting motions that are not the fitted
  program's, and the other way round (sampled: the figure may exceed the largest
  deviation by 4 %). Coordinates are program coordinates in program units.

Tools: the programs are interpreted with ``tools`` when given, else with a stand-in
table holding every tool number the program names (T, H and D words) with no length
and no diameter, the same for both: what is compared is the motion fit changes.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from millpath.errors import MillpathError
from millpath.geometry.spacing import points_along
from millpath.interpret.store import KIND_CODE

CUTS = ("feed", "arc", "cubic", "nurbs")
_TOOL_WORD = re.compile(r"[tThHdD]\s*(\d+)")
_COMMENT = re.compile(r"\([^)]*\)|;.*")


@dataclass
class ReadBack:
    """What the read-back compared: ``motions`` of the fitted program, ``compared``
    cutting motions that differ from the original's, ``deviation`` the largest distance
    found between the two paths (program units)."""

    motions: int
    compared: int
    deviation: float


def stand_in_tools(text: str) -> list:
    """Tool table entries for every tool number in ``text``'s T, H and D words (no
    length, no diameter)."""
    from millpath.io.tooltable import ToolEntry
    nums = {int(n) for line in text.splitlines()
            for n in _TOOL_WORD.findall(_COMMENT.sub("", line))}
    nums.discard(0)
    return [ToolEntry(n, n) for n in sorted(nums)]


def _interpret(text: str, tools, what: str, file):
    from millpath.interpret import run
    res = run(text, tools, machine_units="mm")
    if res.error is not None:
        raise MillpathError(f"{what} does not interpret: line {res.error.line}: "
                            f"{res.error.message}; nothing written", file)
    return res.motions


def _keys(arr: dict, idx: np.ndarray) -> list[bytes]:
    """One key per motion ``idx`` of the interpreter's arrays: kind, start, end (to 1e-7),
    and for arcs centre, turns and plane."""
    arc = (arr["kind"][idx] == KIND_CODE["arc"])[:, None]
    f = np.hstack([arr["start"][idx], arr["end"][idx], np.where(arc, arr["center"][idx], 0.0)])
    f = np.round(f, 7) + 0.0                   # -0.0 and 0.0 alike
    i = np.column_stack([arr["kind"][idx], np.where(arc[:, 0], arr["rotation"][idx], 0),
                         np.where(arc[:, 0], arr["plane"][idx], 0)]).astype(np.int64)
    return [a.tobytes() + b.tobytes() for a, b in zip(f, i)]


def _samples(motions, arr: dict, idx, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 3) along motions ``idx`` at most ``step`` apart (curves as chords
    within ``step / 50``) and the program line of each."""
    from millpath.simulate.path import motion_points
    idx = np.asarray(idx, int)
    if not len(idx):
        return np.zeros((0, 3)), np.zeros(0, int)
    line = arr["line"][idx]
    straight = arr["kind"][idx] == KIND_CODE["feed"]
    A = [arr["start"][idx[straight]]]
    B = [arr["end"][idx[straight]]]
    lines = [line[straight]]
    for k in idx[~straight]:
        p = motion_points(motions[int(k)], step / 50.0)
        A.append(p[:-1])
        B.append(p[1:])
        lines.append(np.full(len(p) - 1, arr["line"][k]))
    A, B, lines = np.vstack(A), np.vstack(B), np.concatenate(lines)
    n = np.maximum(1, np.ceil(np.linalg.norm(B - A, axis=1) / step).astype(np.int64))
    Q, k = points_along(A, B, n, start=True)
    pts = np.vstack([Q, B])
    return pts, np.concatenate([lines[k], lines])


def _changed(ka: list, kb: list):
    """Indices (into ``ka`` and ``kb``, the keys of two programs' cutting motions) of
    the motions not common to both, aligned in order (fit rewrites runs: the motions
    between them are the same in both), and for a changed stretch that is empty in one
    program the index of the motion it stands before there (``len``: after the last)."""
    import bisect
    where: dict[bytes, list[int]] = {}
    for j, k in enumerate(kb):
        where.setdefault(k, []).append(j)
    only_a, only_b, at_a, at_b = [], [], [], []
    i = j = 0
    while i < len(ka) or j < len(kb):
        if i < len(ka) and j < len(kb) and ka[i] == kb[j]:
            i += 1
            j += 1
            continue
        # a changed stretch: up to the next motion of a found in b at or after j
        i2, j2 = i, len(kb)
        while i2 < len(ka):
            js = where.get(ka[i2], [])
            k = bisect.bisect_left(js, j)
            if k < len(js):
                j2 = js[k]
                break
            i2 += 1
        only_a += range(i, i2)
        only_b += range(j, j2)
        if i == i2:
            at_a.append(i)
        if j == j2:
            at_b.append(j)
        i, j = i2, j2
    return only_a, only_b, at_a, at_b


def _stands(arr: dict, cut: np.ndarray, at: list) -> np.ndarray:
    """Where a program stands (n, 3) before its cutting motions ``at`` (indices into
    ``cut``; ``len(cut)``: after the last)."""
    out = []
    for i in at:
        if i < len(cut):
            out.append(arr["start"][cut[i]])
        elif len(cut):
            out.append(arr["end"][cut[-1]])
    return np.asarray(out, float).reshape(-1, 3)


def read_back(original: str, fitted: str, tolerance: float, *, tools=None,
              file=None) -> ReadBack:
    """Interpret ``original`` and ``fitted`` and compare their motion (see the module
    docstring); MillpathError naming the first difference."""
    table = tools if tools is not None else stand_in_tools(original + "\n" + fitted)
    a = _interpret(original, table, "the program", file)
    b = _interpret(fitted, table, "the fitted program", file)
    aa, ab = a.arrays(), b.arrays()
    ra = aa["end"][aa["kind"] == KIND_CODE["traverse"]]
    rbe = ab["end"][ab["kind"] == KIND_CODE["traverse"]]
    if len(ra) != len(rbe) or (len(ra) and not np.allclose(ra, rbe, rtol=0, atol=1e-6)):
        k = next((i for i in range(min(len(ra), len(rbe)))
                  if not np.allclose(ra[i], rbe[i], rtol=0, atol=1e-6)), min(len(ra), len(rbe)))
        rl = ab["line"][ab["kind"] == KIND_CODE["traverse"]]
        line = rl[k] if k < len(rl) else (rl[-1] if len(rl) else 0)
        raise MillpathError(f"the fitted program's rapids differ from the program's (rapid "
                            f"{k + 1}, fitted line {line}); nothing written", file)
    cuts = [KIND_CODE[k] for k in CUTS]
    ca = np.flatnonzero(np.isin(aa["kind"], cuts))
    cb = np.flatnonzero(np.isin(ab["kind"], cuts))
    only_a, only_b, at_a, at_b = _changed(_keys(aa, ca), _keys(ab, cb))
    step = tolerance / 2.0
    pa, _ = _samples(a, aa, ca[only_a], step)
    pb, lb = _samples(b, ab, cb[only_b], step)
    sa, sb = _stands(aa, ca, at_a), _stands(ab, cb, at_b)
    pa = np.vstack([pa, sa])
    pb = np.vstack([pb, sb])
    lb = np.concatenate([lb, np.zeros(len(sb), int)])
    worst = 0.0
    if len(pa) or len(pb):
        # a program left with no cutting motion (moves of no length dropped) is checked
        # against where its motions stand, not sampled itself
        real_a, real_b = len(pa) > 0, len(pb) > 0
        if not real_a:
            pa = aa["end"]
        if not real_b:
            pb = ab["end"]
        if not len(pa) or not len(pb):
            raise MillpathError("the fitted program cuts where the program does not move, "
                                "or the other way round; nothing written", file)
        from scipy.spatial import cKDTree
        # samples step apart, curves sampled on chords within step / 50 of them
        bound = math.hypot(tolerance, step / 2.0) + step / 50.0 + 1e-9
        none = np.zeros(1)
        db = cKDTree(pa).query(pb, distance_upper_bound=4 * bound)[0] if real_b else none
        da = cKDTree(pb).query(pa, distance_upper_bound=4 * bound)[0] if real_a else none
        worst = float(max(db.max(), da.max()))
        if worst > bound:
            if db.max() >= da.max():
                k = int(np.argmax(db))
                at, line = pb[k], f"line {lb[k]} of the fitted program"
            else:
                k = int(np.argmax(da))
                at, line = pa[k], "the program's path"
            far = "more than " + f"{4 * bound:.4g}" if not math.isfinite(worst) else f"{worst:.4g}"
            raise MillpathError(f"the fitted program leaves the program's path by {far} "
                                f"at X{at[0]:.4f} Y{at[1]:.4f} Z{at[2]:.4f} ({line}), more "
                                f"than the tolerance {tolerance:g}; nothing written", file)
    return ReadBack(len(b), len(only_b), worst)
