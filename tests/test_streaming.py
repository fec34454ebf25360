"""Long-run output: results streamed to Parquet equal the in-memory ones exactly,
decimation keeps exactly every k-th record, progress reports come while the run goes and
an exception in a callback stops the run and propagates."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import jointgap
import numpy as np
import pytest
from jointgap import _engine as run_module
from jointgap._stream import StoredChannels, read_column
from jointgap.results import RESULTS_PARQUET, Result

CLEARANCE = Path(__file__).parent.parent / "examples" / "slider_crank_clearance.toml"
T_END = 0.12


@pytest.fixture(scope="module")
def model() -> jointgap.Model:
    return jointgap.load(CLEARANCE)


@pytest.fixture(scope="module")
def in_memory(model: jointgap.Model) -> Result:
    return model.simulate(T_END, rate=10_000)


def test_streamed_equals_in_memory(
    model: jointgap.Model, in_memory: Result, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Small chunks, so that the run spans many row groups and chunk borders.
    monkeypatch.setattr(run_module, "STREAM_CHUNK", 97)
    streamed = model.simulate(T_END, rate=10_000, stream=tmp_path / "run.parquet")
    assert isinstance(streamed.data, StoredChannels)
    assert streamed.stored == tmp_path / "run.parquet"
    import pyarrow.parquet as pq

    assert pq.ParquetFile(tmp_path / "run.parquet").num_row_groups == -(-len(in_memory.time) // 97)
    assert streamed.channels == in_memory.channels
    np.testing.assert_array_equal(streamed.time, in_memory.time)
    for channel in in_memory.channels:
        np.testing.assert_array_equal(streamed[channel], in_memory[channel])
    np.testing.assert_array_equal(np.asarray(streamed.data), in_memory.data)
    assert streamed.impacts == in_memory.impacts
    assert streamed.stats["accepted_steps"] == in_memory.stats["accepted_steps"]


def test_streamed_result_saves_and_loads(
    model: jointgap.Model, in_memory: Result, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    streamed = model.simulate(T_END, rate=10_000, stream=out / RESULTS_PARQUET)
    streamed.save(out)
    assert not (out / "results.csv").exists()
    loaded = Result.load(out)
    assert loaded.stored == out / RESULTS_PARQUET
    np.testing.assert_array_equal(loaded["slider.ax"], in_memory["slider.ax"])
    pd_frame = loaded.to_pandas()
    assert list(pd_frame.columns) == ["time", *in_memory.channels]
    # Saved elsewhere, the file is copied along.
    copy = tmp_path / "copy"
    loaded.save(copy)
    np.testing.assert_array_equal(Result.load(copy)["motor.torque"], in_memory["motor.torque"])


def test_streamed_file_is_plain_parquet(
    model: jointgap.Model, in_memory: Result, tmp_path: Path
) -> None:
    import pandas as pd

    path = tmp_path / "run.parquet"
    model.simulate(T_END, rate=10_000, stream=path)
    frame = pd.read_parquet(path)
    assert list(frame.columns) == ["time", *in_memory.channels]
    np.testing.assert_array_equal(frame["time"].to_numpy(), in_memory.time)
    np.testing.assert_array_equal(frame[in_memory.channels].to_numpy().T, in_memory.data)


def test_streaming_imports_no_pandas(tmp_path: Path) -> None:
    # pa.array and Array.to_numpy import pandas (about 45 MB of a streamed run's peak
    # memory, issue 6); the sink and the reader go around them.
    script = (
        "import sys, jointgap\n"
        f"r = jointgap.load({str(CLEARANCE)!r}).simulate(0.02, rate=10_000, "
        f"stream={str(tmp_path / 'run.parquet')!r})\n"
        "r['slider.ax']\n"
        "assert 'pyarrow' in sys.modules and 'pandas' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", script], check=True)


def test_read_column_of_other_files(tmp_path: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = tmp_path / "other.parquet"
    table = pa.table({"a": pa.array([1.5, None, 3.0], pa.float32()), "b": [1.0, 2.0, 3.0]})
    pq.write_table(table, path, row_group_size=2)
    np.testing.assert_array_equal(read_column(path, "a"), [1.5, np.nan, 3.0])
    np.testing.assert_array_equal(read_column(path, "b"), [1.0, 2.0, 3.0])
    with pytest.raises(KeyError, match="no column 'c'"):
        read_column(path, "c")


def test_selected_channels_stream(model: jointgap.Model, in_memory: Result, tmp_path: Path) -> None:
    streamed = model.simulate(
        T_END, rate=10_000, channels=["slider.*"], stream=tmp_path / "s.parquet"
    )
    assert streamed.channels == [c for c in in_memory.channels if c.startswith("slider.")]
    np.testing.assert_array_equal(streamed["slider.vx"], in_memory["slider.vx"])


def test_selected_channels_equal_the_full_run(model: jointgap.Model, in_memory: Result) -> None:
    # One channel from each group the engine computes only when one of its channels is
    # kept: a body, a revolute, a prismatic, the clearance joint, the driver, the system.
    picked = [
        "slider.ax",
        "crank_rod.fy",
        "slider_guide.moment",
        "rod_slider.fn",
        "rod_slider.mode",
        "motor.torque",
        "system.potential_energy",
    ]
    selected = model.simulate(T_END, rate=10_000, channels=picked)
    assert selected.channels == [c for c in in_memory.channels if c in picked]
    for name in picked:
        np.testing.assert_array_equal(selected[name], in_memory[name], err_msg=name)
    only_slider = model.simulate(T_END, rate=10_000, channels=["slider.ax"])
    np.testing.assert_array_equal(only_slider["slider.ax"], in_memory["slider.ax"])


def test_decimation_keeps_every_kth_record(model: jointgap.Model, in_memory: Result) -> None:
    # Every 7th record, and the end state whatever the decimation drops.
    kept = np.r_[np.arange(0, len(in_memory.time), 7), len(in_memory.time) - 1]
    decimated = model.simulate(T_END, rate=10_000, decimate=7)
    np.testing.assert_array_equal(decimated.time, in_memory.time[kept])
    np.testing.assert_array_equal(decimated.data, in_memory.data[:, kept])
    steps = model.simulate(0.03, every_step=True)
    every_third = model.simulate(0.03, every_step=True, decimate=3)
    kept = np.unique(np.r_[np.arange(0, len(steps.time), 3), len(steps.time) - 1])
    np.testing.assert_array_equal(every_third.time, steps.time[kept])
    np.testing.assert_array_equal(every_third["rod_slider.fn"], steps["rod_slider.fn"][kept])


def test_bad_decimation_is_refused(model: jointgap.Model) -> None:
    with pytest.raises(ValueError, match="decimate = 0"):
        model.simulate(0.01, decimate=0)


def test_progress_reports_while_running(model: jointgap.Model, monkeypatch) -> None:
    # Interval 0: a report at every check, every 16 accepted steps, whatever the speed.
    monkeypatch.setenv("JOINTGAP_PROGRESS_INTERVAL", "0")
    reports: list[tuple[float, int, int]] = []
    result = model.simulate(
        T_END, rate=10_000, method="sdirk4", progress=lambda *p: reports.append(p)
    )
    assert len(reports) == result.stats["accepted_steps"] // 16 > 2
    # A longer interval than the run: no report (the default, 0.2 s, lies between).
    monkeypatch.setenv("JOINTGAP_PROGRESS_INTERVAL", "1e9")
    quiet: list[tuple[float, int, int]] = []
    model.simulate(T_END, rate=10_000, method="sdirk4", progress=lambda *p: quiet.append(p))
    assert quiet == []
    # A check may fall on the last step, which ends at T_END.
    times = [t for t, _, _ in reports]
    assert times == sorted(times) and all(0 < t <= T_END for t in times)
    steps = [s for _, s, _ in reports]
    assert steps == sorted(steps)
    assert all(i <= len(result.impacts["rod_slider"]) for _, _, i in reports)


def test_exception_in_progress_stops_the_run(model: jointgap.Model, monkeypatch) -> None:
    monkeypatch.setenv("JOINTGAP_PROGRESS_INTERVAL", "0")  # the first report comes

    def stop(t: float, steps: int, impacts: int) -> None:
        raise LookupError("display gone")

    with pytest.raises(LookupError, match="display gone"):
        model.simulate(5.0, rate=1000, progress=stop)
    # (a KeyboardInterrupt is Ctrl-C: tests/test_cli_interrupt.py)


def test_exception_in_sink_stops_the_run(model: jointgap.Model, tmp_path: Path) -> None:
    from jointgap import _jointgap

    def full(names: list[str], time: np.ndarray, data: np.ndarray) -> None:
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="No space left"):
        _jointgap.simulate(model.to_json(), '{"t_end": 0.05, "rate": 10000}', None, full, 16)


def test_profile_accounts_for_the_run(model: jointgap.Model) -> None:
    plain = model.simulate(T_END, rate=10_000)
    profiled = model.simulate(T_END, rate=10_000, profile=True)
    assert "profile" not in plain.stats or plain.stats["profile"] is None
    # Measuring changes nothing in the results.
    np.testing.assert_array_equal(profiled.data, plain.data)
    p = profiled.stats["profile"]
    stages = ["forces", "linear_solves", "jacobians", "output", "events", "projection"]
    assert all(p[s] >= 0.0 for s in stages)
    # Stages exclude what they call, so together they fit inside the integration.
    assert 0.0 < sum(p[s] for s in stages) <= p["total"] * 1.001
    assert p["total"] <= profiled.stats["wall_time"]
    assert p["forces"] > 0.0 and p["linear_solves"] > 0.0 and p["output"] > 0.0
