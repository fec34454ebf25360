"""The ``jointgap`` command: run and check model files.

    jointgap run examples/slider_crank_ideal.toml --t-end 0.5 --rate 10000 --out out --plot
    jointgap check examples/slider_crank_ideal.toml

Errors print one line on stderr and set the exit status: 1 invalid model, options or
file; 2 wrong command line; 3 the run stopped early (its results are still written).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from .model import Model
from .results import IMPACTS_CSV, RESULTS_CSV, SUMMARY_JSON, Result, channel_unit
from .run import DEFAULT_OPTIONS, METHODS
from .schema import JOINT_EQUATIONS, ModelError

__all__ = ["main", "build_parser"]

EXIT_INVALID = 1
EXIT_USAGE = 2
EXIT_RUN_FAILED = 3

_EPILOG = """\
quantities may carry units: --t-end "0.5 s", --rate "10 kHz", --max-step "1 us".
exit status: 0 success, 1 invalid model, options or file, 2 wrong command line,
3 the run stopped early (what was computed is still written).
"""

_DESCRIPTION = """\
Planar multibody mechanisms: check and run TOML model files
(format: docs/model-file.md).

example:
  jointgap check examples/slider_crank_ideal.toml
  jointgap run examples/slider_crank_ideal.toml --t-end 0.5 --rate 10000 --out out --plot
"""

_RUN_DESCRIPTION = """\
Simulate a model from t = 0 to --t-end and write
  OUT/results.csv   first column time [s], then every channel <element>.<quantity>
                    (SI units) in model order
  OUT/summary.json  the model, the options, run statistics and status: the run can
                    be repeated from it
  OUT/impacts.csv   for a model with clearance joints: one row per impact (joint,
                    onset_time, onset_speed, peak_force, max_penetration, duration)
and print a short summary with the peaks of the main channels.
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

    run = sub.add_parser(
        "run",
        help="simulate a model file and write results.csv and summary.json",
        description=_RUN_DESCRIPTION,
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    run.add_argument("model", metavar="MODEL.toml", help="model file")
    run.add_argument("--t-end", required=True, metavar="T", help="end time [s], e.g. 0.5")
    run.add_argument(
        "--rate",
        metavar="HZ",
        help="output sampling rate [Hz], e.g. 10000; default: every accepted step",
    )
    run.add_argument(
        "--rtol",
        type=float,
        default=DEFAULT_OPTIONS["rtol"],
        metavar="R",
        help="relative tolerance of the local error test (default %(default)g)",
    )
    run.add_argument(
        "--atol",
        type=float,
        default=DEFAULT_OPTIONS["atol"],
        metavar="A",
        help="absolute tolerance, in m, rad, m/s, rad/s (default %(default)g)",
    )
    run.add_argument(
        "--method",
        choices=METHODS,
        default=DEFAULT_OPTIONS["method"],
        help="integrator: auto (explicit dopri5, switching to implicit sdirk4 when the "
        "problem turns stiff), dopri5 or sdirk4 (default %(default)s)",
    )
    run.add_argument("--max-step", metavar="H", help="largest step [s]; default unbounded")
    run.add_argument(
        "--max-steps",
        type=int,
        metavar="N",
        help=f"step budget; the run fails when spent (default {DEFAULT_OPTIONS['max_steps']:g})",
    )
    run.add_argument(
        "--every-step",
        action="store_true",
        help="also record every accepted step, not only the sampled output",
    )
    run.add_argument(
        "--channel",
        action="append",
        dest="channels",
        metavar="NAME",
        help="record only this channel (repeatable; 'element.*' for all of an element)",
    )
    run.add_argument(
        "--out",
        metavar="DIR",
        help="output folder (default out/<model file name>)",
    )
    run.add_argument(
        "--plot", action="store_true", help="also write DIR/figure.png and DIR/figure.svg"
    )

    check = sub.add_parser(
        "check",
        help="validate a model file and print its elements and degrees of freedom",
        description="Read and check a model file with the engine (units, names, references) "
        "and print its element counts and degrees of freedom.",
    )
    check.add_argument("model", metavar="MODEL.toml", help="model file")
    return parser


def _version() -> str:
    from . import __version__

    return __version__


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``jointgap`` command; returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        if args.command == "run":
            return _run(args)
        return _check(args)
    except ModelError as exc:
        return _fail(str(exc))
    except OSError as exc:
        where = exc.filename if exc.filename is not None else ""
        return _fail(f"{where}: {exc.strerror or exc}" if where else str(exc))
    except ValueError as exc:  # invalid options
        return _fail(str(exc))


def _fail(message: str, status: int = EXIT_INVALID) -> int:
    print(f"jointgap: error: {message}", file=sys.stderr)
    return status


def _load(path: str) -> Model:
    from .io import load

    return load(path)


def _check(args: argparse.Namespace) -> int:
    model = _load(args.model)
    warnings = model.check()
    counts = _counts(model)
    equations = sum(JOINT_EQUATIONS[j["type"]] for j in model.joints.values())
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
    model = _load(args.model)
    out = Path(args.out) if args.out else Path("out") / Path(args.model).stem
    result = model.simulate(
        args.t_end,
        rate=args.rate,
        rtol=args.rtol,
        atol=args.atol,
        method=args.method,
        every_step=args.every_step,
        max_step=args.max_step,
        channels=args.channels,
        max_steps=args.max_steps,
    )
    result.save(out)
    written = [out / RESULTS_CSV, out / SUMMARY_JSON]
    if result.impacts:
        written.append(out / IMPACTS_CSV)
    notes = []
    if args.plot:
        from .plots import save_figure

        try:
            written += save_figure(result, out)
        except ValueError as exc:
            notes.append(f"warning    no figure: {exc}")
    print(_summary(model, args.model, result, written))
    for note in notes:
        print(note)
    if not result.ok:
        return _fail(f"{args.model}: the run {result.message}", EXIT_RUN_FAILED)
    return 0


def _summary(model: Model, path: str, result: Result, written: list[Path]) -> str:
    s = result.stats
    o = result.options
    rate = "every step" if o.get("rate") is None else f"{o['rate']:g} Hz"
    end = f"{result.time[-1]:g}" if len(result.time) else "-"
    lines = [
        f"model      {model.name or Path(path).stem} ({path}): {_counts(model)}",
        f"run        t = 0..{end} s, {len(result.time)} samples ({rate}), "
        f"rtol {o.get('rtol'):g}, atol {o.get('atol'):g}",
        f"method     {s.get('method', '?')}",
        f"steps      {s.get('accepted_steps', 0)} accepted, {s.get('rejected_steps', 0)} rejected;"
        f" {s.get('rhs_evaluations', 0)} rhs evaluations, "
        f"{s.get('jacobian_evaluations', 0)} Jacobians, {s.get('projections', 0)} projections",
        f"wall time  {s.get('wall_time', 0.0):.3g} s",
        f"status     {result.message or result.status}",
    ]
    peaks = main_channels(result)
    if peaks and len(result.time):
        lines.append("peaks      channel                         min            max")
        for c in peaks:
            v = result[c]
            unit = channel_unit(c)
            lines.append(f"           {c:<26} {v.min():>14.6g} {v.max():>14.6g}  {unit}")
    lines += _impact_lines(result)
    for warning in result.warnings:
        lines.append(f"warning    {warning}")
    lines.append("written    " + ", ".join(str(p) for p in written))
    return "\n".join(lines)


def _impact_lines(result: Result) -> list[str]:
    """Per clearance joint: impacts, peak contact force, max penetration, onset speeds."""
    lines = []
    for joint, impacts in result.impacts.items():
        head = f"impacts    {joint}: {len(impacts)}"
        if not impacts:
            lines.append(head)
            continue
        force = max(i.peak_force for i in impacts)
        depth = max(i.max_penetration for i in impacts)
        speeds = [i.onset_speed for i in impacts]
        lines.append(
            f"{head}, peak force {force:.6g} N, max penetration {depth:.4g} m, "
            f"onset speed mean {sum(speeds) / len(speeds):.4g} m/s, max {max(speeds):.4g} m/s"
        )
    return lines


def main_channels(result: Result) -> list[str]:
    """The channels worth a glance: slider-like bodies (position, velocity,
    acceleration along their guide), driver efforts, and the constraint error."""
    chosen: list[str] = []
    model = result.model
    for joint in model.get("joints", []):
        if joint.get("type") != "prismatic":
            continue
        body = joint["body_j"] if joint["body_j"] != "ground" else joint["body_i"]
        axis = joint.get("axis") or [1.0, 0.0]
        c = "x" if abs(axis[0]) >= abs(axis[1]) else "y"
        chosen += [f"{body}.{c}", f"{body}.v{c}", f"{body}.a{c}"]
    for driver in model.get("drivers", []):
        chosen += [f"{driver['name']}.torque", f"{driver['name']}.force"]
    if not chosen:
        for body in model.get("bodies", [])[:3]:
            chosen += [f"{body['name']}.angle", f"{body['name']}.omega"]
    chosen.append("system.constraint_error")
    return [c for c in dict.fromkeys(chosen) if c in result]


if __name__ == "__main__":
    sys.exit(main())
