"""What a wear prediction returns (:func:`jointgap.wear.predict_wear`): its updates as
``progress`` sees them and the whole prediction, apart from the loop so that its figures
and report page read it without importing the loop."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd  # type: ignore[import-untyped]

__all__ = ["HISTORY_COLUMNS", "WearPrediction", "WearStep"]

HISTORY_COLUMNS = (
    "cycles",
    "joint",
    "max_bearing_depth",
    "max_journal_depth",
    "bearing_volume",
    "journal_volume",
    "clearance",
    "peak_contact_force",
    "peak_watch",
)
"""The columns of :attr:`WearPrediction.history` (SI: m, m^3, N; ``peak_watch`` in the
watched channel's unit)."""


@dataclass(frozen=True)
class WearStep:
    """One accepted update, as ``progress`` sees it."""

    cycles: float
    """Cycles worn so far."""
    step: float
    """Cycles of the update just accepted."""
    clearance: float
    """The largest effective clearance of the joints [m]."""
    runs: int
    """Simulations run so far."""


@dataclass
class WearPrediction:
    """What :func:`predict_wear` found.

    Attributes:
        coefficient: the wear coefficient k [1/Pa] and the pair it came from (``None``
            for a value given).
        cycles: cycles worn.
        status: ``"finished"`` (the cycles asked), ``"limit"`` (a joint reached the
            clearance limit), ``"out_of_range"`` (a run on the worn profiles, even
            after the shortest update, took more than ``STEP_BUDGET`` times the unworn
            run's steps), ``"interrupted"`` or
            ``"failed"``; ``message`` says more.
        cycles_to_limit: the cycles at which the clearance limit was reached (by linear
            interpolation within the last update), or ``None``.
        history: one row per joint per evaluated profile (:data:`HISTORY_COLUMNS`).
        profiles: per joint, the profiles after each accepted update: a list of
            ``(cycles, bearing_wear, journal_wear)``, the depths [m] on the grid.
        angles: the grid's angles [rad] (cell centres, each part's body frame).
        runs: simulations run.
    """

    coefficient: float
    pair: str | None
    cycles: float
    status: str
    message: str
    cycles_to_limit: float | None
    history: pd.DataFrame
    profiles: dict[str, list[tuple[float, np.ndarray, np.ndarray]]]
    angles: np.ndarray
    runs: int
    watch: str | None = None
    nominal: dict[str, dict[str, float]] = field(default_factory=dict)
