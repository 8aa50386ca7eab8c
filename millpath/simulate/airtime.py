"""Where each operation's time goes: cutting, feeding through air, traversing.

From the interpreted motion, each motion's seconds (:mod:`millpath.simulate.cycletime`)
and whether it removed material (the Z-map sweep: more than a ten-thousandth of a cell
width from some cell), per operation:

- ``cutting_s``: feed motions (lines, arcs, curves) that removed material;
- ``air_s``: feed motions that removed nothing (links, entries and passes over material
  already cut or above the stock): the time a better path saves;
- ``traverse_s``: rapid traverses; ``dwell_s``: dwells;
- ``air_share``: ``air_s`` over the operation's whole time;
- ``retracts``: traverses that lift the tool;
- ``entries``: times the tool starts removing material after a motion that did not
  (a plunge, a ramp or helix, a lead-in, a pass resuming after a link).
"""

from __future__ import annotations

import numpy as np

from millpath.model.motion import Motion

#: air time over this share of an operation's time is worth a warning
AIR_SHARE_WARN = 1.0 / 3.0
#: an operation running longer than this (seconds) is worth a warning
LONG_OPERATION_S = 2.0 * 3600.0


def time_use(motions: list[Motion], times: np.ndarray, removes: np.ndarray,
             motion_op: np.ndarray, n_ops: int) -> list[dict]:
    """Per operation ``0 .. n_ops - 1``: the figures of the module docstring."""
    n = len(motions)
    kind = np.array([m.kind for m in motions], dtype=object) if n else np.zeros(0, object)
    trav = kind == "traverse"
    dwell = kind == "dwell"
    feed = ~trav & ~dwell
    cut = np.asarray(removes[:n], bool) & feed
    air = feed & ~cut
    zs = np.array([m.start[2] for m in motions], float)
    ze = np.array([m.end[2] for m in motions], float)
    lift = trav & (ze > zs + 1e-9)
    starts = cut & ~np.concatenate([[False], cut[:-1]]) if n else cut
    op = np.asarray(motion_op[:n], np.int64)
    t = np.asarray(times[:n], float)

    def per(mask, w=None):
        return np.bincount(op[mask], weights=None if w is None else w[mask],
                           minlength=n_ops)[:n_ops]
    cs, ai, tr, dw = per(cut, t), per(air, t), per(trav, t), per(dwell, t)
    nr, ne = per(lift), per(starts)
    out = []
    for o in range(n_ops):
        total = cs[o] + ai[o] + tr[o] + dw[o]
        out.append({"cutting_s": round(float(cs[o]), 3), "air_s": round(float(ai[o]), 3),
                    "traverse_s": round(float(tr[o]), 3), "dwell_s": round(float(dw[o]), 3),
                    "air_share": round(float(ai[o] / total), 4) if total > 0 else 0.0,
                    "retracts": int(nr[o]), "entries": int(ne[o])})
    return out


def time_note(op: dict) -> tuple[str, bool, bool] | None:
    """What is worth a warning about one report.json operation (its ``cycle_time_s`` and
    :func:`time_use` figures under ``time``): ``(text, air, long)`` when its air time is
    over :data:`AIR_SHARE_WARN` of its time (``air``) or it runs over
    :data:`LONG_OPERATION_S` (``long``); None otherwise."""
    use = op.get("time") or {}
    total = float(op.get("cycle_time_s", 0.0))
    air = use.get("air_share", 0.0) > AIR_SHARE_WARN
    long = total > LONG_OPERATION_S
    if not (air or long):
        return None
    why = []
    if air:
        why.append(f"{100 * use['air_share']:.0f} % of its {_hms(total)} feeds through air "
                   f"({use.get('entries', 0)} entries, {use.get('retracts', 0)} retracts)")
    if long:
        why.append(f"it runs {_hms(total)}")
    return "; ".join(why), air, long


def _hms(s: float) -> str:
    s = int(round(s))
    if s >= 3600:
        return f"{s // 3600} h {s % 3600 // 60:02d} min"
    return f"{s // 60} min {s % 60:02d} s"
