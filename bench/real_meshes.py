"""Surface operations on real meshes: CPU, wall, peak memory, passes, points.

Each row is a whole ``millpath run`` of a job written here, in a child process (so the
CPU seconds include numba's start-up, the simulation and the report), on:

- ``box-wheel``: a 200 x 200 x 50 mm block with a pocket and a wheel in it, vertical walls
  (:func:`support.prism.box_and_wheel`); rough 12 mm flat, steep-shallow
  finish 6 mm ball, scallop 0.05 mm, tolerance 0.01 mm;
- ``textbox``: OpenCAMLib's ``pycam-textbox.stl``; rough 6 mm flat, waterline 2 mm ball,
  scallop 0.02 mm;
- ``cavity``: ``ktoolcav.stl`` (inch) turned to open upwards (``rotate = [-90, 0, 0]``,
  ``place = "stock-top"``); rough 1/4 in flat, steep-shallow 1/8 in ball, scallop
  0.002 in;
- ``cavity-0.001``: the same with scallop 0.001 in (the issue's "more than 5000
  passes" after 29 minutes): planned, about 350 pass lines;
- ``cavity-refused``: scallop 0.000001 in, refused before planning (time to the refusal);
- ``demo2``: ``demo2.stl`` (146,336 triangles); rough 12 mm bull r1, zigzag 6 mm ball,
  scallop 0.01 mm, tolerance 0.01 mm.

The meshes are read from ``../shared/meshes`` (``--meshes DIR``). Prints one table row
per job and, per operation, passes (pass lines or levels), pieces and CL points, with
the verification's gouge, holder contacts and rapids through material. ``peak_mb`` is
the largest child so far (``RUSAGE_CHILDREN``): run one ``--only`` row per invocation
for each row's own peak.
Run: ``python bench/real_meshes.py [--only NAME ...] [--meshes DIR] [--keep DIR]``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

MESHES = Path(__file__).resolve().parents[2] / "shared" / "meshes"

TOOLS_MM = """
[[tools]]
number = 1
type = "flat"
diameter = {rough_d}
flute_length = 60.0
stickout = 70.0
holder = [[30.0, 40.0], [50.0, 40.0]]

[[tools]]
number = 2
type = "ball"
diameter = {finish_d}
flute_length = 50.0
stickout = 70.0
holder = [[30.0, 40.0], [50.0, 40.0]]
"""


def jobs(meshes: Path) -> dict[str, str]:
    """Job texts by name (``{wheel}`` is filled with the generated STL's path)."""
    box_wheel = f"""units = "mm"
name = "box and wheel"
[stock]
box = [-100.0, -100.0, -50.0, 100.0, 100.0, 0.5]
{TOOLS_MM.format(rough_d=12.0, finish_d=6.0)}
[[operations]]
type = "surface-rough"
surface = "{{wheel}}"
tool = 1
stepdown = 5.0
allowance = 0.3
[[operations]]
type = "surface-finish"
surface = "{{wheel}}"
tool = 2
strategy = "steep-shallow"
scallop = 0.05
tolerance = 0.01
"""
    textbox = f"""units = "mm"
name = "pycam textbox"
[stock]
box = [0.0, 0.0, -10.0, 130.0, 50.0, 3.5]
{TOOLS_MM.format(rough_d=6.0, finish_d=2.0)}
[[operations]]
type = "surface-rough"
surface = "{meshes / 'pycam-textbox.stl'}"
tool = 1
stepdown = 2.0
allowance = 0.2
[[operations]]
type = "surface-finish"
surface = "{meshes / 'pycam-textbox.stl'}"
tool = 2
strategy = "waterline"
scallop = 0.02
tolerance = 0.01
"""
    cavity = """units = "inch"
name = "ktoolcav opening upwards"
[stock]
box = [-2.1, -1.75, -1.7, 2.1, 1.75, 0.0]
[[tools]]
number = 1
type = "flat"
diameter = 0.25
flute_length = 2.0
stickout = 2.5
holder = [[1.0, 1.5], [2.0, 1.5]]
[[tools]]
number = 2
type = "ball"
diameter = 0.125
flute_length = 2.0
stickout = 2.5
holder = [[1.0, 1.5], [2.0, 1.5]]
[[operations]]
type = "surface-rough"
surface = {{ file = "%s", rotate = [-90.0, 0.0, 0.0], place = "stock-top" }}
tool = 1
stepdown = 0.1
allowance = 0.01
[[operations]]
type = "surface-finish"
surface = {{ file = "%s", rotate = [-90.0, 0.0, 0.0], place = "stock-top" }}
tool = 2
strategy = "steep-shallow"
scallop = {scallop}
tolerance = 0.0004
""" % (meshes / "ktoolcav.stl", meshes / "ktoolcav.stl")
    demo2 = f"""units = "mm"
name = "demo2"
[stock]
box = [0.0, -82.0, -25.0, 152.0, 66.0, 25.5]
[[tools]]
number = 1
type = "bull"
diameter = 12.0
corner_radius = 1.0
flute_length = 60.0
stickout = 70.0
holder = [[30.0, 40.0], [50.0, 40.0]]
[[tools]]
number = 2
type = "ball"
diameter = 6.0
flute_length = 60.0
stickout = 70.0
holder = [[30.0, 40.0], [50.0, 40.0]]
[[operations]]
type = "surface-rough"
surface = "{meshes / 'demo2.stl'}"
tool = 1
stepdown = 5.0
allowance = 0.3
[[operations]]
type = "surface-finish"
surface = "{meshes / 'demo2.stl'}"
tool = 2
strategy = "zigzag"
scallop = 0.01
tolerance = 0.01
"""
    return {"box-wheel": box_wheel, "textbox": textbox,
            "cavity": cavity.replace("{scallop}", "0.002").replace("{{", "{").replace("}}", "}"),
            "cavity-0.001": cavity.replace("{scallop}", "0.001").replace("{{", "{")
            .replace("}}", "}"),
            "cavity-refused": cavity.replace("{scallop}", "0.000001").replace("{{", "{")
            .replace("}}", "}"),
            "demo2": demo2}


def run_one(name: str, text: str, work: Path) -> dict:
    """Run one job in a child process; CPU and peak memory from its rusage."""
    job = work / f"{name}.toml"
    job.write_text(text)
    out = work / name
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "millpath.cli.main", "run", str(job), "-o",
                        str(out), "--quiet"], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    row = {"job": name, "cpu_s": round(after.ru_utime + after.ru_stime
                                       - before.ru_utime - before.ru_stime, 1),
           "wall_s": round(wall, 1), "peak_mb": round(after.ru_maxrss / 1024.0),
           "exit": p.returncode}
    if p.returncode:
        row["error"] = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else "?"
        return row
    rep = json.loads((out / "report.json").read_text())
    ops = []
    plans = rep.get("plans", [])                # one section per job operation
    for s in [s for p in plans for s in p.get("surface_rough", [])]:
        ops.append(f"rough {s['layers']} layers {s['pieces']} pieces "
                   f"{s.get('cl_points', '?')} pts")
    for s in [s for p in plans for s in p.get("surface_finish", [])]:
        wl = s.get("waterline") or {}
        ops.append(f"{s['strategy']} {s['pass_lines']} lines {wl.get('levels', 0)} levels "
                   f"{s['pieces']} pieces {s['cl_points']} pts")
    v = rep.get("verification", {})
    row.update(ops="; ".join(ops), gouge=v.get("max_gouge"),
               holder=v.get("holder_contacts"), rapids=v.get("rapids_through_material"))
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="job names (default: all)")
    ap.add_argument("--meshes", type=Path, default=MESHES)
    ap.add_argument("--keep", type=Path, help="write the jobs and outputs here")
    a = ap.parse_args()
    from millpath.part.surface.mesh import write_stl
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from support.prism import box_and_wheel
    work = a.keep or Path(tempfile.mkdtemp(prefix="real_meshes_"))
    work.mkdir(parents=True, exist_ok=True)
    wheel = work / "box_wheel.stl"
    m = box_and_wheel()
    write_stl(m, wheel)
    print(f"# {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}; box-wheel "
          f"{len(m)} triangles; jobs in {work}")
    for name, text in jobs(a.meshes).items():
        if a.only and name not in a.only:
            continue
        row = run_one(name, text.replace("{wheel}", str(wheel)), work)
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
