"""The comparison section of a report: a simulated channel against a measured signal
(:class:`jointgap.comparison.Comparison`): the aligned signals, their difference and
their spectra as plots, the error measures, the settings and the peak-to-peak table
per crank turn."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .encode import minmax_indices, rounded
from .tables import Table, key_value_table

if TYPE_CHECKING:
    from ..comparison import Comparison

__all__ = ["comparison_section"]


def _series(
    x: np.ndarray, y: np.ndarray, label: str, max_points: int, dash: bool = False
) -> dict[str, Any]:
    keep = minmax_indices(np.asarray(y), max_points)
    return {
        "label": label,
        "x": rounded(np.asarray(x)[keep], 9),
        "y": rounded(np.asarray(y)[keep]),
        "dash": dash,
    }


def _plot(
    id: str, title: str, xlabel: str, ylabel: str, series: list[dict[str, Any]], time: bool
) -> dict[str, Any]:
    return {
        "id": id,
        "title": title,
        "xlabel": xlabel,
        "ylabel": ylabel,
        "series": series,
        "markers": False,
        "time": time,
        "kind": "line",
    }


def comparison_section(cmp: Comparison, max_points: int = 20000) -> dict[str, Any]:
    """Plots and tables of a comparison with a measurement."""
    unit = cmp.unit or "-"
    label = f"{cmp.channel} [{unit}]"
    plots = [
        _plot(
            "comparison-signals",
            f"{cmp.channel}: simulated and measured '{cmp.measured_name}', aligned",
            "time [s] (simulation time)",
            label,
            [
                _series(cmp.time, cmp.simulated, "simulated", max_points),
                _series(cmp.time, cmp.measured, "measured", max_points),
            ],
            True,
        ),
        _plot(
            "comparison-difference",
            "difference, simulated - measured",
            "time [s] (simulation time)",
            label,
            [_series(cmp.time, cmp.difference, "difference", max_points)],
            True,
        ),
        _plot(
            "comparison-spectra",
            "amplitude spectra",
            "frequency [Hz]",
            f"amplitude [{unit}]",
            [
                _series(cmp.spectra.frequency, cmp.spectra.simulated, "simulated", max_points),
                _series(cmp.spectra.frequency, cmp.spectra.measured, "measured", max_points),
            ],
            False,
        ),
    ]
    d = cmp.to_dict()
    m = d["measures"]
    measures = key_value_table(
        "comparison-measures",
        "Error measures",
        [
            (f"max absolute error [{unit}]", m["max_abs"]),
            ("max error / measured peak [%]", m["max_percent"]),
            (f"RMS error [{unit}]", m["rms"]),
            ("NRMSE [%]", None if m["nrmse"] is None else 100.0 * m["nrmse"]),
            ("correlation", m["correlation"]),
            (
                f"spectral error (0..{cmp.spectra.f_max:g} Hz) [%]",
                None if m["spectral_error"] is None else 100.0 * m["spectral_error"],
            ),
            ("samples", m["samples"]),
        ],
    )
    how = "estimated" if cmp.lag_estimated else "given"
    settings = key_value_table(
        "comparison-settings",
        "Alignment and conditioning",
        [
            ("simulated channel", cmp.channel),
            ("measured signal", cmp.measured_name),
            ("lag [ms]", f"{1e3 * cmp.lag:.4f} ({how}; measured(t) = simulated(t - lag))"),
            ("low-pass [Hz]", cmp.lowpass if cmp.lowpass is not None else "none"),
            ("offset", "none" if cmp.offset is None else str(cmp.offset)),
            ("sample rate [Hz]", cmp.rate),
            ("interval [s]", f"{cmp.time[0]:.6g}..{cmp.time[-1]:.6g}"),
        ],
    )
    cycles = Table(
        "comparison-cycles",
        f"Peak-to-peak per crank turn ({cmp.crank or 'no crank channel'})",
        [
            "turn",
            "start [s]",
            "end [s]",
            f"simulated [{unit}]",
            f"measured [{unit}]",
            "difference [%]",
        ],
        [
            [c.cycle, c.start, c.end, c.simulated, c.measured, 100.0 * c.relative_difference]
            for c in cmp.cycles
        ],
        seek=1,
        note="" if cmp.cycles else "no complete crank turn in the compared interval",
    )
    return {
        "title": "Simulation against measurement",
        "note": cmp.report().splitlines()[0],
        "plots": plots,
        "tables": [t.to_dict() for t in (measures, settings, cycles)],
        "measures": m,
    }
