"""Tool choice for finishing: the largest ball that fits every concave region and whose
shank and holder never touch the surface.

Curvature convention: principal curvatures of the surface seen from above (upward
normal); positive = concave (a valley, where a ball larger than the radius of
curvature cannot reach the bottom). Lengths in job units.
"""

from __future__ import annotations

import numpy as np

from millpath.model.tool import Tool
from millpath.plan.surface.cutter import Cutter
from millpath.plan.surface.dropcutter import MeshIndex
from millpath.plan.surface.sampler import Sampler


def min_concave_radius(design, region, spacing: float) -> float:
    """Smallest concave radius of curvature of the height field ``design`` over
    ``region`` (xmin, ymin, xmax, ymax), from finite differences ``spacing`` apart
    (choose a few triangle sizes for a mesh). ``inf`` if nowhere concave."""
    x0, y0, x1, y1 = region
    xs = np.arange(x0 + spacing, x1 - spacing + 1e-12, spacing)
    ys = np.arange(y0 + spacing, y1 - spacing + 1e-12, spacing)
    if len(xs) < 3 or len(ys) < 3:
        return float("inf")
    X, Y = np.meshgrid(xs, ys)
    Z = design.height(X, Y)
    if not np.all(np.isfinite(Z)):
        Z = np.where(np.isfinite(Z), Z, np.nanmin(np.where(np.isfinite(Z), Z, np.nan)))
    fy, fx = np.gradient(Z, spacing)
    fyy, fyx = np.gradient(fy, spacing)
    fxy, fxx = np.gradient(fx, spacing)
    fxy = 0.5 * (fxy + fyx)
    g = 1.0 + fx * fx + fy * fy
    # shape operator I^-1 II for the graph z = f(x, y); II = Hess / sqrt(g)
    E, F, G = 1.0 + fx * fx, fx * fy, 1.0 + fy * fy
    L, M, N = fxx / np.sqrt(g), fxy / np.sqrt(g), fyy / np.sqrt(g)
    det = E * G - F * F
    a11 = (G * L - F * M) / det
    a12 = (G * M - F * N) / det
    a21 = (E * M - F * L) / det
    a22 = (E * N - F * M) / det
    tr = a11 + a22
    disc = np.sqrt(np.maximum((a11 - a22) ** 2 + 4.0 * a12 * a21, 0.0))
    kmax = 0.5 * (tr + disc)
    kmax = kmax[1:-1, 1:-1]
    if not np.any(kmax > 1e-12):
        return float("inf")
    return float(1.0 / kmax.max())


def holder_collisions(index: MeshIndex, tool: Tool, region, spacing: float) -> int:
    """Number of grid points (``spacing`` apart over ``region``) where the shank or the
    holder of ``tool`` would touch the surface with the cutter on it."""
    s = Sampler(index, Cutter.from_tool(tool), holder=tuple(tool.holder_cylinders()))
    x0, y0, x1, y1 = region
    X, Y = np.meshgrid(np.arange(x0, x1 + 1e-12, spacing), np.arange(y0, y1 + 1e-12, spacing))
    _, lifted = s.z_safe(X.ravel(), Y.ravel())
    return int(lifted.sum())


def choose_tool(tools: dict[int, Tool], index: MeshIndex, design, region,
                spacing: float) -> tuple[Tool | None, dict]:
    """Pick the largest ball cutter under the smallest concave radius whose holder never
    collides; returns the tool (None if none fits) and an explanation for the report."""
    rho = min_concave_radius(design, region, spacing)
    balls = sorted((t for t in tools.values() if t.type == "ball"),
                   key=lambda t: (-t.radius, t.number))
    why: list[dict] = []
    chosen = None
    for t in balls:
        entry = {"tool": t.number, "diameter": t.diameter}
        if not t.radius < rho:
            entry["rejected"] = (f"radius {t.radius:g} is not below the smallest concave "
                                 f"radius {rho:.4g}")
        else:
            n = holder_collisions(index, t, region, max(spacing, t.radius / 2.0))
            if n:
                entry["rejected"] = f"shank or holder touches the surface at {n} grid points"
            elif chosen is None:
                entry["chosen"] = "largest ball below the smallest concave radius, holder clear"
                chosen = t
        why.append(entry)
        if chosen is not None:
            break
    return chosen, {"min_concave_radius": rho if np.isfinite(rho) else None,
                    "candidates": why,
                    "chosen": chosen.number if chosen else None}
