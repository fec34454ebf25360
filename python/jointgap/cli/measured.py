"""The measured-data commands of ``jointgap``: ``synthesize`` a record, ``compare`` a
simulation with it, ``identify`` contact parameters from it. Parsers and handlers; the
shared options and errors come from :mod:`jointgap.cli.shared`."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .shared import (
    EXIT_RUN_FAILED,
    _add_format_option,
    _add_run_options,
    _command,
    _fail,
    _interrupted,
    _load,
    _run_options,
    _save,
    _write_partial_table,
    _write_table_and_model,
)

__all__ = ["COMMANDS", "add_commands"]

_COMPARE_DESCRIPTION = """\
Compare a simulated channel with a measured signal (e.g. an accelerometer on the
slider): run the model, read the measured file, condition both (optional zero-phase
low-pass, offset removal), estimate the lag of the measurement (cross-correlation,
measured(t) = simulated(t - lag)) unless --lag is given, and print the error
measures on the aligned signals: max absolute error, max error as a percentage of the
measured peak, RMS, NRMSE, correlation, spectral error, peak-to-peak per crank turn
(definitions: docs/comparison.md). Writes OUT/comparison.json and the overlay figure
OUT/comparison.png|svg (aligned signals, their difference, their spectra), the run in
OUT/simulation/ and the measured signal as read (SI) in OUT/measured.csv, from which
'jointgap report OUT' draws the comparison; --report writes OUT/report.html at once.
"""

_IDENTIFY_DESCRIPTION = """\
Fit uncertain contact parameters to a measured signal: scan the bounds of each
--param (in parallel on all cores), refine from the best (bounded Brent for one
parameter, bounded Nelder-Mead for several) and minimise --measure between the
simulated --signal and the measurement (aligned as in 'jointgap compare').
--param joint.quantity=low:high[@start], quantity one of restitution (for ADAMS
IMPACT: the C_max that Eq. 10-11 give for it), c_max, d_max, damping, stiffness,
mu_s, mu_d, mu, viscous, clearance. Prints the trial table (as the paper's Table IV)
and the best values with their uncertainty; --write saves the fitted model. Ctrl-C
stops the runs on every thread, writes the trials that ended to --table, names the
best so far and exits with 130.
"""

_SYNTHESIZE_DESCRIPTION = """\
Turn a simulation into a synthetic measured record, e.g. an accelerometer on the
slider: run the model to --t-end, sampled at --rate (default 50 kHz: well above the
record's rate, since the record interpolates the run linearly and would flatten the
impact peaks of a coarser one), then sample --signal at --sample-rate (default 5 kHz)
on the record's clock t = k / sample-rate, with a lag (--lag, default 0.01 s;
measured(t) = simulated(t - lag), so the record covers t = lag .. t_end), an optional
band limit (--band-limit: a zero-phase 4th-order Butterworth low-pass applied before
sampling), Gaussian noise (--noise, a standard deviation in the signal's unit) and an
offset. Writes FILE.csv (time and the signal, their units in a comment line; the
folder is created) that 'jointgap compare' and 'identify' read.
"""


def add_commands(sub: Any) -> None:
    """Adds compare, identify and synthesize to the ``jointgap`` subcommands."""
    compare = _command(
        sub,
        "compare",
        "compare a simulated channel with a measured signal: lag, error measures, figure",
        _COMPARE_DESCRIPTION,
    )
    _add_measured_options(compare)
    compare.add_argument("--out", metavar="DIR", help="output folder (default out/compare)")
    compare.add_argument(
        "--report",
        action="store_true",
        help="also write OUT/report.html: the simulation's animation and plots with the "
        "aligned signals, their difference and spectra (see 'jointgap report --help')",
    )
    compare.add_argument(
        "--crank-column",
        metavar="NAME|INDEX",
        help="a column of the measured file with the crank angle (--crank-unit rad or deg) "
        "or speed (rad/s or rpm): also compare on crank angle, which removes a lag and a "
        "speed drift alike",
    )
    compare.add_argument(
        "--crank-unit", default="rad", metavar="UNIT", help="unit of --crank-column (default rad)"
    )
    _add_format_option(compare)
    _add_run_options(compare, rate_default="10000", t_end_required=False)

    identify = _command(
        sub,
        "identify",
        "fit contact parameters (restitution, C_max, friction...) to a measured signal",
        _IDENTIFY_DESCRIPTION,
    )
    _add_measured_options(identify)
    identify.add_argument(
        "--param",
        action="append",
        required=True,
        dest="params",
        metavar="JOINT.Q=LOW:HIGH[@START]",
        help="a parameter to fit with its bounds (repeatable)",
    )
    identify.add_argument(
        "--measure",
        choices=("nrmse", "rms", "max_abs", "max_percent"),
        default="nrmse",
        help="error measure to minimise (default %(default)s)",
    )
    identify.add_argument(
        "--scan", type=int, metavar="N", help="scan points per parameter (default 16, or 6 each)"
    )
    identify.add_argument(
        "--max-evaluations",
        type=int,
        metavar="N",
        help="most trials of the refinement after the scan (default 60); a long record "
        "costs a run per trial",
    )
    identify.add_argument(
        "--workers", type=int, metavar="N", help="parallel runs (default: the number of cores)"
    )
    identify.add_argument(
        "--write",
        metavar="OUT.toml",
        help="save the fitted model: MODEL with the fitted values in its units, comments kept",
    )
    identify.add_argument("--table", metavar="TABLE.csv", help="save the trial table as CSV")
    _add_run_options(identify, rate_default="10000", t_end_required=False)

    synthesize = _command(
        sub,
        "synthesize",
        "make a synthetic measured record (e.g. an accelerometer) from a simulation",
        _SYNTHESIZE_DESCRIPTION,
    )
    synthesize.add_argument("--signal", required=True, metavar="CHANNEL", help="e.g. slider.ax")
    synthesize.add_argument("--out", required=True, metavar="FILE.csv", help="record to write")
    synthesize.add_argument("--sample-rate", default="5000", metavar="HZ", help="default 5000")
    synthesize.add_argument("--lag", default="0.01", metavar="S", help="default 0.01 s")
    synthesize.add_argument(
        "--noise", default="0", metavar="SD", help="noise standard deviation (SI or with unit)"
    )
    synthesize.add_argument("--offset", default="0", metavar="X", help="constant offset")
    synthesize.add_argument("--band-limit", metavar="HZ", help="low-pass cut-off [Hz]")
    synthesize.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    _add_run_options(synthesize, rate_default="50000")


def _add_measured_options(parser: argparse.ArgumentParser) -> None:
    """Which measured file and column, how to condition and align it."""
    parser.add_argument("--measured", required=True, metavar="FILE", help="CSV or text file")
    parser.add_argument(
        "--signal", required=True, metavar="CHANNEL", help="simulated channel, e.g. slider.ax"
    )
    parser.add_argument(
        "--column", metavar="NAME|INDEX", help="measured column (default: the --signal name)"
    )
    parser.add_argument(
        "--time-column", default="time", metavar="NAME|INDEX", help="default 'time'"
    )
    parser.add_argument(
        "--sample-rate", metavar="HZ", help="the file has no time column: sampled at this rate"
    )
    parser.add_argument(
        "--unit", metavar="UNIT", help="unit of the measured column, e.g. g, m/s^2, mm"
    )
    parser.add_argument("--lag", metavar="S", help="the measurement's lag [s]; default: estimated")
    parser.add_argument(
        "--max-lag", default="0.05", metavar="S", help="lag search range, +/- (default 0.05 s)"
    )
    parser.add_argument(
        "--lowpass", metavar="HZ", help="zero-phase low-pass cut-off applied to both signals"
    )
    parser.add_argument(
        "--offset",
        default="mean",
        metavar="mean|none|X",
        help="remove each signal's mean (default), nothing, or X from the measurement",
    )
    parser.add_argument("--spectrum-max", metavar="HZ", help="highest frequency of the spectra")


def _measured(args: argparse.Namespace, column: str | None = None, unit: str | None = None) -> Any:
    from ..measured import read_measured

    def index_or_name(text: str | None) -> str | int | None:
        return int(text) if text is not None and text.isdigit() else text

    rate = args.sample_rate
    chosen = index_or_name(column if column is not None else args.column)
    return read_measured(
        args.measured,
        chosen if chosen is not None else str(args.signal),
        time_column=None if rate is not None else index_or_name(args.time_column),
        rate=rate,
        unit=unit if unit is not None else args.unit,
    )


def _compare_options(args: argparse.Namespace) -> dict[str, Any]:
    from .. import units as u

    def hz(text: str | None) -> float | None:
        return None if text is None else u.to_si(text, u.FREQUENCY)

    offset: str | float | None = args.offset
    if args.offset == "none":
        offset = None
    elif args.offset != "mean":
        offset = float(args.offset)
    return {
        "lag": None if args.lag is None else u.to_si(args.lag, u.TIME),
        "max_lag": u.to_si(args.max_lag, u.TIME),
        "lowpass": hz(args.lowpass),
        "offset": offset,
        "spectrum_max": hz(args.spectrum_max),
    }


def _simulated_span(args: argparse.Namespace, measured: Any) -> float:
    """--t-end, or the end of the measurement (a late measurement, the usual case, needs
    no more simulated time than that)."""
    from .. import units as u

    if args.t_end is not None:
        return u.to_si(args.t_end, u.TIME)
    return float(measured.time[-1])


def _compare(args: argparse.Namespace) -> int:
    import json

    from ..comparison import compare
    from ..plots import comparison_figure, save_figures
    from ..report import COMPARISON_JSON, MEASURED_CSV, SIMULATION_DIR
    from ..results import model_channels, require_channel
    from .progress import progress_line

    model = _load(args.model)
    try:  # before the run, not after it
        require_channel(model_channels(model.to_dict()), args.signal)
    except KeyError as exc:
        return _fail(f"--signal {args.signal}: {exc.args[0]}")
    measured = _measured(args)
    span = _simulated_span(args, measured)
    with progress_line(span) as progress:
        result = model.simulate(span, progress=progress, **_run_options(args))
    out = Path(args.out or "out/compare")
    if result.interrupted:
        _save(result, out / SIMULATION_DIR)
        return _interrupted(
            f"the run {result.message}: nothing compared; the simulation up to there is in "
            f"{out / SIMULATION_DIR}"
        )
    if not result.ok:
        return _fail(f"{args.model}: the run {result.message}", EXIT_RUN_FAILED)
    comparison = compare(result, measured, args.signal, **_compare_options(args))
    out.mkdir(parents=True, exist_ok=True)
    (out / COMPARISON_JSON).write_text(json.dumps(comparison.to_dict(), indent=2) + "\n")
    # The simulation (a line shows the writing of a long one) and the signal as read (SI)
    # beside it: 'jointgap report OUT' redraws the comparison from them.
    _save(result, out / SIMULATION_DIR)
    measured.to_csv(out / MEASURED_CSV)
    paths = save_figures({"comparison": comparison_figure(comparison)}, out, args.formats)
    if args.report:
        from ..report import write_run_report
        from .report import REPORT_HTML

        paths.append(write_run_report(result, out / REPORT_HTML, comparison=comparison))
    print(comparison.report())
    if args.crank_column is not None:
        print(_angle_report(args, result, measured))
    written = [out / COMPARISON_JSON, out / SIMULATION_DIR, out / MEASURED_CSV, *paths]
    print("written    " + ", ".join(str(p) for p in written))
    return 0


def _angle_report(args: argparse.Namespace, result: Any, measured: Any) -> str:
    """The error measures with both signals put on the crank angle."""
    from .. import units as u
    from ..comparison import align_on_angle, error_measures
    from ..measured import MeasuredSignal

    crank = _measured(args, column=args.crank_column, unit=args.crank_unit)
    # read_measured gave SI values; an angle or a speed, as the unit's dimension says.
    _, dim = u.to_si_with_dimension(f"1 {args.crank_unit}", (u.ANGLE, u.ANGULAR_SPEED))
    unit = "rad/s" if dim == u.ANGULAR_SPEED else "rad"
    signal = MeasuredSignal(crank.time, crank.values, crank.name, unit, crank.source)
    aligned = align_on_angle(result, measured, args.signal, signal)
    m = error_measures(aligned.simulated, aligned.measured)
    return (
        f"on crank angle ({aligned.crank}, {len(aligned.angle)} points, "
        f"{aligned.angle[0]:.3f}..{aligned.angle[-1]:.3f} rad): max error {m.max_percent:.2f} % "
        f"of the measured peak, NRMSE {100 * m.nrmse:.2f} %, correlation {m.correlation:.4f}"
    )


def _identify(args: argparse.Namespace) -> int:
    import math
    import threading

    from ..identify import Parameter, Trial, identify, trial_frame
    from .progress import progress_line

    model = _load(args.model)
    measured = _measured(args)
    parameters = [Parameter.parse(p) for p in args.params]
    done: list[Trial] = []
    lock = threading.Lock()
    span = _simulated_span(args, measured)
    fit = None  # until it ends: Ctrl-C leaves the trials so far
    budget = args.max_evaluations
    refinement = {} if budget is None else {"max_evaluations": budget}
    with progress_line(span, "trials: 0 done; ") as line:

        def finished(trial: Trial) -> None:  # from the worker threads too
            with lock:
                done.append(trial)
                best = min(t.error for t in done)
            if line is not None:
                line.label = f"trials: {len(done)} done, best {args.measure} {best:.5g}; "

        try:
            fit = identify(
                model,
                measured,
                args.signal,
                parameters,
                t_end=span,
                measure=args.measure,
                scan=args.scan,
                workers=args.workers,
                **refinement,
                compare_options=_compare_options(args),
                progress=finished,
                run_progress=line,
                **_run_options(args),
            )
        except KeyError as exc:  # --signal is not an output of the model
            return _fail(f"--signal {args.signal}: {exc.args[0]}")
        except KeyboardInterrupt:
            pass
    if fit is None:
        with lock:
            trials = sorted(done, key=lambda t: t.trial)
        kept = _write_partial_table(args, trial_frame(parameters, args.measure, trials))
        scored = [t for t in trials if math.isfinite(t.error)]
        best = ""
        if scored:
            top = min(scored, key=lambda t: t.error)
            values = ", ".join(
                f"{p.name} = {v:.6g}" for p, v in zip(parameters, top.values, strict=True)
            )
            best = f" (best so far trial {top.trial}: {values}, {args.measure} {top.error:.5g})"
        return _interrupted(f"the fit stopped after {len(trials)} trials{best}{kept}")
    print(fit.table())
    _write_table_and_model(args, fit.to_frame(), fit.model)
    return 0


def _synthesize(args: argparse.Namespace) -> int:
    from ..measured import synthetic_record
    from .progress import progress_line

    model = _load(args.model)
    # The record needs its signal alone: recording it only keeps a long run small.
    with progress_line(args.t_end) as progress:
        result = model.simulate(
            args.t_end, channels=[args.signal], progress=progress, **_run_options(args)
        )
    if result.interrupted:
        return _interrupted(f"the run {result.message}: no record written ({args.out})")
    if not result.ok:
        return _fail(f"{args.model}: the run {result.message}", EXIT_RUN_FAILED)
    record = synthetic_record(
        result,
        args.signal,
        rate=args.sample_rate,
        lag=args.lag,
        noise=args.noise,
        offset=args.offset,
        band_limit=args.band_limit,
        seed=args.seed,
    )
    record.to_csv(args.out)
    print(
        f"{record.name}: {len(record)} samples at {record.rate:g} Hz, t = "
        f"{record.time[0]:g}..{record.time[-1]:g} s ({record.source})"
    )
    print(f"written    {args.out}")
    return 0


COMMANDS: dict[str, Callable[[argparse.Namespace], int]] = {
    "compare": _compare,
    "identify": _identify,
    "synthesize": _synthesize,
}
