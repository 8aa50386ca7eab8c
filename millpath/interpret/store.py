"""Compact storage of interpreted motion: flat arrays, Motion objects on demand.

A program of a million moves would need a million Python objects as a plain list;
``MotionList`` packs each move into a 100-byte record of one ``bytearray`` (start, end,
feed, center as doubles; kind, line, rotation, plane, state as int32) and builds
:class:`Motion` objects only when indexed or iterated. It is a read-only sequence:
``len``, indexing, slicing, iteration, ``==`` with a list of Motions.

With a ``sink``, the list streams: :meth:`flush` (called by the runner between blocks)
hands the records gathered so far to ``sink(arrays, states, controls)`` and forgets
them, so memory stays bounded whatever the program's length; ``len`` still counts
every motion, but only the records since the last flush can be indexed.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

import numpy as np

from millpath.model.motion import Motion
from millpath.model.toolpath import PLANES

KINDS = ("traverse", "feed", "arc", "cubic", "dwell", "nurbs")
KIND_CODE = {k: i for i, k in enumerate(KINDS)}
PLANE_CODE = {p: i for i, p in enumerate(PLANES)}
#: start xyz, end xyz, feed, center xyz (dwell: seconds in center[0]); kind, line,
#: rotation, plane, index into ``states``
RECORD = struct.Struct("<10d5i")
RSIZE = RECORD.size
PACK = RECORD.pack
DTYPE = np.dtype([("f", "<f8", (10,)), ("i", "<i4", (5,))])


class MotionList(Sequence):
    """Motion records in flat arrays; see the module docstring."""

    #: records gathered before a flush hands them to the sink (about 6.5 MB)
    FLUSH_RECORDS = 1 << 16

    def __init__(self, sink=None) -> None:
        self.buf = bytearray()
        self.states: list[tuple] = []      # (tool_offset, tool, spindle, feed_mode, frame)
        self.controls: dict[int, tuple] = {}
        self.sink = sink
        self.base = 0                      # motions handed to the sink so far
        self.reference = None              # Frame of the part (the work system at start)

    def __len__(self) -> int:
        return self.base + len(self.buf) // RSIZE

    def flush(self, force: bool = False) -> None:
        """With a sink: hand the buffered records over (when there are many, or
        ``force``) and forget them. Controls are keyed by the motion's index within the
        handed-over arrays."""
        if self.sink is None or not self.buf or (
                not force and len(self.buf) < self.FLUSH_RECORDS * RSIZE):
            return
        n = len(self.buf) // RSIZE
        arrays = self.arrays()
        base = self.base
        controls = {k - base: v for k, v in self.controls.items()}
        self.buf = bytearray()
        self.controls = {}
        self.base = base + n
        self.sink(arrays, self.states, controls)

    def kind_at(self, n: int) -> int:
        return struct.unpack_from("<i", self.buf, (n - self.base) * RSIZE + 80)[0]

    def _make(self, n: int) -> Motion:
        if n < self.base:
            raise IndexError("motion already handed to the sink")
        r = RECORD.unpack_from(self.buf, (n - self.base) * RSIZE)
        f = r
        k, line, rot, plane, st = r[10:]
        tlo, tool, spindle, fmode, frame = self.states[st]
        kind = KINDS[k]
        m = Motion(kind, line, (f[0], f[1], f[2]), (f[3], f[4], f[5]), f[6], tlo, tool,
                   PLANES[plane], None, rot, None, 0.0, fmode, spindle, frame)
        if kind == "arc":
            m.center = (f[7], f[8], f[9])
        elif kind == "dwell":
            m.dwell = f[7]
        elif kind == "cubic" or kind == "nurbs":
            m.controls = self.controls.get(n)
        return m

    def __getitem__(self, idx):
        if isinstance(idx, slice):
            return [self._make(n) for n in range(*idx.indices(len(self)))]
        n = len(self)
        if idx < 0:
            idx += n
        if not 0 <= idx < n:
            raise IndexError("motion index out of range")
        return self._make(idx)

    def __iter__(self):
        for n in range(self.base, len(self)):
            yield self._make(n)

    def __eq__(self, other) -> bool:
        if not isinstance(other, Sequence) or len(other) != len(self):
            return False
        return all(a == b for a, b in zip(self, other))

    def __repr__(self) -> str:
        return f"<MotionList of {len(self)} motions>"

    def truncate(self, n: int) -> None:
        """Keep the first ``n`` motions."""
        del self.buf[(n - self.base) * RSIZE:]

    def arrays(self) -> dict[str, np.ndarray]:
        """Numpy arrays (a copy): ``start``, ``end``, ``center`` (n, 3); ``feed`` (n,); ``kind``,
        ``line``, ``rotation``, ``plane``, ``state`` (n,) integer codes (see KINDS,
        PLANES and ``states``)."""
        rec = np.frombuffer(bytes(self.buf), dtype=DTYPE)
        f = rec["f"]
        i = rec["i"]
        return {"start": f[:, 0:3], "end": f[:, 3:6], "feed": f[:, 6], "center": f[:, 7:10],
                "kind": i[:, 0], "line": i[:, 1], "rotation": i[:, 2], "plane": i[:, 3],
                "state": i[:, 4]}
