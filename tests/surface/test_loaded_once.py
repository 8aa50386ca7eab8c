"""Issue 18.3: the pipeline loads each input once. A job whose surface-rough and
surface-finish operations name one STL reads the file once (counted at numpy-stl, the
reader below millpath) and indexes its mesh once (counted at the index kernel), and
plans the same toolpaths as each operation planned alone with nothing shared."""

from __future__ import annotations

import numpy as np

from millpath.job.jobfile import load_job
from millpath.part.surface.mesh import function_mesh, write_stl
from millpath.pipeline import plan_job
from millpath.plan.base import PlanContext
from millpath.plan.surface import dropcutter
from millpath.plan.surface import operation as finish_op
from millpath.plan.surface import rough as rough_op

JOB = """units = "mm"
[stock]
box = [0.0, 0.0, -6.0, 30.0, 20.0, 0.5]
[[tools]]
number = 4
type = "flat"
diameter = 6.0
flute_length = 20.0
stickout = 20.0
[[tools]]
number = 5
type = "ball"
diameter = 6.0
flute_length = 20.0
stickout = 20.0
[[operations]]
type = "surface-rough"
surface = "bump.stl"
tool = 4
stepdown = 3.0
allowance = 0.3
[[operations]]
type = "surface-finish"
surface = "bump.stl"
tool = 5
scallop = 0.1
tolerance = 0.02
compare = false
"""


def _bump(x, y):
    return -5.0 + 4.0 * np.exp(-((x - 15.0) ** 2 + (y - 10.0) ** 2) / 30.0)


def test_one_stl_for_rough_and_finish_is_read_and_indexed_once(tmp_path, monkeypatch):
    from stl import mesh as stl_mesh

    write_stl(function_mesh(_bump, (0.0, 30.0), (0.0, 20.0), 31, 21, "bump"),
              tmp_path / "bump.stl")
    (tmp_path / "job.toml").write_text(JOB)
    job = load_job(tmp_path / "job.toml")

    reads: list[str] = []
    read = stl_mesh.Mesh.from_file

    def counting_read(cls, filename, *args, **kw):
        reads.append(str(filename))
        return read(filename, *args, **kw)
    monkeypatch.setattr(stl_mesh.Mesh, "from_file", classmethod(counting_read))
    indexed: list[tuple[int, float]] = []
    fill = dropcutter._fill_grid

    def counting_fill(tri, box, order, x0, y0, cell, nx, ny):
        indexed.append((len(tri), cell))
        return fill(tri, box, order, x0, y0, cell, nx, ny)
    monkeypatch.setattr(dropcutter, "_fill_grid", counting_fill)

    tp, results, _ = plan_job(job)
    assert reads == [str(tmp_path / "bump.stl")]
    assert len(indexed) == 1, indexed        # no holders: only the surface is indexed

    # each operation alone, with its own (empty) cache, plans the very same moves
    monkeypatch.undo()
    for k, mod in enumerate((rough_op, finish_op)):
        ctx = PlanContext(job.units, job.stock, job.machine, job.tools, job.base_dir,
                          job.path)
        alone = mod.plan(ctx, job.operations[k][1]).toolpath
        shared = results[k].toolpath
        assert len(alone.moves) == len(shared.moves) > 0
        for a, b in zip(alone.moves, shared.moves):
            assert a.kind == b.kind and np.array_equal(a.end, b.end)
