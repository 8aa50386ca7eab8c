"""AP224 (ISO 10303-224, FEATURE_BASED_PROCESS_PLANNING) layer on a Part 21 graph.

Reads the units, the stock (``BLOCK_SHAPE_REPRESENTATION`` or
``CYLINDRICAL_SHAPE_REPRESENTATION``), the material (``MATERIAL_DESIGNATION``) and the
machining features. A feature is an instance with a ``MACHINING_FEATURE`` or
``INSTANCED_FEATURE`` record (complex instances as AP224 writes them) or a simple
instance of a known feature entity of the AIM form ``NAME(name, description, of_shape,
product_definitional)``. Its parameters are found through the graph, by the names of
the representation items, never by their position in the file:

- own parameters: ``PROPERTY_DEFINITION(.., feature)`` <- ``SHAPE_DEFINITION_REPRESENTATION``
  -> representation items (``AXIS2_PLACEMENT_3D`` named 'orientation', measures such
  as 'diameter', descriptive items);
- components: ``PRODUCT_DEFINITION_SHAPE(.., feature)`` <- ``SHAPE_ASPECT`` (role, e.g.
  'diameter occurrence') <- ``SHAPE_DEFINING_RELATIONSHIP`` / ``FEATURE_COMPONENT_RELATIONSHIP``
  -> the component (``CIRCULAR_CLOSED_PROFILE``, ``PATH_FEATURE_COMPONENT``,
  ``HOLE_BOTTOM`` ...) whose own parameters are found the same way; a path component's
  direction comes from its ``DIRECTION_SHAPE_REPRESENTATION``.

Units: every measure carries its unit; lengths are converted to the file's global
length unit (:attr:`Units.length`, 'mm' or 'inch' for the usual files), angles to
degrees. Placement vectors are unit vectors in the file's frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from millpath.errors import MillpathError
from millpath.model.units import MM_PER_FOOT, MM_PER_INCH
from millpath.part.step.p21 import Instance, Ref, StepFile, Typed, read

#: feature entity names of AP224 (and the AP238 AIM) that the layer recognises
FEATURE_TYPES = frozenset({
    "ROUND_HOLE", "SLOT", "POCKET", "STEP", "PLANAR_FACE", "FLAT_FACE", "BOSS",
    "GENERAL_OUTSIDE_PROFILE", "OUTSIDE_PROFILE", "OUTER_ROUND", "REVOLVED_PROFILE",
    "REVOLVED_FLAT", "REVOLVED_ROUND", "TURNED_KNURL", "THREAD", "CHAMFER", "EDGE_ROUND",
    "FILLET", "COMPOSITE_HOLE", "COUNTERBORE_HOLE", "COUNTERSUNK_HOLE", "SPOTFACE",
    "RIB_TOP", "GROOVE", "MARKING", "SPHERICAL_CAP", "GEAR", "PROTRUSION",
    "CIRCULAR_PATTERN", "RECTANGULAR_PATTERN", "GENERAL_PATTERN", "REPLICATE_FEATURE",
})
_GENERIC = frozenset({"CHARACTERIZED_OBJECT", "FEATURE_DEFINITION", "INSTANCED_FEATURE",
                      "MACHINING_FEATURE", "SHAPE_ASPECT", "SHAPE_FEATURE_DEFINITION"})
_SI_PREFIX = {"EXA": 1e18, "PETA": 1e15, "TERA": 1e12, "GIGA": 1e9, "MEGA": 1e6,
              "KILO": 1e3, "HECTO": 1e2, "DECA": 1e1, "DECI": 1e-1, "CENTI": 1e-2,
              "MILLI": 1e-3, "MICRO": 1e-6, "NANO": 1e-9, "PICO": 1e-12, "FEMTO": 1e-15,
              "ATTO": 1e-18}


class Ap224Error(MillpathError):
    """An AP224 file lacks or misstates something the reader needs."""


# --- values ------------------------------------------------------------------------------
@dataclass
class Placement:
    """An ``AXIS2_PLACEMENT_3D``: ``origin``, unit ``axis`` (local Z) and unit ``ref``
    (local X, made orthogonal to the axis); local Y = axis x ref."""

    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    ref: tuple[float, float, float] = (1.0, 0.0, 0.0)
    id: int | None = None

    def matrix(self) -> np.ndarray:
        """3x3 rotation whose columns are local X, Y, Z in the parent frame."""
        z = np.asarray(self.axis, float)
        x = np.asarray(self.ref, float)
        y = np.cross(z, x)
        return np.column_stack([x, y, z])

    def to_parent(self, p) -> np.ndarray:
        return np.asarray(self.origin, float) + self.matrix() @ np.asarray(p, float)

    def to_local(self, p) -> np.ndarray:
        return self.matrix().T @ (np.asarray(p, float) - np.asarray(self.origin, float))

    def as_dict(self) -> dict:
        return {"origin": list(self.origin), "axis": list(self.axis), "ref": list(self.ref)}


@dataclass
class Units:
    """Global units: ``length`` name ('mm', 'inch', 'm' ...), ``length_mm`` (mm per unit),
    ``angle`` ('degree' or 'radian'); measures are reported in ``length`` and degrees."""

    length: str = "mm"
    length_mm: float = 1.0
    angle: str = "degree"

    def as_dict(self) -> dict:
        return {"length": self.length, "length_mm": self.length_mm, "angle": self.angle}


@dataclass
class Stock:
    """Raw material: ``shape`` 'block' (``length`` along placement X, ``width`` along Y,
    ``height`` along Z, the placement at the block's corner of least coordinates) or
    'cylinder' (``diameter``, ``length`` along the axis from the placement origin)."""

    shape: str
    placement: Placement
    dims: dict[str, float]
    id: int | None = None

    def box(self) -> tuple[float, float, float, float, float, float]:
        """Axis-aligned bounds in the file frame (the placement's own frame for a block)."""
        if self.shape == "block":
            return (0.0, 0.0, 0.0, self.dims["length"], self.dims["width"], self.dims["height"])
        r = self.dims["diameter"] / 2.0
        return (-r, -r, 0.0, r, r, self.dims["length"])

    def as_dict(self) -> dict:
        return {"shape": self.shape, "id": self.id, "placement": self.placement.as_dict(),
                **self.dims}


@dataclass
class Component:
    """A feature component: ``type`` (entity, e.g. 'HOLE_BOTTOM'), ``description`` (e.g.
    'flat'), ``role`` (the shape aspect's description, e.g. 'bottom condition occurrence'),
    ``usage`` (the relationship's name and description), its measures and texts."""

    id: int
    type: str
    description: str
    role: str
    usage: str
    params: dict[str, float] = field(default_factory=dict)
    texts: dict[str, str] = field(default_factory=dict)
    placement: Placement | None = None
    direction: tuple[float, float, float] | None = None

    def as_dict(self) -> dict:
        d: dict[str, Any] = {"id": self.id, "type": self.type, "description": self.description,
                             "role": self.role, "usage": self.usage, "params": self.params}
        if self.texts:
            d["texts"] = self.texts
        if self.direction is not None:
            d["direction"] = list(self.direction)
        return d


@dataclass
class Feature:
    """A machining feature: its entity ``type``, ``name``/``description``, ``placement``,
    own measures ``params`` (lengths in the file unit, angles in degrees), ``texts``
    (descriptive items), ``components`` and ``children`` (ids of sub-features)."""

    id: int
    type: str
    name: str
    description: str
    line: int
    placement: Placement | None = None
    params: dict[str, float] = field(default_factory=dict)
    texts: dict[str, str] = field(default_factory=dict)
    components: list[Component] = field(default_factory=list)
    children: list[int] = field(default_factory=list)
    faces: list[int] = field(default_factory=list)   # B-rep faces (recognised features)

    def component(self, *types: str) -> Component | None:
        for c in self.components:
            if c.type in types:
                return c
        return None

    def as_dict(self) -> dict:
        return {"id": self.id, "type": self.type, "name": self.name,
                "description": self.description, "line": self.line,
                "placement": self.placement.as_dict() if self.placement else None,
                "params": self.params, "texts": self.texts,
                "components": [c.as_dict() for c in self.components],
                "children": self.children, **({"faces": self.faces} if self.faces else {})}


@dataclass
class Part:
    """What an AP224 file says about the part to machine."""

    file: str | None
    schema: list[str]
    product: str
    units: Units
    stock: Stock | None
    material: str
    features: list[Feature]
    step: StepFile = field(repr=False, default=None)  # type: ignore[assignment]


# --- reading -----------------------------------------------------------------------------
class GeometryReader:
    def __init__(self, sf: StepFile):
        self.sf = sf
        self._unit_cache: dict[int, tuple[str, float]] = {}
        self.units = Units()
        self._len_mm = 1.0
        self._ang_deg = 180.0 / math.pi

    # units ------------------------------------------------------------------------------
    def unit(self, ref: Any) -> tuple[str, float]:
        """(kind, factor) of a unit: length in mm, angle in degrees, else 1."""
        if not isinstance(ref, Ref):
            return ("", 1.0)
        key = int(ref)
        if key in self._unit_cache:
            return self._unit_cache[key]
        self._unit_cache[key] = ("", 1.0)      # guards against cycles
        inst = self.sf[key]
        kind = ""
        if inst.has("LENGTH_UNIT"):
            kind = "length"
        elif inst.has("PLANE_ANGLE_UNIT"):
            kind = "angle"
        elif inst.has("SOLID_ANGLE_UNIT"):
            kind = "solid angle"
        factor = 1.0
        si = inst.get("SI_UNIT")
        cb = inst.get("CONVERSION_BASED_UNIT")
        if si is not None:
            prefix = _SI_PREFIX.get(str(si[0]), 1.0) if si[0] is not None else 1.0
            name = str(si[1]) if len(si) > 1 else ""
            if name == "METRE":
                kind, factor = "length", prefix * 1000.0
            elif name == "RADIAN":
                kind, factor = "angle", prefix * 180.0 / math.pi
            else:
                factor = prefix
        elif cb is not None and len(cb) >= 2 and isinstance(cb[1], Ref):
            m = self.sf[cb[1]]
            value, uref = self._measure_value(m)
            k2, f2 = self.unit(uref)
            if value is None:
                raise self.sf.error(m, "conversion-based unit without a value", Ap224Error)
            factor = _snap(value * f2)
            kind = kind or k2
        elif inst.has("CONTEXT_DEPENDENT_UNIT"):
            kind = "count"
        self._unit_cache[key] = (kind, factor)
        return kind, factor

    def global_units(self) -> None:
        length = angle = None
        for ctx in self.sf.by_type("GLOBAL_UNIT_ASSIGNED_CONTEXT"):
            for u in ctx.get("GLOBAL_UNIT_ASSIGNED_CONTEXT")[0] or []:
                kind, f = self.unit(u)
                if kind == "length" and length is None:
                    length = f
                elif kind == "angle" and angle is None:
                    angle = f
            if length is not None:
                break
        if length is None:
            length = 1.0
        self._len_mm = length
        if abs(length - 1.0) < 1e-9:
            name = "mm"
        elif abs(length - MM_PER_INCH) < 1e-6:
            name = "inch"
        elif abs(length - 1000.0) < 1e-6:
            name = "m"
        elif abs(length - 10.0) < 1e-9:
            name = "cm"
        elif abs(length - MM_PER_FOOT) < 1e-6:
            name = "foot"
        else:
            name = f"{length:g} mm"
        ang = "radian" if angle is not None and abs(angle - 180 / math.pi) < 1e-9 else "degree"
        self.units = Units(name, length, ang)

    @staticmethod
    def _measure_value(inst: Instance) -> tuple[float | None, Any]:
        """(value, unit ref) of a measure-with-unit or measure representation item."""
        p = inst.get("MEASURE_WITH_UNIT")
        if p is None:
            for name, params in inst.records:
                if name.endswith("MEASURE_WITH_UNIT") and len(params) >= 2:
                    p = params
                    break
        if p is not None:
            v = p[0]
            v = v.value if isinstance(v, Typed) else v
            return (float(v) if isinstance(v, (int, float)) else None), p[1]
        p = inst.get("MEASURE_REPRESENTATION_ITEM")
        if p is not None and len(p) >= 3:
            v = p[1].value if isinstance(p[1], Typed) else p[1]
            return (float(v) if isinstance(v, (int, float)) else None), p[2]
        return None, None

    def measure(self, inst: Instance) -> tuple[str, float] | None:
        """(name, value) of a named measure item, converted to file length unit/degrees."""
        value, uref = self._measure_value(inst)
        if value is None:
            return None
        name = ""
        ri = inst.get("REPRESENTATION_ITEM")
        if ri is not None and ri and isinstance(ri[0], str):
            name = ri[0]
        else:
            mri = inst.get("MEASURE_REPRESENTATION_ITEM")
            if mri is not None and mri and isinstance(mri[0], str):
                name = mri[0]
        kind, f = self.unit(uref)
        if kind == "length" and f != self._len_mm:
            value = value * f / self._len_mm
        elif kind == "angle" and f != 1.0:
            value = value * f
        return name, value

    # geometry ---------------------------------------------------------------------------
    def triple(self, inst, entity: str, what: str) -> list[float]:
        """The three numbers of a CARTESIAN_POINT or DIRECTION instance (missing ones
        0); Ap224Error naming the instance when it is another entity or ``what`` (its
        coordinates, ratios) are not numbers."""
        p = inst.get(entity)
        if p is None or not isinstance(p[1], list):
            raise self.sf.error(inst, f"expected a {entity}", Ap224Error)
        try:
            return [float(v) for v in p[1]] + [0.0] * (3 - len(p[1]))
        except (TypeError, ValueError):
            raise self.sf.error(inst, f"{entity} {what} must be numbers", Ap224Error) from None

    def point(self, ref: Any) -> tuple[float, float, float]:
        c = self.triple(self.sf[ref], "CARTESIAN_POINT", "coordinates")
        return tuple(0.0 if abs(v) < 1e-12 else v for v in c[:3])  # type: ignore[return-value]

    def direction(self, ref: Any, default: tuple) -> tuple[float, float, float]:
        if not isinstance(ref, Ref):
            return default
        inst = self.sf[ref]
        v = self.triple(inst, "DIRECTION", "ratios")
        n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        if not n > 0:
            raise self.sf.error(inst, "zero-length DIRECTION", Ap224Error)
        return tuple(0.0 if abs(x / n) < 1e-12 else x / n for x in v[:3])  # type: ignore

    def placement(self, inst: Instance) -> Placement:
        p = inst.get("AXIS2_PLACEMENT_3D")
        origin = self.point(p[1])
        axis = self.direction(p[2] if len(p) > 2 else None, (0.0, 0.0, 1.0))
        ref = np.array(self.direction(p[3] if len(p) > 3 else None, (1.0, 0.0, 0.0)))
        a = np.array(axis)
        ref = ref - a * float(ref @ a)
        if np.linalg.norm(ref) < 1e-9:          # reference along the axis: pick one
            ref = np.cross(a, [0.0, 1.0, 0.0] if abs(a[1]) < 0.9 else [1.0, 0.0, 0.0])
        ref = ref / np.linalg.norm(ref)
        ref[np.abs(ref) < 1e-12] = 0.0
        return Placement(origin, axis, (float(ref[0]), float(ref[1]), float(ref[2])), inst.id)

    # representations --------------------------------------------------------------------
    def reps_of(self, definition: int) -> list[Instance]:
        """Representations attached to ``definition`` through property definitions."""
        out = []
        for pd in self.sf.users(definition, "PROPERTY_DEFINITION", 2):
            out += self.reps_of_pd(pd.id)
        return out

    def reps_of_pd(self, pd: int) -> list[Instance]:
        out = []
        for sdr in self.sf.inverse(pd):
            for rname in ("SHAPE_DEFINITION_REPRESENTATION", "PROPERTY_DEFINITION_REPRESENTATION"):
                p = sdr.get(rname)
                if p is not None and len(p) >= 2 and isinstance(p[1], Ref) and int(p[0]) == pd:
                    out.append(self.sf[p[1]])
        return out

    def read_items(self, reps: list[Instance], target: Any) -> None:
        """Fill ``target`` (a Feature, Component or Stock-like) from representation items."""
        for rep in reps:
            rname, rp = rep.records[0]
            if len(rp) < 2 or not isinstance(rp[1], list):
                continue
            if rname == "DIRECTION_SHAPE_REPRESENTATION":
                for it in rp[1]:
                    if isinstance(it, Ref) and self.sf[it].has("DIRECTION"):
                        d = self.direction(it, (0.0, 0.0, 1.0))
                        label = rp[0] if isinstance(rp[0], str) else ""
                        if label and hasattr(target, "texts"):
                            target.texts[label] = "direction " + " ".join(f"{v:g}" for v in d)
                        else:
                            target.direction = d
                continue
            if "FACE" in rname or "BREP" in rname:
                continue
            for it in rp[1]:
                if not isinstance(it, Ref):
                    continue
                item = self.sf[it]
                if item.has("AXIS2_PLACEMENT_3D"):
                    name = item.get("AXIS2_PLACEMENT_3D")[0]
                    if target.placement is None or name == "orientation":
                        target.placement = self.placement(item)
                    continue
                dri = item.get("DESCRIPTIVE_REPRESENTATION_ITEM")
                if dri is not None:
                    target.texts[str(dri[0])] = str(dri[1])
                    continue
                m = self.measure(item)
                if m is not None:
                    name, value = m
                    target.params[name or f"#{item.id}"] = value

    # features ---------------------------------------------------------------------------
    def feature_type(self, inst: Instance) -> str | None:
        names = inst.names()
        if "MACHINING_FEATURE" in names or "INSTANCED_FEATURE" in names:
            for n in names:
                if n in FEATURE_TYPES:
                    return n
            for n in names:
                if n not in _GENERIC:
                    return n
            return "MACHINING_FEATURE"
        if len(names) == 1 and names[0] in FEATURE_TYPES:
            # AIM form: (name, description, of_shape -> PRODUCT_DEFINITION_SHAPE, LOGICAL)
            for v in inst.params:
                if isinstance(v, Ref) and self.sf[v].has("PRODUCT_DEFINITION_SHAPE"):
                    return names[0]
        return None

    def text_attr(self, inst: Instance, index: int) -> str:
        for name, p in inst.records:
            if name in ("SHAPE_ASPECT", "CHARACTERIZED_OBJECT") or len(inst.records) == 1:
                if len(p) > index and isinstance(p[index], str):
                    return p[index]
        return ""

    def components(self, fid: int) -> list[Component]:
        out = []
        for pds in self.sf.users(fid, "PRODUCT_DEFINITION_SHAPE", 2):
            for aspect in self.sf.users(pds.id, "SHAPE_ASPECT", 2):
                ap = aspect.get("SHAPE_ASPECT")
                role = ap[1] if isinstance(ap[1], str) else ""
                for rel in self.sf.inverse(aspect.id):
                    rname, rp = rel.records[0]
                    if (not rname.endswith("RELATIONSHIP") or len(rp) < 4
                            or not isinstance(rp[2], Ref) or int(rp[3]) != aspect.id):
                        continue
                    comp = self.sf[rp[2]]
                    c = Component(comp.id, comp.records[0][0] if not comp.complex else comp.type,
                                  self.text_attr(comp, 1), role,
                                  " / ".join(s for s in (rp[0], rp[1]) if isinstance(s, str) and s))
                    self.read_items(self.reps_of(comp.id), c)
                    out.append(c)
        return out

    def feature(self, inst: Instance, ftype: str) -> Feature:
        name = self.text_attr(inst, 0)
        desc = self.text_attr(inst, 1)
        f = Feature(inst.id, ftype, name, desc, self.sf.line_of(inst))
        self.read_items(self.reps_of(inst.id), f)
        f.components = self.components(inst.id)
        for rel in self.sf.users(inst.id, "FEATURE_COMPONENT_RELATIONSHIP", 2):
            rp = rel.get("FEATURE_COMPONENT_RELATIONSHIP")
            other = rp[3]
            if not isinstance(other, Ref):
                continue
            o = self.sf[other]
            if self.feature_type(o):
                f.children.append(int(other))
            else:                 # e.g. CHAMFER -> CHAMFER_OFFSET
                c = Component(o.id, o.type, self.text_attr(o, 1), self.text_attr(o, 1),
                              " / ".join(s for s in rp[:2] if isinstance(s, str) and s))
                self.read_items(self.reps_of(o.id), c)
                f.components.append(c)
        return f

    def stock(self) -> Stock | None:
        for rname, shape in (("BLOCK_SHAPE_REPRESENTATION", "block"),
                             ("CYLINDRICAL_SHAPE_REPRESENTATION", "cylinder")):
            for rep in self.sf.by_type(rname):
                holder = _Holder()
                self.read_items([rep], holder)
                need = ("length", "width", "height") if shape == "block" else ("diameter", "length")
                missing = [k for k in need if k not in holder.params]
                if missing:
                    raise self.sf.error(rep, f"{rname} lacks {', '.join(map(repr, missing))}",
                                        Ap224Error)
                for k in need:
                    if not holder.params[k] > 0:
                        raise self.sf.error(rep, f"stock {k} must be positive", Ap224Error)
                return Stock(shape, holder.placement or Placement(),
                             {k: holder.params[k] for k in need}, rep.id)
        return None

    def material(self) -> str:
        for m in self.sf.by_type("MATERIAL_DESIGNATION"):
            p = m.get("MATERIAL_DESIGNATION")
            if p and isinstance(p[0], str):
                return p[0]
        return ""

    def product(self) -> str:
        for p in self.sf.by_type("PRODUCT"):
            pp = p.get("PRODUCT")
            names = [s for s in pp[:2] if isinstance(s, str) and s]
            return " ".join(dict.fromkeys(names))
        return ""


def _snap(f: float) -> float:
    """Snap a conversion factor to the exact value it approximates (degree, inch, foot)."""
    for exact in (1.0, MM_PER_INCH, MM_PER_FOOT, 180.0 / math.pi):
        if abs(f - exact) <= 1e-7 * exact:
            return exact
    return f


@dataclass
class _Holder:
    params: dict = field(default_factory=dict)
    texts: dict = field(default_factory=dict)
    placement: Placement | None = None
    direction: tuple | None = None


def read_part(source: str | Path | StepFile) -> Part:
    """Read an AP224 file (path or parsed :class:`StepFile`) into a :class:`Part`.

    ISO 14649 (STEP-NC ARM) files are read by :mod:`millpath.part.step.iso14649` into
    the same records."""
    sf = source if isinstance(source, StepFile) else read(source)
    from millpath.part.step.iso14649 import is_iso14649, read_iso14649
    if is_iso14649(sf):
        return read_iso14649(sf)
    r = GeometryReader(sf)
    r.global_units()
    cand = {i.id for name in ("MACHINING_FEATURE", "INSTANCED_FEATURE", *FEATURE_TYPES)
            for i in sf.by_type(name)}
    feats = []
    for iid in [i for i in sf.instances if i in cand]:       # file order
        inst = sf[iid]
        t = r.feature_type(inst)
        if t is not None:
            feats.append(r.feature(inst, t))
    return Part(file=sf.file, schema=sf.schemas, product=r.product(), units=r.units,
                stock=r.stock(), material=r.material(), features=feats, step=sf)
