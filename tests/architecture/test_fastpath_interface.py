"""Issue 18.5: the interpreter's fast path uses the Machine only through its declared
interface (``Machine.FAST_PATH_INTERFACE``), and never a private name. Read from the
source with ``ast``: every attribute of the machine object (``m.NAME``, ``self.m.NAME``)
named in interpret/fastpath.py and interpret/compfast.py (the compensated runs it hands
lines to)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from millpath.interpret.machine import Machine

INTERPRET = Path(__file__).resolve().parents[2] / "millpath" / "interpret"
FAST_MODULES = (INTERPRET / "fastpath.py", INTERPRET / "compfast.py")


def _machine_attributes(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), str(path))
    names = set()
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute):
            continue
        v = node.value
        if (isinstance(v, ast.Name) and v.id == "m") or (
                isinstance(v, ast.Attribute) and v.attr == "m"
                and isinstance(v.value, ast.Name) and v.value.id == "self"):
            names.add(node.attr)
    return names


@pytest.mark.parametrize("path", FAST_MODULES, ids=lambda p: p.name)
def test_fast_path_touches_only_the_declared_interface(path):
    used = _machine_attributes(path)
    assert used, "the fast path names no machine attribute: the check reads nothing"
    assert not {n for n in used if n.startswith("_")}
    assert used <= Machine.FAST_PATH_INTERFACE, sorted(used - Machine.FAST_PATH_INTERFACE)


def test_every_name_of_the_interface_exists_on_a_machine():
    m = Machine({}, "mm")
    missing = [n for n in Machine.FAST_PATH_INTERFACE if not hasattr(m, n)]
    assert not missing, missing
