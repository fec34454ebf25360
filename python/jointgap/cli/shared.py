"""What every ``jointgap`` command shares: the exit statuses, the run options and their
parser, the error and Ctrl-C lines, loading a model file and writing a result. The
command modules (:mod:`.commands`, :mod:`.measured`, :mod:`.study`, :mod:`.report`)
import from here and not from one another."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from .._engine import DEFAULT_OPTIONS, METHODS
from ..model import Model
from ..results import IMPACTS_CSV, RESULTS_CSV, RESULTS_PARQUET, SUMMARY_JSON, Result

__all__ = [
    "EXIT_INTERRUPTED",
    "EXIT_INVALID",
    "EXIT_NOT_CONVERGED",
    "EXIT_RUN_FAILED",
    "EXIT_USAGE",
]

EXIT_INVALID = 1
EXIT_USAGE = 2
EXIT_RUN_FAILED = 3
EXIT_NOT_CONVERGED = 4
EXIT_INTERRUPTED = 130
"""128 + SIGINT, as shells report a command that Ctrl-C ended."""


_EPILOG = """\
quantities may carry units: --t-end "0.5 s", --rate "10 kHz", --max-step "1 us".
exit status: 0 success, 1 invalid model, options or file, 2 wrong command line,
3 the run stopped early (what was computed is still written), 4 not converged,
130 interrupted by Ctrl-C (what was computed is still written).
warnings of the model and its runs: listed by check and run, printed on stderr by
the other commands when they end, once each.
"""


def _command(sub: Any, name: str, help: str, description: str) -> argparse.ArgumentParser:
    """A subcommand that reads a model file, with the shared epilog."""
    parser: argparse.ArgumentParser = sub.add_parser(
        name,
        help=help,
        description=description,
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("model", metavar="MODEL.toml", help="model file")
    return parser


def _add_run_options(
    parser: argparse.ArgumentParser, rate_default: str | None = None, t_end_required: bool = True
) -> None:
    """The options every simulating command shares."""
    parser.add_argument(
        "--t-end", required=t_end_required, metavar="T", help="end time [s], e.g. 0.5"
    )
    parser.add_argument(
        "--rate",
        metavar="HZ",
        default=rate_default,
        help="output sampling rate [Hz], e.g. 10000; default: "
        + (rate_default or "every accepted step"),
    )
    parser.add_argument(
        "--rtol",
        type=float,
        default=DEFAULT_OPTIONS["rtol"],
        metavar="R",
        help="relative tolerance of the local error test (default %(default)g)",
    )
    parser.add_argument(
        "--atol",
        type=float,
        default=DEFAULT_OPTIONS["atol"],
        metavar="A",
        help="absolute tolerance, in m, rad, m/s, rad/s (default %(default)g)",
    )
    parser.add_argument(
        "--method",
        choices=METHODS,
        default=DEFAULT_OPTIONS["method"],
        help="integrator: auto (explicit dopri5, handing the steps to implicit radau5 while "
        "sticking friction is stiff and to sdirk4 when the problem turns stiff otherwise), "
        "dopri5, sdirk4 or radau5 (implicit Radau IIA of order 5) (default %(default)s)",
    )
    parser.add_argument("--max-step", metavar="H", help="largest step [s]; default unbounded")
    parser.add_argument(
        "--max-steps",
        type=int,
        metavar="N",
        help="step budget; the run fails when spent (default 1e7 steps, or 1e6 per simulated "
        "second when that is more)",
    )


def _add_format_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--format",
        nargs="+",
        dest="formats",
        choices=("png", "svg", "pdf"),
        default=["png", "svg"],
        help="figure formats (default: png svg)",
    )


def _run_options(args: argparse.Namespace) -> dict[str, Any]:
    """The shared options as keyword arguments of Model.simulate."""
    return {
        "rate": args.rate,
        "rtol": args.rtol,
        "atol": args.atol,
        "method": args.method,
        "max_step": args.max_step,
        "max_steps": args.max_steps,
    }


def _fail(message: str, status: int = EXIT_INVALID) -> int:
    print(f"jointgap: error: {message}", file=sys.stderr)
    return status


def _interrupted(message: str) -> int:
    """The one line of a command that Ctrl-C stopped (what it kept and where); exit
    status 130."""
    print(f"jointgap: interrupted: {message}", file=sys.stderr)
    return EXIT_INTERRUPTED


def _load(path: str) -> Model:
    from .._model_reader import load

    return load(path)


def _save(result: Result, out: Path) -> list[Path]:
    from .progress import writing_line

    with writing_line(str(out / RESULTS_CSV)) as progress:
        result.save(out, progress)
    written = [
        out / (RESULTS_CSV if result.stored is None else RESULTS_PARQUET),
        out / SUMMARY_JSON,
    ]
    if result.impacts:
        written.append(out / IMPACTS_CSV)
    return written


def _write_partial_table(args: argparse.Namespace, table: Any) -> str:
    """The table so far of a command that Ctrl-C stopped, to ``--table``: ``"; table so
    far in PATH"``, or ``""`` without --table."""
    if not args.table:
        return ""
    Path(args.table).parent.mkdir(parents=True, exist_ok=True)
    table.to_csv(args.table, index=False)
    return f"; the table so far is in {args.table}"


def _write_table_and_model(args: argparse.Namespace, table: Any, model: Model) -> None:
    """``--table`` (a DataFrame as CSV) and ``--write`` (the user's model file with the
    changed values, in the user's units, comments kept), if asked for."""
    if args.table:
        Path(args.table).parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(args.table, index=False)
        print(f"written    {args.table}")
    if args.write:
        from ..writeback import write_back

        for change in write_back(args.model, model, args.write):
            print(f"changed    {change}")
        print(f"written    {args.write}")
