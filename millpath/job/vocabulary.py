"""One vocabulary: the job keys that were renamed so that the same idea has the same
name in every operation (``stepdown``, ``stepover``, ``allowance``).

An old name means its new name in every operation type: it is accepted, with a
one-line deprecation warning naming the new key, wherever the new key is, and refused
naming the new key where the type does not take the new key either. Giving both the
old and the new name is an error naming both. An old name that is itself a key of an
operation type keeps that meaning there (``features``' ``step`` is its STEP file).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from millpath.errors import JobError, Problems, warn

#: old key -> new key, for every operation type
RENAMED: dict[str, str] = {
    "step_down": "stepdown",
    "step_over": "stepover",
    "finish_allowance": "allowance",
    "step": "stepdown",
}


def renamed(op_type: str, schema: dict[str, Any], body: dict[str, Any], index: int,
            file: str | Path | None, problems: Problems) -> dict[str, Any]:
    """``body`` (one [[operations]] table without ``type``, of a type with keys
    ``schema``) with old key names replaced by the new ones; warns once per old name.
    An old name whose new key the type does not take, or given beside its new name, is
    recorded in ``problems`` and left out. ``index`` is the operation's place in the
    file (0-based, printed 1-based)."""
    where = f"operations[{index}]"
    out = dict(body)
    for old, new in RENAMED.items():
        if old not in out or old in schema:
            continue
        value = out.pop(old)
        if new not in schema:
            problems.add(JobError(f"{where}.{old}: '{old}' is now '{new}', which {op_type} "
                                  f"operations do not take", file))
        elif new in out:
            problems.add(JobError(f"{where}.{old}: '{old}' and '{new}' are the same key "
                                  f"('{old}' is the deprecated name); give only '{new}'",
                                  file))
        else:
            warn(f"[operation {index + 1}] '{old}' is deprecated; use '{new}'", file)
            out[new] = value
    return out
