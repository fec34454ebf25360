"""The study section of a report, from a study folder (``jointgap study``):

    DIR/study.json        {"name", "base_model", "parameters": [{"path", "kind", ...}],
                          "metrics": [...], "sampling", "n_cases"}
    DIR/cases.csv         one row per case: case, one column per parameter (named by
    (or cases.parquet)    its path), one per metric, status, reason, run_time_s; headers
                          "name [unit]" (or the bare name, as older tables have them)
    DIR/figures/*.png     the study's figures ('jointgap study-plot'), if any

The page shows the study's settings, every metric against every parameter (finished
cases, hover for the case), the sortable table of cases (failed ones marked) and the
figures, inlined.
"""

from __future__ import annotations

import base64
import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import ReportError
from ..study.store import column_name
from .encode import rounded
from .tables import Table, key_value_table

__all__ = [
    "STUDY_JSON",
    "CASES_CSV",
    "CASES_PARQUET",
    "FIGURES_DIR",
    "MAX_STUDY_PLOTS",
    "study_section",
]

STUDY_JSON = "study.json"
CASES_CSV = "cases.csv"
CASES_PARQUET = "cases.parquet"
FIGURES_DIR = "figures"
MAX_STUDY_PLOTS = 12
"""Most metric-against-parameter plots (metrics first, then parameters, in order)."""
_FIXED = ("case", "status", "reason", "run_time_s")


def _name(entry: Any, what: str, folder: Path) -> str:
    if isinstance(entry, str):
        return entry
    if isinstance(entry, Mapping):
        for key in ("path", "name"):
            if key in entry:
                return str(entry[key])
    raise ReportError(f"{folder / STUDY_JSON}: a {what} entry {entry!r} has no 'path' or 'name'")


def _read_cases(folder: Path) -> Any:
    import pandas as pd  # type: ignore[import-untyped]

    csv, parquet = folder / CASES_CSV, folder / CASES_PARQUET
    if csv.exists():
        return pd.read_csv(csv).rename(columns=column_name)
    if parquet.exists():
        return pd.read_parquet(parquet).rename(columns=column_name)
    raise ReportError(f"{folder}: a study folder needs {CASES_CSV} or {CASES_PARQUET}")


def _cell(v: Any) -> Any:
    if isinstance(v, float):
        return v if math.isfinite(v) else None
    if hasattr(v, "item"):
        return _cell(v.item())
    if v is None:
        return None
    return v if isinstance(v, (int, str)) else str(v)


def study_section(folder: str | Path) -> dict[str, Any]:
    """Tables, plots and figures of a study folder.

    Raises:
        ReportError: study.json unreadable or without a needed key, no cases table, a
            parameter or metric that the cases table lacks.
    """
    folder = Path(folder)
    try:
        info = json.loads((folder / STUDY_JSON).read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise ReportError(f"{folder / STUDY_JSON}: not JSON ({exc})") from None
    if not isinstance(info, Mapping):
        raise ReportError(f"{folder / STUDY_JSON}: expected an object, not {type(info).__name__}")
    for key in ("parameters", "metrics"):
        if not isinstance(info.get(key), list):
            raise ReportError(f"{folder / STUDY_JSON}: '{key}' must be a list")
    parameters = [_name(p, "parameter", folder) for p in info["parameters"]]
    metrics = [_name(m, "metric", folder) for m in info["metrics"]]
    cases = _read_cases(folder)
    source = CASES_CSV if (folder / CASES_CSV).exists() else CASES_PARQUET
    missing = [c for c in [*parameters, *metrics, "status"] if c not in cases.columns]
    if missing:
        raise ReportError(
            f"{folder / source}: no column {', '.join(repr(c) for c in missing)} "
            f"(columns: {', '.join(map(str, cases.columns))})"
        )
    status = cases["status"].astype(str)
    finished = status == "finished"
    columns = [c for c in ("case",) if c in cases.columns] + parameters + metrics
    columns += [c for c in _FIXED[1:] if c in cases.columns]
    columns += [c for c in cases.columns if c not in columns]
    rows = [[_cell(v) for v in row] for row in cases[columns].itertuples(index=False, name=None)]
    given_units = info.get("units")
    units: Mapping[str, Any] = given_units if isinstance(given_units, Mapping) else {}

    def label(column: str) -> str:
        unit = units.get(column)
        return f"{column} [{unit}]" if unit else column

    table = Table(
        "cases",
        "Cases",
        [label(str(c)) for c in columns],
        rows,
        sortable=True,
        note=f"{len(rows)} cases: {int(finished.sum())} finished, {int((~finished).sum())} failed"
        "; click a heading to sort",
        row_classes=["" if ok else "failed" for ok in finished],
    )
    settings = key_value_table(
        "study",
        "Study",
        [
            ("name", info.get("name") or folder.name),
            ("base model", info.get("base_model")),
            ("sampling", _text(info.get("sampling"))),
            ("cases", info.get("n_cases", len(rows))),
            ("finished", int(finished.sum())),
            ("failed", int((~finished).sum())),
            ("metrics", ", ".join(metrics)),
        ],
    )
    params = Table(
        "study-parameters",
        "Parameters",
        ["path", "kind", "unit", "settings (SI)"],
        [
            [
                _name(p, "parameter", folder),
                str(p.get("kind", "")) if isinstance(p, Mapping) else "",
                str(p.get("unit", units.get(_name(p, "parameter", folder), "")))
                if isinstance(p, Mapping)
                else "",
                _text({k: v for k, v in p.items() if k not in ("path", "kind", "unit")})
                if isinstance(p, Mapping)
                else "",
            ]
            for p in info["parameters"]
        ],
    )
    plots: list[dict[str, Any]] = []
    done = cases[finished]
    for metric in metrics:
        for parameter in parameters:
            if len(plots) >= MAX_STUDY_PLOTS:
                break
            try:
                x = done[parameter].astype(float).to_numpy()
                y = done[metric].astype(float).to_numpy()
            except (TypeError, ValueError):
                continue  # a categorical parameter or metric: in the table only
            names = [f"case {_cell(c)}" for c in done["case"]] if "case" in done else None
            plots.append(
                {
                    "id": f"study-{metric}-{parameter}",
                    "title": f"{metric} against {parameter}",
                    "xlabel": label(parameter),
                    "ylabel": label(metric),
                    "kind": "scatter",
                    "time": False,
                    "markers": False,
                    "height": 230,
                    "series": [{"label": metric, "x": rounded(x), "y": rounded(y), "names": names}],
                }
            )
    figures = []
    figure_dir = folder / FIGURES_DIR
    if figure_dir.is_dir():
        for png in sorted(figure_dir.glob("*.png")):
            encoded = base64.b64encode(png.read_bytes()).decode("ascii")
            figures.append({"name": png.stem, "src": f"data:image/png;base64,{encoded}"})
    return {
        "name": str(info.get("name") or folder.name),
        "tables": [settings.to_dict(), params.to_dict()],
        "cases": table.to_dict(),
        "plots": plots,
        "figures": figures,
        "n_cases": len(rows),
        "n_failed": int((~finished).sum()),
    }


def _text(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, str):
        return value
    return json.dumps(value, separators=(", ", ": "))
