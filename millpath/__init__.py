"""millpath: from a part definition to verified RS274NGC (LinuxCNC) programs for 3-axis milling.

Data flow (one package per stage): part -> plan -> model.Toolpath -> fit -> post ->
G-code -> interpret -> simulate -> report.

numba's compiled-kernel cache is kept out of the installed package (a stray
``__pycache__`` full of ``.nbi``/``.nbc`` files left behind by ``pip uninstall`` would
otherwise shadow a later install as a namespace package): unless ``NUMBA_CACHE_DIR`` is
already set, it is a per-user folder ``$XDG_CACHE_HOME/millpath/numba/<digest>`` (default
``~/.cache``; ``MILLPATH_CACHE_DIR`` overrides the ``.../millpath`` part), where the digest
covers every source file of the package, so that a kernel is never reused after any of
the code it calls has changed.

numba's parallel kernels run on OpenMP threads, which by default keep spinning after
each parallel loop, waiting for the next: CPU burnt on a busy machine for nothing.
Unless ``OMP_WAIT_POLICY`` is already set, they sleep instead (``PASSIVE``).

The Python API (imported on first use, so ``import millpath`` stays cheap):
:func:`run_job` (a job file to an output folder, as ``millpath run``), and its stages
:func:`load_job`, :func:`plan_job`, :func:`fit_job`, :func:`post_job`; a program's
motion, as the control runs it, from :func:`millpath.interpret.interpret`. See
docs/api.md.
"""

import os as _os

__version__ = "0.1.0"


def _numba_cache_dir() -> None:
    import hashlib
    from pathlib import Path

    if _os.environ.get("NUMBA_CACHE_DIR"):
        return
    here = Path(__file__).resolve().parent
    h = hashlib.sha1(__version__.encode())
    try:
        for f in sorted(here.rglob("*.py")):
            h.update(f.relative_to(here).as_posix().encode())
            h.update(f.read_bytes())
    except OSError:
        return
    base = Path(_os.environ.get("MILLPATH_CACHE_DIR")
                or Path(_os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "millpath")
    target = base / "numba" / h.hexdigest()[:16]
    try:
        target.mkdir(parents=True, exist_ok=True)
    except OSError:
        return                        # no writable cache: numba compiles in memory
    _os.environ["NUMBA_CACHE_DIR"] = str(target)


_numba_cache_dir()
_os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")


#: public names -> the module defining them (imported on first use)
_API = {"run_job": "millpath.pipeline", "plan_job": "millpath.pipeline",
        "fit_job": "millpath.pipeline", "post_job": "millpath.pipeline",
        "load_job": "millpath.job.jobfile"}

__all__ = sorted(_API)


def __getattr__(name: str):
    if name in _API:
        import importlib
        return getattr(importlib.import_module(_API[name]), name)
    raise AttributeError(f"module 'millpath' has no attribute {name!r}")
