"""The ``jointgap`` command: check, run, plot, calibrate and converge model files.

    jointgap check examples/slider_crank_clearance.toml
    jointgap run examples/slider_crank_clearance.toml --t-end 0.5 --rate 10000 --out out \
        --ideal examples/slider_crank_ideal.toml --plot
    jointgap plot out
    jointgap calibrate examples/slider_crank_clearance.toml --restitution 0.55 --t-end 0.5
    jointgap converge examples/slider_crank_clearance.toml --t-end 0.5

Errors print one line on stderr and set the exit status: 1 invalid model, options or
file; 2 wrong command line; 3 the run stopped early (its results are still written);
4 not converged (converge, calibrate); 130 interrupted by Ctrl-C (what was computed up
to then is still written, the runs with status "interrupted"). The warnings of the
model and its runs (implausible magnitudes, impacts between output samples) are listed
by check and run, and printed on stderr by every other command when it ends, once each.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from ..errors import ModelError, RunWarning
from ..model import Model
from ..results import RESULTS_PARQUET, SUMMARY_JSON, Result, channel_unit, main_channels
from .progress import progress_line
from .shared import (
    _EPILOG,
    EXIT_INTERRUPTED,
    EXIT_NOT_CONVERGED,
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

__all__ = ["main", "build_parser"]

IDEAL_DIR = "ideal"
CONTACT_STATISTICS_CSV = "contact_statistics.csv"
DEVIATION_CSV = "deviation.csv"

_DESCRIPTION = """\
Planar multibody mechanisms with clearance joints: check, run, plot, calibrate,
check convergence, compare with measurements and identify contact parameters of
TOML model files (format: docs/model-file.md).

examples:
  jointgap check examples/slider_crank_clearance.toml
  jointgap run examples/slider_crank_clearance.toml --t-end 0.5 --rate 10000 --out out \\
      --ideal examples/slider_crank_ideal.toml --plot
  jointgap plot out
  jointgap calibrate examples/slider_crank_clearance.toml --restitution 0.55 --t-end 0.5
  jointgap converge examples/slider_crank_clearance.toml --t-end 0.5
"""

_RUN_DESCRIPTION = """\
Simulate a model from t = 0 to --t-end and write
  OUT/results.csv   first column time [s], then every channel <element>.<quantity>
                    (SI units) in model order
  OUT/summary.json  the model, the options, run statistics and status: the run can
                    be repeated from it
  OUT/impacts.csv   for a model with clearance joints: one row per impact (joint,
                    onset_time, onset_speed, peak_force, max_penetration, duration)
  OUT/contact_statistics.csv
                    per clearance joint: impacts, time fractions in free flight,
                    impact and continuous contact, peak force, max penetration,
                    mean and max onset speed
  OUT/ideal/        with --ideal: the same files for the ideal model, and
  OUT/deviation.csv how far the clearance run departs from it (RMS and peak
                    difference of the slider acceleration and the motor efforts)
and print a short summary with the peaks of the main channels and the contact
statistics. --plot writes the figure set (see 'jointgap plot --help'). Ctrl-C writes
the results up to there (status "interrupted" in summary.json) and exits with 130.
"""

_PLOT_DESCRIPTION = """\
Write the figure set of a saved result (a folder written by 'jointgap run'):
  figure                the overview, every main channel against time
  <slider>_displacement, <slider>_velocity, <slider>_acceleration
  <driver>_torque       (or _force)
  contact_force_<joint> and orbit_<joint>  for each clearance joint: the normal
                        force, and the journal centre inside the clearance circle
                        (mm, bearing frame, coloured by contact mode)
With --ideal (or an ideal/ folder inside RESULT), ideal and clearance runs are
overlaid. One file per figure and format.
"""

_CALIBRATE_DESCRIPTION = """\
Damping calibration of an ADAMS IMPACT clearance joint (docs/physics.md section 3, the
founding paper's Eq. 10-11): for a target restitution r, run, average the onset
speeds V_avg of the selected impacts, set C_max = 3 K (1 - r^2) / (4 V_avg) d_max^n,
and repeat until the integer part of C_max no longer changes (or --tolerance).
Prints the iteration table; --write saves the calibrated model. Ctrl-C writes the
iterations that ended to --table and exits with 130.

Without --restitution, the inverse: the restitution that C_max (--c-max or the
model's) corresponds to, at the V_avg of one run (or at --v-avg, without a run).
"""

_CONVERGE_DESCRIPTION = """\
Check that a run is converged: run at the given tolerances and at --levels tighter
ones (each ten times tighter), and compare with the tightest: impact counts and
onset times (to one output sample), peaks (--peak-tol) and NRMSE (--nrmse-tol) of
the main outputs (slider motion, driver efforts, contact forces). Says plainly
whether the run at the given tolerance has converged, and which tolerance would.
Exit status 4 when it has not, 3 when a run stops early (no verdict then).
"""


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``jointgap`` command."""
    parser = argparse.ArgumentParser(
        prog="jointgap",
        description=_DESCRIPTION,
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"jointgap {_version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    run = _command(
        sub,
        "run",
        "simulate a model file and write results.csv and summary.json",
        _RUN_DESCRIPTION,
    )
    _add_run_options(run)
    run.add_argument(
        "--every-step",
        action="store_true",
        help="also record every accepted step, not only the sampled output",
    )
    run.add_argument(
        "--decimate",
        type=int,
        metavar="K",
        help="keep every K-th output record (e.g. of --every-step); default all",
    )
    run.add_argument(
        "--stream",
        action="store_true",
        help="write the samples to OUT/results.parquet in chunks as the run goes (instead "
        "of results.csv at the end): memory holds one chunk, for long runs",
    )
    run.add_argument(
        "--channel",
        action="append",
        dest="channels",
        metavar="NAME",
        help="record only this channel (repeatable; 'element.*' for all of an element)",
    )
    run.add_argument(
        "--interpreted",
        action="store_true",
        help="evaluate the equations of motion interpreted, not by native code compiled from "
        "the model (the same results; docs/compiled.md)",
    )
    run.add_argument(
        "--energy",
        action="store_true",
        help="also keep the energy accounts: work of drivers and applied loads, energy "
        "dissipated, and system.energy_balance (about three more evaluations per step)",
    )
    run.add_argument(
        "--out",
        metavar="DIR",
        help="output folder (default out/<model file name>)",
    )
    run.add_argument(
        "--ideal",
        metavar="IDEAL.toml",
        help="also run this model (the same mechanism with ideal joints) with the same "
        "options into OUT/ideal; report the deviation and overlay it in the figures",
    )
    run.add_argument("--plot", action="store_true", help="also write the figure set into OUT")
    run.add_argument(
        "--report",
        nargs="?",
        const="",
        metavar="FILE.html",
        help="also write an interactive report: animation, plots, statistics in one "
        "self-contained file (default OUT/report.html; see 'jointgap report --help')",
    )
    _add_format_option(run)

    plot = sub.add_parser(
        "plot",
        help="write the figure set of a saved result",
        description=_PLOT_DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    plot.add_argument("result", metavar="RESULT", help="result folder written by 'jointgap run'")
    plot.add_argument("--ideal", metavar="IDEAL", help="result folder of the ideal run to overlay")
    plot.add_argument("--out", metavar="DIR", help="folder for the figures (default RESULT)")
    _add_format_option(plot)

    calibrate = _command(
        sub,
        "calibrate",
        "calibrate the C_max of an ADAMS IMPACT clearance joint for a restitution",
        _CALIBRATE_DESCRIPTION,
    )
    calibrate.add_argument(
        "--joint", help="clearance joint (default: the model's only adams_impact one)"
    )
    calibrate.add_argument(
        "--restitution", type=float, metavar="R", help="target restitution, in (0, 1]"
    )
    calibrate.add_argument(
        "--c-max",
        metavar="C",
        help="starting C_max [N*s/m] (default: the model's); without --restitution, the "
        "C_max whose restitution is wanted",
    )
    calibrate.add_argument(
        "--v-avg", metavar="V", help="inverse only: the average onset speed [m/s], no run"
    )
    calibrate.add_argument(
        "--min-onset-speed",
        metavar="V",
        help="V_avg over impacts with at least this onset speed [m/s] (default: all)",
    )
    calibrate.add_argument(
        "--window",
        nargs=2,
        metavar=("START", "END"),
        help="V_avg over impacts with onsets in this time window [s], e.g. the steady "
        "state after a ramp: --window 0.2 0.5 (END may be 'end')",
    )
    calibrate.add_argument(
        "--tolerance",
        type=float,
        metavar="C",
        help="stop when two runs' C_max differ by less than this [N*s/m] "
        "(default: the same integer part)",
    )
    calibrate.add_argument(
        "--max-iterations", type=int, default=40, metavar="N", help="most runs (default 40)"
    )
    calibrate.add_argument(
        "--write",
        metavar="OUT.toml",
        help="save the calibrated model: MODEL with the new c_max in its unit, comments kept",
    )
    calibrate.add_argument("--table", metavar="TABLE.csv", help="save the iteration table as CSV")
    _add_run_options(calibrate, t_end_required=False)

    converge = _command(
        sub,
        "converge",
        "check that a run's peaks and impacts are converged in the tolerance",
        _CONVERGE_DESCRIPTION,
    )
    converge.add_argument(
        "--levels", type=int, default=2, metavar="N", help="tighter tolerances (default 2)"
    )
    converge.add_argument(
        "--peak-tol",
        type=float,
        default=0.01,
        metavar="F",
        help="largest relative change of a peak (default %(default)g)",
    )
    converge.add_argument(
        "--nrmse-tol",
        type=float,
        default=0.01,
        metavar="F",
        help="largest NRMSE of a main output (default %(default)g)",
    )
    _add_run_options(converge, rate_default="10000")

    for module in _command_modules():
        module.add_commands(sub)
    check = sub.add_parser(
        "check",
        help="validate a model file and print its elements and degrees of freedom",
        description="Read and check a model file with the engine (units, names, references) "
        "and print its element counts and degrees of freedom.",
    )
    check.add_argument("model", metavar="MODEL.toml", help="model file")
    return parser


# Modules that add subcommands: each has `add_commands(sub)` and a `COMMANDS` table.
_COMMAND_MODULES = ("measured", "study", "report", "wear")


def _command_modules() -> list[Any]:
    import importlib

    return [importlib.import_module(f".{name}", __package__) for name in _COMMAND_MODULES]


def _version() -> str:
    from .._version import __version__

    return __version__


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``jointgap`` command; returns the exit status."""
    args = build_parser().parse_args(argv)
    commands = {
        "run": _run,
        "check": _check,
        "plot": _plot,
        "calibrate": _calibrate,
        "converge": _converge,
    }
    for module in _command_modules():
        commands.update(module.COMMANDS)
    try:
        return _with_clean_warnings(commands[args.command], args)
    except ModelError as exc:
        return _fail(str(exc))
    except OSError as exc:
        where = exc.filename if exc.filename is not None else ""
        return _fail(f"{where}: {exc.strerror or exc}" if where else str(exc))
    except ValueError as exc:  # invalid options
        return _fail(str(exc))
    except KeyboardInterrupt:  # outside a run (a run returns its partial result)
        return _interrupted("stopped by Ctrl-C")


_OWN_WARNINGS = ("run", "check")
"""The commands that list the model's and the run's warnings in their own output."""


def _with_clean_warnings(command: Callable[[argparse.Namespace], int], args: Any) -> int:
    """Runs a command with Python's warnings printed as one line each on stderr,
    ``jointgap: warning: ...``, without the source path. The warnings of its runs (the
    model's magnitudes, impacts between samples: :class:`RunWarning` and each Result's
    ``warnings``) are printed the same way once each when it ends, however many runs gave
    them, except by the commands that list them in their output (:data:`_OWN_WARNINGS`)
    and by a command that Ctrl-C stopped (it prints one line)."""
    from .._engine import collecting_warnings

    with warnings.catch_warnings(), collecting_warnings() as notes:
        warnings.showwarning = _show_warning
        warnings.simplefilter("ignore", RunWarning)
        if args.command in _OWN_WARNINGS:
            return command(args)
        try:
            status = command(args)
        except Exception:  # an error line follows them (not after Ctrl-C: one line)
            _print_warnings(notes)
            raise
        if status != EXIT_INTERRUPTED:
            _print_warnings(notes)
        return status


def _print_warnings(lines: Sequence[str]) -> None:
    """Prints warnings on stderr as Python's are printed, each distinct line once."""
    for line in dict.fromkeys(lines):
        _show_warning(line)


def _show_warning(message: Warning | str, *_: Any, **__: Any) -> None:
    print(f"jointgap: warning: {message}", file=sys.stderr)


def _check(args: argparse.Namespace) -> int:
    model = _load(args.model)
    warnings = model.check()
    counts = _counts(model)
    equations = model.joint_equations()
    print(f"{model.name or Path(args.model).stem} ({args.model}): valid")
    n_points = len(model.ground_points)
    print(f"  {counts}, {n_points} ground point{'' if n_points == 1 else 's'}")
    print(f"  joint equations: {equations}")
    print(
        f"  degrees of freedom: {model.degrees_of_freedom()} without drivers, "
        f"{model.degrees_of_freedom(with_drivers=True)} with drivers"
    )
    for warning in warnings:
        print(f"  warning: {warning}")
    return 0


def _counts(model: Model) -> str:
    parts = []
    for label, items in (
        ("body", model.bodies),
        ("joint", model.joints),
        ("driver", model.drivers),
        ("force", model.forces),
    ):
        plural = "bodies" if label == "body" else label + "s"
        parts.append(f"{len(items)} {label if len(items) == 1 else plural}")
    return ", ".join(parts)


def _run(args: argparse.Namespace) -> int:
    from ..plots import save_figure_set
    from ..statistics import (
        contact_statistics,
        deviation_from_ideal,
        deviation_table,
        format_statistics,
        statistics_table,
    )

    model = _load(args.model)
    out = Path(args.out) if args.out else Path("out") / Path(args.model).stem
    options = _run_options(args)
    with progress_line(args.t_end) as progress:
        result = model.simulate(
            args.t_end,
            every_step=args.every_step,
            channels=args.channels,
            decimate=args.decimate,
            energy=args.energy,
            compiled=not args.interpreted,
            stream=out / RESULTS_PARQUET if args.stream else None,
            progress=progress,
            **options,
        )
    written = _save(result, out)
    if result.interrupted:
        return _interrupted(f"the run {result.message}: the results up to there are in {out}")
    ideal = None
    if args.ideal:
        # The ideal run records as the clearance run does: same sampling, same memory.
        with progress_line(args.t_end, "ideal run: ") as progress:
            ideal = _load(args.ideal).simulate(
                args.t_end,
                every_step=args.every_step,
                channels=args.channels,
                decimate=args.decimate,
                stream=out / IDEAL_DIR / RESULTS_PARQUET if args.stream else None,
                progress=progress,
                **options,
            )
        written += _save(ideal, out / IDEAL_DIR)
        if ideal.interrupted:
            return _interrupted(
                f"the ideal run {ideal.message}: the results up to there are in "
                f"{out / IDEAL_DIR}, the run's in {out}"
            )
    stats = contact_statistics(result)
    deviations = deviation_from_ideal(result, ideal) if ideal is not None else []
    if stats:
        statistics_table(stats).to_csv(out / CONTACT_STATISTICS_CSV, index=False)
        written.append(out / CONTACT_STATISTICS_CSV)
    if deviations:
        deviation_table(deviations).to_csv(out / DEVIATION_CSV, index=False)
        written.append(out / DEVIATION_CSV)
    notes = []
    if args.plot:
        try:
            written += save_figure_set(result, out, ideal=ideal, formats=args.formats)
        except ValueError as exc:
            notes.append(f"warning    no figure: {exc}")
    if args.report is not None:
        from .report import report_after_run

        notes += report_after_run(result, ideal, out, args.model, written, args.report)
    print(
        _summary(
            model, args.model, result, written, format_statistics(stats, deviations, result.model)
        )
    )
    for note in notes:
        print(note)
    if ideal is not None and not ideal.ok:
        return _fail(f"{args.ideal}: the ideal run {ideal.message}", EXIT_RUN_FAILED)
    if not result.ok:
        return _fail(f"{args.model}: the run {result.message}", EXIT_RUN_FAILED)
    return 0


def _summary(model: Model, path: str, result: Result, written: list[Path], contact: str) -> str:
    s = result.stats
    o = result.options
    rate = _sampling(o)
    end = f"{result.time[-1]:g}" if len(result.time) else "-"
    lines = [
        f"model      {model.name or Path(path).stem} ({path}): {_counts(model)}",
        f"run        t = 0..{end} s, {len(result.time)} samples ({rate}), "
        f"rtol {o.get('rtol'):g}, atol {o.get('atol'):g}",
        f"method     {s.get('method', '?')}",
        f"steps      {s.get('accepted_steps', 0)} accepted, {s.get('rejected_steps', 0)} rejected;"
        f" {s.get('rhs_evaluations', 0)} rhs evaluations, "
        f"{s.get('jacobian_evaluations', 0)} Jacobians, {s.get('newton_iterations', 0)} Newton "
        f"iterations, {s.get('projections', 0)} projections",
        f"wall time  {s.get('wall_time', 0.0):.3g} s",
        f"evaluation {s.get('compiled', '?')}",
        f"status     {result.message or result.status}",
    ]
    peaks = main_channels(result)
    if peaks and len(result.time):
        lines.append("peaks      channel                         min            max")
        for c in peaks:
            v = result[c]
            unit = channel_unit(c)
            lines.append(f"           {c:<26} {v.min():>14.6g} {v.max():>14.6g}  {unit}")
    for k, line in enumerate(contact.splitlines()):
        lines.append(("contact    " if k == 0 else "           ") + line)
    for warning in result.warnings:
        lines.append(f"warning    {warning}")
    lines.append("written    " + ", ".join(str(p) for p in written))
    return "\n".join(lines)


def _sampling(options: dict[str, Any]) -> str:
    """How a run's records were taken, e.g. ``every step and 10000 Hz``."""
    rate = options.get("rate")
    every = "every step" if rate is None or options.get("every_step") else ""
    text = " and ".join(x for x in (every, "" if rate is None else f"{rate:g} Hz") if x)
    decimate = int(options.get("decimate") or 1)
    return text if decimate == 1 else f"{text}, 1 record in {decimate} kept"


def _plot(args: argparse.Namespace) -> int:
    from ..plots import save_figure_set

    folder = Path(args.result)
    result = Result.load(folder)
    ideal = None
    if args.ideal:
        ideal = Result.load(Path(args.ideal))
    elif (folder / IDEAL_DIR / SUMMARY_JSON).exists():
        ideal = Result.load(folder / IDEAL_DIR)
    paths = save_figure_set(result, Path(args.out or folder), ideal=ideal, formats=args.formats)
    print("written    " + ", ".join(str(p) for p in paths))
    return 0


def _calibrate(args: argparse.Namespace) -> int:
    from .. import units as u
    from ..calibration import (
        ImpactSelection,
        Iteration,
        average_onset_speed,
        calibrate_damping,
        iteration_frame,
        restitution_from_damping,
    )

    model = _load(args.model)
    joint = args.joint or _impact_joint(model)
    c_max = None if args.c_max is None else u.to_si(args.c_max, u.DAMPING)
    selection = ImpactSelection(
        min_speed=0.0 if args.min_onset_speed is None else u.to_si(args.min_onset_speed, u.SPEED),
        start=0.0 if args.window is None else u.to_si(args.window[0], u.TIME),
        end=None
        if args.window is None or args.window[1] == "end"
        else u.to_si(args.window[1], u.TIME),
    )
    options = _run_options(args)
    if args.t_end is None and (args.restitution is not None or args.v_avg is None):
        raise ValueError("--t-end is needed to run the model (only --v-avg goes without a run)")
    if args.restitution is None:
        law = model.joints[joint]["clearance"]["normal_law"]
        c = c_max if c_max is not None else float(law["c_max"])
        resolved = model.clearance_data()[joint]
        k, d_max, n = resolved["stiffness"], resolved["d_max"], resolved["exponent"]
        if args.v_avg is not None:
            v_avg, source = u.to_si(args.v_avg, u.SPEED), "given"
        else:
            from ..variants import with_parameters

            with progress_line(args.t_end) as progress:
                probe = with_parameters(model, {f"{joint}.c_max": c}).simulate(
                    args.t_end, channels=[f"{joint}.fn"], progress=progress, **options
                )
            if probe.interrupted:
                return _interrupted(f"the run {probe.message}: no V_avg, nothing written")
            if not probe.ok:
                return _fail(f"{args.model}: the run {probe.message}", EXIT_RUN_FAILED)
            v_avg, count = average_onset_speed(probe, joint, selection)
            source = f"over {count} impacts, {selection.describe()}"
        print(f"joint      {joint}: K = {k:.4g} N/m^{n:g}, d_max = {d_max:g} m")
        print(f"V_avg      {v_avg:.6g} m/s ({source})")
        try:
            r = restitution_from_damping(c, v_avg, k, d_max, n)
        except ValueError as exc:  # more than plastic: an answer, not a failure
            print(f"C_max      {c:.6g} N*s/m  ->  no restitution: {exc}")
            return 0
        print(f"C_max      {c:.6g} N*s/m  ->  restitution r = {r:.4f}")
        return 0
    done: list[Iteration] = []
    calibration = None  # until it ends: Ctrl-C leaves the table so far
    with progress_line(args.t_end, "run 1: ") as line:

        def finished(it: Iteration) -> None:
            done.append(it)
            if line is not None:
                line.label = f"run {it.iteration + 1}: "

        try:
            calibration = calibrate_damping(
                model,
                joint,
                args.restitution,
                args.t_end,
                c_max=c_max,
                selection=selection,
                tolerance=args.tolerance,
                max_iterations=args.max_iterations,
                progress=finished,
                run_progress=line,
                # The impact list is what V_avg needs: one channel keeps each run small.
                channels=[f"{joint}.fn"],
                **options,
            )
        except KeyboardInterrupt:
            pass
    if calibration is None:
        kept = _write_partial_table(args, iteration_frame(done))
        last = f" (last C_max {done[-1].c_max:.2f} N*s/m)" if done else ""
        return _interrupted(
            f"calibration run {len(done) + 1} stopped, {len(done)} done{last}{kept}"
        )
    print(calibration.table())
    _write_table_and_model(args, calibration.to_frame(), calibration.model)
    return 0 if calibration.converged else EXIT_NOT_CONVERGED


def _impact_joint(model: Model) -> str:
    """The model's only clearance joint with the ADAMS IMPACT law."""
    joints = [
        name
        for name, j in model.joints.items()
        if j["type"] == "clearance_revolute"
        and j["clearance"]["normal_law"]["type"] == "adams_impact"
    ]
    if len(joints) != 1:
        found = ", ".join(joints) if joints else "none"
        raise ValueError(f"name the joint with --joint (adams_impact clearance joints: {found})")
    return joints[0]


def _converge(args: argparse.Namespace) -> int:
    from ..convergence import LARGE_MEMORY, RunStopped, check_convergence, memory_need

    model = _load(args.model)
    options = _run_options(args)
    need = memory_need(model, args.t_end, args.rate, args.levels)
    if need > LARGE_MEMORY:
        print(
            f"converge: the {args.levels + 1} runs keep about {need / 1e6:.0f} MB of samples; "
            "a lower --rate or a shorter --t-end needs less",
            file=sys.stderr,
        )
    check = None
    try:
        with progress_line(args.t_end) as progress:

            def level(k: int, runs: int, rtol: float, atol: float) -> None:
                if progress is not None:  # the line names the run: "level 2/3 rtol 1e-09: "
                    progress.label = f"level {k}/{runs} rtol {rtol:g}: "

            check = check_convergence(
                model,
                args.t_end,
                levels=args.levels,
                peak_tolerance=args.peak_tol,
                nrmse_tolerance=args.nrmse_tol,
                level=level,
                progress=progress,
                **options,
            )
    except KeyboardInterrupt:
        pass
    except RunStopped as exc:
        return _fail(f"{args.model}: {exc}", EXIT_RUN_FAILED)
    if check is None:
        return _interrupted("a run stopped before every tolerance level ran: nothing compared")
    print(check.table())
    print()
    print(check.verdict())
    return 0 if check.ok else EXIT_NOT_CONVERGED
