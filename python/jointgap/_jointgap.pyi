"""Type stubs of the compiled engine (crates/jointgap-py): JSON in, NumPy arrays out."""

import numpy as np
import numpy.typing as npt

def check_model(model_json: str) -> list[str]:
    """Checks a model (JSON, SI units, radians) and returns its warnings.

    Raises ValueError naming the offending element: ``<kind> '<name>': <problem>``.
    """

def clearance_data(model_json: str) -> str:
    """Each clearance joint's resolved contact data as a JSON list of ``{"joint",
    "bearing_radius", "journal_radius", "clearance", "stiffness", "exponent"}`` (SI).

    Raises ValueError naming the offending element.
    """

def simulate(
    model_json: str, options_json: str
) -> tuple[npt.NDArray[np.float64], list[str], npt.NDArray[np.float64], str]:
    """Runs a simulation with the GIL released.

    Returns ``(time, names, data[n_channels, n_samples], summary_json)``; the summary
    holds ``stats``, ``status`` (``{"status": "finished"}`` or ``{"status": "failed",
    "time": t, "reason": ...}``), ``warnings``, ``impacts`` (per clearance joint) and
    ``clearances`` (as :func:`clearance_data`). Raises ValueError for an invalid model
    or invalid options.
    """

def simulate_batch(
    models_json: list[str], options_json: str, threads: int | None = None
) -> list[
    tuple[
        tuple[npt.NDArray[np.float64], list[str], npt.NDArray[np.float64], str] | None,
        str | None,
    ]
]:
    """Runs many models with the same options on ``threads`` threads (all cores by
    default), the GIL released. Returns, in order, ``(arrays, None)`` as :func:`simulate`
    gives them or ``(None, message)`` for a model that could not run."""
