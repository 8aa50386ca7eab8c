"""The package's import graph (issue 18): no cycle between millpath's subpackages
(imports inside functions included), no module importing another module's ``_private``
name, and no source file over 800 lines. Read from the source with ``ast``, so the
check sees every import, not only those executed."""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PKG = Path(__file__).resolve().parents[2] / "millpath"
MAX_LINES = 800


def _modules() -> dict[str, Path]:
    out = {}
    for f in PKG.rglob("*.py"):
        rel = f.relative_to(PKG.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = f
    return out


def _imports(name: str, path: Path):
    """(imported module, imported names) for every import in the file."""
    tree = ast.parse(path.read_text(), str(path))
    pkg = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, []
        elif isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if node.level:
                base = pkg.split(".")
                base = base[:len(base) - node.level + 1]
                mod = ".".join(base + ([mod] if mod else []))
            yield mod, [a.name for a in node.names]


def _layer(mod: str) -> str:
    """The subpackage (``millpath.plan``) or top module (``millpath.pipeline``)."""
    parts = mod.split(".")
    return ".".join(parts[:2])


def _graph():
    mods = _modules()
    edges = defaultdict(set)
    private = []
    for name, path in mods.items():
        for mod, names in _imports(name, path):
            if not mod.startswith("millpath"):
                continue
            a, b = _layer(name), _layer(mod)
            if a != b and b != "millpath":
                edges[a].add((b, f"{name} -> {mod}"))
            for n in names:
                target = f"{mod}.{n}"
                if n.startswith("_") and not n.startswith("__") and target not in mods \
                        and mod != name:
                    private.append(f"{name} imports {mod}.{n}")
    return edges, private


def test_no_cycle_between_subpackages():
    edges, _ = _graph()
    graph = {a: {b for b, _ in bs} for a, bs in edges.items()}
    why = {(a, b): w for a, bs in edges.items() for b, w in bs}
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


def test_no_private_name_imported_across_modules():
    _, private = _graph()
    assert not private, "\n".join(private)


def test_no_source_file_over_800_lines():
    long = {str(p.relative_to(PKG)): n for p in PKG.rglob("*.py")
            if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, long
