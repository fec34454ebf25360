"""The ``wear`` command of ``jointgap``: wear over life of a model's revolute clearance
joints (:func:`jointgap.wear.predict_wear`), its tables, figures and report page in a
folder, resumed from that folder when run again with the same inputs."""

from __future__ import annotations

import argparse
import inspect
import sys
from collections.abc import Callable
from typing import Any

from .shared import EXIT_RUN_FAILED, _fail, _interrupted, _load

__all__ = ["COMMANDS", "add_commands"]

_DESCRIPTION = """\
Predict how the revolute clearance joints of MODEL wear over CYCLES cycles: Archard's
law on each part's angular grid, the wear of simulated steady cycles scaled over many
cycles by updates whose size step doubling chooses, the worn profiles fed back into the
joints (docs/wear.md). Writes to OUT: history.csv (deepest wear, worn volume,
clearance, peak contact force and the watched peak after each update), profiles_<joint>
.csv, summary.json, the figures (wear_history.png, wear_profile_<joint>.png) and
report.html; state.json after every update, from which the same command resumes.
A planar joint needs its 'length' (the bearing's, along the axis), or give --length; a
spatial clearance_cylindrical joint has its journal's own.
"""


def add_commands(sub: Any) -> None:
    """Adds ``wear`` to the ``jointgap`` subcommands."""
    from .. import wear

    parser = sub.add_parser(
        "wear",
        help="predict the wear of the journals in their bearings over many cycles",
        description=_DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    default = {k: v.default for k, v in inspect.signature(wear.predict_wear).parameters.items()}
    parser.add_argument("model", metavar="MODEL.toml", help="model file")
    parser.add_argument("--cycles", type=float, required=True, metavar="N", help="cycles to wear")
    parser.add_argument(
        "--coefficient",
        metavar="K",
        help=f"wear coefficient: a pair ({', '.join(wear.wear_pairs())}) or a value with units, "
        "e.g. '1e-4 mm^3/(N*m)' (default: the engine's pair, steel in brass, dry)",
    )
    parser.add_argument("--out", metavar="DIR", required=True, help="folder of the results")
    parser.add_argument(
        "--joint", action="append", metavar="NAME", help="a joint to wear (repeat; default all)"
    )
    parser.add_argument(
        "--cells",
        type=int,
        default=default["cells"],
        metavar="N",
        help="cells of each grid (default %(default)s)",
    )
    parser.add_argument(
        "--period", metavar="T", help="a cycle's duration (default: from the driver)"
    )
    parser.add_argument(
        "--warmup",
        metavar="T",
        help="time before the first steady cycle (default: the ramp and a cycle)",
    )
    parser.add_argument(
        "--cycles-per-run",
        type=int,
        default=default["cycles_per_run"],
        metavar="N",
        help="steady cycles each run averages (default %(default)s)",
    )
    parser.add_argument(
        "--tolerance",
        type=float,
        default=default["tolerance"],
        metavar="F",
        help="largest step-doubling difference as a fraction of the predicted depth "
        "(default %(default)g)",
    )
    parser.add_argument(
        "--limit", metavar="C", help="stop when a joint's clearance reaches C, e.g. '0.6 mm'"
    )
    parser.add_argument(
        "--every-cycle", action="store_true", help="no extrapolation: wear each simulated cycle"
    )
    parser.add_argument("--watch", metavar="CHANNEL", help="channel whose peak the history keeps")
    parser.add_argument(
        "--length",
        metavar="L",
        help="bearing length of the planar joints whose model gives none, e.g. '10 mm'",
    )


def _wear(args: argparse.Namespace) -> int:
    from ..wear import WearStep, predict_wear

    model = _load(args.model)

    def show(step: WearStep) -> None:
        print(
            f"\rcycles {step.cycles:.6g} (update of {step.step:.4g}), clearance "
            f"{step.clearance * 1e3:.5g} mm, {step.runs} runs",
            end="",
            file=sys.stderr,
            flush=True,
        )

    p = predict_wear(
        model,
        args.cycles,
        coefficient=args.coefficient,
        joints=args.joint,
        cells=args.cells,
        period=args.period,
        warmup=args.warmup,
        cycles_per_run=args.cycles_per_run,
        tolerance=args.tolerance,
        clearance_limit=args.limit,
        every_cycle=args.every_cycle,
        watch=args.watch,
        length=args.length,
        out=args.out,
        progress=show,
    )
    print(file=sys.stderr)
    print(
        f"coefficient {p.coefficient:.4g} 1/Pa ({p.pair or 'given'}), {p.cycles:.6g} cycles, "
        f"{p.runs} runs"
    )
    for joint, steps in p.profiles.items():
        _, b, w = steps[-1]
        print(
            f"  {joint}: deepest wear bearing {b.max() * 1e6:.4g} um, "
            f"journal {w.max() * 1e6:.4g} um"
        )
    if p.cycles_to_limit is not None:
        print(f"  the clearance limit is reached after {p.cycles_to_limit:.6g} cycles")
    print(f"written    {args.out}/ (history.csv, profiles, figures, report.html)")
    if p.status == "out_of_range":
        print(f"  {p.message}")
    if p.status == "interrupted":
        return _interrupted(f"{p.message}: resume with the same command")
    if p.status == "failed":
        return _fail(p.message, EXIT_RUN_FAILED)
    return 0


COMMANDS: dict[str, Callable[[argparse.Namespace], int]] = {"wear": _wear}
