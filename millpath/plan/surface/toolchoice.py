"""Tool choice for finishing: the largest ball that fits every concave region and whose
shank and holder never touch the surface.

Curvature: the smallest concave radius (a valley seen from above, where a ball larger
than the radius of curvature cannot reach the bottom) is measured on the mesh itself,
see :func:`mesh_concave_radius`. Lengths in job units.
"""

from __future__ import annotations

import numpy as np

from millpath.geometry.rows import unique_rows
from millpath.model.tool import Tool
from millpath.plan.surface.dropcutter import MeshIndex, surface_cutter
from millpath.plan.surface.sampler import Sampler

#: concave edges sharper than this percentile are taken as faceting of the mesh (a
#: height grid of a steep wall has staircase creases) and left out of the tool choice
CURVATURE_PERCENTILE = 99.5


def holder_collisions(index: MeshIndex, tool: Tool, region, spacing: float) -> int:
    """Number of grid points (``spacing`` apart over ``region``) where the shank or the
    holder of ``tool`` would touch the surface with the cutter on it."""
    s = Sampler(index, surface_cutter(tool), holder=tuple(tool.holder_cylinders()))
    x0, y0, x1, y1 = region
    X, Y = np.meshgrid(np.arange(x0, x1 + 1e-12, spacing), np.arange(y0, y1 + 1e-12, spacing))
    _, lifted = s.z_safe(X.ravel(), Y.ravel())
    return int(lifted.sum())


def choose_tool(tools: dict[int, Tool], index: MeshIndex, design, region,
                spacing: float) -> tuple[Tool | None, dict]:
    """Pick the largest ball cutter under the smallest concave radius whose holder never
    collides; returns the tool (None if none fits) and an explanation for the report."""
    rho = mesh_concave_radius(index.mesh, region, CURVATURE_PERCENTILE)
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
                    "curvature": (f"from vertex normals along the mesh edges, the sharpest "
                                  f"{100 - CURVATURE_PERCENTILE:g}% of concave edges left "
                                  f"out as faceting"),
                    "candidates": why,
                    "chosen": chosen.number if chosen else None}


def mesh_concave_radius(mesh, region=None, percentile: float = 100.0) -> float:
    """Smallest concave radius of curvature of a triangle mesh (job units).

    Vertex normals are the area-weighted normals of the triangles around each vertex
    (oriented up); along an edge ``p_i p_j`` the normal curvature is
    ``k = (n_j - n_i) . (p_j - p_i) / |p_j - p_i|^2`` (exact on a sphere), negative
    where the surface is concave seen from above (a valley). Robust on steep walls,
    where finite differences of the height field are not. ``region`` (xmin, ymin, xmax,
    ymax) keeps edges whose midpoint lies inside; ``percentile`` < 100 ignores the
    sharpest edges (mesh noise). ``inf`` if no edge is concave."""
    t = mesh.triangles
    n = len(t)
    V, inv, _ = unique_rows(np.round(t.reshape(-1, 3), 9))
    F = inv.reshape(n, 3)
    fn = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])      # length = 2 * area
    fn[fn[:, 2] < 0] *= -1.0
    vn = np.zeros_like(V)
    for j in range(3):
        np.add.at(vn, F[:, j], fn)
    ln = np.linalg.norm(vn, axis=1)
    vn[ln > 0] /= ln[ln > 0, None]
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    e.sort(axis=1)
    e, _, uses = unique_rows(e)
    # normals at the mesh's boundary are one-sided: leave its edges out
    rim = np.zeros(len(V), bool)
    rim[e[uses == 1].ravel()] = True
    e = e[~rim[e[:, 0]] & ~rim[e[:, 1]]]
    pi, pj = V[e[:, 0]], V[e[:, 1]]
    if region is not None:
        x0, y0, x1, y1 = region
        m = 0.5 * (pi + pj)
        keep = (m[:, 0] >= x0) & (m[:, 0] <= x1) & (m[:, 1] >= y0) & (m[:, 1] <= y1)
        e, pi, pj = e[keep], pi[keep], pj[keep]
    d = pj - pi
    L2 = np.einsum("ij,ij->i", d, d)
    ok = (L2 > 0) & (ln[e[:, 0]] > 0) & (ln[e[:, 1]] > 0)
    k = np.einsum("ij,ij->i", vn[e[ok, 1]] - vn[e[ok, 0]], d[ok]) / L2[ok]
    concave = -k[k < 0]
    if len(concave) == 0:
        return float("inf")
    kmax = float(np.percentile(concave, percentile)) if percentile < 100 else float(concave.max())
    return 1.0 / kmax if kmax > 0 else float("inf")
