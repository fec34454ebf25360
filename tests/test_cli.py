"""The jointgap command: run, check, help and errors."""

from __future__ import annotations

import csv
import json
import subprocess
import sys

import pytest
from jointgap.cli import EXIT_INVALID, EXIT_RUN_FAILED, main


def jointgap_cli(*args: str) -> subprocess.CompletedProcess[str]:
    """Runs the command in a fresh interpreter, as a user would."""
    return subprocess.run(
        [sys.executable, "-m", "jointgap", *args], capture_output=True, text=True, timeout=120
    )


def test_help_lists_the_commands() -> None:
    done = jointgap_cli("--help")
    assert done.returncode == 0
    assert "usage: jointgap" in done.stdout
    assert "run" in done.stdout and "check" in done.stdout
    assert "exit status" in done.stdout


def test_run_help_lists_every_option(capsys) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["run", "--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    for option in (
        "--t-end",
        "--rate",
        "--rtol",
        "--atol",
        "--method",
        "--max-step",
        "--out",
        "--plot",
    ):
        assert option in out
    assert "{auto,dopri5,sdirk4,radau5}" in out


def test_check_help(capsys) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["check", "--help"])
    assert exit_.value.code == 0
    assert "degrees of freedom" in capsys.readouterr().out


def test_run_writes_results_and_summary(examples, tmp_path, capsys, engine) -> None:
    out = tmp_path / "run"
    status = main(
        [
            "run",
            str(examples / "slider_crank_ideal.toml"),
            "--t-end",
            "0.5",
            "--rate",
            "10000",
            "--out",
            str(out),
        ]
    )
    assert status == 0
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    assert header[0] == "time"
    for channel in ("slider.x", "slider.vx", "slider.ax", "motor.torque"):
        assert channel in header
    assert len(rows) == 1 + 5001
    last = dict(zip(header, map(float, rows[-1]), strict=True))
    assert last["time"] == pytest.approx(0.5, abs=1e-12)
    assert last["slider.x"] == pytest.approx(0.40, abs=1e-7)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "finished"
    assert summary["model"]["name"] == "slider_crank_ideal"
    assert summary["options"]["t_end"] == 0.5 and summary["options"]["rate"] == 10000.0
    assert summary["stats"]["accepted_steps"] > 0
    printed = capsys.readouterr().out
    assert "model      slider_crank_ideal" in printed
    assert "status     finished" in printed
    assert "slider.ax" in printed and "motor.torque" in printed
    assert "-98.69" in printed  # peak slider acceleration, -r w^2 (1 + r/L)


def test_run_with_plot_writes_figures(examples, tmp_path, engine) -> None:
    out = tmp_path / "plot"
    args = [
        "run",
        str(examples / "slider_crank_ideal.toml"),
        "--t-end",
        "0.05",
        "--out",
        str(out),
        "--plot",
    ]
    assert main(args) == 0
    assert (out / "figure.png").stat().st_size > 10_000
    assert (out / "figure.svg").read_text().lstrip().startswith("<?xml")


def test_check_prints_counts_and_degrees_of_freedom(examples, capsys, engine) -> None:
    assert main(["check", str(examples / "slider_crank_ideal.toml")]) == 0
    out = capsys.readouterr().out
    assert "3 bodies, 4 joints, 1 driver, 0 forces, 1 ground point" in out
    assert "degrees of freedom: 1 without drivers, 0 with drivers" in out


def test_bad_file_exits_non_zero_with_one_clear_line(write_model, engine) -> None:
    path = write_model(
        """
        [[body]]
        name = "crank"
        mass = "2.37 m"
        inertia = 0.01
        """
    )
    done = jointgap_cli("run", str(path), "--t-end", "0.1")
    assert done.returncode == EXIT_INVALID
    assert done.stderr == (
        f"jointgap: error: {path}:3: body 'crank': mass '2.37 m': expected a mass [kg], "
        "got a length [m]\n"
    )
    assert "Traceback" not in done.stderr


def test_missing_file_exits_non_zero(tmp_path, capsys) -> None:
    assert main(["check", str(tmp_path / "none.toml")]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert err == f"jointgap: error: {tmp_path / 'none.toml'}: No such file or directory\n"


def test_bad_option_exits_non_zero(examples, tmp_path, capsys, engine) -> None:
    args = ["run", str(examples / "pendulum.toml"), "--t-end", "-1", "--out", str(tmp_path)]
    assert main(args) == EXIT_INVALID
    assert capsys.readouterr().err == "jointgap: error: option t_end = -1: must be positive\n"


def test_failed_run_still_writes_results(examples, tmp_path, capsys, engine) -> None:
    out = tmp_path / "failed"
    args = [
        "run",
        str(examples / "slider_crank_ideal.toml"),
        "--t-end",
        "0.5",
        "--max-steps",
        "5",
        "--out",
        str(out),
    ]
    assert main(args) == EXIT_RUN_FAILED
    err = capsys.readouterr().err
    assert err.startswith("jointgap: error: ")
    assert "the run failed at t = " in err
    assert json.loads((out / "summary.json").read_text())["status"] == "failed"
    assert (out / "results.csv").read_text().startswith("time,")


def test_usage_error_exits_2(capsys) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["run", "model.toml"])  # --t-end is required
    assert exit_.value.code == 2
    assert "the following arguments are required: --t-end" in capsys.readouterr().err


def test_figures_label_their_axes_with_units(examples, engine) -> None:
    import jointgap
    from jointgap.plots import figure

    crank = jointgap.load(examples / "slider_crank_ideal.toml").simulate(0.05, rate=1000)
    labels = [ax.get_ylabel() for ax in figure(crank).axes]
    assert labels == [
        "slider displacement [mm]",
        "slider velocity [m/s]",
        "slider acceleration [m/s$^2$]",
        "motor torque [N m]",
    ]
    assert figure(crank).axes[-1].get_xlabel() == "time [s]"
    pendulum = jointgap.load(examples / "pendulum.toml").simulate(0.5, rate=100)
    labels = [ax.get_ylabel() for ax in figure(pendulum).axes]
    assert labels == ["x [m]", "y [m]", "angle [deg]"]


def test_run_with_ideal_counterpart_then_plot(tmp_path, capsys, engine) -> None:
    """The founding case with its ideal counterpart: contact statistics and deviation in
    the summary and as tables, the figure set, and `jointgap plot` redoing the figures
    from the saved folders (the ideal/ folder found by itself)."""
    out = tmp_path / "founding"
    status = main(
        [
            "run",
            "examples/slider_crank_clearance.toml",
            "--t-end",
            "0.3",
            "--rate",
            "5000",
            "--out",
            str(out),
            "--ideal",
            "examples/slider_crank_ideal.toml",
            "--plot",
            "--format",
            "png",
            "pdf",
        ]
    )
    text = capsys.readouterr().out
    assert status == 0, text
    assert "contact    rod_slider:" in text and "impacts; free flight" in text
    assert "slider.ax vs ideal: RMS" in text and "motor.torque vs ideal" in text
    with open(out / "contact_statistics.csv") as f:
        row = next(csv.DictReader(f))
    with open(out / "impacts.csv") as f:
        assert int(row["impacts"]) == len(list(csv.DictReader(f)))
    with open(out / "deviation.csv") as f:
        assert [r["channel"] for r in csv.DictReader(f)] == ["slider.ax", "motor.torque"]
    assert (out / "ideal" / "results.csv").exists()
    for stem in ("figure", "slider_acceleration", "motor_torque", "orbit_rod_slider"):
        assert (out / f"{stem}.png").stat().st_size > 0
        assert (out / f"{stem}.pdf").stat().st_size > 0
    assert not (out / "figure.svg").exists()
    figures = tmp_path / "figures"
    assert main(["plot", str(out), "--out", str(figures), "--format", "svg"]) == 0
    assert "contact_force_rod_slider.svg" in capsys.readouterr().out
    svg = (figures / "slider_acceleration.svg").read_text()
    assert "ideal" in svg and "clearance" in svg


def test_synthesize_then_compare_from_the_command_line(tmp_path, capsys, engine) -> None:
    """A synthetic accelerometer record (5 kHz, 12 ms late) compared with the model it
    came from: the lag comes back within one sample, the errors are the noise's."""
    record = tmp_path / "accelerometer.csv"
    model = "examples/slider_crank_clearance.toml"
    assert (
        main(
            [
                "synthesize",
                model,
                "--signal",
                "slider.ax",
                "--t-end",
                "0.3",
                "--out",
                str(record),
                "--lag",
                "0.012",
                "--noise",
                "2",
                "--rtol",
                "1e-6",
                "--atol",
                "1e-9",
            ]
        )
        == 0
    )
    assert "written" in capsys.readouterr().out
    out = tmp_path / "cmp"
    assert (
        main(
            [
                "compare",
                model,
                "--measured",
                str(record),
                "--signal",
                "slider.ax",
                "--out",
                str(out),
                "--rtol",
                "1e-6",
                "--atol",
                "1e-9",
                "--format",
                "png",
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    lag_ms = float(text.split("lag: ")[1].split(" ms")[0])
    assert abs(lag_ms - 12.0) < 0.2
    assert "NRMSE" in text and "max error / measured peak" in text
    summary = json.loads((out / "comparison.json").read_text())
    assert abs(summary["lag"] - 0.012) < 2e-4
    assert (out / "comparison.png").stat().st_size > 0
    # A measured column that is not there is named, with the ones that are.
    status = main(
        [
            "compare",
            model,
            "--measured",
            str(record),
            "--signal",
            "slider.ax",
            "--column",
            "accel",
            "--out",
            str(out),
        ]
    )
    assert status == EXIT_INVALID
    assert "no data column 'accel'" in capsys.readouterr().err
    # A simulated channel that is not there is named before the run: nothing is written.
    missing = tmp_path / "missing"
    args = ["compare", model, "--measured", str(record), "--signal", "slider.acc"]
    assert main([*args, "--out", str(missing)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert "--signal slider.acc: no channel 'slider.acc'; close matches: " in err
    assert "slider.ax" in err and "Traceback" not in err and not missing.exists()


def test_compare_on_crank_angle(tmp_path, capsys, engine) -> None:
    """A record with the slider acceleration and the crank speed in rpm, 8 ms late: on
    the crank angle (speed integrated from the model's zero) the two signals agree to
    the noise, with no lag to estimate."""
    import jointgap
    import numpy as np
    from jointgap.measured import synthetic_record

    model = "examples/slider_crank_clearance.toml"
    run = jointgap.load(model).simulate(0.3, rate=50_000, rtol=1e-6, atol=1e-9)
    acc = synthetic_record(run, "slider.ax", lag=0.008, noise=1.0)
    speed = synthetic_record(run, "crank.omega", lag=0.008)
    path = tmp_path / "rig.csv"
    rows = np.column_stack([acc.time, acc.values, speed.values * 60 / (2 * np.pi)])
    np.savetxt(path, rows, delimiter=",", header="time,slider.ax,crank speed", comments="")
    args = [
        "compare",
        model,
        "--measured",
        str(path),
        "--signal",
        "slider.ax",
        "--out",
        str(tmp_path / "cmp"),
        "--rtol",
        "1e-6",
        "--atol",
        "1e-9",
        "--format",
        "png",
    ]
    assert main([*args, "--crank-column", "crank speed", "--crank-unit", "rpm"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("on crank angle"))
    # The noise alone (1 m/s^2 over a range of about 1300 m/s^2) is NRMSE 0.08 %; the
    # speed integrated from 5 kHz samples adds a little angle error at the impacts.
    nrmse = float(line.split("NRMSE ")[1].split(" %")[0])
    assert nrmse < 0.3, line
