"""Type stubs of the compiled engine (crates/jointgap-py): JSON in, NumPy arrays out."""

from collections.abc import Callable

import numpy as np
import numpy.typing as npt

__all__ = [
    "EngineError",
    "channel_counts",
    "channel_names",
    "check_model",
    "clearance_data",
    "compilations",
    "defaults",
    "simulate",
    "simulate_batch",
]

class EngineError(ValueError):
    """An error of the engine: the message names the offending element, ``<kind>
    '<element>': <problem>``, and the attributes hold its parts."""

    category: str
    """``model``, ``assembly`` or ``options``."""
    kind: str | None
    """The element's kind (body, joint, driver, force, marker); None for the model as a
    whole or the options."""
    element: str | None
    """The element's name."""
    key: str | None
    """The offending key as the model file writes it, dotted for a nested one
    (``normal_law.restitution``), or the option's name; None where no one key is at
    fault."""
    problem: str
    """What is wrong, without the element."""

def defaults() -> str:
    """The engine's defaults as JSON: ``gravity`` [m/s^2], ``normal_law`` (``exponent``,
    ``clip``) and ``options`` (every run option but ``t_end``)."""

def compilations() -> int:
    """How many models this process has compiled. The engine keeps the models it
    prepared last, keyed by their JSON text: checking a model and then running it (or
    estimating its output) compiles it once."""

def check_model(model_json: str) -> list[str]:
    """Checks a model (JSON, SI units, radians) as far as a run goes before its first
    step (assembled, every channel evaluated at t = 0) and returns its warnings; the
    prepared model is kept for its run.

    Raises EngineError naming the offending element: ``<kind> '<name>': <problem>``.
    """

def clearance_data(model_json: str) -> str:
    """Each clearance joint as the engine resolves it, without a run, as a JSON list of
    ``{"joint", "bearing_radius", "journal_radius", "clearance", "stiffness",
    "exponent", "d_max", "normal_law", "friction"}`` (SI): ``d_max`` that of an
    adams_impact law, given or the bearing material's (null for the other laws), and the
    two laws in force with every default filled in.

    Raises EngineError naming the offending element.
    """

def channel_names(model_json: str, options_json: str | None = None) -> list[str]:
    """The channels a run records, in result order, without running it: with options,
    those a run with them records (the model prepared and kept for its run, so one that
    does not assemble raises too); without, every channel of the model (model order).
    Raises EngineError naming the offending element, or for unknown channels."""

def channel_counts(models_json: list[str], options_json: str) -> list[int | None]:
    """How many channels a run of each model with the options records (as
    :func:`channel_names`), None for a model the engine refuses: a batch's estimate of its
    output size. Every model is prepared and kept for the batch's run, however many."""

def simulate(
    model_json: str,
    options_json: str,
    progress: Callable[[float, int, int], object] | None = None,
    sink: Callable[[list[str], npt.NDArray[np.float64], npt.NDArray[np.float64]], object]
    | None = None,
    chunk: int = 8192,
    interval: float = 0.2,
) -> tuple[npt.NDArray[np.float64], list[str], npt.NDArray[np.float64], str]:
    """Runs a simulation with the GIL released.

    ``progress(t, steps, impacts)`` is called about every ``interval`` seconds of wall
    time (0: at every check, every 16 accepted steps), and Ctrl-C is checked as often;
    with ``sink``, the samples go to ``sink(names, time, data)`` in chunks of ``chunk``
    samples and the returned arrays hold none of them. Ctrl-C (or a KeyboardInterrupt
    raised by either callable) ends the run with status interrupted and what it
    computed; any other exception raised by either callable stops the run and is
    raised again here.

    Returns ``(time, names, data[n_channels, n_samples], summary_json)``; the summary
    holds ``stats``, ``status`` (``{"status": "finished"}``, ``{"status": "failed",
    "time": t, "reason": ...}`` or ``{"status": "interrupted", "time": t}``),
    ``warnings``, ``impacts`` (per clearance joint), ``clearances`` (per clearance joint,
    the first six keys of :func:`clearance_data`), ``peaks`` (per channel, the largest
    absolute value over the samples, and every step with ``step_peaks``) and ``samples``
    (for an ``every_step`` run with a rate: the indices of the output samples among the
    records; else null).
    Raises EngineError for an invalid model or invalid options.
    """

def simulate_batch(
    models_json: list[str],
    options_json: str,
    threads: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    interval: float = 0.2,
) -> tuple[
    list[
        tuple[
            tuple[npt.NDArray[np.float64], list[str], npt.NDArray[np.float64], str] | None,
            EngineError | None,
        ]
    ],
    bool,
]:
    """Runs many models with the same options on ``threads`` threads (all cores by
    default), the GIL released while they run.

    The calling thread checks Ctrl-C and calls ``progress(running, ended)`` (runs going,
    runs ended) every ``interval`` seconds of wall time and once at the end. Ctrl-C (or
    a KeyboardInterrupt raised by ``progress``) stops the batch: the runs going end with
    status interrupted and what they computed, the models not started do not run. Any
    other exception of ``progress`` stops the batch in the same way and is raised again
    here. A model this process holds prepared (its output size just estimated with
    :func:`channel_names`) runs without being compiled again.

    Returns ``(slots, interrupted)``: in order, ``(arrays, None)`` as :func:`simulate`
    gives them, ``(None, error)`` for a model that could not run or ``(None, None)``
    for one not started; and whether the batch was stopped."""
