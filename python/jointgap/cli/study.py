"""The study commands of ``jointgap``: ``study`` runs a parametric or Monte Carlo study
file (locally or on a Dask cluster), ``study-plot`` draws its standard figures."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .shared import EXIT_RUN_FAILED, _fail, _interrupted

__all__ = ["COMMANDS", "add_commands"]

_LISTED_FAILURES = 5

_STUDY_DESCRIPTION = """\
Run every case of a study file (format: docs/studies.md): a base model, parameters
addressed by path (rod_slider.clearance, motor.speed, gravity, model) as lists,
ranges or distributions, and the metrics to keep per case. Cases run in parallel on
the local cores, or on an existing Dask cluster with --scheduler. Writes
  OUT/study.json     the resolved study (parameters in SI, metrics, case count)
  OUT/cases.jsonl    one line per case as it ends (what a restart skips)
  OUT/cases.csv      one row per case: case, the parameters (SI; a model as its
  OUT/cases.parquet  file name), the metrics, status, reason, run_time_s; each
                     header with its unit, e.g. "rod_slider.clearance [m]"
  OUT/series/        with time_series in the study file: case_NNNNNN.parquet
  OUT/study.lock     who runs the study while it runs: a second run on the same
                     OUT is refused, naming it
Run it again into the same OUT to finish an interrupted study: only the missing
cases run. A case that fails is kept with its reason; the others go on. Ctrl-C
drops the cases not started, lets the running ones end and stores them (Ctrl-C
again does not drop them), writes the tables and exits with status 130. Exit
status 3 when cases are missing at the end (the cluster lost them).
"""

_PLOT_DESCRIPTION = """\
Draw the standard figures of a study folder into DIR/figures: every metric against
the first grid parameter (--x), one line per value of the second (--lines), one panel
per value of any other; a heat map of every metric over those two; for sampled
parameters, histograms of the metrics and their rank correlation (Spearman) with
every sampled parameter (sensitivity). Failed cases are left out.
"""


def add_commands(sub: Any) -> None:
    """Adds ``study`` and ``study-plot`` to the ``jointgap`` subcommands."""
    study = sub.add_parser(
        "study",
        help="run a parametric or Monte Carlo study file on all cores or a Dask cluster",
        description=_STUDY_DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    study.add_argument("study", metavar="STUDY.toml", help="study file")
    study.add_argument("--out", metavar="DIR", help="study folder (default out/<study file name>)")
    study.add_argument(
        "--scheduler",
        metavar="tcp://HOST:PORT",
        help="run the cases on this Dask scheduler's workers (default: the local cores)",
    )
    study.add_argument(
        "--workers", type=int, metavar="N", help="local threads (default: every core)"
    )
    study.add_argument(
        "--dry-run", action="store_true", help="check the study file and list it, run nothing"
    )
    study.add_argument("--no-progress", action="store_true", help="no progress bar")

    plot = sub.add_parser(
        "study-plot",
        help="draw a study's figures: metric against parameters, heat maps, histograms",
        description=_PLOT_DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    plot.add_argument("dir", metavar="DIR", help="study folder written by 'jointgap study'")
    plot.add_argument("--x", metavar="PATH", help="parameter on the x axis")
    plot.add_argument("--lines", metavar="PATH", help="parameter with one line per value")
    plot.add_argument(
        "--format",
        nargs="+",
        dest="formats",
        choices=("png", "svg", "pdf"),
        default=["png"],
        help="figure formats (default: png)",
    )


def _study(args: argparse.Namespace) -> int:
    import sys

    from ..study import load_study, run_study

    study = load_study(args.study)
    print(_describe(study, args.study))
    if args.dry_run:
        return 0
    out = Path(args.out) if args.out else Path("out") / Path(args.study).stem
    try:
        run = run_study(
            study,
            out,
            scheduler=args.scheduler,
            workers=args.workers,
            progress=None if args.no_progress else sys.stderr,
        )
    except KeyboardInterrupt:
        return _interrupted(
            f"the cases that ended are stored in {out}; run the same command again to finish"
        )
    print(
        f"ran        {run.ran} cases in {run.wall_time:.3g} s on {run.where}"
        f" ({run.skipped} stored before)"
    )
    failed = run.table[run.table["status"] == "failed"]
    if len(failed):
        print(f"failed     {len(failed)} of {run.n_cases} cases:")
        for _, row in failed.head(_LISTED_FAILURES).iterrows():
            print(f"           case {row['case']}: {row['reason']}")
    written = [out / name for name in ("study.json", "cases.csv", "cases.parquet")]
    print("written    " + ", ".join(str(p) for p in written))
    if not run.complete:
        lost = "; ".join(f"case {k}: {why}" for k, why in sorted(run.missing.items())[:3])
        return _fail(
            f"{run.n_cases - len(run.table)} cases missing ({lost}): run again to finish",
            EXIT_RUN_FAILED,
        )
    return 0


def _describe(study: Any, path: str) -> str:
    """``study  NAME (FILE): N cases, grid over a (4) x b (6); metrics ...``."""
    grid = [f"{p.path} ({len(p.values)})" for p in study.parameters if not p.sampled]
    drawn = [f"{p.path} ({p.kind})" for p in study.parameters if p.sampled]
    if drawn:
        how = study.sampling.replace("_", " ")
        grid.append(f"{study.samples} {how} draws of {', '.join(drawn)}")
    design = " x ".join(grid) or "the base model alone"
    return (
        f"study      {study.name} ({path}): {len(study.cases())} cases, {design}\n"
        f"metrics    {', '.join(m.name for m in study.metrics)}"
    )


def _study_plot(args: argparse.Namespace) -> int:
    from ..study.plots import save_study_figures

    paths = save_study_figures(args.dir, x=args.x, lines=args.lines, formats=args.formats)
    print("written    " + ", ".join(str(p) for p in paths))
    return 0


COMMANDS: dict[str, Callable[[argparse.Namespace], int]] = {
    "study": _study,
    "study-plot": _study_plot,
}
