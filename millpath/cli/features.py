"""``millpath features PART.stp [--json]``: what an AP224 file says about the part.

Prints the product, units, stock, material and every machining feature with its
parameters and placement (a rich table), then the features the planner cannot machine
with the reason. ``--json`` prints the same as one JSON document for programs.
"""

from __future__ import annotations

import json
from pathlib import Path

import click


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def _vec(v) -> str:
    return "(" + ", ".join(_fmt(x) for x in v) + ")"


def part_summary(path: Path, body=None, setup: str = "+Z") -> dict:
    """The JSON document of ``millpath features --json``. A file without AP224 features
    is read as a B-rep solid and its features are recognised (``solid`` section)."""
    from millpath.part.step.ap224 import read_part
    from millpath.part.step.shapes import feature_shapes

    part = read_part(path)
    solid = None
    if not part.features:
        from millpath.plan.features.solid import load_solid
        sp = load_solid(path, body=body, setup=setup)
        part, shapes, solid = sp.part, sp.shapes, sp.info
        solid["box"] = list(sp.box)
    else:
        from millpath.part.step.setup import turned
        part = turned(part, setup)
        shapes = feature_shapes(part)
    return {
        "file": str(path),
        "schema": part.schema,
        "product": part.product,
        "units": part.units.as_dict(),
        "material": part.material,
        "stock": part.stock.as_dict() if part.stock else None,
        "features": [f.as_dict() for f in part.features],
        "machinable": [{"id": s.id, "kind": s.kind} for s in shapes.shapes],
        "unmachinable": [{"id": u.id, "type": u.type, "reason": u.reason}
                         for u in shapes.skipped],
        **({"solid": solid} if solid is not None else {}),
    }


@click.command(name="features")
@click.argument("part", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of a table.")
@click.option("--body", default=None, help="Solid to read (number or name) in a multi-body file.")
@click.option("--setup", default="+Z", help="Axis of the file that points up (+Z, -Z, +X ...).")
def command(part: Path, as_json: bool, body: str | None, setup: str) -> None:
    """List the stock, units, material and machining features of a STEP file: AP224
    features as written, or features recognised from a solid (AP203/AP214/AP242)."""
    doc = part_summary(part, int(body) if body and body.isdigit() else body, setup)
    if as_json:
        click.echo(json.dumps(doc, indent=2))
        return
    from rich.console import Console
    from rich.markup import escape as esc
    from rich.table import Table

    con = Console(width=max(Console().width, 120))
    u = doc["units"]
    con.print(f"[bold]{esc(doc['file'])}[/bold]  schema "
              f"{esc(', '.join(doc['schema'])) or '?'}")
    con.print(f"product: {esc(doc['product']) or '-'}")
    con.print(f"units: length {u['length']} ({_fmt(u['length_mm'])} mm), angle {u['angle']} "
              f"(measures shown in {u['length']} and degrees)")
    con.print(f"material: {esc(doc['material']) or '-'}")
    st = doc["stock"]
    if st:
        dims = ", ".join(f"{k} {_fmt(v)}" for k, v in st.items()
                         if k not in ("shape", "id", "placement"))
        pl = st["placement"]
        con.print(f"stock: {st['shape']} #{st['id']}: {dims}; origin {_vec(pl['origin'])} "
                  f"axis {_vec(pl['axis'])}")
    else:
        con.print("stock: none in the file")
    if doc.get("solid"):
        so = doc["solid"]
        con.print(f"solid: {esc(so['entity'])} (body {so['body']} of {so['bodies']}"
                  f"{', ' + esc(repr(so['name'])) if so['name'] else ''}), {so['faces']} faces,"
                  f" setup {so['setup']}, box {_vec(so['box'])}: features recognised")
    title = "recognised machining features" if doc.get("solid") else "machining features"
    t = Table(title=f"{len(doc['features'])} {title}", show_lines=True)
    for col in ("#id", "type", "name", "placement (origin / axis / ref)", "parameters",
                "components"):
        t.add_column(col, overflow="fold")
    for f in doc["features"]:
        pl = f["placement"]
        place = (f"{_vec(pl['origin'])}\n{_vec(pl['axis'])}\n{_vec(pl['ref'])}" if pl else "-")
        params = "\n".join([f"{k} = {_fmt(v)}" for k, v in f["params"].items()]
                           + [f"{k}: {v}" for k, v in f["texts"].items()])
        comps = []
        for c in f["components"]:
            vals = ", ".join(f"{k} {_fmt(v)}" for k, v in c["params"].items())
            desc = f" '{c['description']}'" if c["description"] else ""
            comps.append(f"{c['type']}{desc}" + (f": {vals}" if vals else ""))
        if f["children"]:
            comps.append("sub-features " + ", ".join(f"#{i}" for i in f["children"]))
        if f.get("faces"):
            comps.append("faces " + " ".join(str(i) for i in f["faces"]))
        t.add_row(f"#{f['id']}", f["type"], esc(f["name"] or f["description"]), place,
                  esc(params) or "-", esc("\n".join(comps)) or "-")
    con.print(t)
    if doc["unmachinable"]:
        con.print("[bold]not machinable by the features planner:[/bold]")
        for x in doc["unmachinable"]:
            con.print(f"  #{x['id']} {x['type']}: {esc(x['reason'])}")
