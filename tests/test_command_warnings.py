"""Every command prints the warnings of the runs it makes: the model's implausible
magnitudes and the impacts that fell between output samples, on stderr, once each
however many runs gave them ('run' and 'check' list them in their own output,
tests/test_model_checks.py)."""

from __future__ import annotations

from pathlib import Path

import jointgap
import pandas as pd
import pytest
from jointgap.cli import EXIT_NOT_CONVERGED, main
from jointgap.study.execute import Case, run_case

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FOUNDING = EXAMPLES / "slider_crank_clearance.toml"
SPEED = (
    "jointgap: warning: driver 'motor': speed = 300 rad/s (2865 rpm) moves the points of "
    "the driven body at up to 24 m/s"
)
"""The start of the magnitude warning of ``speed = 300`` (a plain number: rad/s)."""


@pytest.fixture(scope="module")
def fast(tmp_path_factory) -> Path:
    """The founding case with ``speed = 300`` instead of ``"300 rpm"``: warned, not refused."""
    text = FOUNDING.read_text(encoding="utf-8")
    assert text.count('speed = "300 rpm"') == 1
    path = tmp_path_factory.mktemp("fast") / "fast.toml"
    path.write_text(text.replace('speed = "300 rpm"', "speed = 300"), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def record(fast, tmp_path_factory) -> Path:
    """A synthetic accelerometer record of the fast model (0.04 s from t = 0.01 s)."""
    from jointgap.measured import synthetic_record

    result = jointgap.load(fast).simulate(0.05, rate=20_000, channels=["slider.ax"])
    path = tmp_path_factory.mktemp("record") / "accelerometer.csv"
    synthetic_record(result, "slider.ax", lag=0.01, noise=1.0, duration=0.04).to_csv(path)
    return path


def printed_once(capsys, start: str) -> None:
    """The command printed the warning starting with ``start`` exactly once, on stderr."""
    captured = capsys.readouterr()
    assert captured.err.count(start) == 1, captured.err
    assert start.removeprefix("jointgap: warning: ") not in captured.out


def test_calibrate_prints_them_once_over_its_runs(fast, tmp_path, capsys, engine) -> None:
    table = tmp_path / "calibration.csv"
    args = ["calibrate", str(fast), "--restitution", "0.55", "--t-end", "0.05"]
    assert main([*args, "--max-iterations", "3", "--table", str(table)]) in (0, EXIT_NOT_CONVERGED)
    assert len(pd.read_csv(table)) >= 2  # runs
    printed_once(capsys, SPEED)


def test_converge_prints_them_once_over_its_levels(fast, capsys, engine) -> None:
    args = ["converge", str(fast), "--t-end", "0.02", "--rate", "2000", "--levels", "1"]
    assert main(args) in (0, EXIT_NOT_CONVERGED)
    printed_once(capsys, SPEED)


def test_synthesize_prints_them(fast, tmp_path, capsys, engine) -> None:
    args = ["synthesize", str(fast), "--signal", "slider.ax", "--t-end", "0.02"]
    assert main([*args, "--out", str(tmp_path / "m.csv")]) == 0
    printed_once(capsys, SPEED)


def test_compare_prints_them(fast, record, tmp_path, capsys, engine) -> None:
    args = ["compare", str(fast), "--measured", str(record), "--signal", "slider.ax"]
    assert main([*args, "--lag", "0.01", "--out", str(tmp_path / "cmp")]) == 0
    printed_once(capsys, SPEED)


def test_identify_prints_them_once_over_its_trials(fast, record, tmp_path, capsys, engine) -> None:
    args = ["identify", str(fast), "--measured", str(record), "--signal", "slider.ax"]
    args += ["--lag", "0.01", "--param", "rod_slider.c_max=10000:20000", "--scan", "3"]
    assert main([*args, "--workers", "2"]) == 0
    printed_once(capsys, SPEED)


def test_study_prints_them_once_over_its_cases(fast, tmp_path, capsys, engine) -> None:
    study = tmp_path / "study.toml"
    study.write_text(
        f'[study]\nmodel = "{fast}"\nt_end = "0.02 s"\nrate = "2 kHz"\n'
        '[parameters]\n"rod_slider.clearance" = ["0.3 mm", "0.4 mm", "0.5 mm"]\n'
        '[metrics]\npeak_contact_force = "peak_contact_force"\n',
        encoding="utf-8",
    )
    args = ["study", str(study), "--out", str(tmp_path / "out"), "--no-progress"]
    assert main([*args, "--workers", "2"]) == 0
    printed_once(capsys, SPEED)


def test_a_study_case_carries_its_warnings_home(fast, engine) -> None:
    """A case run on a Dask worker, in another process, brings its runs' warnings back
    in its outcome: the study prints those too."""
    model = jointgap.load(fast).to_dict()
    outcome = run_case(Case(0, {}, model, {"t_end": 0.01, "rate": 1000}, ()))
    assert any(w.startswith(SPEED.removeprefix("jointgap: warning: ")) for w in outcome.warnings)


def test_impacts_between_samples_are_printed_by_calibrate(capsys, engine) -> None:
    """The note of the founding case at 1 kHz (impacts of about 0.2 ms, samples 1 ms
    apart, tests/test_run_checks.py), from the run of the inverse calibration."""
    args = ["calibrate", str(FOUNDING), "--c-max", "17155", "--t-end", "0.5", "--rate", "1000"]
    assert main(args) == 0
    printed_once(capsys, "jointgap: warning: impacts between output samples: rod_slider: ")
