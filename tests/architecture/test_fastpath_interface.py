"""Issue 18.5: the interpreter's fast path uses the Machine only through its declared
interface (``Machine.FAST_PATH_INTERFACE``), and never a private name. Read from the
source with ``ast``: every attribute of the machine object (``m.NAME``, ``self.m.NAME``)
named in interpret/fastpath.py and interpret/compfast.py (the compensated runs it hands
lines to), and of its compensation executor (``m.comp.NAME``)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from millpath.interpret.machine import Machine

INTERPRET = Path(__file__).resolve().parents[2] / "millpath" / "interpret"
FAST_MODULES = (INTERPRET / "fastpath.py", INTERPRET / "compfast.py")
#: the machine's executors, whose attributes are named as ``executor.NAME``
EXECUTORS = ("comp", "cycles")


def _is_machine(v: ast.AST) -> bool:
    """``m`` or ``self.m``."""
    return (isinstance(v, ast.Name) and v.id == "m") or (
        isinstance(v, ast.Attribute) and v.attr == "m"
        and isinstance(v.value, ast.Name) and v.value.id == "self")


def _machine_attributes(path: Path) -> set[str]:
    """Every ``m.NAME`` (``self.m.NAME``), and ``m.comp.NAME`` as ``comp.NAME`` (an
    executor's state and moves: compensation, canned cycles)."""
    tree = ast.parse(path.read_text(), str(path))
    names = set()
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute):
            continue
        v = node.value
        if _is_machine(v) and node.attr not in EXECUTORS:
            names.add(node.attr)
        elif isinstance(v, ast.Attribute) and v.attr in EXECUTORS and _is_machine(v.value):
            names.add(f"{v.attr}.{node.attr}")
    return names


@pytest.mark.parametrize("path", FAST_MODULES, ids=lambda p: p.name)
def test_fast_path_touches_only_the_declared_interface(path):
    used = _machine_attributes(path)
    assert used, "the fast path names no machine attribute: the check reads nothing"
    assert not {n for n in used if n.startswith("_")}
    assert used <= Machine.FAST_PATH_INTERFACE, sorted(used - Machine.FAST_PATH_INTERFACE)


def test_every_name_of_the_interface_exists_on_a_machine():
    m = Machine({}, "mm")
    missing = []
    for name in Machine.FAST_PATH_INTERFACE:
        obj = m
        for part in name.split("."):
            if not hasattr(obj, part):
                missing.append(name)
                break
            obj = getattr(obj, part)
    assert not missing, missing


def test_no_fast_path_module_aliases_an_executor():
    """``c = m.comp`` would hide its attributes from the check above."""
    for path in FAST_MODULES:
        tree = ast.parse(path.read_text(), str(path))
        for node in ast.walk(tree):
            if isinstance(node, ast.Assign) and isinstance(node.value, ast.Attribute):
                v = node.value
                assert not (v.attr in EXECUTORS and _is_machine(v.value)), path.name
