"""Planners proven on generated jobs: jobs a user could write, run through the pipeline.

For each operation type (grid-pocket, pocket, profile, die-cavity, surface-rough,
surface-finish, features from AP224 files and from STEP solids) this draws random jobs from a
fixed seed (numpy's Generator: the same seed gives the same jobs), writes each as a job
file in a temp folder and runs it with :func:`millpath.pipeline.run_job`, as
``millpath run`` does. Each job ends as one of:

- written: the proof passed and program.ngc was written; then the independent check
  (:mod:`generated_check`: LinuxCNC's rs274 and shapely against the job's own geometry)
  runs on it;
- refused up front: a one-line ``MillpathError`` before any program (counted by reason),
  or a features operation's own refusal of a feature no tool of the job can machine
  (``unmachinable = "refuse"``, the default; the proof found nothing);
- refused by the proof after planning (``UnsafeProgramError``): a planner bug; the job
  is copied to the replay folder;
- crashed: any other exception (a bug), also copied to the replay folder.

Usage: ``python bench/generated_jobs.py --jobs 30 --seed 1 --types grid-pocket,pocket``.
Millimetres throughout.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import re
import shutil
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from shapely.geometry import Polygon

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))   # support.rs274
import generated_check as gc  # noqa: E402
import generated_shapes as gs  # noqa: E402

TYPES = ("grid-pocket", "pocket", "profile", "die-cavity", "surface-rough", "surface-finish",
         "features-ap224", "features-solid")
#: messages of errors found after planning (the program is bad, not the request)
AFTER_PLANNING = ("does not interpret", "differs from the planned")
#: errors of the interpreter: a planned program the control refuses
AFTER_TYPES = ("GCodeError", "InterpreterError")
REPLAY = Path(__file__).resolve().parent / "generated_replay"


@dataclass
class Job:
    """A job file's tables (``toml``), its extra files and the geometry to check."""

    toml: dict
    geometry: gc.Geometry | dict[int, gc.Geometry]   # per tool number, or for all
    files: dict[str, str | bytes] = field(default_factory=dict)


def _val(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, float):
        return repr(round(v, 4))
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_val(x) for x in v) + "]"
    return str(v)


def toml_text(job: dict) -> str:
    """TOML of a job dict: top keys, [stock], [[tools]], [[operations]] (+ sub-tables)."""
    out = [f"{k} = {_val(v)}" for k, v in job.items() if not isinstance(v, (dict, list))
           or k not in ("stock", "simulation", "tools", "operations")]
    for name in ("stock", "simulation"):
        if name in job:
            out += ["", f"[{name}]"] + [f"{k} = {_val(v)}" for k, v in job[name].items()]
    for name in ("tools", "operations"):
        for t in job.get(name, []):
            out += ["", f"[[{name}]]"]
            subs = {k: v for k, v in t.items() if isinstance(v, dict)}
            out += [f"{k} = {_val(v)}" for k, v in t.items() if k not in subs]
            for k, v in subs.items():
                out += ["", f"[{name}.{k}]"] + [f"{a} = {_val(b)}" for a, b in v.items()]
    return "\n".join(out) + "\n"


def _tool(rng, types=("flat",), depth: float = 10.0) -> dict:
    d = float(rng.choice([3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0]))
    t = str(rng.choice(types))
    flute = round(depth + float(rng.uniform(3, 15)), 1)
    tool = {"number": int(rng.integers(1, 20)), "type": t, "diameter": d,
            "flute_length": flute, "stickout": round(flute + float(rng.uniform(5, 20)), 1)}
    if t == "bull":
        tool["corner_radius"] = round(float(rng.uniform(0.1, 0.45)) * d, 2)
    if rng.random() < 0.5:
        tool["holder"] = [[round(d * 2 + 10, 1), 40.0]]
    return tool


def _cutting(rng) -> dict:
    return {"feed": round(float(rng.uniform(200, 2000))), "spindle": 8000}


def _centre_geometry(tool: dict, tol: float, region: Polygon, side: str, top: float = 0.0,
                     floor: float = -np.inf, surface=None) -> gc.Geometry:
    return gc.Geometry(top=top, radius=tool["diameter"] / 2, tool_type=tool["type"],
                       corner_radius=tool.get("corner_radius", 0.0), tol=tol + 0.001,
                       region=region, side=side, floor=floor, surface=surface)


def grid_pocket_job(rng) -> Job:
    """A grid-pocket: random polygon, flat / Bezier / measured bottom, layers."""
    zhi = -float(rng.uniform(2, 10))
    zlo = zhi - float(rng.uniform(0, 8))
    tool = _tool(rng, ("flat", "ball", "bull"), -zlo)
    kind = str(rng.choice(gs.KINDS))
    poly = gs.polygon(rng, kind, (10.0, 10.0), float(rng.uniform(40, 80)),
                      float(rng.uniform(40, 80)), tool["diameter"])
    p = Polygon(poly)
    b = p.bounds
    op = {"type": "grid-pocket", "tool": tool["number"], "polygon": poly, **_cutting(rng),
          "motion": str(rng.choice(["line", "arc"])), "zigzag": bool(rng.random() < 0.7),
          "navigation": str(rng.choice(["wall-first", "straight-first"]))}
    files = {}
    form = str(rng.choice(["flat", "bezier", "measured"]))
    if form == "flat":
        z = round(zhi, 3)
        op["bottom"] = {"bezier": [[z, z], [z, z]]}
        surface = gc.bezier_surface([[z, z], [z, z]], b)
    elif form == "bezier":
        n = int(rng.integers(3, 5))
        net = np.round(rng.uniform(zlo, zhi, size=(n, n)), 3).tolist()
        op["bottom"] = {"bezier": net}
        surface = gc.bezier_surface(net, b)
    else:
        step = float(rng.uniform(4, 12))
        xs = np.linspace(b[0], b[2], max(2, int(np.ceil((b[2] - b[0]) / step)) + 1))
        ys = np.linspace(b[1], b[3], max(2, int(np.ceil((b[3] - b[1]) / step)) + 1))
        kx, ky, ph = rng.uniform(0.02, 0.15, 2).tolist() + [float(rng.uniform(0, 6))]
        zs = np.round(zhi + (zlo - zhi) * 0.5 * (1 + np.sin(kx * xs[None, :] + ph)
                                                  * np.cos(ky * ys[:, None])), 4)
        xs, ys = np.round(xs, 4), np.round(ys, 4)
        rows = [f"{x},{y},{zs[j, i]}" for j, y in enumerate(ys) for i, x in enumerate(xs)]
        files["bottom.csv"] = "x,y,z\n" + "\n".join(rows) + "\n"
        op["bottom"] = {"points": "bottom.csv"}
        surface = gc.grid_surface(xs, ys, zs)
    r = rng.random()
    if r < 0.45:
        op["stepdown"] = round(float(rng.uniform(1.0, 5.0)), 2)
    elif r < 0.65:
        k = int(rng.integers(1, 4))
        op["depths"] = sorted(np.round(rng.uniform(zhi, -0.5, k), 2).tolist(), reverse=True)
        op["depths"] = [d for i, d in enumerate(op["depths"]) if d not in op["depths"][:i]]
    if rng.random() < 0.4:
        g = (rng.uniform(0.3, 0.7, 2) * tool["diameter"]).round(3).tolist()
        op["grid"] = g
    tol = 0.005
    if rng.random() < 0.3:
        tol = round(float(rng.uniform(0.002, 0.02)), 4)
        op["tolerance"] = tol
    job = {"units": "mm", "name": f"generated grid-pocket ({kind}, {form} bottom)",
           "stock": {"box": [0.0, 0.0, round(zlo - 5, 1), round(b[2] + 10, 1),
                             round(b[3] + 10, 1), 0.0]},
           "tools": [tool], "operations": [op]}
    return Job(job, _centre_geometry(tool, tol, p, "inside", surface=surface), files)


def _twod(rng, op_type: str) -> tuple[dict, dict, Polygon, list]:
    depth = round(float(rng.uniform(1.0, 15.0)), 2)
    tool = _tool(rng, ("flat", "bull"), depth)
    kind = str(rng.choice(gs.KINDS))
    origin = (30.0, 30.0) if op_type == "profile" else (10.0, 10.0)
    poly = gs.polygon(rng, kind, origin, float(rng.uniform(30, 90)),
                      float(rng.uniform(30, 70)), tool["diameter"])
    isl = gs.islands(rng, poly, tool["diameter"], int(rng.integers(0, 3)),
                     gap=tool["diameter"] * float(rng.uniform(1.1, 2.0)))
    op = {"type": op_type, "tool": tool["number"], "polygon": poly, "depth": depth,
          "stepdown": round(float(rng.uniform(0.3, 1.0)) * depth, 2), **_cutting(rng)}
    if isl:
        op["islands"] = isl
    if rng.random() < 0.3:
        op["tolerance"] = round(float(rng.uniform(0.005, 0.05)), 4)
    op["direction"] = str(rng.choice(["climb", "conventional"]))
    return op, tool, Polygon(poly, isl), [kind]


def pocket_job(rng) -> Job:
    """A pocket: random outline and islands, offset / zigzag / adaptive clearing."""
    op, tool, region, tags = _twod(rng, "pocket")
    op["strategy"] = str(rng.choice(["offset", "zigzag", "adaptive"]))
    if rng.random() < 0.5:
        op["stepover"] = round(float(rng.uniform(0.2, 0.7)) * tool["diameter"], 3)
    if op["strategy"] == "zigzag":
        op["angle"] = round(float(rng.uniform(0, 180)), 1)
    if op["strategy"] == "adaptive":
        op["engagement"] = round(float(rng.uniform(0.08, 0.3)), 3)
    if rng.random() < 0.3:
        op["allowance"] = round(float(rng.uniform(0.1, 0.5)), 2)
    op["entry"] = str(rng.choice(["helix", "ramp"]))
    if rng.random() < 0.3:
        op["ramp_angle"] = round(float(rng.uniform(1.0, 10.0)), 1)
    b = region.bounds
    job = {"units": "mm", "name": f"generated pocket ({tags[0]}, {op['strategy']})",
           "fit": str(rng.choice(["none", "arcs"])),
           "stock": {"box": [0.0, 0.0, -round(op["depth"] + 5, 1), round(b[2] + 10, 1),
                             round(b[3] + 10, 1), 0.0]},
           "tools": [tool], "operations": [op]}
    tol = op.get("tolerance", 0.01)
    return Job(job, _centre_geometry(tool, tol, region, "inside", floor=-op["depth"]))


def profile_job(rng) -> Job:
    """A profile: random outline with holes, outside or inside, leads and tabs."""
    op, tool, region, tags = _twod(rng, "profile")
    op["side"] = str(rng.choice(["outside", "inside"]))
    op["compensation"] = str(rng.choice(["cam", "control"]))
    if rng.random() < 0.4:
        op["lead_radius"] = round(float(rng.uniform(0.55, 1.5)) * tool["diameter"], 3)
    if op["side"] == "outside" and rng.random() < 0.4:
        op["tabs"] = int(rng.integers(1, 5))
        op["tab_height"] = round(float(rng.uniform(0.2, 0.5)) * op["depth"], 2)
        if rng.random() < 0.5:
            op["tab_width"] = round(float(rng.uniform(1.0, 3.0)) * tool["diameter"], 2)
    b = region.bounds
    job = {"units": "mm", "name": f"generated profile ({tags[0]}, {op['side']})",
           "fit": str(rng.choice(["none", "arcs"])),
           "stock": {"box": [0.0, 0.0, -round(op["depth"] + 5, 1), round(b[2] + 30, 1),
                             round(b[3] + 30, 1), 0.0]},
           "tools": [tool], "operations": [op]}
    tol = op.get("tolerance", 0.01)
    return Job(job, _centre_geometry(tool, tol, region, op["side"], floor=-op["depth"]))


#: the four-point basis (u = 0, 1/3, 2/3, 1), rows L1..L4, columns u^3, u^2, u, 1, and
#: the end derivatives of a segment through P1..P4, as the die-cavity document gives them
_LAGRANGE = np.array([[-4.5, 9.0, -5.5, 1.0], [13.5, -22.5, 9.0, 0.0],
                      [-13.5, 18.0, -4.5, 0.0], [4.5, -4.5, 1.0, 0.0]])


def four_point_outline(points: np.ndarray, n: int = 400) -> np.ndarray:
    """The closed die-cavity outline through ``points`` (4k, 2), evaluated here from the
    document's definitions (Mohamed 2006): each four points a cubic through them at
    u = 0, 1/3, 2/3, 1; a gap between one segment's end and the next one's start is
    a cubic through the two ends whose derivatives (per u) equal the neighbours'."""
    segs = [points[k:k + 4] for k in range(0, len(points), 4)]
    u = np.linspace(0.0, 1.0, n)
    basis = np.column_stack([u ** 3, u ** 2, u, np.ones_like(u)]) @ _LAGRANGE.T
    d0 = lambda q: -5.5 * q[0] + 9 * q[1] - 4.5 * q[2] + q[3]        # noqa: E731
    d1 = lambda q: -q[0] + 4.5 * q[1] - 9 * q[2] + 5.5 * q[3]         # noqa: E731
    out = []
    for i, a in enumerate(segs):
        out.append(basis @ a)
        c = segs[(i + 1) % len(segs)]
        if np.hypot(*(a[3] - c[0])) > 1e-9:
            # the blend B from B1 = a's end to B4 = c's start, its inner points B2, B3
            # from B'(0) = a'(1) and B'(1) = c'(0)
            b1, b4 = a[3], c[0]
            m = np.array([[9.0, -4.5], [4.5, -9.0]])
            rhs = np.array([d1(a) + 5.5 * b1 - b4, d0(c) + b1 - 5.5 * b4])
            b2, b3 = np.linalg.solve(m, rhs)
            out.append(basis @ np.array([b1, b2, b3, b4]))
    return np.concatenate(out)


def die_cavity_job(rng) -> Job:
    """A die-cavity: a smooth random closed outline given as 2 to 4 four-point
    segments (blended), in a plate; blind or through; CAM or control compensation."""
    plate = round(float(rng.uniform(6.0, 30.0)), 1)
    through = rng.random() < 0.3
    depth = plate if through else round(float(rng.uniform(1.0, plate - 0.5)), 2)
    tool = _tool(rng, ("flat",), depth)
    d = tool["diameter"]
    r0 = float(rng.uniform(max(3.0 * d, 15.0), 70.0))
    k = np.arange(2, 5)
    amp, ph = rng.uniform(0.0, 0.12, 3), rng.uniform(0, 2 * math.pi, 3)
    nseg = int(rng.integers(2, 5))
    # each segment's span of angle, and the gap the blend crosses after it: about as
    # long as the segments beside it (a blend much shorter than its neighbours must
    # turn their end speeds round within it and loops; a user's outline does not)
    spans = rng.uniform(0.5, 1.0, nseg)
    gaps = rng.uniform(0.6, 1.2, nseg) * 0.5 * (spans + np.roll(spans, -1))
    scale = 2 * math.pi / float(spans.sum() + gaps.sum())
    spans, gaps = spans * scale, gaps * scale
    ang, a0 = [], float(rng.uniform(0, 2 * math.pi))
    for sp, gp in zip(spans, gaps):
        ang += list(a0 + sp * np.arange(4) / 3.0)
        a0 += sp + gp
    ang = np.asarray(ang)
    rad = r0 * (1.0 + (amp[:, None] * np.cos(k[:, None] * ang[None, :] + ph[:, None])).sum(0))
    c = r0 * 1.25 + 20.0
    pts = np.round(np.column_stack([c + rad * np.cos(ang), c + rad * np.sin(ang)]), 3)
    if rng.random() < 0.5:
        pts = pts[::-1].copy()                   # clockwise, segments reversed too
    outline = four_point_outline(pts)
    region = Polygon(outline)
    if not region.is_valid:
        region = region.buffer(0)
    op = {"type": "die-cavity", "tool": tool["number"], "points": pts.tolist(),
          "close": True, "tolerance": round(float(10 ** rng.uniform(-3.5, -1.5)), 5),
          "depth": depth, "stepdown": round(float(rng.uniform(0.2, 1.0)) * min(depth, 10.0), 2),
          "allowance": round(float(rng.uniform(0.0, 0.5)), 2), **_cutting(rng),
          "compensation": str(rng.choice(["cam", "control"]))}
    if rng.random() < 0.5:
        op["stepover"] = round(float(rng.uniform(0.2, 0.7)) * d, 3)
    if op["compensation"] == "control" and rng.random() < 0.5:
        op["entry"] = "arc"
    if through:
        op["breakthrough"] = round(float(rng.uniform(0.2, 2.0)), 2)
    side = 2 * c
    job = {"units": "mm", "name": f"generated die-cavity ({nseg} segments"
                                  f"{', through' if through else ''})",
           "stock": {"box": [0.0, 0.0, 0.0, round(side, 1), round(side, 1), plate]},
           "tools": [tool], "operations": [op]}
    floor = -op.get("breakthrough", 0.0) if through else plate - depth
    return Job(job, _centre_geometry(tool, op["tolerance"], region, "inside", top=plate,
                                     floor=floor))


def _surface_part(rng) -> tuple[dict, bytes, np.ndarray, float]:
    """A height-field part as an STL file: (stock table, STL bytes, its triangles as
    the file holds them (float32), depth from the stock top to the lowest point)."""
    w, h = float(rng.uniform(25, 50)), float(rng.uniform(25, 50))
    xs, ys, z = gs.heightfield(rng, w, h)
    data = gs.stl_bytes(gs.heightfield_triangles(xs, ys, z))
    tri = np.frombuffer(data, dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")],
                        offset=84)["v"].astype(float)
    top = round(float(rng.uniform(0.0, 2.0)), 2)
    stock = {"box": [0.0, 0.0, round(float(z.min()) - 3.0, 1), round(w, 3), round(h, 3), top]}
    return stock, data, tri, top - float(z.min())


def _rough_op(rng, tool: dict) -> dict:
    op = {"type": "surface-rough", "tool": tool["number"], "surface": "part.stl",
          "stepdown": round(float(rng.uniform(0.5, 4.0)), 2),
          "allowance": round(float(rng.uniform(0.1, 1.0)), 2),
          "angle": round(float(rng.uniform(0, 180)), 1), **_cutting(rng)}
    if rng.random() < 0.5:
        op["stepover"] = round(float(rng.uniform(0.3, 0.8)) * tool["diameter"], 3)
    return op


def _surface_geometry(tool: dict, tri: np.ndarray, tol: float, top: float,
                      allowance: float = 0.0) -> gc.Geometry:
    return gc.Geometry(top=top, radius=tool["diameter"] / 2, tool_type=tool["type"],
                       corner_radius=tool.get("corner_radius", 0.0), tol=tol + 0.001,
                       region=Polygon(), side="surface", mesh=tri, allowance=allowance)


def surface_rough_job(rng) -> Job:
    """A surface-rough of a generated height-field part (bumps, dips, steep bosses and
    cavities) from a block: flat or bull end mill, random step-down, step-over,
    allowance and pass angle."""
    stock, data, tri, depth = _surface_part(rng)
    tool = _tool(rng, ("flat", "bull"), depth)
    op = _rough_op(rng, tool)
    job = {"units": "mm", "name": "generated surface-rough", "stock": stock,
           "tools": [tool], "operations": [op]}
    tol = 0.25 * op["allowance"]                 # the tolerance surface-rough plans to
    return Job(job, _surface_geometry(tool, tri, tol, stock["box"][5], op["allowance"]),
               {"part.stl": data})


def surface_finish_job(rng) -> Job:
    """Roughing then a surface-finish of a generated height-field part: ball or bull
    cutter; zigzag, waterline or steep-shallow; published or variable side step;
    random scallop, tolerance and angle."""
    stock, data, tri, depth = _surface_part(rng)
    rough = _tool(rng, ("flat", "bull"), depth)
    tool = _tool(rng, ("ball", "ball", "bull"), depth)
    tool["number"] = rough["number"] % 19 + 1
    op = {"type": "surface-finish", "tool": tool["number"], "surface": "part.stl",
          "strategy": str(rng.choice(["zigzag", "waterline", "steep-shallow"])),
          "side_step": str(rng.choice(["published", "variable"])),
          "scallop": round(float(10 ** rng.uniform(-1.7, -1.0)), 4),
          "angle": round(float(rng.uniform(0, 180)), 1), **_cutting(rng)}
    tol = 0.005
    if rng.random() < 0.5:
        tol = round(float(rng.uniform(0.003, 0.02)), 4)
        op["tolerance"] = tol
    if op["strategy"] == "steep-shallow" and rng.random() < 0.5:
        op["steep_angle"] = round(float(rng.uniform(30.0, 70.0)), 1)
    job = {"units": "mm", "name": f"generated surface-finish ({op['strategy']}, "
                                  f"{tool['type']})", "stock": stock,
           "tools": [rough, tool], "operations": [_rough_op(rng, rough), op]}
    top = stock["box"][5]
    ra = job["operations"][0]["allowance"]
    geo = {rough["number"]: _surface_geometry(rough, tri, 0.25 * ra, top, ra),
           tool["number"]: _surface_geometry(tool, tri, tol, top)}
    return Job(job, geo, {"part.stl": data})


#: the tool crib of a generated features job: flat end mills and drills (mm)
FEATURE_TOOLS = [(1, "flat", 20.0), (2, "flat", 12.0), (3, "flat", 8.0), (4, "flat", 6.0),
                 (5, "flat", 3.0), (6, "drill", 5.0), (7, "drill", 8.5), (8, "drill", 10.0)]


def _feature_tools(height: float) -> list[dict]:
    out = []
    for n, kind, d in FEATURE_TOOLS:
        flute = round(max(height + 5.0, 2.5 * d), 1)
        t = {"number": n, "type": kind, "diameter": d, "flute_length": flute,
             "stickout": round(flute + 10.0, 1)}
        if kind == "drill":
            t["point_angle"] = 118.0
        out.append(t)
    return out


def _place(taken: list, shape, block) -> bool:
    """``shape`` fits in ``block`` 3 mm clear of the features already ``taken``."""
    if not block.buffer(-3.0).contains(shape) or any(
            shape.distance(t) < 3.0 for t in taken):
        return False
    taken.append(shape)
    return True


def features_ap224_job(rng) -> Job:
    """An AP224 part (written to the standard with millpath's AP224 writer): a block
    with 1 to 5 features from its top face, 3 mm apart: round holes (through or flat
    bottomed), rectangular pockets with corner radii, circular pockets, and slots
    across the block placed as ISO 10303-224 places them; the tool crib of
    ``FEATURE_TOOLS``."""
    from shapely.geometry import Point, box
    from millpath.part.step.build import Ap224Builder
    L, W = round(float(rng.uniform(60, 160)), 1), round(float(rng.uniform(40, 100)), 1)
    H = round(float(rng.uniform(8, 30)), 1)
    b = Ap224Builder("GENERATED", units="mm", material="aluminium",
                     description="generated block")
    b.block(L, W, H)
    block = box(0, 0, L, W)
    taken: list = []
    levels: list[tuple[float, Polygon]] = []
    kinds = []
    for _ in range(int(rng.integers(1, 6))):
        kind = str(rng.choice(["hole", "pocket", "circular", "slot"]))
        depth = round(float(rng.uniform(1.0, H - 1.5)), 2)
        for _try in range(20):
            cx, cy = float(rng.uniform(0, L)), float(rng.uniform(0, W))
            if kind == "hole":
                d = round(float(rng.uniform(3.2, 30.0)), 2)
                shape = Point(cx, cy).buffer(d / 2, quad_segs=256)
                if not _place(taken, shape, block):
                    continue
                through = rng.random() < 0.5
                b.hole((round(cx, 3), round(cy, 3), H), d, H if through else depth,
                       bottom="through" if through else "flat")
                levels.append((-math.inf if through else H - depth, shape))
            elif kind in ("pocket", "circular"):
                if kind == "pocket":
                    pl, pw = (round(float(v), 2) for v in rng.uniform(10, 50, 2))
                    rc = round(float(rng.uniform(1.6, min(pl, pw) / 2 - 0.1)), 2)
                    shape = box(cx - pl / 2, cy - pw / 2, cx + pl / 2, cy + pw / 2)
                    shape = shape.buffer(-rc, join_style=2).buffer(rc, quad_segs=256)
                    dims = {"length": pl, "width": pw, "corner_radius": rc}
                else:
                    d = round(float(rng.uniform(10, 50)), 2)
                    shape = Point(cx, cy).buffer(d / 2, quad_segs=256)
                    dims = {"diameter": d}
                if not _place(taken, shape, block):
                    continue
                b.pocket((round(cx, 3), round(cy, 3), H), depth,
                         "rectangular" if kind == "pocket" else "circular", **dims)
                levels.append((H - depth, shape))
            else:
                width = round(float(rng.uniform(6.0, 20.0)), 2)
                along_x = rng.random() < 0.5
                c = round(cy if along_x else cx, 3)
                shape = (box(-1.0, c - width / 2, L + 1.0, c + width / 2) if along_x else
                         box(c - width / 2, -1.0, c + width / 2, W + 1.0))
                inner = shape.intersection(block.buffer(-3.0))
                if (c - width / 2 < 3.0 or c + width / 2 > (W if along_x else L) - 3.0
                        or any(inner.distance(t) < 3.0 for t in taken)):
                    continue
                taken.append(inner)
                start = (0.0, c, H - depth) if along_x else (c, 0.0, H - depth)
                b.slot_iso(start, (1.0, 0.0) if along_x else (0.0, 1.0),
                           L if along_x else W, width, depth)
                levels.append((H - depth, shape))
            kinds.append(kind)
            break
    job = {"units": "mm", "name": f"generated AP224 block ({', '.join(kinds) or 'plain'})",
           "tools": _feature_tools(H),
           "operations": [{"type": "features", "step": "part.stp"}]}
    geo = {t["number"]: gc.Geometry(top=H, radius=t["diameter"] / 2, tool_type="flat",
                                    corner_radius=0.0, tol=0.01 + 0.001, region=block,
                                    side="air", levels=levels)
           for t in job["tools"]}
    return Job(job, geo, {"part.stp": b.text()})


@contextlib.contextmanager
def _quiet_fd1():
    """OpenCASCADE's STEP writer prints to the process's standard output: to /dev/null."""
    sys.stdout.flush()
    keep = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        yield
    finally:
        os.dup2(keep, 1)
        os.close(keep)
        os.close(null)


def _afr_builder():
    """The OpenCASCADE solid helpers of the recognition tests (tests/afr/builder.py)."""
    import importlib.util
    name = "afr_builder"
    if name not in sys.modules:
        path = Path(__file__).resolve().parents[1] / "tests" / "afr" / "builder.py"
        spec = importlib.util.spec_from_file_location(name, path)
        mod = importlib.util.module_from_spec(spec)
        sys.modules[name] = mod
        spec.loader.exec_module(mod)
    return sys.modules[name]


def features_solid_job(rng) -> Job:
    """A STEP solid (AP214, made with OpenCASCADE's Booleans as a CAD system makes it):
    a plate with 1 to 5 features, 3 mm apart: through and flat-bottomed holes,
    counterbores, pockets with corner radii, closed obround slots, slots across the
    plate and steps along an edge; its features recognised from the B-rep. Half the
    plates have features on both the top and the bottom face; their job machines one
    side (``setup`` "+Z" or "-Z") and lists the other side's features
    (``unmachinable = "list"``)."""
    from shapely.affinity import scale
    from shapely.geometry import LineString, Point, box
    ob = _afr_builder()
    L, W = round(float(rng.uniform(60, 160)), 1), round(float(rng.uniform(40, 100)), 1)
    H = round(float(rng.uniform(8, 30)), 1)
    part = ob.box(0, 0, 0, L, W, H)
    block = box(0, 0, L, W)
    two_faced = rng.random() < 0.5
    taken: list = []
    #: (face, depth from that face or None for through, section in the file's XY)
    levels: list[tuple[str, float | None, Polygon]] = []
    kinds, cuts = [], []

    def span(face: str, depth: float | None) -> tuple[float, float]:
        """(z0, height) of a cutting body removing ``depth`` from ``face``, 1 mm past it."""
        if depth is None:
            return -1.0, H + 2.0
        return (H - depth, depth + 1.0) if face == "top" else (-1.0, depth + 1.0)

    for _ in range(int(rng.integers(1, 6))):
        kind = str(rng.choice(["hole", "counterbore", "pocket", "obround", "slot", "step"]))
        face = str(rng.choice(["top", "bottom"])) if two_faced else "top"
        depth = round(float(rng.uniform(1.0, H - 1.5)), 2)
        for _try in range(20):
            cx, cy = round(float(rng.uniform(0, L)), 3), round(float(rng.uniform(0, W)), 3)
            if kind in ("hole", "counterbore"):
                d = round(float(rng.uniform(3.2, 24.0)), 2)
                big = round(d + float(rng.uniform(3.0, 10.0)), 2) if kind == "counterbore" \
                    else d
                shape = Point(cx, cy).buffer(big / 2, quad_segs=256)
                if not _place(taken, shape, block):
                    continue
                through = kind == "counterbore" or rng.random() < 0.5
                z0, h = span(face, None if through else depth)
                cuts.append(ob.cylinder(cx, cy, z0, d / 2, h))
                levels.append((face, None if through else depth,
                               Point(cx, cy).buffer(d / 2, quad_segs=256)))
                if kind == "counterbore":
                    cb = round(float(rng.uniform(1.0, min(depth, H - 2.0))), 2)
                    z0, h = span(face, cb)
                    cuts.append(ob.cylinder(cx, cy, z0, big / 2, h))
                    levels.append((face, cb, shape))
            elif kind == "pocket":
                pl, pw = (round(float(v), 2) for v in rng.uniform(10, 50, 2))
                rc = round(float(rng.uniform(2.0, min(pl, pw) / 2 - 0.1)), 2)
                x0, y0 = round(cx - pl / 2, 3), round(cy - pw / 2, 3)
                shape = box(x0, y0, x0 + pl, y0 + pw).buffer(-rc, join_style=2) \
                    .buffer(rc, quad_segs=256)
                if not _place(taken, shape, block):
                    continue
                cuts.append(ob.rounded_rect(x0, y0, x0 + pl, y0 + pw, *span(face, depth), rc))
                levels.append((face, depth, shape))
            elif kind == "obround":
                w = round(float(rng.uniform(6.5, 16.0)), 2)
                ln = round(float(rng.uniform(5.0, 40.0)), 2)
                shape = LineString([(cx, cy), (cx + ln, cy)]).buffer(w / 2, quad_segs=256)
                if not _place(taken, shape, block):
                    continue
                cuts.append(ob.obround(cx, cy, cx + ln, *span(face, depth), w))
                levels.append((face, depth, shape))
            else:
                width = round(float(rng.uniform(6.5, 20.0)), 2)
                along_x = rng.random() < 0.5
                extent = W if along_x else L
                c = 0.0 if kind == "step" else round(float(rng.uniform(0, extent)), 3)
                if kind == "step":
                    c = width / 2 if rng.random() < 0.5 else extent - width / 2
                shape = (box(-1.0, c - width / 2, L + 1.0, c + width / 2) if along_x else
                         box(c - width / 2, -1.0, c + width / 2, W + 1.0))
                if kind != "step" and c - width / 2 < 3.0 or c + width / 2 > extent - 3.0:
                    continue
                inner = shape.intersection(block)
                if any(inner.distance(t) < 3.0 for t in taken):
                    continue
                taken.append(inner)
                bx = inner.bounds
                grow = [-1.0 if bx[0] <= 0 else 0.0, -1.0 if bx[1] <= 0 else 0.0,
                        1.0 if bx[2] >= L else 0.0, 1.0 if bx[3] >= W else 0.0]
                z0, h = span(face, depth)
                cuts.append(ob.box(bx[0] + grow[0], bx[1] + grow[1], z0,
                                   bx[2] + grow[2], bx[3] + grow[3], z0 + h))
                levels.append((face, depth, shape))
            kinds.append(kind if face == "top" else f"{kind} below")
            break
    if cuts:
        part = ob.unify(ob.cut(part, *cuts))
    with tempfile.TemporaryDirectory() as tmp, _quiet_fd1():
        path = ob.write_step(part, Path(tmp) / "part.stp")
        text = path.read_text()
    tools = _feature_tools(H)
    op = {"type": "features", "step": "part.stp"}
    up = "top"
    if two_faced:
        up = str(rng.choice(["top", "bottom"]))
        op.update(setup="+Z" if up == "top" else "-Z", unmachinable="list")
    # the machine frame: the file's for "+Z"; for "-Z" turned about X (y, z -> -y, -z)
    if up == "top":
        top, region = H, block
        def frame(g): return g
    else:
        top, region = 0.0, box(0, -W, L, 0)
        def frame(g): return scale(g, 1.0, -1.0, origin=(0, 0))
    air = [(-math.inf, frame(g)) if depth is None else (top - depth, frame(g))
           for face, depth, g in levels if depth is None or face == up]
    job = {"units": "mm", "name": f"generated solid plate ({', '.join(kinds) or 'plain'})",
           "tools": tools, "operations": [op]}
    geo = {t["number"]: gc.Geometry(top=top, radius=t["diameter"] / 2, tool_type="flat",
                                    corner_radius=0.0, tol=0.01 + 0.001, region=region,
                                    side="air", levels=air)
           for t in tools}
    return Job(job, geo, {"part.stp": text})


MAKERS = {"grid-pocket": grid_pocket_job, "pocket": pocket_job, "profile": profile_job,
          "die-cavity": die_cavity_job, "surface-rough": surface_rough_job,
          "surface-finish": surface_finish_job, "features-ap224": features_ap224_job,
          "features-solid": features_solid_job}


@dataclass
class Outcome:
    kind: str          # "written" | "upfront" | "refused" | "crashed"
    reason: str = ""   # the message, numbers replaced by # (to count reasons)
    message: str = ""
    check: gc.CheckResult | None = None
    cpu: float = 0.0


def write_job(job: Job, folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in job.files.items():
        if isinstance(data, bytes):
            (folder / name).write_bytes(data)
        else:
            (folder / name).write_text(data)
    path = folder / "job.toml"
    path.write_text(toml_text(job.toml))
    return path


def _reason(msg: str) -> str:
    msg = msg.split(": ", 1)[1] if msg.startswith("/") and ": " in msg else msg
    return re.sub(r"-?\d+(\.\d+)?(e-?\d+)?", "#", msg)[:110]


def run_one(job: Job, folder: Path) -> Outcome:
    """Write ``job`` into ``folder`` and run it; the independent check on a program."""
    from millpath.errors import MillpathError
    from millpath.pipeline import run_job
    from millpath.verify.gate import UnsafeProgramError
    path = write_job(job, folder)
    t0 = time.process_time()
    try:
        run_job(path, folder / "out", pictures=False)
    except UnsafeProgramError as e:
        if e.problems and all(p.kind == "feature not machined" for p in e.problems):
            # the features operation's own refusal (unmachinable = "refuse", the
            # default): no tool of the job can machine a feature; the proof found nothing
            return Outcome("upfront", _reason(e.message), cpu=time.process_time() - t0)
        return Outcome("refused", _reason(e.message), e.message,
                       cpu=time.process_time() - t0)
    except MillpathError as e:
        if type(e).__name__ in AFTER_TYPES or any(w in e.message for w in AFTER_PLANNING):
            return Outcome("crashed", _reason(e.message), e.message,
                           cpu=time.process_time() - t0)
        return Outcome("upfront", _reason(e.message), cpu=time.process_time() - t0)
    except Exception as e:  # noqa: BLE001 - every other exception is a bug to report
        return Outcome("crashed", f"{type(e).__name__}: {e}"[:200],
                       cpu=time.process_time() - t0)
    cpu = time.process_time() - t0
    chk = gc.check_program(folder / "out" / "program.ngc", folder / "out" / "tools.tbl",
                           "mm", job.geometry)
    return Outcome("written", check=chk, cpu=cpu)


def jobs_of(op_type: str, n: int, seed: int) -> list[Job]:
    """``n`` jobs of ``op_type`` from ``seed`` (the same for the same arguments)."""
    rng = np.random.default_rng([seed, TYPES.index(op_type)])
    return [MAKERS[op_type](rng) for _ in range(n)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--jobs", type=int, default=10, help="jobs per type")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--first", type=int, default=0,
                    help="run jobs FIRST.. of the seed's sequence (a run continued)")
    ap.add_argument("--types", default=",".join(TYPES))
    ap.add_argument("--replay", type=Path, default=REPLAY, help="folder for failing jobs")
    ap.add_argument("--verbose", action="store_true", help="one line per job")
    a = ap.parse_args(argv)
    rows = []
    failing = 0
    for op_type in a.types.split(","):
        counts = {"written": 0, "upfront": 0, "refused": 0, "crashed": 0, "check": 0}
        upfront: dict[str, int] = {}
        cpu = 0.0
        saved = []
        with tempfile.TemporaryDirectory(prefix="millpath-gen-") as tmp:
            for k, job in enumerate(jobs_of(op_type, a.first + a.jobs, a.seed)):
                if k < a.first:
                    continue
                folder = Path(tmp) / f"{op_type}-{k:03d}"
                o = run_one(job, folder)
                cpu += o.cpu
                counts[o.kind] += 1
                bad = o.kind in ("refused", "crashed")
                if o.kind == "upfront":
                    upfront[o.reason] = upfront.get(o.reason, 0) + 1
                if o.check is not None and not o.check.ok:
                    counts["check"] += 1
                    bad = True
                if a.verbose:
                    print(f"  {op_type} {k:3d} {job.toml['name']}: {o.kind} {o.cpu:.1f}s "
                          f"{o.reason} {'; '.join(o.check.problems) if o.check else ''}")
                if bad:
                    dest = a.replay / f"seed{a.seed}-{op_type}-{k:03d}"
                    shutil.rmtree(dest, ignore_errors=True)
                    write_job(job, dest)
                    why = o.message or o.reason or "; ".join(o.check.problems)
                    (dest / "why.txt").write_text(f"{o.kind}: {why}\n")
                    saved.append((dest / "job.toml", o.kind, why))
        failing += len(saved)
        rows.append((op_type, a.jobs, counts, upfront, cpu, saved))
    print(f"{'type':12} {'jobs':>5} {'written':>8} {'upfront':>8} {'refused':>8} "
          f"{'crashed':>8} {'check':>6} {'CPU s':>8}")
    for op_type, n, c, up, cpu, saved in rows:
        print(f"{op_type:12} {n:5d} {c['written']:8d} {c['upfront']:8d} {c['refused']:8d} "
              f"{c['crashed']:8d} {c['check']:6d} {cpu:8.1f}")
        for reason, k in sorted(up.items(), key=lambda t: -t[1]):
            print(f"    up front x{k}: {reason}")
        for path, kind, why in saved:
            print(f"    {kind}: {path}: {why[:300]}")
    return 1 if failing else 0


if __name__ == "__main__":
    sys.exit(main())
