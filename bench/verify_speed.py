"""Full verification vs today's Z-map simulation: the surface-mould example and a
200,000-move finishing program.

For each program, side by side, in CPU seconds of this process (the machine is shared):

- ``zmap``: the Z-map simulation alone (``simulate_motions`` with
  ``accuracy=None``: Z-map gouge / left, rapids, holder contacts, cycle time);
- ``full``: what ``millpath run`` now does after posting: interpret the program, the
  round trip against the planned toolpath, the Z-map simulation and the exact
  gouge / material-left check against the design mesh (meshing included).

Prints both, their ratio (target <= 2) and the peak resident memory (target < 2 GB on
the 200,000-move program). The 200,000-move program is the one of
``bench/sim_speed.py`` (6 mm ball, 200 x 200 mm, 0.2 mm moves); its design is the tip
surface lowered by 0.15 mm, below the ball everywhere (the ball dips at most
R (1 - cos 15 deg) = 0.10 mm below its tip on these slopes), so it is a clean program
whose cutter passes close to the design everywhere. Numba kernels are compiled by a
warm-up on a small program first.

Run: ``python bench/verify_speed.py [--moves N] [--skip-mould]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from sim_speed import finishing_toolpath, surface  # noqa: E402


class _Lowered:
    def height(self, x, y):
        return surface(np.asarray(x, float), np.asarray(y, float)) - 0.15


def _cpu() -> float:
    t = os.times()
    return t.user + t.system


def _program(tp, tools, units="mm"):
    from millpath.post.writer import post_with_lines
    return post_with_lines(tp, tools)


def _verify(tp, tools, stock, design, resolution, program, move_lines, references=None,
            motion_op=None):
    """(zmap seconds, full seconds, result of the full run)."""
    from millpath.interpret import interpret
    from millpath.simulate import simulate_motions
    from millpath.simulate.approach import approach_from_above
    from millpath.verify.roundtrip import compare_toolpath
    motions = interpret(program, tools, machine_units=tp.units)
    motions = approach_from_above(list(motions), stock.zmax)
    c0 = _cpu()
    simulate_motions(motions, tools, stock, resolution=resolution, design=design,
                     accuracy=None)
    zmap = _cpu() - c0
    c0 = _cpu()
    motions = interpret(program, tools, machine_units=tp.units)
    diffs = compare_toolpath(tp, move_lines, motions, 2e-4)
    motions = approach_from_above(list(motions), stock.zmax)
    r = simulate_motions(motions, tools, stock, resolution=resolution, design=design,
                         references=references, motion_op=motion_op)
    full = _cpu() - c0
    return zmap, full, r, diffs


def _row(name, zmap, full, r, diffs):
    j = r.to_json()
    print(f"{name:<22} zmap {zmap:8.1f} s   full {full:8.1f} s   ratio {full / zmap:5.2f}   "
          f"max_gouge {j['max_gouge']}  max_left {j['max_left']}  "
          f"gouging_moves {j.get('gouging_moves')}  round-trip differences {len(diffs)}  "
          f"chords {r.exact.chords if r.exact else 0}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--moves", type=int, default=200_000)
    ap.add_argument("--skip-mould", action="store_true")
    a = ap.parse_args()
    from millpath.model import Stock, Tool
    tool = {1: Tool(1, "ball", 6.0, flute_length=20, stickout=40)}
    stock = Stock(0, 0, -30, 200, 200, 0)
    # warm-up: compile the kernels
    small = finishing_toolpath(500, 20.0)
    prog, ml = _program(small, tool)
    _verify(small, tool, Stock(0, 0, -30, 20, 20, 0), _Lowered(), 0.1, prog, ml)
    if not a.skip_mould:
        from millpath import pipeline as P
        from millpath.job.jobfile import load_job
        job = load_job(Path(__file__).resolve().parents[1] / "millpath/examples/surface-mould/job.toml")
        tp, results, st = P.plan_job(job)
        tp = P.fit_job(job, tp)
        prog, ml = _program(tp, job.tools)
        from millpath.interpret import interpret
        refs = None
        c0 = _cpu()
        refs = P._references(job, results, st, tp)
        mesh_s = _cpu() - c0
        mo = interpret(prog, job.tools, machine_units=job.units)
        mop = P._motion_ops(tp, ml, mo)
        design = P.MinDesign([r.design for r in results if r.design is not None])
        res = P.default_resolution(job, st, tp)
        zmap, full, r, diffs = _verify(tp, job.tools, st, design, res, prog, ml, refs, mop)
        _row(f"surface-mould ({len(tp.moves)} moves)", zmap, full + mesh_s, r, diffs)
    tp = finishing_toolpath(a.moves)
    prog, ml = _program(tp, tool)
    zmap, full, r, diffs = _verify(tp, tool, stock, _Lowered(), 0.1, prog, ml)
    _row(f"finishing ({len(tp.moves)} moves)", zmap, full, r, diffs)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"peak resident memory {peak:.0f} MB")


if __name__ == "__main__":
    main()
