"""A helix entry down to a start where a ball touches a block's edge near its equator:
the drop-cutter height rises steeply towards the block, so a helix circle through the
start must bend away from it. Checked against the analytic drop of a ball onto the
corner of a block (x >= 0, y >= 0, top Z = 0), sampled along the whole helix."""

import math

import numpy as np

from millpath.plan.entry import helix_entry

R = 4.0          # ball radius


def ball_floor(xs, ys):
    """Tip Z of a ball of radius R lowered onto the block at (xs, ys)."""
    dx = np.maximum(-np.asarray(xs, float), 0.0)
    dy = np.maximum(-np.asarray(ys, float), 0.0)
    d = np.hypot(dx, dy)
    return np.where(d < R, np.sqrt(np.maximum(R * R - d * d, 0.0)) - R, -1e9)


def helix_points(hx, z_from, n=200_000):
    """Tip positions along the helix from z_from down to its end."""
    tx, ty, tz = hx.end
    cx, cy = hx.center
    a0 = math.atan2(ty - cy, tx - cx)
    s = np.linspace(0.0, 1.0, n)
    ang = a0 + 2 * math.pi * hx.turns * s                 # counter-clockwise
    return (cx + hx.radius * np.cos(ang), cy + hx.radius * np.sin(ang),
            z_from + (tz - z_from) * s)


def test_helix_to_a_start_on_a_steep_flank_stays_above_the_part():
    # the start of a pass hugging the block's corner, the ball 0.003 mm from leaving it
    away = math.radians(219.8)
    d = R - 0.003
    start = (d * math.cos(away), d * math.sin(away), float(ball_floor(
        [d * math.cos(away)], [d * math.sin(away)])[0]))
    z_from = start[2] + 5.0
    hx = helix_entry(start, z_from, R, centre_ok=lambda xs, ys: True, floor=ball_floor,
                     samples=192, first=away)
    assert hx is not None
    xs, ys, zs = helix_points(hx, z_from)
    assert np.all(zs >= ball_floor(xs, ys) - 1e-9)


def test_first_direction_is_tried_first():
    hx = helix_entry((0.0, 0.0, -1.0), 1.0, 4.0, centre_ok=lambda xs, ys: True,
                     floor=lambda xs, ys: np.full(len(xs), -5.0), first=1.0)
    assert abs(math.atan2(hx.center[1], hx.center[0]) - 1.0) < 1e-12
