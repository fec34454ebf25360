"""Every run is trustworthy or plainly marked (issue 21, section 2 and the initial state
of clearance joints): non-finite numbers stop a run, an impossible initial penetration
is an error, an output too large for memory is refused, impacts between samples are
reported, a study window outside the run and a measured signal of another quantity are
errors, a record shorter than the lag search is a warning."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import jointgap
import numpy as np
import pytest
from jointgap import _engine as run_module
from jointgap._output_size import OutputSize
from jointgap.cli import EXIT_INVALID, EXIT_RUN_FAILED, main
from jointgap.errors import OutputTooLarge, RunWarning

FOUNDING = "slider_crank_clearance.toml"
W = 300.0 * 2.0 * np.pi / 60.0
"""The founding case's crank speed after the ramp [rad/s] (300 rpm) ..."""
T_RAMP = 0.2
"""... reached linearly from rest in 0.2 s."""


def founding_with(examples: Path, tmp_path: Path, old: str, new: str) -> Path:
    """The founding example file with one line's text replaced."""
    text = (examples / FOUNDING).read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = tmp_path / "model.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


# ------------------------------------------------------------------ non-finite numbers


def test_mass_whose_weight_overflows_is_an_error(examples, tmp_path, capsys, engine) -> None:
    """The reproducer: mass = "1e308 kg" on the crank ran to "finished" with
    motor.torque = inf. Its weight overflows: an error naming the body, the file's line."""
    path = founding_with(examples, tmp_path, 'mass = "2.37 kg"', 'mass = "1e308 kg"')
    status = main(["run", str(path), "--t-end", "0.05", "--rate", "1000", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert status == EXIT_INVALID
    assert re.search(r"model.toml:\d+: body 'crank'.*mass = 1e308 kg: its weight", err), err
    assert "overflows the floating-point range" in err
    with pytest.raises(jointgap.ModelError, match="body 'crank'.*mass = 1e308 kg"):
        jointgap.load(path).simulate(0.05, rate=1000)


def test_overflow_during_a_run_fails_with_time_and_channel(
    examples, tmp_path, capsys, engine
) -> None:
    """A crank inertia of 5e305 kg m^2: finite at t = 0, but its kinetic energy J w^2 / 2
    passes the largest double when w = sqrt(2 f64max / J), at t* = 0.171 s of the ramp.
    The run fails there, names the channel, keeps the finite samples before it; the
    command writes them and exits 3, never "finished"."""
    inertia = 5e305
    path = founding_with(
        examples, tmp_path, 'inertia = "0.01201 kg*m^2"', f'inertia = "{inertia:g} kg*m^2"'
    )
    rate = 10_000.0
    t_star = T_RAMP / W * np.sqrt(2.0) * np.sqrt(np.finfo(float).max / inertia)
    result = jointgap.load(path).simulate(0.3, rate=rate)
    assert result.status == "failed" and not result.ok
    assert "system.kinetic_energy = inf" in result.message
    failed_at = float(re.search(r"failed at t = (\S+) s", result.message).group(1))
    assert t_star <= failed_at <= t_star + 1.0 / rate + 1e-6
    assert result.time[-1] < t_star
    assert np.all(np.isfinite(result.data))

    out = tmp_path / "out"
    status = main(["run", str(path), "--t-end", "0.3", "--rate", "1000", "--out", str(out)])
    captured = capsys.readouterr()
    assert status == EXIT_RUN_FAILED
    assert "finished" not in captured.out
    assert "system.kinetic_energy = inf" in captured.err
    assert (out / "results.csv").exists()


def test_overflow_at_the_start_is_a_model_error(examples, tmp_path, capsys, engine) -> None:
    """An inertia of 1e308 kg m^2 overflows in the first evaluation (the motor
    accelerates the crank from rest): an error before the run, naming the element of the
    first non-finite channel."""
    path = founding_with(
        examples, tmp_path, 'inertia = "0.01201 kg*m^2"', 'inertia = "1e308 kg*m^2"'
    )
    status = main(["run", str(path), "--t-end", "0.05", "--rate", "1000", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert status == EXIT_INVALID
    assert "joint 'ground_crank'" in err and "at the initial state (t = 0)" in err, err


def test_check_refuses_what_the_run_refuses_at_the_start(
    examples, tmp_path, capsys, engine
) -> None:
    """``check`` evaluates every channel at t = 0 as a run does before its first step: the
    model above, which ``check`` used to pass, fails ``check`` with the run's own error."""
    path = founding_with(
        examples, tmp_path, 'inertia = "0.01201 kg*m^2"', 'inertia = "1e308 kg*m^2"'
    )
    assert main(["check", str(path)]) == EXIT_INVALID
    checked = capsys.readouterr()
    assert "valid" not in checked.out
    status = main(["run", str(path), "--t-end", "0.05", "--rate", "1000", "--out", str(tmp_path)])
    assert status == EXIT_INVALID
    ran = capsys.readouterr().err
    line = re.search(r"model.toml:\d+: joint 'ground_crank': fx = (NaN|-?inf) at the initial", ran)
    assert line, ran
    assert checked.err == ran  # the same line, word for word


def test_every_example_passes_check_without_a_warning(examples, capsys, engine) -> None:
    for path in sorted(examples.glob("*.toml")):
        if "[[body]]" not in path.read_text(encoding="utf-8"):
            continue  # a study or calibration file
        assert main(["check", str(path)]) == 0, path.name
        captured = capsys.readouterr()
        assert "valid" in captured.out and "warning" not in captured.out, captured.out
        assert captured.err == "", (path.name, captured.err)


# ------------------------------------------------------------------ initial penetration


def test_journal_deep_in_its_bearing_is_an_error_naming_the_joint(
    examples, tmp_path, capsys, engine
) -> None:
    """The reproducer: joint crank_rod's point_i at the crank's centre (the old silent
    default [0, 0], here given explicitly) instead of its pin A. Assembly moves the rod,
    and the rod_slider journal starts 39.5 mm outside its 0.5 mm clearance."""
    path = founding_with(examples, tmp_path, 'point_i = "A"', "point_i = [0, 0]")
    with pytest.raises(jointgap.ModelError) as error:
        jointgap.load(path).simulate(0.05, rate=1000)
    message = str(error.value)
    assert "joint 'rod_slider'" in message
    assert "the journal starts 39.5000 mm deep in the bearing" in message
    assert "only under 1e6 N" in message and "wrong point" in message
    assert main(["check", str(path)]) == EXIT_INVALID
    status = main(["run", str(path), "--t-end", "0.05", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert status == EXIT_INVALID
    assert re.search(r"model.toml:\d+: joint 'rod_slider'", err), err
    assert not (tmp_path / "o").exists()


# ------------------------------------------------------------------ output size


def test_output_size_is_samples_times_channels(examples, engine) -> None:
    """The estimate: floor(t_end rate) + 1 samples (thinned by decimate) x the channels the
    engine records, 8 bytes a value with the time column."""
    model = jointgap.load(examples / FOUNDING)
    options = run_module.run_options(0.05, rate=1e9)
    size = run_module.output_size(model.to_dict(), options)
    channels = model.simulate(1e-4, rate=1e4).channels
    assert size == OutputSize(50_000_001, len(channels))
    assert size.memory == 8 * 50_000_001 * (len(channels) + 1)
    thinned = run_module.run_options(0.05, rate=1e9, decimate=10, channels=["slider.*"])
    assert run_module.output_size(model.to_dict(), thinned) == OutputSize(5_000_001, 9)
    assert run_module.output_size(model.to_dict(), run_module.run_options(0.05)) is None


def test_an_output_too_large_for_memory_is_refused(
    examples, tmp_path, capsys, monkeypatch, engine
) -> None:
    """The reproducer: --t-end 0.05 --rate 1e9 grew to 24 GB and was killed. On a machine
    of 16 GB (set here, so that the test does not depend on the machine) it is refused
    before it starts, with the figure and the ways out; streamed, it would run."""
    monkeypatch.setattr(run_module, "machine_memory", lambda: 16_000_000_000)
    path = examples / FOUNDING
    channels = len(jointgap.load(path).simulate(1e-4, rate=1e4).channels)
    memory = 8 * 50_000_001 * (channels + 1) / 1e9
    out = tmp_path / "big"
    status = main(["run", str(path), "--t-end", "0.05", "--rate", "1e9", "--out", str(out)])
    err = capsys.readouterr().err
    assert status == EXIT_INVALID
    assert f"50,000,001 samples x {channels} channels = {memory:.3g} GB in memory" in err, err
    assert "above the limit of 4 GB (0.25 of this machine's 16 GB of memory)" in err
    for way_out in ("--stream", "--decimate", "--rate"):
        assert way_out in err
    assert not out.exists()
    with pytest.raises(OutputTooLarge, match="stream=PATH"):
        jointgap.load(path).simulate(0.05, rate=1e9)
    # A batch holds all its results at once: two runs of half the size are refused too.
    half = run_module.run_options(0.025, rate=1e9)
    with pytest.raises(OutputTooLarge, match="2 runs x 25,000,001 samples"):
        run_module.simulate_many([jointgap.load(path).to_dict()] * 2, half)


# ------------------------------------------------------------------ impacts between samples


def test_impacts_between_samples_are_reported(examples, tmp_path, capsys, engine) -> None:
    """The founding case sampled at 1 kHz: impacts of 0.24-0.4 ms fall between samples
    (checked here against the sample times). The API warns, the result keeps the note,
    the command prints it as a line of its summary (not a Python warning); at 10 kHz and
    with every step recorded no impact is missed and nothing is said."""
    model = jointgap.load(examples / FOUNDING)
    with pytest.warns(RunWarning, match="impacts between output samples: rod_slider: ") as w:
        result = model.simulate(0.3, rate=1000)
    missed = sum(
        not np.any((result.time >= i.onset_time) & (result.time <= i.onset_time + i.duration))
        for i in result.impacts["rod_slider"]
        if np.isfinite(i.duration)
    )
    total = len(result.impacts["rod_slider"])
    assert missed > 0
    note = str(w[0].message)
    assert f"rod_slider: {missed} of {total} impacts had no output sample" in note
    assert "output interval 1 ms" in note and "--every-step" in note
    assert note in result.warnings
    for quiet in ({"rate": 10_000}, {"rate": 1000, "every_step": True}):
        with warnings.catch_warnings():
            warnings.simplefilter("error", RunWarning)
            notes = model.simulate(0.3, **quiet).warnings
        assert not any("between output samples" in n for n in notes)

    status = main(
        [
            "run",
            str(examples / FOUNDING),
            "--t-end",
            "0.3",
            "--rate",
            "1000",
            "--out",
            str(tmp_path),
        ]
    )
    captured = capsys.readouterr()
    assert status == 0
    assert f"warning    impacts between output samples: rod_slider: {missed} of" in captured.out
    assert "RunWarning" not in captured.err and "between output samples" not in captured.err


# ------------------------------------------------------------------ study window


def test_study_window_after_the_run_is_rejected_before_any_case(
    examples, tmp_path, capsys, engine
) -> None:
    """The reproducer: window = ["0.2 s", "end"] with t_end = "0.1 s"; rejected when the
    file is read, naming its line, as docs/studies.md promises."""
    study = tmp_path / "study.toml"
    study.write_text(
        f"""[study]
model = "{examples / FOUNDING}"
t_end = "0.1 s"
rate = "1 kHz"

[parameters]
"rod_slider.clearance" = ["0.5 mm"]

[metrics]
late_peak = {{ stat = "peak", channel = "slider.ax", window = ["0.2 s", "end"] }}
""",
        encoding="utf-8",
    )
    from jointgap.study import StudyError, load_study

    with pytest.raises(StudyError, match=r"study.toml:10: \[metrics\] late_peak .*starts at"):
        load_study(study)
    status = main(["study", str(study), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == EXIT_INVALID
    assert "the window starts at 0.2 s, not before the run ends (t_end = 0.1 s)" in err
    assert not (tmp_path / "out" / "cases.jsonl").exists()


# ------------------------------------------------------------------ compare


@pytest.fixture
def record(examples, tmp_path, engine) -> Path:
    """A synthetic accelerometer record of the founding case's slider, 0.3 s at 5 kHz."""
    path = tmp_path / "record.csv"
    assert (
        main(
            [
                "synthesize",
                str(examples / FOUNDING),
                "--signal",
                "slider.ax",
                "--t-end",
                "0.3",
                "--rate",
                "10000",
                "--out",
                str(path),
            ]
        )
        == 0
    )
    return path


def test_compare_with_another_quantity_is_an_error(examples, tmp_path, record, capsys) -> None:
    """The reproducer: a record whose header says slider.ax [m], compared with slider.ax
    (m/s^2): an error naming both units, exit 1, no Python warning."""
    capsys.readouterr()
    text = record.read_text(encoding="utf-8").replace("slider.ax [m/s^2]", "slider.ax [m]")
    wrong = tmp_path / "wrong.csv"
    wrong.write_text(text, encoding="utf-8")
    args = ["compare", str(examples / FOUNDING), "--measured", str(wrong), "--signal", "slider.ax"]
    status = main([*args, "--out", str(tmp_path / "cmp")])
    err = capsys.readouterr().err
    assert status == EXIT_INVALID
    assert "slider.ax is an acceleration [m/s^2], measured 'slider.ax' is a length [m]" in err
    assert "UserWarning" not in err and ".py" not in err


def test_short_record_gets_a_clean_warning(examples, tmp_path, record, capsys) -> None:
    """A record of 0.06 s against a lag search of ±0.05 s: the comparison runs, with one
    warning line (no UserWarning, no source path)."""
    capsys.readouterr()
    lines = record.read_text(encoding="utf-8").splitlines()
    head = [n for n, line in enumerate(lines) if line.startswith("time")][0]
    short = tmp_path / "short.csv"
    short.write_text("\n".join(lines[: head + 1 + 300]) + "\n", encoding="utf-8")
    args = ["compare", str(examples / FOUNDING), "--measured", str(short), "--signal", "slider.ax"]
    status = main([*args, "--out", str(tmp_path / "cmp"), "--t-end", "0.3"])
    err = capsys.readouterr().err
    assert status == 0, err
    expected = "jointgap: warning: compare: measured 'slider.ax' lasts 0.0598 s, shorter than"
    assert expected in err, err
    assert "UserWarning" not in err and ".py" not in err
