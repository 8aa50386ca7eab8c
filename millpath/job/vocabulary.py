"""One vocabulary: the job keys that were renamed so that the same idea has the same
name in every operation (``stepdown``, ``stepover``, ``allowance``, ``safe_z``, ``feed``,
``plunge_feed``, ``tolerance``, ...).

An old name is still accepted, with a one-line deprecation warning naming the new key;
giving both the old and the new name is an error naming both.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from millpath.errors import JobError, warn

#: operation type -> {old key: new key}
RENAMED: dict[str, dict[str, str]] = {
    "die-cavity": {"step_down": "stepdown"},
    "features": {"step_down": "stepdown", "finish_allowance": "allowance"},
    "grid-pocket": {"step": "stepdown"},
    "pocket": {"finish_allowance": "allowance"},
    "surface-rough": {"step_over": "stepover"},
}


def renamed(op_type: str, body: dict[str, Any], index: int,
            file: str | Path | None) -> dict[str, Any]:
    """``body`` (one [[operations]] table without ``type``) with old key names replaced
    by the new ones; warns once per old name; JobError when both names are given.
    ``index`` is the operation's place in the file (0-based, printed 1-based)."""
    table = RENAMED.get(op_type, {})
    out = dict(body)
    for old, new in table.items():
        if old not in out:
            continue
        if new in out:
            raise JobError(f"operations[{index}]: '{old}' and '{new}' are the same key "
                           f"('{old}' is the deprecated name); give only '{new}'", file)
        warn(f"[operation {index + 1}] '{old}' is deprecated; use '{new}'", file)
        out[new] = out.pop(old)
    return out
