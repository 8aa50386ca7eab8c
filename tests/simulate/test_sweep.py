"""The chord sweep against brute force, arcs in every plane, canned-cycle expansion."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.geometry.cutter import Cutter
from millpath.model.motion import Motion
from millpath.model import Operation, Stock, Tool, Toolpath
from millpath.simulate import simulate_motions, simulate_toolpath
from millpath.simulate.path import toolpath_motions

TOOLS = [Tool(1, "flat", 6.0), Tool(2, "ball", 6.0), Tool(3, "bull", 6.0, corner_radius=1.5),
         Tool(4, "drill", 6.0, point_angle=118.0)]


def _profile(tool: Tool, r: np.ndarray) -> np.ndarray:
    """The cutter's surface above the tip, written out per shape (checked against
    :class:`~millpath.geometry.cutter.Cutter` below)."""
    R, rc = tool.radius, tool.corner_radius
    if tool.type == "flat":
        return np.zeros_like(r)
    if tool.type == "drill":
        return r / math.tan(math.radians(tool.point_angle) / 2.0)
    e = np.maximum(r - (R - rc), 0.0)
    return rc - np.sqrt(np.maximum(rc * rc - e * e, 0.0))


@pytest.mark.parametrize("tool", TOOLS, ids=lambda t: t.type)
def test_array_profile_matches_the_cutter(tool):
    r = np.linspace(0.0, tool.radius, 37)
    assert _profile(tool, r) == pytest.approx(Cutter.of(tool).height(r), abs=1e-12)


def _brute(tool: Tool, a, b, xs, ys, top, n=1001):
    """Lowest tool surface over densely sampled tip positions (an upper bound of the
    exact sweep, within the sampling step times the slope)."""
    X, Y = np.meshgrid(xs, ys)
    out = np.full(X.shape, float(top))
    for t in np.linspace(0.0, 1.0, n):
        p = np.asarray(a, float) + t * (np.asarray(b, float) - np.asarray(a, float))
        d = np.hypot(X - p[0], Y - p[1])
        z = np.where(d <= tool.radius, p[2] + _profile(tool, np.minimum(d, tool.radius)),
                     np.inf)
        np.minimum(out, z, out=out)
    return out


@pytest.mark.parametrize("tool", TOOLS, ids=lambda t: t.type)
@pytest.mark.parametrize("b", [(14.0, 9.0, -4.5), (6.5, 11.0, -0.2), (12.0, 5.1, -5.0)],
                         ids=["ramp", "steep", "shallow"])
def test_sweep_of_a_3d_chord_matches_dense_stamping(tool, b):
    a = (5.0, 5.0, -1.0)
    tp = Toolpath()
    tp.begin(Operation("t", "t", tool.number))
    tp.rapid(a[0], a[1], 5)
    tp.line(*a, 100)
    tp.line(*b, 100)
    stock = Stock(0, 0, -10, 20, 16, 0)
    r = simulate_toolpath(tp, {tool.number: tool}, stock, resolution=0.25)
    z = r.zmap
    ref = _brute(tool, a, b, z.xs(), z.ys(), 0.0)
    ref = np.maximum(ref, stock.zmin)
    seg = math.dist(a, b)
    step = seg / 1000
    # exact sweep is below dense stamping by at most ~ step (slope <= 1 profiles)
    diff = z.heights - ref
    assert diff.max() <= 1e-9
    assert diff.min() >= -(step * 4 + 1e-9)


def test_xz_arc_clockwise_goes_below_its_centre():
    # G18 G2 from X-5 to X5 about the origin: the lower half circle (first axis Z)
    arc = Motion("arc", 1, (-5.0, 0.0, 0.0), (5.0, 0.0, 0.0), feed=100, tool=1, plane="XZ",
                 center=(0.0, 0.0, 0.0), rotation=-1)
    tool = Tool(1, "flat", 2.0)
    r = simulate_motions([arc], {1: tool}, Stock(-10, -5, -10, 10, 5, 1), resolution=0.05)
    z = r.zmap
    xs = z.xs()
    for x in (0.0, 2.5, 4.0, -4.0, 5.3):
        i = int(np.argmin(np.abs(xs - x)))
        xc = xs[i]
        xa = max(abs(xc) - 1.0, 0.0)                           # tool radius 1
        want = -math.sqrt(25.0 - xa * xa) if xa <= 5.0 else 1.0
        j = int(np.argmin(np.abs(z.ys())))
        # chords stay within res/20 of the arc, normal to it: vertically tol / cos(slope)
        tol = (0.05 / 20) / math.sqrt(1.0 - (xa / 5.0) ** 2) + 1e-9
        assert z.heights[j, i] == pytest.approx(want, abs=tol), xc
    assert z.height_at(0.0, 2.0) == 1.0                    # outside the tool: untouched


def test_yz_helix_counter_clockwise_matches_its_geometry():
    # G19 G3 full circle in YZ (first Y, second Z) about (y, z) = (0, 0), radius 4,
    # advancing 2 along X: counter-clockwise about +X it rises first and reaches its
    # lowest point (z = -4, y = 0) three quarters along, at x = 1.5 (clockwise: 0.5)
    arc = Motion("arc", 1, (0.0, 4.0, 0.0), (2.0, 4.0, 0.0), feed=100, tool=2, plane="YZ",
                 center=(0.0, 0.0, 0.0), rotation=1)
    r = simulate_motions([arc], {2: Tool(2, "ball", 2.0)}, Stock(-3, -8, -8, 5, 8, 6),
                         resolution=0.05)
    low = r.zmap.heights.min()
    assert low == pytest.approx(-4.0, abs=0.01)
    j, i = np.unravel_index(np.argmin(r.zmap.heights), r.zmap.heights.shape)
    assert abs(r.zmap.ys()[j]) < 0.1 and abs(r.zmap.xs()[i] - 1.5) < 0.1


def test_cubic_motion_stays_on_its_bezier():
    cub = Motion("cubic", 1, (0.0, 0.0, -1.0), (10.0, 0.0, -1.0), feed=100, tool=1,
                 controls=((0.0, 8.0), (10.0, 8.0)))
    r = simulate_motions([cub], {1: Tool(1, "flat", 1.0)}, Stock(-2, -2, -3, 12, 8, 0),
                         resolution=0.05)
    # apex of the curve: y = 0.75 * 8 = 6 at x = 5; the tool (r 0.5) cuts to y ~ 6.5
    assert r.zmap.height_at(5.0, 6.3) == -1.0
    assert r.zmap.height_at(5.0, 6.7) == 0.0


def _drill_tp(cycle, **kw):
    tp = Toolpath()
    tp.begin(Operation("d", "d", 1))
    tp.rapid(0, 0, 10)
    tp.drill(5, 5, -8, 2, 100, cycle=cycle, **kw)
    return tp


def test_g81_g99_returns_to_r_and_g98_to_initial_z():
    ms, _ = toolpath_motions(_drill_tp("G81"))
    kinds = [(m.kind, m.end) for m in ms[1:]]
    assert kinds == [("traverse", (5, 5, 10)), ("traverse", (5, 5, 2)),
                     ("feed", (5, 5, -8)), ("traverse", (5, 5, 2))]
    ms, _ = toolpath_motions(_drill_tp("G81", retract_initial=True))
    assert ms[-1].end == (5, 5, 10)


def test_g83_pecks_retract_to_r_and_g73_breaks_chips():
    ms, _ = toolpath_motions(_drill_tp("G83", peck=3.0))
    feeds = [m.end[2] for m in ms if m.kind == "feed"]
    assert feeds == [-1.0, -4.0, -7.0, -8.0]
    ups = [m.end[2] for m in ms if m.kind == "traverse" and m.end[2] == 2]
    assert len(ups) == 5                       # down to R once, back to R after 3 pecks, out
    ms, _ = toolpath_motions(_drill_tp("G73", peck=3.0))
    assert [m.end[2] for m in ms if m.kind == "traverse"][3:6] == \
        pytest.approx([-1 + 0.254, -4 + 0.254, -7 + 0.254])


def test_g85_and_g89_feed_out_and_g89_dwells():
    ms, _ = toolpath_motions(_drill_tp("G89", dwell=0.5))
    assert [m.kind for m in ms[-3:]] == ["feed", "dwell", "feed"]
    assert ms[-2].dwell == 0.5 and ms[-1].end == (5, 5, 2)


def test_drill_below_r_plane_first_rises_to_r():
    tp = Toolpath()
    tp.begin(Operation("d", "d", 1))
    tp.rapid(0, 0, -1)
    tp.drill(5, 5, -8, 2, 100)
    ms, _ = toolpath_motions(tp)
    assert ms[1].end == (0, 0, 2) and ms[2].end == (5, 5, 2)


def test_almost_vertical_chord_is_swept_without_losing_digits():
    tool = Tool(2, "ball", 6.0)
    tp = Toolpath()
    tp.begin(Operation("t", "t", 2))
    tp.rapid(10.0, 10.0, 5.0)
    tp.line(10.0 + 1e-11, 10.0, -4.0, 100)
    r = simulate_toolpath(tp, {2: tool}, Stock(0, 0, -10, 20, 20, 0), resolution=0.1)
    z = r.zmap
    X, Y = np.meshgrid(z.xs(), z.ys())
    d = np.hypot(X - 10.0, Y - 10.0)
    inside = d <= 2.9
    want = -4.0 + 3.0 - np.sqrt(9.0 - d[inside] ** 2)
    assert np.abs(z.heights[inside] - want).max() < 1e-9


try:
    from hypothesis import given, settings, strategies as st
except ImportError:                                  # pragma: no cover
    given = None

if given is not None:
    coord = st.floats(-4.0, 24.0, allow_nan=False)
    depth = st.floats(-6.0, 1.0, allow_nan=False)

    @settings(max_examples=20, deadline=None)
    @given(st.sampled_from(TOOLS), coord, coord, depth, coord, coord, depth,
           st.floats(0.0, 1.0))
    def test_random_chords_never_cut_more_than_the_tool_and_miss_nothing(
            tool, xa, ya, za, xb, yb, zb, vertical):
        if vertical > 0.8:                    # a fifth of the cases: vertical
            xb, yb = xa, ya
        elif 0.0 < math.dist((xa, ya), (xb, yb)) < 1e-3:
            return      # near-vertical: exact only to ~1e-6 dz horizontally (tested above)
        a, b = (xa, ya, za), (xb, yb, zb)
        tp = Toolpath()
        tp.begin(Operation("t", "t", tool.number))
        tp.rapid(xa, ya, 5)
        tp.line(*a, 100)
        tp.line(*b, 100)
        stock = Stock(0, 0, -10, 20, 16, 0)
        r = simulate_toolpath(tp, {tool.number: tool}, stock, resolution=0.25)
        z = r.zmap
        # the plunge from above to a is part of the sweep too
        ref = np.minimum(_brute(tool, (xa, ya, 5.0), a, z.xs(), z.ys(), 0.0, n=51),
                         _brute(tool, a, b, z.xs(), z.ys(), 0.0, n=1001))
        ref = np.maximum(ref, stock.zmin)
        step = math.dist(a, b) / 1000 + 1e-9
        diff = z.heights - ref
        assert diff.max() <= 1e-8              # rounding only
        assert diff.min() >= -(step * 4 + 1e-9)
