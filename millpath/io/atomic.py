"""Atomic output: single files through a temporary file and a rename, whole output
folders staged beside the folder and switched in with one rename.

Output folder protocol (:func:`staged_dir`, :func:`output_lock`) for a folder ``OUT``
whose parent ``P`` is writable:

- ``P/.OUT.lock``: an advisory lock (``flock``) held for the whole run; a second run
  into the same folder fails at once with a message naming the folder and the other
  run's process id. The kernel drops the lock when a run dies, even by SIGKILL.
- ``P/.OUT.staging-*``: the new output, written file by file.
- the switch: the staging folder and ``OUT`` are exchanged in one ``renameat2``
  (``RENAME_EXCHANGE``) where the system has it, else ``OUT`` is renamed to
  ``P/.OUT.backup-*`` and the staging folder renamed to ``OUT`` (a kill between the
  two leaves ``OUT`` missing and the backup complete: the next run restores it).
- leftovers of killed runs (staging and backup folders) are removed by the next run.

When ``P`` is not writable but ``OUT`` is, the lock and the staging folder live inside
``OUT`` (``OUT/.millpath.lock``, ``OUT/.staging-*``) and files are renamed in one at a
time: each file is whole, but a kill during the switch can mix old and new files.

An existing ``OUT`` is replaced only when it holds nothing but millpath output (a
``.millpath-output`` marker, or only ``*.ngc *.tbl *.json *.png *.html`` files); any
other content is an error, so a mistaken ``-o ~`` never removes a user's files.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import errno
import fcntl
import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from millpath.errors import MillpathError

MARKER = ".millpath-output"
_OUTPUT_SUFFIXES = (".ngc", ".tbl", ".json", ".png", ".html")
_HELD: dict[str, int] = {}          # resolved output folder -> lock fd held by this process


def write_text(path: str | Path, text: str) -> None:
    write_bytes(path, text.encode("utf-8"))


def write_bytes(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and a rename; an error (a full
    disk) leaves no file and names ``path``."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=p.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.chmod(tmp, 0o666 & ~_umask())      # as open() would create it, not mkstemp's 0600
        os.replace(tmp, p)
    except BaseException as e:
        if os.path.exists(tmp):
            os.unlink(tmp)
        if isinstance(e, OSError):
            raise _named(e, tmp, p) from None
        raise


def _named(e: OSError, was: str | Path, name: str | Path) -> OSError:
    """``e`` naming ``name`` where it named ``was`` (a temporary file or the staging
    folder) or nothing (a write to a full disk names no file)."""
    old = e.filename
    new = str(name) if old is None or str(old) == str(was) else \
        str(old).replace(str(was), str(name), 1)
    return OSError(e.errno, e.strerror or str(e), new)


def _umask() -> int:
    """The process umask (read by setting it and putting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _key(final: Path) -> str:
    return str(final.absolute())


def _parent_writable(final: Path) -> bool:
    parent = final.absolute().parent
    return parent.is_dir() and os.access(parent, os.W_OK | os.X_OK)


def _lock_path(final: Path) -> Path:
    final = final.absolute()
    if _parent_writable(final):
        return final.parent / f".{final.name}.lock"
    return final / ".millpath.lock"


@contextmanager
def output_lock(final: str | Path) -> Iterator[None]:
    """Hold the output folder ``final`` for this run (re-entrant within the process).

    Raises MillpathError naming the folder when another run holds it."""
    final = Path(final)
    key = _key(final)
    if key in _HELD:
        yield
        return
    parent = final.absolute().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise MillpathError(f"cannot create the output folder's parent: "
                            f"{e.strerror or e}", parent) from None
    if not _parent_writable(final):
        try:
            final.mkdir(exist_ok=True)
        except OSError as e:
            raise MillpathError(f"cannot create the output folder: {e.strerror or e}",
                                final) from None
    lock = _lock_path(final)
    try:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as e:
        raise MillpathError(f"output folder is not writable: {e.strerror or e}", final) \
            from None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as e:
        other = os.pread(fd, 32, 0).decode(errors="replace").strip() or "?"
        os.close(fd)
        if e.errno in (errno.EWOULDBLOCK, errno.EACCES):
            raise MillpathError(f"output folder is being written by another millpath run "
                                f"(process {other}); wait for it or choose another folder",
                                final) from None
        raise
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    _HELD[key] = fd
    try:
        _clean_leftovers(final)
        yield
    finally:
        del _HELD[key]
        os.close(fd)                  # releases the flock


def _leftovers(final: Path, kind: str) -> list[Path]:
    final = final.absolute()
    if _parent_writable(final):
        return sorted(final.parent.glob(f".{final.name}.{kind}-*"))
    return sorted(final.glob(f".{kind}-*")) if final.is_dir() else []


def _clean_leftovers(final: Path) -> None:
    """Remove staging folders of killed runs; restore a backup when a run died between
    moving the old output away and moving the new one in."""
    final = final.absolute()
    for d in _leftovers(final, "staging"):
        shutil.rmtree(d, ignore_errors=True)
    backups = _leftovers(final, "backup")
    if backups and not final.exists():
        newest = max(backups, key=lambda p: p.stat().st_mtime)
        os.rename(newest, final)
        backups.remove(newest)
    for d in backups:
        shutil.rmtree(d, ignore_errors=True)


def _check_replaceable(final: Path) -> None:
    if not final.exists():
        return
    if not final.is_dir():
        raise MillpathError("the output path exists and is not a folder", final)
    if (final / MARKER).exists():
        return
    foreign = [p.name for p in final.iterdir()
               if not p.name.startswith(".") and not (p.is_file()
                                                      and p.suffix in _OUTPUT_SUFFIXES)]
    if foreign:
        raise MillpathError(f"the output folder holds files millpath did not write "
                            f"({', '.join(sorted(foreign)[:3])}); choose a new or empty "
                            f"folder", final)


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths atomically (Linux renameat2). False where unsupported."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p,
                   ctypes.c_uint]
    rc = fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    if rc == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP):
        return False
    raise OSError(err, os.strerror(err), str(b))


@contextmanager
def staged_dir(final: str | Path) -> Iterator[Path]:
    """Yield an empty staging folder; on success it becomes ``final`` in one switch.

    On error, or if the process dies, ``final`` keeps its previous content whole (see the
    module docstring for the protocol and the fallback when the parent is read-only).
    """
    final = Path(final).absolute()
    with output_lock(final):
        _check_replaceable(final)
        whole = _parent_writable(final)
        where = final.parent if whole else final
        prefix = f".{final.name}.staging-" if whole else ".staging-"
        tmp = Path(tempfile.mkdtemp(prefix=prefix, dir=where))
        try:
            yield tmp
            (tmp / MARKER).write_text("written by millpath; the folder is replaced as a "
                                      "whole by the next run\n")
            tmp.chmod(0o777 & ~_umask())
            if whole:
                _switch(tmp, final)
            else:
                _switch_files(tmp, final)
        except OSError as e:             # a full disk: name the output, not the staging
            raise _named(e, tmp, final) from None
        finally:
            if tmp.exists():
                shutil.rmtree(tmp, ignore_errors=True)


def _switch(tmp: Path, final: Path) -> None:
    if not final.exists():
        os.rename(tmp, final)
        return
    if _exchange(tmp, final):           # tmp now holds the previous output
        shutil.rmtree(tmp, ignore_errors=True)
        return
    backup = Path(tempfile.mkdtemp(prefix=f".{final.name}.backup-", dir=final.parent))
    os.rmdir(backup)
    os.rename(final, backup)
    try:
        os.rename(tmp, final)
    except BaseException:
        os.rename(backup, final)
        raise
    shutil.rmtree(backup, ignore_errors=True)


def _switch_files(tmp: Path, final: Path) -> None:
    """Fallback inside a read-only parent: old output files removed, new ones renamed in."""
    new = {f.name for f in tmp.iterdir()}
    for f in final.iterdir():
        if f.is_file() and not f.name.startswith(".") and f.name not in new:
            f.unlink()
    for f in sorted(tmp.iterdir(), key=lambda p: p.name == MARKER):
        os.replace(f, final / f.name)
