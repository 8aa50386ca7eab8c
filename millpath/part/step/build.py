"""Write AP224 feature files: the structure of the published AP224 sample, for
fixtures, examples and benchmarks.

>>> b = Ap224Builder("PLATE", units="mm", material="aluminium 6061-T6")
>>> b.block(225.0, 100.0, 12.5)
>>> b.hole((112.5, 50.0, 12.5), 75.0, 12.5, bottom="through")
>>> text = b.text()

Each feature is a complex instance ``(CHARACTERIZED_OBJECT FEATURE_DEFINITION
INSTANCED_FEATURE MACHINING_FEATURE <TYPE> SHAPE_ASPECT)`` with an 'orientation'
placement (axis pointing into the material) and components linked by shape aspects
and relationships, with named measure items carrying units. Lengths are in the
builder's unit; angles in degrees.
"""

from __future__ import annotations



from millpath.model.units import MM_PER_INCH
from millpath.part.step.p21 import DERIVED, Enum, Instance, Ref, StepFile, Typed
from millpath.part.step.writer import write


class Ap224Builder:
    """Accumulates instances; :meth:`text` returns the Part 21 file."""

    def __init__(self, product: str, units: str = "mm", material: str = "",
                 description: str = ""):
        if units not in ("mm", "inch"):
            raise ValueError("units must be 'mm' or 'inch'")
        self.sf = StepFile()
        self.sf.header = [
            ("FILE_DESCRIPTION", [[description or "AP224 feature model"], "2;1"]),
            ("FILE_NAME", [product, "2026-01-01T00:00:00", ["millpath"], ["millpath"],
                           "millpath AP224 builder", "millpath", ""]),
            ("FILE_SCHEMA", [["FEATURE_BASED_PROCESS_PLANNING"]]),
        ]
        self._next = 1
        dim_len = self.add("DIMENSIONAL_EXPONENTS", [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        dim_one = self.add("DIMENSIONAL_EXPONENTS", [0.0] * 7)
        mm = self.complex(("LENGTH_UNIT", []), ("NAMED_UNIT", [DERIVED]),
                          ("SI_UNIT", [Enum("MILLI"), Enum("METRE")]))
        if units == "inch":
            conv = self.add("LENGTH_MEASURE_WITH_UNIT", [Typed("LENGTH_MEASURE", MM_PER_INCH), mm])
            self.length_unit = self.complex(("CONVERSION_BASED_UNIT", ["INCH", conv]),
                                            ("LENGTH_UNIT", []), ("NAMED_UNIT", [dim_len]))
        else:
            self.length_unit = mm
        rad = self.complex(("NAMED_UNIT", [DERIVED]), ("PLANE_ANGLE_UNIT", []),
                           ("SI_UNIT", [None, Enum("RADIAN")]))
        conv = self.add("PLANE_ANGLE_MEASURE_WITH_UNIT",
                        [Typed("PLANE_ANGLE_MEASURE", 0.017453292519943295), rad])
        self.angle_unit = self.complex(("CONVERSION_BASED_UNIT", ["DEGREE", conv]),
                                       ("NAMED_UNIT", [dim_one]), ("PLANE_ANGLE_UNIT", []))
        sr = self.complex(("NAMED_UNIT", [DERIVED]), ("SI_UNIT", [None, Enum("STERADIAN")]),
                          ("SOLID_ANGLE_UNIT", []))
        unc = self.add("UNCERTAINTY_MEASURE_WITH_UNIT",
                       [Typed("LENGTH_MEASURE", 1e-6), self.length_unit, "closure",
                        "maximum model space distance"])
        self.ctx = self.complex(
            ("GEOMETRIC_REPRESENTATION_CONTEXT", [3]),
            ("GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT", [[unc]]),
            ("GLOBAL_UNIT_ASSIGNED_CONTEXT", [[self.length_unit, self.angle_unit, sr]]),
            ("REPRESENTATION_CONTEXT", ["ID1", "3D"]))
        self.count_unit = self.add("CONTEXT_DEPENDENT_UNIT", [dim_one, "COUNT"])
        app = self.add("APPLICATION_CONTEXT", ["Mechanical Process Planning with Features"])
        self.add("APPLICATION_PROTOCOL_DEFINITION", ["international standard",
                                                     "feature_based_process_planning", 2001, app])
        pc = self.add("PRODUCT_CONTEXT", ["Feature Based Process Planning", app, "Mechanical"])
        prod = self.add("PRODUCT", [product, product, "", [pc]])
        self.pdf = self.add("PRODUCT_DEFINITION_FORMATION", ["1", "ORIGINAL", prod])
        self.pdc = self.add("PRODUCT_DEFINITION_CONTEXT",
                            ["feature definitions", app, "manufacturing planning"])
        self.pd = self.add("PRODUCT_DEFINITION", [product, "product design", self.pdf, self.pdc])
        self.pds = self.add("PRODUCT_DEFINITION_SHAPE", ["product shape", "shape for product",
                                                         self.pd])
        self.material_name = material
        self._stock_rep: Ref | None = None

    # --- low level -----------------------------------------------------------------------
    def add(self, name: str, params: list) -> Ref:
        return self.complex((name, params))

    def complex(self, *records: tuple[str, list]) -> Ref:
        i = self._next
        self._next += 1
        self.sf.instances[i] = Instance(i, [(n, list(p)) for n, p in records])
        return Ref(i)

    def point(self, p) -> Ref:
        return self.add("CARTESIAN_POINT", ["", [float(v) for v in p]])

    def direction(self, d) -> Ref:
        return self.add("DIRECTION", ["", [float(v) for v in d]])

    def placement(self, origin, axis=(0.0, 0.0, -1.0), ref=(1.0, 0.0, 0.0),
                  name: str = "orientation") -> Ref:
        return self.add("AXIS2_PLACEMENT_3D", [name, self.point(origin), self.direction(axis),
                                               self.direction(ref)])

    def length(self, name: str, value: float) -> Ref:
        return self.complex(("LENGTH_MEASURE_WITH_UNIT", []), ("MEASURE_REPRESENTATION_ITEM", []),
                            ("MEASURE_WITH_UNIT", [Typed("LENGTH_MEASURE", float(value)),
                                                   self.length_unit]),
                            ("REPRESENTATION_ITEM", [name]))

    def angle(self, name: str, value: float) -> Ref:
        return self.complex(("MEASURE_REPRESENTATION_ITEM", []),
                            ("MEASURE_WITH_UNIT", [Typed("PLANE_ANGLE_MEASURE", float(value)),
                                                   self.angle_unit]),
                            ("PLANE_ANGLE_MEASURE_WITH_UNIT", []), ("REPRESENTATION_ITEM", [name]))

    def count(self, name: str, value: float) -> Ref:
        return self.add("MEASURE_REPRESENTATION_ITEM",
                        [name, Typed("COUNT_MEASURE", float(value)), self.count_unit])

    def _params(self, owner: Ref, items: list[Ref]) -> None:
        pd = self.add("PROPERTY_DEFINITION", ["", "", owner])
        rep = self.add("SHAPE_REPRESENTATION_WITH_PARAMETERS", ["", items, self.ctx])
        self.add("SHAPE_DEFINITION_REPRESENTATION", [pd, rep])

    def _feature(self, ftype: str, name: str, placement: Ref, items: list[Ref] = ()) -> Ref:
        f = self.complex(("CHARACTERIZED_OBJECT", ["", name]), ("FEATURE_DEFINITION", []),
                         ("INSTANCED_FEATURE", []), ("MACHINING_FEATURE", []), (ftype, []),
                         ("SHAPE_ASPECT", ["", name, self.pds, Enum("T")]))
        self._params(f, [placement, *items])
        return f

    def _component(self, feature: Ref, ctype: str, description: str, role: str,
                   usage: tuple[str, str], items: list[Ref], direction=None,
                   rel: str = "SHAPE_DEFINING_RELATIONSHIP") -> Ref:
        fpds = self._feature_pds.get(int(feature))
        if fpds is None:
            fpds = self.add("PRODUCT_DEFINITION_SHAPE", ["", "", feature])
            self._feature_pds[int(feature)] = fpds
        fcd = self.add("FEATURE_COMPONENT_DEFINITION", ["", ""])
        cpds = self.add("PRODUCT_DEFINITION_SHAPE", ["", "", fcd])
        comp = self.add(ctype, ["", description, cpds, Enum("F")])
        if items:
            self._params(comp, items)
        if direction is not None:
            pd = self.add("PROPERTY_DEFINITION", ["", "", comp])
            rep = self.add("DIRECTION_SHAPE_REPRESENTATION", ["", [self.direction(direction)],
                                                              self.ctx])
            self.add("PROPERTY_DEFINITION_REPRESENTATION", [pd, rep])
        aspect = self.add("SHAPE_ASPECT", ["", role, fpds, Enum("T")])
        self.add(rel, [usage[0], usage[1], comp, aspect])
        return comp

    @property
    def _feature_pds(self) -> dict[int, Ref]:
        if not hasattr(self, "_fpds"):
            self._fpds: dict[int, Ref] = {}
        return self._fpds

    # --- part data -----------------------------------------------------------------------
    def block(self, length: float, width: float, height: float, origin=(0.0, 0.0, 0.0)) -> None:
        """Block stock: ``length`` along X, ``width`` along Y, ``height`` along Z from the
        corner ``origin``."""
        pl = self.placement(origin, (0.0, 0.0, 1.0), (1.0, 0.0, 0.0))
        rep = self.add("BLOCK_SHAPE_REPRESENTATION", [
            "base shape", [pl, self.length("length", length), self.length("width", width),
                           self.length("height", height)], self.ctx])
        self._stock_rep = rep
        self._material(rep)

    def cylinder(self, diameter: float, length: float, origin=(0.0, 0.0, 0.0)) -> None:
        """Cylindrical bar stock: axis +Z from ``origin`` (the centre of its bottom face)
        for ``length``, as RAMP files write it."""
        pl = self.placement(origin, (0.0, 0.0, 1.0), (1.0, 0.0, 0.0))
        rep = self.add("CYLINDRICAL_SHAPE_REPRESENTATION", [
            "base shape", [pl, self.length("length", length),
                           self.length("diameter", diameter)], self.ctx])
        self._stock_rep = rep
        self._material(rep)

    def _material(self, stock_rep: Ref | None) -> None:
        if not self.material_name:
            return
        mpd = self.add("PRODUCT_DEFINITION", ["", self.material_name, self.pdf, self.pdc])
        self.add("MATERIAL_DESIGNATION", [self.material_name, [mpd]])
        if stock_rep is not None:
            bpds = self.add("PRODUCT_DEFINITION_SHAPE", ["base shape", "base shape for part", mpd])
            self.add("SHAPE_DEFINITION_REPRESENTATION", [bpds, stock_rep])

    # --- features ------------------------------------------------------------------------
    def hole(self, entry, diameter: float, depth: float, bottom: str = "flat",
             name: str = "", axis=(0.0, 0.0, -1.0), **bottom_params: float) -> Ref:
        """A ROUND_HOLE whose placement is at ``entry`` and whose depth runs ``depth``
        from it along ``axis`` (default -Z: ``entry`` on the face the hole opens into;
        RAMP files also write a bore with its origin at its bottom and axis +Z);
        ``bottom`` one of through, flat, spherical (``radius``), conical (``tip_angle``),
        flat with radius (``corner_radius``), flat with taper (``taper_angle``)."""
        axis = tuple(float(a) for a in axis)
        pl = self.placement(entry, axis)
        f = self._feature("ROUND_HOLE", name, pl)
        self._component(f, "CIRCULAR_CLOSED_PROFILE", "", "diameter occurrence",
                        ("diameter", "profile usage"), [pl, self.length("diameter", diameter)])
        self._component(f, "PATH_FEATURE_COMPONENT", "linear", "hole depth occurrence",
                        ("hole depth", "path feature component usage"),
                        [pl, self.length("distance", depth)], direction=axis)
        items: list[Ref] = []
        for k, v in bottom_params.items():
            label = k.replace("_", " ")
            items.append(self.angle(label, v) if "angle" in k else self.length(label, v))
        self._component(f, "HOLE_BOTTOM", bottom, "bottom condition occurrence",
                        ("", "hole bottom usage"), items, rel="FEATURE_COMPONENT_RELATIONSHIP")
        return f

    def slot(self, start, direction, length: float, width: float, depth: float,
             ends=("open", "open"), name: str = "", axis=(0.0, 0.0, -1.0)) -> Ref:
        """A SLOT with a SQUARE_U_PROFILE: centreline from ``start`` along ``direction``
        (XY) for ``length``; ``ends`` at start and end. The depth runs from ``start``
        along ``axis``: -Z (default) with ``start`` on the top face, or +Z with ``start``
        on the slot's floor (the RAMP files' way, axis out of the material)."""
        d = (float(direction[0]), float(direction[1]), 0.0)
        pl = self.placement(start, tuple(float(a) for a in axis), d)
        return self._slot(pl, d, length, width, depth, ends, name)

    def _slot(self, pl: Ref, d, length: float, width: float, depth: float, ends,
              name: str) -> Ref:
        """A SLOT at placement ``pl``: its U profile, its course of travel ``d`` for
        ``length`` and its two ends."""
        f = self._feature("SLOT", name, pl)
        self._component(f, "SQUARE_U_PROFILE", "sweep", "swept shape occurrence",
                        ("", "profile usage"),
                        [pl, self.length("width", width), self.length("depth", depth),
                         self.angle("first angle", 90.0), self.angle("second angle", 90.0),
                         self.length("first radius", 0.0), self.length("second radius", 0.0)])
        self._component(f, "PATH_FEATURE_COMPONENT", "linear", "course of travel occurrence",
                        ("course of travel", "path feature component usage"),
                        [pl, self.length("distance", length)], direction=d)
        for which, e in zip(("course of travel start", "course of travel end"), ends):
            self._component(f, "SLOT_END", e, "end condition occurrence",
                            (which, "slot end usage"), [], rel="FEATURE_COMPONENT_RELATIONSHIP")
        return f

    def slot_iso(self, floor_start, direction, length: float, width: float, depth: float,
                 ends=("open", "open"), name: str = "") -> Ref:
        """A SLOT placed as ISO 10303-224 defines it (ISO/TS 10303-1814): origin at one
        end of the course of travel on the slot's floor (``floor_start``), placement Z
        along the course (``direction``, XY), Y away from the part (+Z), X = Y x Z."""
        d = (float(direction[0]), float(direction[1]), 0.0)
        x = (-d[1], d[0], 0.0)                   # (0, 0, 1) x d: Y = Z x X = +Z
        pl = self.placement(floor_start, d, x)
        return self._slot(pl, d, length, width, depth, ends, name)

    def pocket(self, center, depth: float, profile: str, bottom: str = "planar",
               name: str = "", angle_ref=(1.0, 0.0, 0.0), floor_radius: float = 0.0,
               **dims: float) -> Ref:
        """A POCKET centred at ``center`` (top face); ``profile`` rectangular (``length``,
        ``width``, ``corner_radius``), circular (``diameter``) or ngon
        (``circumscribed_diameter``, ``number_of_sides``, ``corner_radius``);
        ``floor_radius``: the fillet between walls and a planar floor."""
        pl = self.placement(center, (0.0, 0.0, -1.0), angle_ref)
        desc = {"rectangular": "closed rectangular", "circular": "circular cutout"}.get(
            profile, "complex")
        f = self._feature("POCKET", name or desc, pl)
        items = [pl]
        for k, v in dims.items():
            label = k.replace("_", " ")
            items.append(self.count(label, v) if k == "number_of_sides" else
                         self.length(label, v))
        ctype = {"rectangular": "RECTANGULAR_CLOSED_PROFILE",
                 "circular": "CIRCULAR_CLOSED_PROFILE",
                 "ngon": "NGON_CLOSED_PROFILE"}[profile]
        self._component(f, ctype, "", "closed boundary occurrence", ("", "profile usage"), items)
        self._component(f, "PATH_FEATURE_COMPONENT", "linear", "pocket depth occurrence",
                        ("pocket depth", "path feature component usage"),
                        [pl, self.length("distance", depth)], direction=(0.0, 0.0, -1.0))
        self._component(f, "POCKET_BOTTOM", bottom, "bottom condition occurrence",
                        ("pocket depth end", "pocket bottom usage"),
                        [self.length("radius", floor_radius)] if floor_radius > 0 else [],
                        rel="FEATURE_COMPONENT_RELATIONSHIP")
        return f

    def step(self, start, direction, length: float, profile_angle: float = 90.0,
             name: str = "") -> Ref:
        """A STEP along an edge: course of travel from ``start`` along ``direction`` for
        ``length``; removal boundary a VEE_PROFILE of ``profile_angle`` (AP224 gives no
        width or depth for a step)."""
        d = (float(direction[0]), float(direction[1]), 0.0)
        pl = self.placement(start, (0.0, 0.0, -1.0), d)
        f = self._feature("STEP", name, pl)
        self._component(f, "PATH_FEATURE_COMPONENT", "linear", "course of travel occurrence",
                        ("course of travel", "path feature component usage"),
                        [pl, self.length("distance", length)], direction=d)
        self._component(f, "VEE_PROFILE", "v-shape", "removal boundary occurrence",
                        ("removal boundary", "profile usage"),
                        [pl, self.angle("profile angle", profile_angle),
                         self.angle("tilt angle", 0.0), self.length("profile radius", 0.0)])
        return f

    def planar_face(self, start, direction, length: float, width: float, depth: float,
                    name: str = "", axis=(0.0, 0.0, -1.0)) -> Ref:
        """A PLANAR_FACE: course of travel ``length`` along ``direction``, removal
        boundary a LINEAR_PROFILE of ``width``, 'removal depth' ``depth`` from ``start``
        along ``axis`` (-Z: ``start`` on the face before machining; +Z: on the finished
        face, the axis out of the material)."""
        d = (float(direction[0]), float(direction[1]), 0.0)
        pl = self.placement(start, tuple(float(a) for a in axis), d)
        f = self._feature("PLANAR_FACE", name, pl, [self.length("removal depth", depth)])
        self._component(f, "PATH_FEATURE_COMPONENT", "linear", "course of travel occurrence",
                        ("course of travel", "path feature component usage"),
                        [pl, self.length("distance", length)], direction=d)
        self._component(f, "LINEAR_PROFILE", "", "removal boundary occurrence",
                        ("removal boundary", "profile usage"),
                        [pl, self.length("profile length", width)])
        return f

    def text(self) -> str:
        return write(self.sf)


