"""B-rep solids of a STEP file (AP203, AP214, AP242) through OpenCASCADE.

:func:`read_solids` returns the solids of a file with their names and the file's units
and material as the Part 21 reader finds them. OpenCASCADE converts lengths to
millimetres: the shapes are in mm, ``units`` says what the file used. ``setup`` turns
the part so that the given axis of the file ('+Z', '-Z', '+X', '-X', '+Y', '-Y') points
up (+Z): the direction the tool comes from.

Errors (one line, naming the file and the entity): OpenCASCADE missing (names the
``step-brep`` extra), an unreadable file, a file with no solid, an open shell, a
``body`` that is not in the file.

OpenCASCADE never reads a file millpath has not read first: the Part 21 reader refuses
dangling references, self-references and reference cycles among geometry and topology
(:meth:`~millpath.part.step.p21.StepFile.check_tree`), which OpenCASCADE follows without
a guard. Its read itself runs in a child process (:func:`transfer_step`), so that a
native crash on what is left becomes a one-line error naming the file.
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from millpath.errors import GeometryError, MillpathError

STEP_BREP_EXTRA = ("reading B-rep solids needs the optional extra: "
                   "pip install 'millpath[step-brep]'")
SETUPS = ("+Z", "-Z", "+X", "-X", "+Y", "-Y")
#: Part 21 entities that are solids, and those that are only surfaces
_SOLID_ENTITIES = ("MANIFOLD_SOLID_BREP", "BREP_WITH_VOIDS", "FACETED_BREP")
_SHELL_ENTITIES = ("OPEN_SHELL", "SHELL_BASED_SURFACE_MODEL", "CLOSED_SHELL")


class BrepError(GeometryError):
    """A STEP file holds no machinable solid (or not the one asked for)."""


@dataclass
class Body:
    """One solid: its index (1-based, file order), name, Part 21 entity ('#93') and the
    OpenCASCADE shape (mm, turned to the setup)."""

    index: int
    name: str
    entity: str
    shape: Any = field(repr=False)


@dataclass
class BrepFile:
    file: str
    schema: list[str]
    product: str
    units: Any                     # millpath.part.step.ap224.Units
    material: str
    bodies: list[Body]


def occ(path=None) -> None:
    """Import check for OpenCASCADE; raises a one-line error naming the extra."""
    try:
        import OCP  # noqa: F401
    except ImportError:
        raise MillpathError(STEP_BREP_EXTRA, path) from None


class quiet_stdout:
    """Send what OpenCASCADE prints on file descriptor 1 to a temporary file."""

    def __enter__(self):
        sys.stdout.flush()
        self._tmp = tempfile.TemporaryFile()
        self._saved = os.dup(1)
        os.dup2(self._tmp.fileno(), 1)
        self.lines: list[str] = []
        return self

    def __exit__(self, *exc) -> None:
        os.dup2(self._saved, 1)
        os.close(self._saved)
        self._tmp.seek(0)
        text = self._tmp.read().decode("utf-8", "replace")
        self._tmp.close()
        self.lines = [re.sub(r"\x1b\[[0-9;]*m", "", ln) for ln in text.splitlines()]


def _entities(sf) -> tuple[list[tuple[str, str]], list[str]]:
    """(solids as (entity, name), shells) of a parsed Part 21 file, in file order."""
    solids, shells = [], []
    for iid, inst in sf.instances.items():
        names = inst.names()
        for n in _SOLID_ENTITIES:
            if n in names:
                p = inst.get(n)
                name = p[0] if p and isinstance(p[0], str) else ""
                solids.append((f"{n} #{iid}", name))
        for n in _SHELL_ENTITIES:
            if n in names and n != "CLOSED_SHELL":
                shells.append(f"{n} #{iid}")
    return solids, shells


def transfer_step(path: Path) -> tuple[Any, list[str]]:
    """OpenCASCADE's read and transfer of the STEP file ``path`` in a forked child, which
    hands the shape back in OpenCASCADE's binary format: ``(shape or None when nothing
    transferred, the lines OpenCASCADE printed)``. A child killed by a signal (a native
    crash) is a :class:`BrepError` naming the file and the signal; a file OpenCASCADE
    cannot read is one too. Costs a fork and the shape's binary round trip (about 40 ms
    on the 1,800-entity solid-hole-model part)."""
    from OCP.BinTools import BinTools
    from OCP.TopoDS import TopoDS_Shape
    with tempfile.TemporaryDirectory(prefix="millpath-step-") as tmp:
        out, log = os.path.join(tmp, "shape.bin"), os.path.join(tmp, "log.txt")
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:                                  # the child: read, write, leave
            code = 3
            try:
                code = _transfer_child(path, out, log)
            finally:
                os._exit(code)
        _, status = os.waitpid(pid, 0)
        if os.WIFSIGNALED(status):
            raise BrepError(f"OpenCASCADE crashed reading this file (signal "
                            f"{os.WTERMSIG(status)})", path)
        code = os.WEXITSTATUS(status)
        lines = Path(log).read_text(errors="replace").splitlines() \
            if os.path.exists(log) else []
        if code == 1:
            raise BrepError("OpenCASCADE cannot read the STEP file", path)
        if code not in (0, 2):
            why = lines[-1].strip() if lines else f"exit status {code}"
            raise BrepError(f"OpenCASCADE failed reading this file ({why})", path)
        if code == 2:
            return None, lines
        shape = TopoDS_Shape()
        if not BinTools.Read_s(shape, out):
            raise BrepError("OpenCASCADE's shape could not be read back", path)
        return shape, lines


def _transfer_child(path: Path, out: str, log: str) -> int:
    """In the child: 0 with the shape written to ``out``, 1 when the file cannot be
    read, 2 when nothing transferred, 3 on an exception (its message last in ``log``);
    OpenCASCADE's printed lines go to ``log``."""
    import faulthandler
    import resource
    faulthandler.disable()                    # a crash is reported by the parent
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    lines: list[str] = []
    try:
        from OCP.BinTools import BinTools
        from OCP.IFSelect import IFSelect_RetDone
        from OCP.STEPControl import STEPControl_Reader
        reader = STEPControl_Reader()
        q = quiet_stdout()
        with q:
            status = reader.ReadFile(str(path))
            n = reader.TransferRoots() if status == IFSelect_RetDone else 0
        lines = q.lines
        if status != IFSelect_RetDone:
            return 1
        shape = reader.OneShape() if n else None
        if shape is None or shape.IsNull():
            return 2
        return 0 if BinTools.Write_s(shape, out) else 3
    except BaseException as e:                    # noqa: BLE001 - reported by the parent
        lines.append(" ".join(f"{type(e).__name__}: {e}".split()))
        return 3
    finally:
        with open(log, "w") as fh:
            fh.write("\n".join(lines))


def rotation_to_setup(setup: str):
    """gp_Trsf turning the file's ``setup`` axis to +Z (identity for '+Z')."""
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Trsf
    import math
    t = gp_Trsf()
    o = gp_Pnt(0, 0, 0)
    turns = {"+Z": None, "-Z": ((1, 0, 0), math.pi), "+X": ((0, 1, 0), -math.pi / 2),
             "-X": ((0, 1, 0), math.pi / 2), "+Y": ((1, 0, 0), math.pi / 2),
             "-Y": ((1, 0, 0), -math.pi / 2)}
    turn = turns[setup]
    if turn is not None:
        t.SetRotation(gp_Ax1(o, gp_Dir(*turn[0])), turn[1])
    return t


def free_edges(solid) -> int:
    """Edges of ``solid`` bounding only one face (not seams, not degenerate)."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp
    from millpath.part.brep.faces import as_edge, as_face

    from millpath.part.brep.faces import ancestor_map
    m = ancestor_map()
    TopExp.MapShapesAndUniqueAncestors_s(solid, TopAbs_EDGE, TopAbs_FACE, m)
    n = 0
    for i in range(1, m.Extent() + 1):
        e = as_edge(m.FindKey(i))
        faces = m.FindFromIndex(i)
        if faces.Size() == 1 and not BRep_Tool.Degenerated_s(e) \
                and not BRep_Tool.IsClosed_s(e, as_face(faces.First())):
            n += 1
    return n


def read_solids(path: str | Path, setup: str = "+Z") -> BrepFile:
    """The solids of the STEP file ``path`` (mm, turned so ``setup`` points up)."""
    occ(path)
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.TopAbs import TopAbs_SHELL, TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    from millpath.part.step.ap224 import Units, read_part
    from millpath.part.step.p21 import read
    p = Path(path)
    if not p.is_file():
        raise BrepError("no such STEP file", p)
    if setup not in SETUPS:
        raise MillpathError(f"setup: one of {', '.join(SETUPS)} expected, not {setup!r}", p)
    sf = read(p)
    sf.check_tree()
    try:
        part = read_part(sf)
        units, product, material = part.units, part.product, part.material
    except MillpathError:
        units, product, material = Units(), "", ""
    solid_ents, shell_ents = _entities(sf)
    shape, _ = transfer_step(p)
    solids = []
    if shape is not None and not shape.IsNull():
        ex = TopExp_Explorer(shape, TopAbs_SOLID)
        while ex.More():
            solids.append(ex.Current())
            ex.Next()
    if not solids:
        if shape is not None and not shape.IsNull() and TopExp_Explorer(shape, TopAbs_SHELL).More():
            what = (shell_ents[0] if shell_ents else solid_ents[0][0] if solid_ents
                    else "shell")
            raise BrepError(f"{what}: the part is an open shell (surfaces), not a closed "
                            "solid: machine it with surface operations", p)
        raise BrepError("no solid in the file (no MANIFOLD_SOLID_BREP or BREP_WITH_VOIDS)", p)
    trsf = rotation_to_setup(setup)
    bodies = []
    for i, s in enumerate(solids):
        ent, name = solid_ents[i] if i < len(solid_ents) else (f"solid {i + 1}", "")
        nfree = free_edges(s)
        if nfree:
            raise BrepError(f"{ent}: the solid's shell is open ({nfree} free edges): "
                            "not a closed solid", p)
        if setup != "+Z":
            s = BRepBuilderAPI_Transform(s, trsf, True).Shape()
        bodies.append(Body(i + 1, name, ent, s))
    return BrepFile(str(p), sf.schemas, product, units, material, bodies)


def choose_body(bf: BrepFile, body: int | str | None) -> Body:
    """The body to machine: the only one, or ``body`` (1-based number or name)."""
    if body is None:
        if len(bf.bodies) > 1:
            names = ", ".join(f"{b.index} {b.name!r}" if b.name else str(b.index)
                              for b in bf.bodies)
            raise BrepError(f"the file has {len(bf.bodies)} solids ({names}): say which "
                            "with body = N or body = \"name\"", bf.file)
        return bf.bodies[0]
    for b in bf.bodies:
        if (isinstance(body, int) and b.index == body) or (isinstance(body, str)
                                                           and b.name == body):
            return b
    raise BrepError(f"body {body!r}: not in the file ({len(bf.bodies)} solids)", bf.file)
