"""The ``report`` command of ``jointgap``: one self-contained interactive HTML file of
a results folder or a model file; and the helper behind ``jointgap run --report``."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .progress import progress_line
from .shared import EXIT_RUN_FAILED, _add_run_options, _fail, _interrupted, _load, _run_options

if TYPE_CHECKING:
    from ..results import Result

__all__ = ["COMMANDS", "REPORT_HTML", "add_commands", "report_after_run"]

REPORT_HTML = "report.html"

_REPORT_DESCRIPTION = """\
Write one self-contained HTML file (no network needed to view it, every script
inlined) from SOURCE:
  a folder of 'jointgap run'     the mechanism's animation (play, pause, speed, time
                                 slider; clearances drawn magnified), the journal
                                 orbit in its clearance circle, interactive plots of
                                 the main channels with a cursor at the animation's
                                 time, the model, options, contact statistics, impact
                                 list and run statistics; with an ideal/ subfolder
                                 (run --ideal) or --ideal, against the ideal run
  a folder of 'jointgap compare' the same for the simulation, with the aligned
                                 signals, difference, spectra and error measures
  a study folder (study.json)    the study's settings, every metric against every
                                 parameter, the table of cases, the figures
  a model file (MODEL.toml)      runs it first (--t-end, --rate... as 'jointgap run';
                                 --ideal IDEAL.toml runs the ideal model beside it)
A spatial model's run (dimension = 3) is drawn in 3D (rotate, zoom; each clearance
joint's pin orbit in its sphere or cylinder, magnified), plotly.js inlined.
Default output: SOURCE/report.html for a folder, out/<model name>/report.html for a
model file. Details: docs/report.md.
"""


def _add_report_options(parser: argparse.ArgumentParser) -> None:
    from ..report.scene import DEFAULT_MAX_FRAMES

    parser.add_argument(
        "--magnify",
        type=float,
        metavar="M",
        help="draw each clearance M times larger than it is (default: a round factor that "
        "makes the smallest clearance about 2 %% of the drawing)",
    )
    parser.add_argument(
        "--max-frames",
        type=int,
        default=DEFAULT_MAX_FRAMES,
        metavar="N",
        help="most animation frames, evenly spaced in time (default %(default)s)",
    )


def add_commands(sub: Any) -> None:
    """Adds ``report`` to the ``jointgap`` subcommands."""
    report = sub.add_parser(
        "report",
        help="write an interactive HTML report (animation, plots, statistics) of a "
        "results folder or a model",
        description=_REPORT_DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    report.add_argument(
        "source", metavar="SOURCE", help="results folder (run, compare, study) or model file"
    )
    report.add_argument("--out", metavar="FILE.html", help="report file to write")
    report.add_argument(
        "--ideal",
        metavar="IDEAL",
        help="the ideal run to compare with: a result folder (SOURCE a run folder) or a "
        "model file (SOURCE a model file)",
    )
    _add_report_options(report)
    _add_run_options(report, rate_default="10000", t_end_required=False)


def _size(path: Path) -> str:
    return f"{path.stat().st_size / 1e6:.2f} MB"


def _report(args: argparse.Namespace) -> int:
    from ..report import folder_report_data, run_report_data, write
    from ..results import Result

    source = Path(args.source)
    options = {"magnify": args.magnify, "max_frames": args.max_frames}
    if source.is_dir():
        ideal = Result.load(Path(args.ideal)) if args.ideal else None
        data = folder_report_data(source, ideal=ideal, **options)
        out = Path(args.out) if args.out else source / REPORT_HTML
    else:
        if args.t_end is None:
            raise ValueError(f"{source}: --t-end is needed to run the model for its report")
        model = _load(str(source))
        run_options = _run_options(args)
        with progress_line(args.t_end) as progress:
            result = model.simulate(args.t_end, progress=progress, **run_options)
        ideal = None
        if args.ideal and not result.interrupted:
            with progress_line(args.t_end, "ideal run: ") as progress:
                ideal = _load(args.ideal).simulate(args.t_end, progress=progress, **run_options)
        out = Path(args.out) if args.out else Path("out") / source.stem / REPORT_HTML
        if result.interrupted or (ideal is not None and ideal.interrupted):
            stopped = result if result.interrupted else ideal
            assert stopped is not None
            write(run_report_data(result, source=str(source), **options), out)
            which = "run" if stopped is result else "ideal run"
            return _interrupted(f"the {which} {stopped.message}: the report of the run is {out}")
        data = run_report_data(result, ideal=ideal, source=str(source), **options)
        if not result.ok:
            write(data, out)
            print(f"written    {out} ({_size(out)})")
            return _fail(f"{source}: the run {result.message}", EXIT_RUN_FAILED)
    write(data, out)
    print(f"written    {out} ({_size(out)})")
    return 0


def report_after_run(
    result: Result,
    ideal: Result | None,
    out: Path,
    model_file: str,
    written: list[Path],
    path: str = "",
) -> list[str]:
    """``jointgap run --report [FILE]``: writes FILE (default OUT/report.html) and adds
    it to ``written``; returns notes for the summary (a report that cannot be drawn is a
    warning, not a failure: the results are written)."""
    from ..report import ReportError, write_run_report

    target = Path(path) if path else out / REPORT_HTML
    try:
        written_path = write_run_report(result, target, ideal=ideal, source=model_file)
    except ReportError as exc:
        return [f"warning    no report: {exc}"]
    written.append(written_path)
    return []


COMMANDS: dict[str, Callable[[argparse.Namespace], int]] = {"report": _report}
