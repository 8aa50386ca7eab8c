"""Triangle mesh of a height-field design ``height(x, y) -> z``, walls included.

A quadtree over the box: a cell is kept whole when its centre and edge midpoints lie
within ``flat_tol`` of the plane through its corners, its corners do not jump by more
than ``slope * size`` and its edges, sampled ``sqrt(8 size flat_tol)`` apart, stay
within ``flat_tol`` of the lines between their corners (a wall curved with radius
``size`` or more that crosses an edge is seen); otherwise it is split, down to cells of
``min_size``. Each
smooth leaf becomes two triangles through its corner heights. A smallest cell crossed
by one wall (its corners fall into a high and a low group, each smooth, flat or
sloped, the jump between them larger than either group's spread) is cut along the
wall: the crossings on its edges are found by bisection of ``height`` to 1e-12 of the
edge (a real jump there, not a steep smooth slope), the high and low parts become
triangles through the design's heights at their corners and just on their side of
each crossing (checked within ``flat_tol`` at their centroids), and the wall a
vertical quad between the crossings, from the low side's heights to the high side's (a
chord of the true wall: off it by ``min_size^2 / (4 radius)`` on a wall curved with
``radius``). Any other smallest cell (two walls, a wall's corner) becomes a ramp
across the cell. Heights of ``-inf`` (no
part) become ``floor``. Triangles wind counter-clockwise seen from above, so normals
point out of the material (up, or away from the high side on a wall). Job units.
"""

from __future__ import annotations

import math

import numpy as np

from millpath.geometry.flatmerge import merge_horizontal


def _h(design, x, y, floor):
    z = np.asarray(design.height(x, y), float).reshape(np.shape(x))
    return np.where(np.isfinite(z), np.maximum(z, floor), floor)


def height_field_mesh(design, box: tuple[float, float, float, float], *, size: float,
                      min_size: float, flat_tol: float, floor: float,
                      slope: float = 4.0, max_cells: int = 4_000_000,
                      merge: bool = False, wall_size: float | None = None) -> np.ndarray:
    """Triangles (n, 3, 3) of ``design`` over ``box`` = (xmin, ymin, xmax, ymax);
    ``merge``: each height's horizontal triangles merged into few (see
    :func:`millpath.geometry.flatmerge.merge_horizontal`). ``wall_size`` (default
    ``min_size``): a smallest cell holding a jump (corners apart by more than
    ``slope * min_size``) that cannot be cut as one wall is split further, down to cells
    of at most ``wall_size``, before it becomes a ramp; a ramp is then off the design by
    at most the diagonal of such a cell."""
    wall_size = min_size if wall_size is None else min(float(wall_size), min_size)
    # edge samples close enough that a wall curved with radius >= size crossing an edge
    # between two of them dips into the cell by at most flat_tol: h^2 / (8 r) <= flat_tol
    edge_step = math.sqrt(8.0 * size * flat_tol)
    x0, y0, x1, y1 = map(float, box)
    nx = max(1, int(math.ceil((x1 - x0) / size)))
    ny = max(1, int(math.ceil((y1 - y0) / size)))
    w = (x1 - x0) / nx
    hgt = (y1 - y0) / ny
    j, i = np.mgrid[0:ny, 0:nx]
    cx = (x0 + i * w).ravel().astype(float)
    cy = (y0 + j * hgt).ravel().astype(float)
    cw = np.full(cx.shape, w)
    ch = np.full(cx.shape, hgt)
    out = []
    total = 0
    depth = 0
    while len(cx):
        depth += 1
        X = np.stack([cx, cx + cw, cx + cw, cx, cx + cw / 2, cx + cw / 2, cx + cw, cx + cw / 2,
                      cx], axis=1)
        Y = np.stack([cy, cy, cy + ch, cy + ch, cy + ch / 2, cy, cy + ch / 2, cy + ch,
                      cy + ch / 2], axis=1)
        Z = _h(design, X, Y, floor)
        z0, z1, z2, z3 = Z[:, 0], Z[:, 1], Z[:, 2], Z[:, 3]
        # plane-ish prediction: centre = mean of corners, edge mids = mean of their ends
        pred = np.stack([(z0 + z1 + z2 + z3) / 4, (z0 + z1) / 2, (z1 + z2) / 2,
                         (z2 + z3) / 2, (z3 + z0) / 2], axis=1)
        dev = np.abs(Z[:, 4:] - pred).max(axis=1)
        spread = Z[:, :4].max(axis=1) - Z[:, :4].min(axis=1)
        size_ = np.maximum(cw, ch)
        rough = (dev > flat_tol) | (spread > slope * size_)
        smooth = np.flatnonzero(~rough)
        if len(smooth):                 # a wall may cross an edge between its samples
            rough[smooth] = _edges_off(design, cx[smooth], cy[smooth], cw[smooth],
                                       ch[smooth], Z[smooth, :4], floor, flat_tol,
                                       edge_step)
        split = rough & (size_ > min_size)
        walls = np.flatnonzero(rough & ~split)
        handled = np.zeros(0, np.int64)
        if len(walls):
            wt, done = _wall_cells(design, X[walls], Y[walls], Z[walls], cw[walls],
                                   ch[walls], floor, flat_tol, slope)
            out.append(wt)
            handled = walls[done]
            # a jump not cut as one wall (a corner, two walls, a side off its triangles):
            # smaller cells, down to wall_size
            rest = walls[~done]
            split[rest[(size_[rest] > wall_size * (1 + 1e-9))
                       & (spread[rest] > slope * min_size)]] = True
        keep = ~split
        keep[handled] = False
        if keep.any():
            a = np.stack([X[keep, 0], Y[keep, 0], z0[keep]], axis=1)
            b = np.stack([X[keep, 1], Y[keep, 1], z1[keep]], axis=1)
            c = np.stack([X[keep, 2], Y[keep, 2], z2[keep]], axis=1)
            d = np.stack([X[keep, 3], Y[keep, 3], z3[keep]], axis=1)
            out.append(np.stack([a, b, c], axis=1))
            out.append(np.stack([a, c, d], axis=1))
        total += int(keep.sum()) * 2
        if total > max_cells:
            raise ValueError(f"design mesh needs more than {max_cells} triangles")
        s = np.flatnonzero(split)
        hw, hh = cw[s] / 2, ch[s] / 2
        cx = np.concatenate([cx[s], cx[s] + hw, cx[s], cx[s] + hw])
        cy = np.concatenate([cy[s], cy[s], cy[s] + hh, cy[s] + hh])
        cw = np.tile(hw, 4)
        ch = np.tile(hh, 4)
    if not out:
        return np.zeros((0, 3, 3))
    tri = np.concatenate(out)
    if not merge:
        return np.ascontiguousarray(tri)
    # cell corners made by different sums (a parent's corner plus half its width...)
    # differ in the last bits: put every coordinate on a cell line exactly on it, so
    # neighbours share their corners and edges
    for a, o, d in ((0, x0, w), (1, y0, hgt)):
        u = d / 2.0 ** depth
        k = np.round((tri[:, :, a] - o) / u)
        g = o + k * u
        on = np.abs(tri[:, :, a] - g) <= 1e-9 * u
        tri[:, :, a] = np.where(on, g, tri[:, :, a])
    return merge_horizontal(tri, 4.0 * max(w, hgt))


def _edges_off(design, cx, cy, cw, ch, corners, floor, flat_tol, step, chunk=20_000):
    """Whether a cell's edges leave the straight line between their corner heights by
    more than ``flat_tol`` somewhere, sampled at most ``step`` apart (the mesh follows
    that line; a wall crossing an edge between the centre and midpoint samples shows
    here)."""
    k = max(1, int(math.ceil(float(np.max(np.maximum(cw, ch))) / step)) - 1)
    t = np.arange(1, k + 1) / (k + 1)
    out = np.zeros(len(cx), bool)
    for a in range(0, len(cx), chunk):
        b = slice(a, a + chunk)
        x, y, w, h, z = cx[b, None], cy[b, None], cw[b, None], ch[b, None], corners[b]
        # edges 0-1 (y = cy), 1-2 (x = cx + w), 3-2 (y = cy + h), 0-3 (x = cx)
        X = np.concatenate([x + t * w, x + w + 0 * t, x + t * w, x + 0 * t], axis=1)
        Y = np.concatenate([y + 0 * t, y + t * h, y + h + 0 * t, y + t * h], axis=1)
        z0, z1, z2, z3 = (z[:, i:i + 1] for i in range(4))
        line = np.concatenate([z0 + t * (z1 - z0), z1 + t * (z2 - z1), z3 + t * (z2 - z3),
                               z0 + t * (z3 - z0)], axis=1)
        out[b] = (np.abs(_h(design, X, Y, floor) - line) > flat_tol).any(axis=1)
    return out


def _wall_cells(design, X, Y, Z, cw, ch, floor, flat_tol, slope):
    """Cut smallest cells crossed by a single wall along it (see the module doc).
    Returns (triangles, which cells were handled)."""
    zc = Z[:, :4]
    mid = (zc.max(axis=1) + zc.min(axis=1)) / 2
    high = zc > mid[:, None]
    nh = high.sum(axis=1)
    size = np.maximum(cw, ch)
    # each side smooth (no jump of its own), the jump between them larger than either
    # side's spread, not a saddle (diagonal corners high)
    hi_min = np.where(high, zc, np.inf).min(axis=1)
    lo_max = np.where(~high, zc, -np.inf).max(axis=1)
    hi_spread = np.where(high, zc, -np.inf).max(axis=1) - hi_min
    lo_spread = lo_max - np.where(~high, zc, np.inf).min(axis=1)
    saddle = (nh == 2) & (high[:, 0] == high[:, 2])
    gap = hi_min - lo_max
    ok = ((hi_spread <= slope * size) & (lo_spread <= slope * size)
          & (gap > np.maximum(hi_spread, lo_spread)) & ~saddle & (nh > 0) & (nh < 4))
    idx = np.flatnonzero(ok)
    if not len(idx):
        return np.zeros((0, 3, 3)), ok
    Xc, Yc, Zc, H = X[idx, :4], Y[idx, :4], Z[idx, :4], high[idx]
    level = (hi_min[idx] + lo_max[idx]) / 2
    # crossings on the 4 edges (corner k -> k+1), with the height just on either side
    # of the wall (the ends of the bisection's last bracket)
    cross = np.zeros((len(idx), 4, 2))
    zcross = np.zeros((len(idx), 4, 2))        # [.., 0]: high side, [.., 1]: low side
    jump = np.ones((len(idx), 4), bool)
    for e in range(4):
        a, b = e, (e + 1) % 4
        ax, ay, bx, by = Xc[:, a], Yc[:, a], Xc[:, b], Yc[:, b]
        lo_t = np.zeros(len(idx))
        hi_t = np.ones(len(idx))
        ha = H[:, a]
        za, zb = Zc[:, a].copy(), Zc[:, b].copy()
        for _ in range(40):
            t = (lo_t + hi_t) / 2
            z = _h(design, ax + (bx - ax) * t, ay + (by - ay) * t, floor)
            same_a = (z > level) == ha
            lo_t = np.where(same_a, t, lo_t)
            hi_t = np.where(same_a, hi_t, t)
            za = np.where(same_a, z, za)
            zb = np.where(same_a, zb, z)
        t = (lo_t + hi_t) / 2
        cross[:, e, 0] = ax + (bx - ax) * t
        cross[:, e, 1] = ay + (by - ay) * t
        zcross[:, e, 0] = np.where(ha, za, zb)
        zcross[:, e, 1] = np.where(ha, zb, za)
        # a real wall: the height jumps across the bracket (not a steep smooth slope)
        jump[:, e] = (H[:, a] == H[:, b]) | (np.abs(za - zb) > gap[idx] / 2)
    good = jump.all(axis=1)
    # the wall between the two crossings is their chord: the design must change side
    # within flat_tol of the chord's midpoint (a corner of the outline, or a wall bowed
    # more than that, is not one wall across the cell)
    change = H != np.roll(H, -1, axis=1)                 # edge k -> k+1 crosses
    e1 = np.argmax(change, axis=1)
    e2 = 3 - np.argmax(change[:, ::-1], axis=1)
    rows = np.arange(len(idx))
    p, q = cross[rows, e1], cross[rows, e2]
    mid = (p + q) / 2
    d = q - p
    n = np.stack([-d[:, 1], d[:, 0]], axis=1)
    n /= np.maximum(np.hypot(n[:, 0], n[:, 1]), 1e-300)[:, None]
    hc = np.stack([np.where(H, Xc, 0.0).sum(axis=1), np.where(H, Yc, 0.0).sum(axis=1)],
                  axis=1) / H.sum(axis=1)[:, None]
    n *= np.where(((hc - mid) * n).sum(axis=1) < 0, -1.0, 1.0)[:, None]
    z_hi = _h(design, mid[:, 0] + n[:, 0] * flat_tol, mid[:, 1] + n[:, 1] * flat_tol, floor)
    z_lo = _h(design, mid[:, 0] - n[:, 0] * flat_tol, mid[:, 1] - n[:, 1] * flat_tol, floor)
    good &= (z_hi > level) & (z_lo <= level)
    # every cell's points: its corners (0-3), each edge's crossing on the high side
    # (4-7) and on the low side (8-11); each pattern of high corners gives its
    # triangles as rows of those numbers
    P = np.concatenate([np.stack([Xc, Yc, Zc], axis=2),
                        np.concatenate([cross, zcross[:, :, :1]], axis=2),
                        np.concatenate([cross, zcross[:, :, 1:]], axis=2)], axis=1)
    cells = np.flatnonzero(good)
    code = H[cells].astype(np.int64) @ np.array([1, 2, 4, 8])
    parts, owners, sides, local = [], [], [], []
    for pat in np.unique(code):
        cs = cells[code == pat]
        rows, sd = _pattern(int(pat))
        parts.append(P[cs][:, rows].reshape(-1, 3, 3))
        owners.append(np.repeat(cs, len(rows)))
        sides.append(np.tile(sd, len(cs)))
        local.append(np.tile(np.arange(len(rows)), len(cs)))
    if parts:
        # in the order of the cells, each cell's triangles as its pattern lists them
        order = np.lexsort((np.concatenate(local), np.concatenate(owners)))
        t = np.concatenate(parts)[order]
        owner_a = np.concatenate(owners)[order]
        side_a = np.concatenate(sides)[order]
    else:
        t = np.zeros((0, 3, 3))
        owner_a = np.zeros(0, np.int64)
        side_a = np.zeros(0, np.int64)
    # each side's triangles within flat_tol of the design at their centroids (where
    # the centroid is on that side: a curved wall's chord is off by its sagitta)
    s = np.flatnonzero(side_a >= 0)
    if len(s):
        cen = t[s].mean(axis=1)
        zd = _h(design, cen[:, 0], cen[:, 1], floor)
        same = (zd > level[owner_a[s]]) == (side_a[s] == 1)
        bad = same & (np.abs(zd - cen[:, 2]) > flat_tol)
        good[owner_a[s][bad]] = False
    t = t[good[owner_a]] if len(t) else t
    handled = np.zeros(len(ok), bool)
    handled[idx[good]] = True
    return t, handled


_PATTERNS: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _pattern(code: int) -> tuple[np.ndarray, np.ndarray]:
    """Triangles of a wall cell whose high corners are the bits of ``code`` (corner k:
    bit k; one wall, not a saddle): rows of point numbers (corners 0-3, high-side
    crossings 4-7, low-side 8-11 on edge k -> k+1) and each triangle's side (1 high,
    0 low, -1 the wall). The high part's fan, the low part's, then the wall (two
    triangles from the crossing where the way round leaves the high side, normal to
    the low side)."""
    if code not in _PATTERNS:
        H = [bool(code >> k & 1) for k in range(4)]
        polys: dict[bool, list[int]] = {True: [], False: []}
        ends = []
        for k in range(4):
            polys[H[k]].append(k)
            if H[k] != H[(k + 1) % 4]:
                polys[True].append(4 + k)
                polys[False].append(8 + k)
                ends.append((k, H[k]))
        rows, side = [], []
        for h in (True, False):
            pts = polys[h]
            for j in range(1, len(pts) - 1):
                rows.append([pts[0], pts[j], pts[j + 1]])
                side.append(1 if h else 0)
        (kp, hp), (kq, _) = ends
        if not hp:
            kp, kq = kq, kp
        rows += [[8 + kp, 8 + kq, 4 + kq], [8 + kp, 4 + kq, 4 + kp]]
        side += [-1, -1]
        _PATTERNS[code] = (np.array(rows, np.int64), np.array(side, np.int64))
    return _PATTERNS[code]
