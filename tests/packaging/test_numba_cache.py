"""numba's kernel cache lives outside the package: a cache file inside an
installed package survives ``pip uninstall`` and turns ``site-packages/millpath`` into a
namespace package that shadows the next install."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import millpath

PKG = Path(millpath.__file__).resolve().parent


def _run(code: str, env: dict[str, str]) -> str:
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=True, cwd=env.get("HOME")).stdout


def _env(tmp_path: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items()
           if k not in ("NUMBA_CACHE_DIR", "MILLPATH_CACHE_DIR", "XDG_CACHE_HOME")}
    env["XDG_CACHE_HOME"] = str(tmp_path / "xdg")
    env["HOME"] = str(tmp_path)
    env["PYTHONPATH"] = str(PKG.parent)
    return env


def test_kernel_cache_is_written_outside_the_package(tmp_path):
    before = {p for p in PKG.rglob("*.nb[ic]")}
    env = _env(tmp_path)
    out = _run("import importlib, numpy as np, os\ns = importlib.import_module('millpath.fit.segment')\n"
               "P = np.array([[0., 0, 0], [1, 0, 0], [2, 0, 0]])\n"
               "s.tangents(P, 0.5)\n"
               "print(os.environ['NUMBA_CACHE_DIR'])", env)
    cache = Path(out.strip())
    assert cache.is_relative_to(tmp_path / "xdg" / "millpath" / "numba")
    assert {p for p in PKG.rglob("*.nb[ic]")} <= before      # nothing new in the package
    assert any(cache.rglob("*.nbi"))                           # and the kernel was cached


def test_user_settings_are_respected(tmp_path):
    env = _env(tmp_path)
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "mine")
    assert _run("import millpath, os; print(os.environ['NUMBA_CACHE_DIR'])", env).strip() \
        == str(tmp_path / "mine")
    del env["NUMBA_CACHE_DIR"]
    env["MILLPATH_CACHE_DIR"] = str(tmp_path / "mp")
    out = _run("import millpath, os; print(os.environ['NUMBA_CACHE_DIR'])", env).strip()
    assert Path(out).is_relative_to(tmp_path / "mp" / "numba")
