"""view.html: one self-contained page, no network.

The page is ``template.html`` with the style sheet, the viewer script, the scene data
and three.js inlined. three.js's ES modules (``vendor/``, unchanged) are reached through
an import map of ``data:`` URLs, so the page loads nothing but itself: no CDN, no
external script, style sheet or font. The scene data is a JSON block whose typed arrays
are base64 (little-endian) strings; every ``/`` in it is written ``\\/`` and every
``<`` as ``\\u003c`` (same JSON values), so no text of the program (a comment holding
``</script>`` or ``<!--``) can end or change the block.
"""

from __future__ import annotations

import base64
import html
import json
import re
from functools import lru_cache
from importlib import resources
from typing import Any

THREE_VERSION = "0.185.0"
_CORE_IMPORT = '"./three.core.min.js"'


def _asset(name: str) -> str:
    return (resources.files("millpath.report.viewer") / name).read_text(encoding="utf-8")


def _data_url(js: str) -> str:
    return "data:text/javascript;base64," + base64.b64encode(js.encode("utf-8")).decode("ascii")


@lru_cache(maxsize=1)
def import_map() -> str:
    """The import map: ``three``, ``three/core`` and ``three/addons/OrbitControls`` as
    ``data:`` URLs of the vendored modules."""
    core = _asset("vendor/three.core.min.js")
    module = _asset("vendor/three.module.min.js")
    if _CORE_IMPORT not in module:
        raise RuntimeError("vendored three.module.min.js does not import three.core.min.js")
    module = module.replace(_CORE_IMPORT, '"three/core"')
    orbit = _asset("vendor/OrbitControls.js")
    return json.dumps({"imports": {
        "three": _data_url(module),
        "three/core": _data_url(core),
        "three/addons/OrbitControls": _data_url(orbit),
    }})


def b64(a) -> str:
    """Base64 of a numpy array's bytes, in the array's own byte order."""
    return base64.b64encode(a.tobytes()).decode("ascii")


def render_page(data: dict[str, Any], *, title: str, units: str, version: str) -> str:
    """The HTML text of a viewer page showing ``data`` (see :mod:`.scene`)."""
    parts = {
        "TITLE": html.escape(title),
        "UNITS": html.escape(units),
        "VERSION": html.escape(version),
        "THREE_VERSION": THREE_VERSION,
        "STYLE": _asset("viewer.css"),
        "IMPORTMAP": import_map(),
        "DATA": json.dumps(data, separators=(",", ":"), allow_nan=False)
        .replace("/", "\\/").replace("<", "\\u003c"),
        "APP": _asset("viewer.js"),
    }
    return re.sub(r"\{\{([A-Z_]+)\}\}", lambda m: parts[m.group(1)], _asset("template.html"))
