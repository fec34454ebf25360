"""One self-contained HTML file: the page template with the style sheet, the scripts
(package data in ``assets/``) and the report's data (JSON) inlined, so that it opens
offline in any browser and asks the network for nothing."""

from __future__ import annotations

import html
import json
import re
from importlib import resources
from os import PathLike
from pathlib import Path
from typing import Any

from .encode import strict

__all__ = ["ASSETS", "plotly_script", "render", "write"]

ASSETS = ("report.css", "plot.js", "report.js")
"""The inlined files of ``jointgap/report/assets``, in page order."""
_TEMPLATE = "report.html"


def _asset(name: str) -> str:
    return resources.files(__package__).joinpath("assets", name).read_text(encoding="utf-8")


def _json_for_script(data: Any) -> str:
    """JSON that cannot end its ``<script>`` element early: ``<``, ``>`` and ``&``
    escaped as ``\\u003c``... (still valid JSON)."""
    text = json.dumps(strict(data), separators=(",", ":"), allow_nan=False, ensure_ascii=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def plotly_script() -> str:
    """plotly.js as its Python wheel ships it (``plotly/package_data/plotly.min.js``):
    the 3D view of a spatial run draws with it, inlined so that the page needs no
    network."""
    path = resources.files("plotly").joinpath("package_data", "plotly.min.js")
    return path.read_text(encoding="utf-8")


def render(data: dict[str, Any]) -> str:
    """The page as text: ``data`` (see :mod:`jointgap.report`) with its ``title``;
    with plotly.js inlined when it holds a spatial run (``data["run"]["spatial"]``)."""
    page = _asset(_TEMPLATE)
    css, plot_js, report_js = (_asset(name) for name in ASSETS)
    run = data.get("run") or {}
    plotly_js = plotly_script() if run.get("spatial") else ""
    for script in (plot_js, report_js, plotly_js):
        if "</script" in script.lower():
            raise RuntimeError("an inlined script contains '</script'")
    parts = {
        "plotly_js": f"<script>\n{plotly_js}\n</script>" if plotly_js else "",
        "title": html.escape(str(data.get("title", "jointgap report"))),
        "generator": html.escape(str(data.get("generator", "jointgap"))),
        "css": css,
        "plot_js": plot_js,
        "report_js": report_js,
        "data": _json_for_script(data),
    }
    # One pass over the template only: inlined text is never searched for placeholders.
    return re.sub(r"\{\{(\w+)\}\}", lambda m: parts[m.group(1)], page)


def write(data: dict[str, Any], path: str | PathLike[str]) -> Path:
    """Writes :func:`render` of ``data`` to ``path`` (its folder created)."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(render(data), encoding="utf-8")
    return out
