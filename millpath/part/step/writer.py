"""ISO 10303-21 writer: the inverse of :func:`millpath.part.step.p21.parse`.

``parse(write(sf))`` gives the same header and instance graph as ``sf`` (same ids,
records, values and value types). Reals are written with ``repr`` precision and always
carry a decimal point (``1.``, ``2.5E-07``); strings escape ``'`` as ``''``, ``\\`` as
``\\\\`` and every character outside printable ASCII as ``\\X2\\hhhh\\X0\\`` (or
``\\X4\\`` beyond the basic plane). One instance per line.
"""

from __future__ import annotations

import math

from millpath.part.step.p21 import DERIVED, Binary, Enum, Instance, Record, Ref, StepFile, Typed


def encode_string(s: str) -> str:
    """A Part 21 string literal (with quotes) for ``s``."""
    out = []
    run: list[str] = []        # pending non-ASCII characters

    def flush() -> None:
        if not run:
            return
        if all(ord(c) <= 0xFFFF for c in run):
            out.append("\\X2\\" + "".join(f"{ord(c):04X}" for c in run) + "\\X0\\")
        else:
            out.append("\\X4\\" + "".join(f"{ord(c):08X}" for c in run) + "\\X0\\")
        run.clear()

    for c in s:
        if " " <= c <= "~":
            flush()
            if c == "'":
                out.append("''")
            elif c == "\\":
                out.append("\\\\")
            else:
                out.append(c)
        else:
            run.append(c)
    flush()
    return "'" + "".join(out) + "'"


def format_real(v: float) -> str:
    """A Part 21 REAL: digits, a decimal point, optional exponent (``E``)."""
    if not math.isfinite(v):
        raise ValueError(f"cannot write the non-finite real {v!r} to a STEP file")
    r = repr(float(v))
    mant, _, exp = r.partition("e")
    if "." not in mant:
        mant += "."
    return mant + ("E" + exp if exp else "")


def format_value(v) -> str:
    if v is None:
        return "$"
    if v is DERIVED:
        return "*"
    if isinstance(v, Ref):
        return f"#{int(v)}"
    if isinstance(v, Enum):
        return f".{v}."
    if isinstance(v, Binary):
        return f'"{v}"'
    if isinstance(v, str):
        return encode_string(v)
    if isinstance(v, bool):
        return ".T." if v else ".F."
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return format_real(v)
    if isinstance(v, Typed):
        return f"{v.name}({format_value(v.value)})"
    if isinstance(v, (list, tuple)):
        return "(" + ",".join(format_value(x) for x in v) + ")"
    raise TypeError(f"cannot write {type(v).__name__} value {v!r} to a STEP file")


def format_record(rec: Record) -> str:
    name, params = rec
    return name + "(" + ",".join(format_value(p) for p in params) + ")"


def format_instance(inst: Instance) -> str:
    if len(inst.records) == 1:
        return f"#{inst.id}={format_record(inst.records[0])};"
    return f"#{inst.id}=(" + "".join(format_record(r) for r in inst.records) + ");"


def write(sf: StepFile) -> str:
    """Part 21 text of a :class:`StepFile` (header and data section)."""
    lines = ["ISO-10303-21;", "HEADER;"]
    lines += [format_record(r) + ";" for r in sf.header]
    lines += ["ENDSEC;", "DATA;"]
    lines += [format_instance(inst) for inst in sf.instances.values()]
    lines += ["ENDSEC;", "END-ISO-10303-21;", ""]
    return "\n".join(lines)
