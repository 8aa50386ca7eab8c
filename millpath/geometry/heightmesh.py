"""Triangle mesh of a height-field design ``height(x, y) -> z``, walls included.

A quadtree over the box: a cell is kept whole when its centre and edge midpoints lie
within ``flat_tol`` of the plane through its corners and its corners do not jump by more
than ``slope * size``; otherwise it is split, down to cells of ``min_size``. Each leaf
becomes two triangles through its corner heights, so a vertical wall becomes a ramp
at most ``min_size`` wide lying across the true wall: the mesh is within ``min_size``
(horizontally) and ``flat_tol`` (vertically) of the design. Heights of ``-inf`` (no
part) become ``floor``. Triangles wind counter-clockwise seen from above, so normals
point out of the material (up, or away from the high side on a wall). Job units.
"""

from __future__ import annotations

import math

import numpy as np


def _h(design, x, y, floor):
    z = np.asarray(design.height(x, y), float).reshape(np.shape(x))
    return np.where(np.isfinite(z), np.maximum(z, floor), floor)


def height_field_mesh(design, box: tuple[float, float, float, float], *, size: float,
                      min_size: float, flat_tol: float, floor: float,
                      slope: float = 4.0, max_cells: int = 4_000_000) -> np.ndarray:
    """Triangles (n, 3, 3) of ``design`` over ``box`` = (xmin, ymin, xmax, ymax)."""
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
    while len(cx):
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
        split = ((dev > flat_tol) | (spread > slope * size_)) & (size_ > min_size)
        keep = ~split
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
    return np.ascontiguousarray(np.concatenate(out))
