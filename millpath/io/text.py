"""Reading a user's text file (job, points, measured grid) with one-line errors."""

from __future__ import annotations

from pathlib import Path

from millpath.errors import MillpathError


def read_text(path: str | Path, what: str, error: type[MillpathError] = MillpathError) -> str:
    """The UTF-8 text of ``path``; ``error`` (naming the file) when it is missing, a
    folder or not UTF-8. ``what`` names the file's role in messages ("points file")."""
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"no such {what}", p) from None
    except IsADirectoryError:
        raise error(f"is a folder, not a {what}", p) from None
    except UnicodeDecodeError:
        raise error(f"{what} is not UTF-8 text", p) from None
