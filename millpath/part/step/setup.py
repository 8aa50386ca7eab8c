"""An AP224 part turned so that one of its stock's axes points up (the job's ``setup``).

The features are placed in the stock's frame (:mod:`millpath.part.step.shapes`); a
setup other than '+Z' replaces the stock's placement by the same block seen with the
named axis of the stock frame as +Z, its corner of least coordinates again at the
origin, so the features are read from that side. Rotations are proper (a right-handed
frame stays right-handed): '-Z' turns about X, '+X' / '-X' about Y, '+Y' / '-Y' about X.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from millpath.part.step.ap224 import Ap224Error, Part, Placement, Stock

#: new coordinates = ROTATION[setup] @ old (stock frame)
ROTATION = {
    "+Z": np.eye(3),
    "-Z": np.array([[1, 0, 0], [0, -1, 0], [0, 0, -1]], float),
    "+X": np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], float),
    "-X": np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0]], float),
    "+Y": np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], float),
    "-Y": np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]], float),
}


def turned(part: Part, setup: str) -> Part:
    """``part`` with its stock turned so that axis ``setup`` of the stock frame is +Z
    (the part itself when ``setup`` is '+Z'). Ap224Error for a cylindrical stock on
    its side."""
    if setup == "+Z":
        return part
    if setup not in ROTATION:
        raise Ap224Error(f"setup: one of {', '.join(ROTATION)} expected, "
                         f"not {setup!r}", part.file)
    r = ROTATION[setup]
    st = part.stock
    if st is None:
        raise Ap224Error(f"setup {setup}: the file has no stock to turn", part.file)
    base = st.placement
    if st.shape != "block":
        raise Ap224Error(f"setup {setup}: only a block stock can be turned (the file's "
                         f"stock is a {st.shape})", part.file)
    b = np.asarray(st.box(), float)
    corners = np.array([[x, y, z] for x in (b[0], b[3]) for y in (b[1], b[4])
                        for z in (b[2], b[5])])
    new = corners @ r.T
    lo = new.min(axis=0)
    size = new.max(axis=0) - lo
    dims = {"length": float(size[0]), "width": float(size[1]), "height": float(size[2])}
    m = base.matrix() @ r.T                     # new local axes in the file frame
    origin = base.to_parent(r.T @ lo)
    pl = Placement(tuple(float(v) for v in origin), tuple(float(v) for v in m[:, 2]),
                   tuple(float(v) for v in m[:, 0]), base.id)
    return dataclasses.replace(part, stock=Stock("block", pl, dims, st.id))
