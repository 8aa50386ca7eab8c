"""Cycle time: acceleration-limited (trapezoidal) speed profiles along the motion.

Model (job units; rates in units/min, acceleration in units/s^2 as in
:class:`millpath.model.stock.Machine`):

- feed moves run at their feed rate capped by ``machine.max_feed`` (inverse-time
  feeds: the move's length times F per minute, capped likewise); arcs also at most
  ``sqrt(acceleration * radius)`` (centripetal limit); traverses at ``machine.rapid``;
- every move speeds up and slows down at ``machine.acceleration`` (trapezoid, or
  triangle when too short to reach its speed);
- the tool stops at the program's start and end, before and after every traverse and
  dwell, and at sharp corners: junctions between feed moves whose directions differ by
  more than ``corner_angle`` degrees, or that do not meet (tool change). At smoother
  junctions it keeps the lower of the two moves' speeds, as far as acceleration allows
  (look-ahead over the whole program);
- dwells add their seconds.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from millpath.model.motion import Motion
from millpath.model.stock import Machine
from millpath.model.toolpath import PLANE_AXES, Toolpath
from millpath.simulate.path import arc_params, motion_points, toolpath_motions


def _tangents(mo: Motion) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(start tangent, end tangent, length, radius or inf) of one motion."""
    s = np.asarray(mo.start, float)
    e = np.asarray(mo.end, float)
    if mo.kind == "arc":
        r, t0, sweep, dn = arc_params(mo)
        a1, a2, an = PLANE_AXES[mo.plane]
        length = math.hypot(r * abs(sweep), dn)
        sg = 1.0 if sweep >= 0 else -1.0
        out = []
        for th in (t0, t0 + sweep):
            v = np.zeros(3)
            v[a1] = -math.sin(th) * r * abs(sweep) * sg
            v[a2] = math.cos(th) * r * abs(sweep) * sg
            v[an] = dn
            out.append(v)
        return out[0], out[1], length, r
    if mo.kind == "cubic" or mo.kind == "nurbs":
        size = float(np.linalg.norm(e - s))
        if mo.kind == "nurbs":
            size = max(size, mo.controls.extent())
        pts = motion_points(mo, 1e-4 * max(1e-3, size))
        seg = np.diff(pts, axis=0)
        length = float(np.linalg.norm(seg, axis=1).sum())
        return seg[0], seg[-1], length, math.inf
    d = e - s
    return d, d, float(np.linalg.norm(d)), math.inf


@njit(cache=True)
def _plan(L, vmax, junction, accel):
    """Seconds per move given lengths, cruise speeds (units/s) and junction speed caps.

    ``junction[i]`` caps the speed between move i-1 and i (junction[0] and
    junction[n] are 0: start and end at rest)."""
    n = L.shape[0]
    v = junction.copy()
    for i in range(n):                        # forward: reachable from the previous
        lim = math.sqrt(v[i] * v[i] + 2.0 * accel * L[i])
        if v[i + 1] > lim:
            v[i + 1] = lim
    for i in range(n - 1, -1, -1):            # backward: able to slow down for the next
        lim = math.sqrt(v[i + 1] * v[i + 1] + 2.0 * accel * L[i])
        if v[i] > lim:
            v[i] = lim
    t = np.zeros(n)
    for i in range(n):
        if L[i] <= 0.0:
            continue
        v0 = v[i]
        v1 = v[i + 1]
        vm = vmax[i]
        vp2 = accel * L[i] + 0.5 * (v0 * v0 + v1 * v1)
        if vp2 <= vm * vm:
            vp = math.sqrt(vp2)
            t[i] = (2.0 * vp - v0 - v1) / accel
        else:
            d_acc = (vm * vm - v0 * v0) / (2.0 * accel)
            d_dec = (vm * vm - v1 * v1) / (2.0 * accel)
            t[i] = (vm - v0) / accel + (vm - v1) / accel + (L[i] - d_acc - d_dec) / vm
    return t


def motion_times(motions: list[Motion], machine: Machine, *,
                 corner_angle: float = 10.0) -> np.ndarray:
    """Seconds spent on each motion (dwells included), per the module's model."""
    n = len(motions)
    if n == 0:
        return np.zeros(0)
    a = float(machine.acceleration)
    if not a > 0:
        raise ValueError("machine acceleration must be positive")
    S = np.array([m.start for m in motions], float).reshape(n, 3)
    E = np.array([m.end for m in motions], float).reshape(n, 3)
    kinds = [m.kind for m in motions]
    t_in = E - S
    t_out = t_in.copy()
    L = np.linalg.norm(t_in, axis=1)
    feed = np.array([m.feed for m in motions], float)
    kind = np.zeros(n, np.int8)               # 0 feed-like, 1 traverse, 2 dwell/none
    radius = np.full(n, np.inf)
    dwell = np.zeros(n)
    for i, k in enumerate(kinds):
        if k == "traverse":
            kind[i] = 1
        elif k == "arc" or (k in ("cubic", "nurbs") and motions[i].controls is not None):
            t_in[i], t_out[i], L[i], radius[i] = _tangents(motions[i])
        elif k == "dwell":
            kind[i] = 2
            L[i] = 0.0
            dwell[i] = max(0.0, motions[i].dwell)
        # anything else (feed, rs274's NURBS without control points): a straight feed
    inv = np.array([m.feed_mode == "inverse_time" for m in motions])
    f = np.where(inv, feed * L, feed)         # inverse time: F moves per minute
    f = np.where(f > 0, f, machine.max_feed)
    vmax = np.minimum(f, machine.max_feed) / 60.0
    with np.errstate(invalid="ignore"):
        vmax = np.where(np.isfinite(radius) & (radius > 0),
                        np.minimum(vmax, np.sqrt(a * radius)), vmax)
    vmax = np.where(kind == 1, machine.rapid / 60.0, vmax)
    vmax = np.where(vmax > 0, vmax, 1e-9)
    # junction i sits between motions i-1 and i
    junction = np.zeros(n + 1)
    if n > 1:
        u, w = t_out[:-1], t_in[1:]
        nu, nw = np.linalg.norm(u, axis=1), np.linalg.norm(w, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            cosang = np.einsum("ij,ij->i", u, w) / (nu * nw)
        smooth = ((kind[:-1] == 0) & (kind[1:] == 0) & (L[:-1] > 0) & (L[1:] > 0)
                  & (np.abs(E[:-1] - S[1:]).max(axis=1) <= 1e-9)
                  & (nu > 0) & (nw > 0)
                  & (cosang >= math.cos(math.radians(corner_angle))))
        junction[1:-1] = np.where(smooth, np.minimum(vmax[:-1], vmax[1:]), 0.0)
    return _plan(L, vmax, junction, a) + dwell


def cycle_time(path: Toolpath | list[Motion], machine: Machine | None = None, *,
               corner_angle: float = 10.0) -> float:
    """Total seconds to run a Toolpath or interpreted motion on ``machine``.

    ``machine`` defaults to :meth:`Machine.default_for` the toolpath's units (mm for
    motion lists). See the module docstring for the model.
    """
    if isinstance(path, Toolpath):
        machine = machine or Machine.default_for(path.units)
        motions, _ = toolpath_motions(path)
    else:
        machine = machine or Machine()
        motions = path
    return float(motion_times(motions, machine, corner_angle=corner_angle).sum())


def operation_times(tp: Toolpath, machine: Machine | None = None, *,
                    corner_angle: float = 10.0) -> list[dict]:
    """Per operation of ``tp``: type, name, tool, moves, cycle_time_s."""
    machine = machine or Machine.default_for(tp.units)
    motions, src = toolpath_motions(tp)
    t = motion_times(motions, machine, corner_angle=corner_angle)
    return times_by_operation(tp, src, t)


def times_by_operation(tp: Toolpath, src: list[int], t: np.ndarray) -> list[dict]:
    secs = [0.0] * len(tp.ops)
    for ti, mi in zip(t, src):
        secs[tp.moves[mi].op] += float(ti)
    moves = [0] * len(tp.ops)
    for m in tp.moves:
        moves[m.op] += 1
    return [{"type": op.type, "name": op.name, "tool": op.tool, "moves": moves[k],
             "cycle_time_s": secs[k]} for k, op in enumerate(tp.ops)]
