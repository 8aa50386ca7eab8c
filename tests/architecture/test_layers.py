"""The package's import graph: the layers of ARCHITECTURE.md, each importing
only those below it (so no cycle between subpackages), imports inside functions
included; no module using another module's ``_private`` name; no source file over 800
lines. Read from the source with ``ast``, so the check sees every import, not only those
executed: ``import a.b``, ``from a import b`` (``b`` a module or a name), relative
imports, and a string naming a millpath module (``importlib.import_module`` tables such
as plan/registry.py)."""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PKG = Path(__file__).resolve().parents[2] / "millpath"
DOC = PKG.parent / "ARCHITECTURE.md"
MAX_LINES = 800

#: ARCHITECTURE.md's layers, lowest first; a layer may import only layers before it
LAYERS = [
    ("millpath.errors", "millpath.progress", "millpath.threads"),
    ("millpath.model", "millpath.geometry"),
    ("millpath.io", "millpath.gcode"),
    ("millpath.part",),
    ("millpath.plan",),
    ("millpath.job",),
    ("millpath.fit",),
    ("millpath.post",),
    ("millpath.program",),
    ("millpath.interpret",),
    ("millpath.simulate",),
    ("millpath.verify",),
    ("millpath.report",),
    ("millpath.pipeline",),
    ("millpath.cli", "millpath.examples"),
]
RANK = {name: i for i, names in enumerate(LAYERS) for name in names}


def _modules() -> dict[str, Path]:
    out = {}
    for f in PKG.rglob("*.py"):
        rel = f.relative_to(PKG.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = f
    return out


MODULES = _modules()


class _Uses(ast.NodeVisitor):
    """Every millpath module a file imports (with the line) and every ``_private``
    name it takes from another module: ``from m import _x``, or ``m._x`` where ``m``
    is a name bound to a module by an import."""

    def __init__(self, name: str, path: Path):
        self.name = name
        self.pkg = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
        self.imports: list[tuple[str, int]] = []
        self.private: list[str] = []
        self.aliases: dict[str, str] = {}           # local name -> module

    def _absolute(self, node: ast.ImportFrom) -> str:
        mod = node.module or ""
        if not node.level:
            return mod
        base = self.pkg.split(".")
        base = base[:len(base) - node.level + 1]
        return ".".join(base + ([mod] if mod else []))

    def visit_Import(self, node: ast.Import) -> None:
        for a in node.names:
            self.imports.append((a.name, node.lineno))
            if a.asname:
                self.aliases[a.asname] = a.name
            else:
                self.aliases.setdefault(a.name.split(".")[0], a.name.split(".")[0])

    def visit_ImportFrom(self, node: ast.ImportFrom) -> None:
        mod = self._absolute(node)
        for a in node.names:
            sub = f"{mod}.{a.name}"
            if sub in MODULES:                   # from package import module
                self.imports.append((sub, node.lineno))
                self.aliases[a.asname or a.name] = sub
            else:
                self.imports.append((mod, node.lineno))
                if _is_private(a.name) and mod != self.name:
                    self.private.append(f"{self.name}:{node.lineno} imports {mod}.{a.name}")

    def visit_Attribute(self, node: ast.Attribute) -> None:
        target = _dotted(node.value, self.aliases)
        if (target is not None and target in MODULES and target != self.name
                and _is_private(node.attr) and f"{target}.{node.attr}" not in MODULES):
            self.private.append(f"{self.name}:{node.lineno} uses {target}.{node.attr}")
        self.generic_visit(node)

    def visit_Constant(self, node: ast.Constant) -> None:
        if isinstance(node.value, str) and node.value in MODULES:
            self.imports.append((node.value, node.lineno))


def _is_private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _dotted(node: ast.AST, aliases: dict[str, str]) -> str | None:
    """The module an expression ``a`` / ``a.b.c`` names through the file's imports."""
    if isinstance(node, ast.Name):
        return aliases.get(node.id)
    if isinstance(node, ast.Attribute):
        base = _dotted(node.value, aliases)
        return f"{base}.{node.attr}" if base is not None else None
    return None


def _layer(mod: str) -> str:
    """The subpackage (``millpath.plan``) or top module (``millpath.pipeline``)."""
    return ".".join(mod.split(".")[:2])


def _scan():
    edges: dict[str, set[tuple[str, str]]] = defaultdict(set)
    private: list[str] = []
    for name, path in sorted(MODULES.items()):
        uses = _Uses(name, path)
        uses.visit(ast.parse(path.read_text(), str(path)))
        private += uses.private
        for mod, line in uses.imports:
            if not mod.startswith("millpath."):
                continue
            a, b = _layer(name), _layer(mod)
            if a != b:
                edges[a].add((b, f"{name}:{line} -> {mod}"))
    return edges, private


EDGES, PRIVATE = _scan()


def test_every_layer_is_documented():
    layers = {_layer(m) for m in MODULES if m != "millpath"}
    missing = sorted(layers - set(RANK))
    assert not missing, f"add {missing} to LAYERS here and to ARCHITECTURE.md"
    text = DOC.read_text()
    for names in LAYERS:
        for n in names:
            short = n.split(".", 1)[1]
            assert n not in layers or f"\n{short} " in text, \
                f"ARCHITECTURE.md does not describe the layer {short}"


def test_layers_import_only_layers_below():
    upward = sorted(why for a, bs in EDGES.items() for b, why in bs
                    if a in RANK and b in RANK and RANK[b] >= RANK[a] and a != b)
    assert not upward, "imports of a layer not below the importer:\n" + "\n".join(upward)


def test_no_cycle_between_subpackages():
    graph = {a: {b for b, _ in bs} for a, bs in EDGES.items()}
    why = {(a, b): w for a, bs in EDGES.items() for b, w in bs}
    cycles = []
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(n: str) -> None:
        state[n] = 1
        stack.append(n)
        for m in sorted(graph.get(n, ())):
            if state.get(m) == 1:
                loop = stack[stack.index(m):] + [m]
                cycles.append(", ".join(why[(x, y)] for x, y in zip(loop, loop[1:])))
            elif m not in state:
                visit(m)
        stack.pop()
        state[n] = 2

    for n in sorted(graph):
        if n not in state:
            visit(n)
    assert not cycles, "import cycles:\n" + "\n".join(cycles)


def test_no_private_name_used_across_modules():
    assert not PRIVATE, "\n".join(PRIVATE)


def test_no_source_file_over_800_lines():
    long = {str(p.relative_to(PKG)): n for p in PKG.rglob("*.py")
            if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, long


def _check(source: str, name: str = "millpath.plan.x") -> tuple[list, list]:
    """Imports and private uses the scanner finds in ``source`` (as module ``name``)."""
    path = PKG / (name.split(".", 1)[1].replace(".", "/") + ".py")
    uses = _Uses(name, path)
    uses.visit(ast.parse(source))
    return [m for m, _ in uses.imports], uses.private


def test_scanner_sees_every_form_of_import():
    """The checks above see what they claim to (a scanner that saw nothing would pass
    them): each form names its module, a private use is found however it is reached."""
    imports, private = _check(
        "import millpath.simulate.zmap as zm\n"
        "from millpath import pipeline\n"
        "from .. import report\n"
        "def f():\n"
        "    from millpath.fit.arcs import _x\n"
        "    return zm._private, pipeline._hidden, report.__doc__\n"
        "TABLE = {'a': 'millpath.cli.main'}\n")
    assert imports == ["millpath.simulate.zmap", "millpath.pipeline", "millpath.report",
                       "millpath.fit.arcs", "millpath.cli.main"]
    assert [p.split(" ", 1)[1] for p in private] == [
        "imports millpath.fit.arcs._x", "uses millpath.simulate.zmap._private",
        "uses millpath.pipeline._hidden"]
    _, own = _check("from millpath.plan.x import _mine\n")
    assert own == []
